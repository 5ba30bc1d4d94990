#!/usr/bin/env python3
"""Rays per pixel that LRay's centre-first ladder needs to reach each of POV-Ray's error levels.

A deterministic measure of the adaptive sampler, for comparing two
builds without timing noise: the ray counts of a render (`--stats`, every
kind) do not change from run to run, and the time of a frame follows them
on a given scene. For each scene this renders the centre-first ladder
(`--noise-threshold T --min-samples 1`, Embree, 2 threads) at the size of
an earlier `run.py` output, measures each image against that run's LRay
reference (the same RMSE as run.py: 8-bit sRGB values), and interpolates
the rays per pixel at the RMSE of each POV-Ray run of it (log-log between
neighbouring thresholds).

    bench/time_vs_error/run.py --out /tmp/tve                # once, for the references
    bench/time_vs_error/rays_to_error.py --tve /tmp/tve --lray build/lray
    bench/time_vs_error/rays_to_error.py --tve /tmp/tve --lray /tmp/other/lray --scenes ring
    bench/time_vs_error/rays_to_error.py --tve /tmp/tve --flags "--edge-lattice 5 --sparse-centres"

Needs numpy and PIL (scripts/setup --bench: build/peers/bin/python).
"""

import argparse
import csv
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = os.path.join(HERE, "scenes")
LADDER = [0.5, 0.4, 0.3, 0.25, 0.2, 0.17, 0.15, 0.13, 0.12, 0.11, 0.1, 0.085, 0.07, 0.06, 0.05,
          0.04, 0.03, 0.025, 0.02, 0.015, 0.01]


def rgb(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255


def interpolate(points, target):
    """The rays per pixel at RMSE `target` on the ladder's (rmse, rays) points, or None."""
    for (e0, r0), (e1, r1) in zip(points, points[1:]):
        if e0 >= target >= e1:
            if e0 == e1:
                return r1
            a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(r0) + a * (math.log(r1) - math.log(r0)))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tve", required=True, help="an earlier run.py --out folder (its references)")
    ap.add_argument("--lray", default=os.path.join(ROOT, "build", "lray"))
    ap.add_argument("--scenes", default="", help="comma-separated (default: the run's)")
    ap.add_argument("--ladder", default=",".join(str(t) for t in LADDER))
    ap.add_argument("--flags", default="",
                    help="more lray options for every render, e.g. '--edge-lattice 5 --sparse-centres'")
    args = ap.parse_args()
    rows = list(csv.DictReader(open(os.path.join(args.tve, "results.csv"))))
    scenes = args.scenes.split(",") if args.scenes else sorted({r["scene"] for r in rows
                                                                  if r["renderer"] == "lray"})
    ladder = [float(t) for t in args.ladder.split(",")]
    levels = {}
    for r in rows:
        if r["renderer"] == "povray" and r["mode"] != "reference":
            levels.setdefault(r["scene"], []).append((r["setting"], float(r["rmse"])))
    out = tempfile.mkdtemp(prefix="rays_to_error.")
    print("| scene | " + " | ".join(s for s, _ in levels[scenes[0]]) + " |")
    print("|---" * (1 + len(levels[scenes[0]])) + "|")
    for scene in scenes:
        ref_row = next(r for r in rows if r["scene"] == scene and r["renderer"] == "lray"
                       and r["mode"] == "reference")
        ref = rgb(os.path.join(args.tve, ref_row["image"]))
        height, width = ref.shape[:2]
        points = []
        for t in ladder:
            stats = os.path.join(out, "stats.json")
            cmd = [args.lray, os.path.join(SCENES, scene + ".lua"), out, "--backend", "embree",
                   "-t", "2", "-w", str(width), "-H", str(height), "--linear", "-q", "--stats",
                   stats, "--noise-threshold", str(t), "--min-samples", "1", "--max-samples",
                   "256"] + shlex.split(args.flags)
            if scene == "ring":
                cmd += ["--frames", "10"]  # as run.py renders it
            subprocess.run(cmd, check=True)
            with open(stats) as f:
                s = json.load(f)
            image = rgb(s["frames"][0]["file"])
            rmse = math.sqrt(np.mean((image - ref) ** 2))
            points.append((rmse, s["rays"]["total"] / (width * height)))
        cells = []
        for _, target in levels[scene]:
            r = interpolate(points, target)
            cells.append("%.3f" % r if r is not None else "out of range")
        print("| %s | %s |" % (scene, " | ".join(cells)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
