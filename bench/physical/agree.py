"""bench/physical: converged LRay (path) against converged Mitsuba 3 and
Cycles renders of the same scenes. Each renderer renders each scene twice
with different seeds; the pair's difference gives its own noise. Reported
per scene and peer: every channel's mean (LRay over the peer, - 1), and
the RMSE between the two renderers' two-render means beside the RMSE their
noise alone would give (sqrt(MSE(A1, A2) / 4 + MSE(B1, B2) / 4)); a ratio
near 1 is agreement down to the noise.

  build/peers/bin/python bench/physical/agree.py [--out build/physical]
      [--spp 1024] [--scenes cornell,glossy,...] [--peers mitsuba,cycles]

Needs `scripts/setup --bench` (the peers in build/peers). Writes
agreement.csv, agreement.md and NAME.png (LRay | Mitsuba | Cycles, sRGB)
to --out.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = {"cornell": (128, 128), "glossy": (160, 120), "glass": (160, 120), "mesh": (160, 120),
          "mixed": (160, 120)}
# Scenes of the gallery (scenes/) with a twin here, rendered on request.
GALLERY = {"cornell_gi": (256, 256)}


def lua_path(name):
    if name in GALLERY:
        return os.path.join(ROOT, "scenes", name + ".lua")
    return os.path.join(HERE, "scenes", name + ".lua")


def size(name):
    return GALLERY.get(name) or SCENES[name]


def read_exr(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path), dtype=np.float64)[:, :, :3]


def render_lray(name, out, spp, seed, threads, backend="embree", extra=()):
    """spp must be a square (LRay takes n x n samples per pixel), or None
    for the sampling `extra` asks for (adaptive)."""
    w, h = size(name)
    samples = ["-s", str(int(round(math.sqrt(spp))))] if spp else []
    folder = out + ".d"
    os.makedirs(folder, exist_ok=True)
    stats = os.path.join(folder, "stats.json")
    start = time.perf_counter()
    subprocess.run([os.path.join(ROOT, "build", "lray"), lua_path(name),
                    folder, "-q", "-f", "exr", *samples, "--seed", str(seed), "-w", str(w),
                    "-H", str(h), "-t", str(threads), "--backend", backend, "--stats", stats,
                    *extra], check=True)
    wall = time.perf_counter() - start
    os.replace(os.path.join(folder, name + ".exr"), out)
    with open(stats) as f:
        render = json.load(f)["times"]["render"]
    return {"render_s": render, "wall_s": wall}


def render_peer(peer, name, out, spp, seed, threads, extra=()):
    w, h = size(name)
    start = time.perf_counter()
    p = subprocess.run([sys.executable, os.path.join(HERE, peer + "_twin.py"), name, out,
                        "--width", str(w), "--height", str(h), "--spp", str(spp),
                        "--seed", str(seed), "--threads", str(threads), *extra],
                       check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    line = [l for l in p.stdout.splitlines() if l.startswith("{")][-1]
    return {"render_s": json.loads(line)["render_s"], "wall_s": wall}


def render(renderer, name, out, spp, seed, threads):
    if renderer == "lray":
        return render_lray(name, out, spp, seed, threads)
    return render_peer(renderer, name, out, spp, seed, threads)


def mse(a, b):
    return float(np.mean((a - b) ** 2))


def srgb(x):
    x = np.clip(x, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def write_png(path, image):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    data = np.ascontiguousarray((srgb(image) * 255 + 0.5).astype(np.uint8))
    mi.Bitmap(data, mi.Bitmap.PixelFormat.RGB).write(path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "physical"))
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--peers", default="mitsuba,cycles")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    peers = [p for p in a.peers.split(",") if p]
    rows = []
    for name in a.scenes.split(","):
        images, noise, times = {}, {}, {}
        for renderer in ["lray", *peers]:
            pair = []
            for seed in (1, 2):
                path = os.path.join(a.out, f"{name}.{renderer}.{seed}.exr")
                times[(renderer, seed)] = render(renderer, name, path, a.spp, seed, a.threads)
                pair.append(read_exr(path))
            images[renderer] = (pair[0] + pair[1]) / 2
            noise[renderer] = mse(pair[0], pair[1]) / 4  # the variance of the pair's mean
            print(f"{name} {renderer}: {times[(renderer, 1)]['render_s']:.1f} s render",
                  file=sys.stderr, flush=True)
        strip = [images["lray"]] + [images[p] for p in peers]
        write_png(os.path.join(a.out, name + ".png"), np.concatenate(strip, axis=1))
        lray = images["lray"]
        for p in peers:
            means_l, means_p = lray.mean(axis=(0, 1)), images[p].mean(axis=(0, 1))
            rel = means_l / means_p - 1
            rmse = math.sqrt(mse(lray, images[p]))
            expected = math.sqrt(noise["lray"] + noise[p])
            rows.append({"scene": name, "peer": p, "spp": a.spp,
                         "lray_mean": " ".join(f"{x:.5f}" for x in means_l),
                         "peer_mean": " ".join(f"{x:.5f}" for x in means_p),
                         "mean_diff_r": rel[0], "mean_diff_g": rel[1], "mean_diff_b": rel[2],
                         "rmse": rmse, "rmse_noise": expected, "rmse_ratio": rmse / expected,
                         "lray_render_s": times[("lray", 1)]["render_s"],
                         "peer_render_s": times[(p, 1)]["render_s"]})
    with open(os.path.join(a.out, "agreement.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = ["| scene | peer | mean R, G, B: LRay / peer - 1 | RMSE | RMSE from noise | ratio |"
             " render s (LRay, peer) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['peer']} | {100 * r['mean_diff_r']:+.2f} %, "
                     f"{100 * r['mean_diff_g']:+.2f} %, {100 * r['mean_diff_b']:+.2f} % | "
                     f"{r['rmse']:.4f} | {r['rmse_noise']:.4f} | {r['rmse_ratio']:.2f} | "
                     f"{r['lray_render_s']:.1f}, {r['peer_render_s']:.1f} |")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "agreement.md"), "w") as f:
        f.write(f"{a.spp} samples per pixel, {a.threads} threads, two seeds each\n\n" + table)
    print(table)


if __name__ == "__main__":
    main()
