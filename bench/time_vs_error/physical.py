"""Run time against image error on bench/physical's scenes: LRay's path
tracer (fixed and adaptive sampling, both backends) beside Mitsuba 3 and
Blender Cycles, each against its own converged reference (rendered with
another seed: it shares no samples with the renders it judges), same
size, same threads, in one run.

For every rung of a peer's ladder, the LRay render time that reaches the
same RMSE (interpolated in log-log along LRay's fixed ladder on Embree) is
divided by the peer's render time: the "time ratio" (targets: at most 1/3
against Mitsuba, at most 1 against Cycles). Wall times (the whole process)
are recorded too.

  build/peers/bin/python bench/time_vs_error/physical.py [--out build/tve-physical]
      [--scenes cornell,...] [--ref-spp 4096] [--quick]

Needs `scripts/setup --bench`. Writes results.csv, results.md and
time_vs_error_physical.png to --out.
"""

import argparse
import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "bench", "physical"))
import agree  # noqa: E402  (the renderers' runners and the scenes' sizes)

REF_SEED = 99
LADDER = {
    "lray": [1, 4, 16, 64, 256],  # squares: LRay takes n x n samples
    "mitsuba": [1, 4, 16, 64, 256],
    "cycles": [1, 4, 16, 64, 256],
}
LRAY_THRESHOLDS = ["0.2", "0.1", "0.05", "0.025"]
CYCLES_ADAPTIVE = [(1024, "0.1"), (1024, "0.05"), (1024, "0.02"), (1024, "0.01")]


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def interpolate_time(ladder, target):
    """The time at which the (time, error) ladder reaches error `target`,
    log-log between its rungs; None outside it."""
    pts = sorted(ladder, key=lambda p: p[0])
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if (e0 - target) * (e1 - target) <= 0 and e0 != e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "tve-physical"))
    ap.add_argument("--scenes", default=",".join(agree.SCENES))
    ap.add_argument("--peers", default="mitsuba,cycles")
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="short ladders, 256-sample references")
    a = ap.parse_args()
    if a.quick:
        a.ref_spp = 256
        for k in LADDER:
            LADDER[k] = LADDER[k][:3]
        del LRAY_THRESHOLDS[2:]
        del CYCLES_ADAPTIVE[1:]
    os.makedirs(a.out, exist_ok=True)
    peers = [p for p in a.peers.split(",") if p]
    rows = []

    def add(scene, renderer, variant, setting, path, times, reference):
        rows.append({"scene": scene, "renderer": renderer, "variant": variant,
                     "setting": setting, "render_s": times["render_s"], "wall_s": times["wall_s"],
                     "rmse": rmse(agree.read_exr(path), reference)})
        r = rows[-1]
        print(f"{scene} {renderer} {variant} {setting}: {r['render_s']:.2f} s, "
              f"RMSE {r['rmse']:.4f}", file=sys.stderr, flush=True)

    for scene in a.scenes.split(","):
        refs = {}
        for renderer in ["lray", *peers]:
            path = os.path.join(a.out, f"{scene}.{renderer}.ref.exr")
            if not os.path.exists(path):
                agree.render(renderer, scene, path, a.ref_spp, REF_SEED, a.threads)
            refs[renderer] = agree.read_exr(path)
        for backend in ("embree", "kdtree"):
            for spp in LADDER["lray"]:
                path = os.path.join(a.out, f"{scene}.lray.{backend}.{spp}.exr")
                t = agree.render_lray(scene, path, spp, 1, a.threads, backend)
                add(scene, "lray", f"fixed {backend}", spp, path, t, refs["lray"])
        for threshold in LRAY_THRESHOLDS:
            path = os.path.join(a.out, f"{scene}.lray.adaptive.{threshold}.exr")
            t = agree.render_lray(scene, path, None, 1, a.threads, "embree",
                                  ["--noise-threshold", threshold])
            add(scene, "lray", "adaptive embree", threshold, path, t, refs["lray"])
        for peer in peers:
            for spp in LADDER[peer]:
                path = os.path.join(a.out, f"{scene}.{peer}.{spp}.exr")
                t = agree.render_peer(peer, scene, path, spp, 1, a.threads)
                add(scene, peer, "fixed", spp, path, t, refs[peer])
            if peer == "cycles":
                for spp, threshold in CYCLES_ADAPTIVE:
                    path = os.path.join(a.out, f"{scene}.cycles.adaptive.{threshold}.exr")
                    t = agree.render_peer(peer, scene, path, spp, 1, a.threads,
                                          ["--adaptive", threshold])
                    add(scene, peer, "adaptive", threshold, path, t, refs[peer])

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    write_tables(rows, peers, a)
    plot(rows, a.out)


def write_tables(rows, peers, a):
    lines = [f"Reference {a.ref_spp} spp (seed {REF_SEED}), {a.threads} threads. For each "
             "peer rung: the LRay time (fixed, Embree; and the best of fixed and adaptive) "
             "reaching the same RMSE over the peer's render time.", "",
             "| scene | peer | rung | peer RMSE | peer render s | LRay fixed s | ratio fixed |"
             " LRay best s | ratio best | peer wall s | LRay wall s (fixed) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    worst = {}
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene and r["renderer"] == "lray"]
        fixed = [(r["render_s"], r["rmse"]) for r in mine if r["variant"] == "fixed embree"]
        fixed_wall = [(r["wall_s"], r["rmse"]) for r in mine if r["variant"] == "fixed embree"]
        adaptive = [(r["render_s"], r["rmse"]) for r in mine if r["variant"] == "adaptive embree"]
        for r in rows:
            if r["scene"] != scene or r["renderer"] not in peers:
                continue
            tf = interpolate_time(fixed, r["rmse"])
            ta = interpolate_time(adaptive, r["rmse"]) if adaptive else None
            tw = interpolate_time(fixed_wall, r["rmse"])
            best = min(t for t in (tf, ta) if t) if (tf or ta) else None
            ratio = best / r["render_s"] if best else None
            if ratio:
                key = r["renderer"]
                worst[key] = max(worst.get(key, 0), ratio)
            lines.append(
                f"| {scene} | {r['renderer']} {r['variant']} | {r['setting']} | {r['rmse']:.4f} | "
                f"{r['render_s']:.2f} | {fmt(tf)} | {fmt(tf and tf / r['render_s'])} | "
                f"{fmt(best)} | "
                f"{fmt(ratio)} | {r['wall_s']:.2f} | {fmt(tw)} |")
    lines += ["", "Worst ratio (best LRay mode): " +
              ", ".join(f"{k} {v:.2f}" for k, v in worst.items())]
    if "mitsuba" in peers and "cycles" in peers:
        lines += ["", *peer_against_peer(rows)]
    with open(os.path.join(a.out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def peer_against_peer(rows):
    """Cycles' render time (the best of its fixed and adaptive ladders) to
    each Mitsuba rung's RMSE over Mitsuba's: what a peer does against the
    1/3-of-Mitsuba target, so that a miss that is the target's can be told
    from one that is LRay's."""
    lines = ["Cycles against Mitsuba (a peer against the same target): Cycles' best render "
             "time to each Mitsuba rung's RMSE over Mitsuba's render time.", "",
             "| scene | Mitsuba spp | Mitsuba RMSE | Mitsuba s | Cycles s | Cycles / Mitsuba |",
             "|---|---|---|---|---|---|"]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        cycles = [r for r in rows if r["scene"] == scene and r["renderer"] == "cycles"]
        ladders = [[(r["render_s"], r["rmse"]) for r in cycles if r["variant"] == variant]
                   for variant in ("fixed", "adaptive")]
        for r in rows:
            if r["scene"] != scene or r["renderer"] != "mitsuba":
                continue
            times = [t for t in (interpolate_time(ladder, r["rmse"]) for ladder in ladders) if t]
            best = min(times) if times else None
            lines.append(f"| {scene} | {r['setting']} | {r['rmse']:.4f} | {r['render_s']:.2f} | "
                         f"{fmt(best)} | {fmt(best and best / r['render_s'])} |")
    return lines


def fmt(x):
    return "-" if x is None else f"{x:.2f}"


def plot(rows, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(1, len(scenes), figsize=(4 * len(scenes), 3.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        series = {}
        for r in rows:
            if r["scene"] == scene:
                series.setdefault(f"{r['renderer']} {r['variant']}", []).append(
                    (r["render_s"], r["rmse"]))
        for label, pts in series.items():
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=label)
        ax.set_title(scene)
        ax.set_xlabel("render time (s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("RMSE against own reference")
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time_vs_error_physical.png"), dpi=110)


if __name__ == "__main__":
    main()
