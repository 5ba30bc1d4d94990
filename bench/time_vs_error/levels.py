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
    bench/time_vs_error/levels.py --refs /tmp/tve --find-threshold

With --find-threshold (needs --refs), each pair's --noise-threshold is
replaced first by the largest threshold on a 2 % grid from half to twice
it whose render is at or below POV-Ray's RMSE: LRay's run at POV-Ray's
very level, not at the next step of run.py's ladder (whose steps of
1.2-1.4x overshoot a level by up to one step, and more where a class of
edges is cut one level deeper at once).

A pair is "scene|POV-Ray's options|LRay's options" (320x180 and 2 threads
unless -w, -H, -t say otherwise). The default pairs are the levels where
LRay's render time alone was closest to a third of POV-Ray's
(bench/README.md, "Time to error"), at thresholds near each level (with
--find-threshold, where the search starts).
"""

import argparse
import os
import shutil
import statistics
import sys
import tempfile

import run as tve

SPARSE = "--min-samples 1 --edge-lattice 5 --sparse-centres --max-samples 256"
DEFAULT_PAIRS = [
    "glass|-A|--noise-threshold 0.8 " + SPARSE,
    "pigments|+A0.3 +AM2 +R3|--noise-threshold 0.08 " + SPARSE,
    "ring|+A0.3 +AM2 +R3|--noise-threshold 0.04 " + SPARSE,
    "ring|+A0.1 +AM2 +R3|--noise-threshold 0.04 " + SPARSE,
    "ring|+A0.03 +AM2 +R4|--noise-threshold 0.008 " + SPARSE,
]


def quartiles(v):
    if len(v) < 2:
        return "one run"
    q = statistics.quantiles(v, n=4)
    return "%.1f-%.1f" % (1000 * q[0], 1000 * q[2])


def threshold_of(opts):
    return float(opts[opts.index("--noise-threshold") + 1])


def with_threshold(opts, threshold):
    out = list(opts)
    out[out.index("--noise-threshold") + 1] = "%.6g" % threshold
    return out


def find_threshold(runner, a, scene, opts, ref, level):
    """The largest threshold t * 1.02^-k (k = -35..35) whose render's RMSE
    against LRay's reference `ref` is at or below `level`. Both backends
    render the same images, so the first one's runs decide."""
    t = threshold_of(opts)
    for k in range(-35, 36):
        threshold = t * 1.02 ** -k
        _, _, image, _, _ = runner.lray_render(scene, a.backends[0], "find",
                                               with_threshold(opts, threshold))
        if tve.rmse(tve.read_rgb(image), ref) <= level:
            return threshold
    sys.exit("levels: no threshold from %g to %g reaches POV-Ray's RMSE %.5f on %s"
             % (2 * t, t / 2, level, scene))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--lray", default=os.path.join(tve.ROOT, "build", "lray"))
    p.add_argument("--runs", type=int, default=31, help="runs of each renderer (default 31)")
    p.add_argument("--pair", action="append",
                   help="scene|POV-Ray options|LRay options (repeatable)")
    p.add_argument("--backends", type=tve.csv_list(["embree", "kdtree"]),
                   default=["embree", "kdtree"])
    p.add_argument("--refs", help="a run.py --out folder: RMSE against its references")
    p.add_argument("--find-threshold", action="store_true",
                   help="LRay's threshold: the largest at or below POV-Ray's RMSE (needs --refs)")
    p.add_argument("-w", "--width", type=int, default=320)
    p.add_argument("-H", "--height", type=int, default=180)
    p.add_argument("-t", "--threads", type=int, default=2)
    a = p.parse_args()
    if a.find_threshold and not a.refs:
        sys.exit("levels: --find-threshold needs --refs")
    if not shutil.which("povray"):
        sys.exit("levels: povray is not on PATH (scripts/setup --bench installs it)")
    pairs = [tuple(part.strip() for part in spec.split("|")) for spec in a.pair or DEFAULT_PAIRS]
    for scene, _, _ in pairs:
        if scene not in tve.SCENES:
            sys.exit("levels: no bench scene %r" % scene)
    # run.py's runner renders and times each run (its renders and POV-Ray's
    # working folder in a temporary --out).
    a.out = tempfile.mkdtemp(prefix="lray-levels-")
    a.scenes = sorted({scene for scene, _, _ in pairs})
    a.no_pov = False
    runner = tve.Runner(a)
    runner.prepare_pov()
    print("%dx%d, %d threads, %d alternating runs each; ms: median (quartiles)"
          % (a.width, a.height, a.threads, a.runs))
    for scene, pov_opts, lray_opts in pairs:
        pov_opts, lray_opts = pov_opts.split(), lray_opts.split()
        # The first run of each gives its image; the timers run it again.
        _, seconds, pov_image, _, pov_timer = runner.pov_render(scene, "levels", pov_opts)
        pov_times = [seconds]
        if a.refs:
            # Each renderer against its own reference, read once a pair.
            refs = os.path.join(a.refs, "renders", scene)
            pov_rmse = tve.rmse(tve.read_rgb(pov_image),
                                tve.read_rgb(os.path.join(refs, "pov-reference.png")))
            lray_ref = tve.read_rgb(os.path.join(refs, "lray-reference.png"))
        if a.find_threshold:
            lray_opts = with_threshold(lray_opts, find_threshold(runner, a, scene, lray_opts,
                                                                 lray_ref, pov_rmse))
        lray_times, lray_images, lray_timers = {}, {}, {}
        for b in a.backends:
            _, seconds, lray_images[b], _, lray_timers[b] = runner.lray_render(
                scene, b, "levels-" + b, lray_opts)
            lray_times[b] = [seconds]
        for _ in range(a.runs - 1):
            pov_times.append(pov_timer()[1])
            for b in a.backends:
                lray_times[b].append(lray_timers[b]()[1])
        pov = statistics.median(pov_times)
        line = "%s, POV-Ray %s: %.1f ms (%s)" % (scene, " ".join(pov_opts[:3]), 1000 * pov,
                                                  quartiles(pov_times))
        if a.refs:
            line += ", RMSE %.5f" % pov_rmse
        print(line)
        for b in a.backends:
            m = statistics.median(lray_times[b])
            line = "  LRay %s %s: %.2f ms (%s), POV-Ray / LRay %.2f" % (
                b, " ".join(lray_opts[:2]), 1000 * m, quartiles(lray_times[b]), pov / m)
            if a.refs:
                line += ", RMSE %.5f" % tve.rmse(tve.read_rgb(lray_images[b]), lray_ref)
            print(line)
    shutil.rmtree(a.out, ignore_errors=True)


if __name__ == "__main__":
    main()
