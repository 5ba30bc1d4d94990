#!/usr/bin/python3
"""POV-Ray's trace time against LRay's render time at chosen error levels,
in many alternating runs.

run.py times every run of its ladders a few times; where a target is
decided by frames of a few milliseconds, this times just the pairs that
decide it, many times over, one run of each in turn: POV-Ray at one of
its levels, then LRay's run that reaches that level's RMSE (found on
run.py's ladders) on each backend. It prints each renderer's median and
quartiles and the ratio of the medians. With --refs (a run.py --out
folder of the same size) it also gives each run's RMSE against that
run's references, to show LRay's run is at POV-Ray's error or below.

    bench/time_vs_error/levels.py                      # the default pairs, 31 runs each
    bench/time_vs_error/levels.py --runs 11 --refs /tmp/tve --pair \\
        "pigments|+A0.3 +AM2 +R3|--noise-threshold 0.07 --min-samples 1 --edge-lattice 5"

A pair is "scene|POV-Ray's options|LRay's options" (320x180 and 2 threads
unless -w, -H, -t say otherwise). The default pairs are the levels where
LRay's render time alone was closest to a third of POV-Ray's
(bench/README.md, "Time to error").
"""

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

import run as tve

SPARSE = "--min-samples 1 --edge-lattice 5 --sparse-centres --max-samples 256"
DEFAULT_PAIRS = [
    "glass|-A|--noise-threshold 0.8 " + SPARSE,
    "pigments|+A0.3 +AM2 +R3|--noise-threshold 0.07 " + SPARSE,
    "ring|+A0.1 +AM2 +R3|--noise-threshold 0.035 " + SPARSE,
]


def pov_command(scene, opts, a):
    cmd = ["povray", "+I%s.pov" % scene, "+Olevels.png", "+W%d" % a.width, "+H%d" % a.height, "+FN",
           "-D", "-V", "+WT%d" % a.threads] + opts
    info = tve.SCENES[scene]
    if "frame" in info:
        last, f = info["frames"] - 1, info["frame"]
        cmd += ["+KFI0", "+KFF%d" % last, "+KI0", "+KF1", "+SF%d" % f, "+EF%d" % f]
    return cmd


def pov_run(scene, opts, a, folder):
    """Renders once in `folder`: (trace seconds, the image's path)."""
    for old in os.listdir(folder):
        if old.startswith("levels") and old.endswith(".png"):
            os.remove(os.path.join(folder, old))
    _, log = tve.run_checked(pov_command(scene, opts, a), cwd=folder)
    times = re.findall(r"Trace Time:.*\(\s*([\d.]+) seconds\)", log)
    if not times:
        raise tve.BenchError("povray printed no trace time:\n%s" % log[-2000:])
    image = [p for p in os.listdir(folder) if p.startswith("levels") and p.endswith(".png")][0]
    return sum(float(t) for t in times), os.path.join(folder, image)


def lray_run(scene, opts, backend, a, folder):
    """Renders once: (--stats render seconds, the image's path)."""
    out = os.path.join(folder, "lray-out")
    shutil.rmtree(out, ignore_errors=True)
    stats = os.path.join(folder, "stats.json")
    cmd = [a.lray, os.path.join(tve.SCENE_DIR, scene + ".lua"), out, "--backend", backend,
           "-t", str(a.threads), "-w", str(a.width), "-H", str(a.height), "--linear", "-q",
           "--stats", stats] + opts
    if "frame" in tve.SCENES[scene]:
        cmd += ["--frames", str(tve.SCENES[scene]["frame"])]
    tve.run_checked(cmd)
    with open(stats) as f:
        seconds = sum(fr["times"]["render"] for fr in json.load(f)["frames"])
    return seconds, os.path.join(out, os.listdir(out)[0])


def quartiles(v):
    if len(v) < 2:
        return "one run"
    q = statistics.quantiles(v, n=4)
    return "%.1f-%.1f" % (1000 * q[0], 1000 * q[2])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--lray", default=os.path.join(tve.ROOT, "build", "lray"))
    p.add_argument("--runs", type=int, default=31, help="runs of each renderer (default 31)")
    p.add_argument("--pair", action="append",
                   help="scene|POV-Ray options|LRay options (repeatable)")
    p.add_argument("--backends", type=tve.csv_list(["embree", "kdtree"]),
                   default=["embree", "kdtree"])
    p.add_argument("--refs", help="a run.py --out folder: RMSE against its references")
    p.add_argument("-w", "--width", type=int, default=320)
    p.add_argument("-H", "--height", type=int, default=180)
    p.add_argument("-t", "--threads", type=int, default=2)
    a = p.parse_args()
    if not shutil.which("povray"):
        sys.exit("levels: povray is not on PATH (scripts/setup --bench installs it)")
    folder = tempfile.mkdtemp(prefix="lray-levels-")
    for name in os.listdir(tve.SCENE_DIR):
        if not name.endswith(".lua"):
            shutil.copy(os.path.join(tve.SCENE_DIR, name), folder)
    print("%dx%d, %d threads, %d alternating runs each; ms: median (quartiles)"
          % (a.width, a.height, a.threads, a.runs))
    for spec in a.pair or DEFAULT_PAIRS:
        scene, pov_opts, lray_opts = (s.strip() for s in spec.split("|"))
        if scene not in tve.SCENES:
            sys.exit("levels: no bench scene %r" % scene)
        if tve.SCENES[scene].get("mesh"):
            tve.write_torus_mesh2(os.path.join(folder, "mesh200k_mesh.inc"))
        pov_opts, lray_opts = pov_opts.split(), lray_opts.split()
        pov_times, lray_times = [], {b: [] for b in a.backends}
        images = {}
        for _ in range(a.runs):
            seconds, images["povray"] = pov_run(scene, pov_opts, a, folder)
            pov_times.append(seconds)
            for b in a.backends:
                seconds, image = lray_run(scene, lray_opts, b, a, folder)
                lray_times[b].append(seconds)
                if a.refs and b not in images:
                    kept = os.path.join(folder, "kept-%s.png" % b)
                    shutil.copy(image, kept)
                    images[b] = kept
        pov = statistics.median(pov_times)
        line = "%s, POV-Ray %s: %.1f ms (%s)" % (scene, " ".join(pov_opts[:3]), 1000 * pov,
                                                  quartiles(pov_times))
        if a.refs:
            ref = tve.read_rgb(os.path.join(a.refs, "renders", scene, "pov-reference.png"))
            line += ", RMSE %.5f" % tve.rmse(tve.read_rgb(images["povray"]), ref)
        print(line)
        for b in a.backends:
            m = statistics.median(lray_times[b])
            line = "  LRay %s %s: %.2f ms (%s), POV-Ray / LRay %.2f" % (
                b, " ".join(lray_opts[:2]), 1000 * m, quartiles(lray_times[b]), pov / m)
            if a.refs:
                ref = tve.read_rgb(os.path.join(a.refs, "renders", scene, "lray-reference.png"))
                line += ", RMSE %.5f" % tve.rmse(tve.read_rgb(images[b]), ref)
            print(line)
    shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
