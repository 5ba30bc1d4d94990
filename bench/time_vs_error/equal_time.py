#!/usr/bin/python3
"""The README's equal-time picture: the bench's area-light scene rendered
with fixed 2 x 2 sampling (every light cell) beside adaptive sampling at
--noise-threshold 0.1 (spread light sampling, its default), which take
about the same time on this machine, each shown by its penumbrae (a crop,
pixels enlarged) and titled with its render time
(lray's --stats, median of --runs) and its RMSE against the converged
reference (-s 16, every cell, another --seed), as run.py measures them.

    bench/time_vs_error/equal_time.py [--out fixed_vs_adaptive.png] [--runs 3]

Needs numpy and matplotlib (scripts/setup --bench).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run as bench  # noqa: E402  (read_rgb, rmse: the same error as the time-to-error runs)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "scenes", "arealight.lua")
SIZE = ["-w", "320", "-H", "180", "-t", "2"]
CROP = (slice(40, 170), slice(40, 280))  # rows, columns: the shadows
MODES = [("fixed 2 x 2, every cell", ["-s", "2", "--light-sampling", "all"]),
         ("adaptive 0.1, spread", ["--noise-threshold", "0.1"])]


def render(lray, out, name, extra):
    """The image's path and lray's render time."""
    folder = os.path.join(out, name)
    stats = os.path.join(out, name + ".json")
    subprocess.run([lray, SCENE, folder, "-q", "--stats", stats] + SIZE + extra, check=True)
    with open(stats) as f:
        seconds = json.load(f)["times"]["render"]
    return os.path.join(folder, "arealight.png"), seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lray", default=os.path.join(ROOT, "build", "lray"))
    ap.add_argument("--out", default=os.path.join(HERE, "fixed_vs_adaptive.png"))
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        ref, _ = render(args.lray, tmp, "reference",
                        ["-s", "16", "--light-sampling", "all", "--seed", "1"])
        reference = bench.read_rgb(ref)
        fig, axes = plt.subplots(1, len(MODES), figsize=(8, 2.4), dpi=100)
        for ax, (title, extra) in zip(axes, MODES):
            times = []
            for _ in range(args.runs):
                path, seconds = render(args.lray, tmp, "mode", extra)
                times.append(seconds)
            image = bench.read_rgb(path)
            error = bench.rmse(image, reference)
            label = f"{title}: {statistics.median(times):.2f} s, RMSE {error:.4f}"
            print(label)
            ax.imshow(image[CROP], interpolation="nearest")
            ax.set_title(label, fontsize=9)
            ax.axis("off")
        fig.tight_layout()
        fig.savefig(args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
