#!/usr/bin/python3
"""What motion blur costs (issue 36's target: a blurred frame at 16 samples
per pixel takes at most 1.5x the same frame rendered sharp).

Each case renders one frame with its shutter open (--shutter) and again
closed (--shutter 0), 4 x 4 samples per pixel, on each backend, `--runs`
times, and reports the medians of lray's own --stats times: `render` (the
tiles), `build` (the acceleration structure) and `scene` (every
scene(clock) call and the conversion; `scene_calls` of them with the
shutter open). A table (markdown) goes to stdout. See bench/README.md,
"Motion blur", for the current figures.

    bench/motion/motion_cost.py                 # 2 threads, 3 runs
    bench/motion/motion_cost.py --threads 1 --runs 5
    bench/motion/motion_cost.py --instructions  # callgrind, a quarter of the size
    bench/motion/motion_cost.py --embree-alone  # what Embree's own motion blur costs

Times on a shared machine wander by 10 % and more from run to run;
`--instructions` counts the instructions of the tile rendering instead
(valgrind's callgrind, inclusive in lray::sampleTile, one thread, each
image a quarter of the width and height): deterministic, but blind to
cache misses and latency, so it reads lower than the times.

`--embree-alone` asks how much of the ratio is Embree's: each case runs
through build/bench_throughput (one thread, Embree, the same rays traced
again through the backend alone, bench/throughput/README.md) under `perf
record`, sharp and blurred, and reports three ratios, blurred over sharp:
LRay's render, the backend alone (Embree with LRay's shape callbacks) and
Embree's own code (perf samples in libembree3). Needs `perf`.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
LRAY = os.path.join(ROOT, "build", "lray")
BENCH_THROUGHPUT = os.path.join(ROOT, "build", "bench_throughput")

# name -> (scene, frame, shutter, extra options)
CASES = {
    "crowd (900 spheres drift, 900 cubes spin, a 20k-triangle cloth waves)":
        (os.path.join(HERE, "scenes", "crowd.lua"), 0, "0.5", ["-w", "640", "-H", "360"]),
    "motion.lua frame 0 (a spinning wheel, thin lens)":
        (os.path.join(ROOT, "scenes", "motion.lua"), 0, "0.5", ["-w", "640", "-H", "320"]),
    "ring.lua frame 2 (the camera orbits: every ray)":
        (os.path.join(ROOT, "scenes", "ring.lua"), 2, "0.5", ["-w", "640", "-H", "480"]),
}


def run(scene, frame, shutter, extra, backend, threads, out):
    stats = os.path.join(out, "stats.json")
    subprocess.run([LRAY, scene, out, "-q", "--frames", f"{frame}:{frame}", "-s", "4",
                    "--shutter", shutter, "--backend", backend, "-t", str(threads),
                    "--stats", stats] + extra, check=True)
    with open(stats) as f:
        s = json.load(f)
    return s["times"], s["frames"][0]["scene_calls"]


def instructions(scene, frame, shutter, extra, backend, out):
    """Instructions lray spends in its tile sampler, from callgrind."""
    size = [str(int(v) // 4) if k in ("-w", "-H") else v
            for k, v in zip([None] + extra[:-1], extra)]
    profile = os.path.join(out, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={profile}", LRAY,
                    scene, out, "-q", "--frames", f"{frame}:{frame}", "-s", "4", "--shutter",
                    shutter, "--backend", backend, "-t", "1"] + size,
                   check=True, capture_output=True)
    report = subprocess.run(["callgrind_annotate", "--inclusive=yes", profile], check=True,
                            capture_output=True, text=True).stdout
    for line in report.splitlines():
        if "lray::sampleTile" in line:
            return int(line.split()[0].replace(",", ""))
    raise RuntimeError("no lray::sampleTile in the profile")


def embree_alone(scene, frame, shutter, extra, out):
    """(render s, backend-alone s, Embree's own perf samples) of one frame."""
    data = os.path.join(out, "perf.data")
    result = subprocess.run(["perf", "record", "-q", "-F", "2000", "-o", data, BENCH_THROUGHPUT,
                             scene, "-s", "4", "--frame", str(frame), "--shutter", shutter,
                             "--repeats", "3"] + extra,
                            check=True, capture_output=True, text=True)
    line = json.loads(result.stdout.strip().splitlines()[-1])
    report = subprocess.run(["perf", "report", "-i", data, "--sort", "dso", "-q", "-n"],
                            check=True, capture_output=True, text=True).stdout
    samples = sum(int(row.split()[1]) for row in report.splitlines() if "libembree" in row)
    return line["render_s"], line["raw_s"]["total"], samples


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--backends", nargs="+", default=["embree", "kdtree"])
    ap.add_argument("--instructions", action="store_true",
                    help="count instructions under callgrind instead of timing")
    ap.add_argument("--embree-alone", action="store_true",
                    help="how much of the ratio is Embree's own (perf, bench_throughput)")
    args = ap.parse_args()
    if args.embree_alone:
        print("bench_throughput, Embree, 1 thread, 4 x 4 samples per pixel; blurred / sharp\n")
        print("| scene | render sharp / blurred (s) | LRay's render | backend alone | "
              "Embree's own code |")
        print("|---|---|---|---|---|")
        with tempfile.TemporaryDirectory() as out:
            for name, (scene, frame, shutter, extra) in CASES.items():
                sharp = embree_alone(scene, frame, "0", extra, out)
                blurred = embree_alone(scene, frame, shutter, extra, out)
                r = [b / a for a, b in zip(sharp, blurred)]
                print(f"| {name} | {sharp[0]:.3f} / {blurred[0]:.3f} | {r[0]:.2f} | "
                      f"{r[1]:.2f} | {r[2]:.2f} |", flush=True)
        return
    if args.instructions:
        print("callgrind, 1 thread, 4 x 4 samples per pixel, a quarter of the size\n")
        print("| scene | backend | sharp (instructions) | blurred (instructions) | ratio |")
        print("|---|---|---|---|---|")
        with tempfile.TemporaryDirectory() as out:
            for name, (scene, frame, shutter, extra) in CASES.items():
                for backend in args.backends:
                    sharp = instructions(scene, frame, "0", extra, backend, out)
                    blurred = instructions(scene, frame, shutter, extra, backend, out)
                    print(f"| {name} | {backend} | {sharp:,} | {blurred:,} | "
                          f"{blurred / sharp:.2f} |", flush=True)
        return
    print(f"{args.threads} thread(s), 4 x 4 samples per pixel, medians of {args.runs} runs\n")
    print("| scene | backend | render sharp (s) | render blurred (s) | ratio | build sharp / "
          "blurred (s) | scene(clock) sharp / blurred (s, calls) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as out:
        for name, (scene, frame, shutter, extra) in CASES.items():
            for backend in args.backends:
                # Sharp and blurred runs alternate, so that a change in the
                # machine's load falls on both.
                runs = {"0": [], shutter: []}
                for _ in range(args.runs):
                    for open_ in runs:
                        runs[open_].append(run(scene, frame, open_, extra, backend, args.threads,
                                               out))
                times = {open_: ({k: statistics.median(r[0][k] for r in rs)
                                  for k in ("render", "build", "scene")}, rs[0][1])
                         for open_, rs in runs.items()}
                sharp, blurred = times["0"][0], times[shutter][0]
                print(f"| {name} | {backend} | {sharp['render']:.3f} | {blurred['render']:.3f} | "
                      f"{blurred['render'] / sharp['render']:.2f} | {sharp['build']:.3f} / "
                      f"{blurred['build']:.3f} | {sharp['scene']:.3f} / {blurred['scene']:.3f} "
                      f"({times[shutter][1]}) |", flush=True)


if __name__ == "__main__":
    main()
