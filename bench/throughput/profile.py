#!/usr/bin/python3
"""Where a render's time goes: a perf profile of each bench scene, by kind.

For each scene of bench/time_vs_error (and, with --gallery, scenes/*.lua)
this renders one frame at a fixed setting with --stats, then again under
`perf record`, starting the sampling when the render starts (after the
script, scene and acceleration structure: their times from the first run),
and sorts the samples into kinds by the function (or library) they fell in:

    traversal     Embree's own code (libembree3), the kd-tree's traversal
    shape tests   the shapes' ray tests, triangle hits, CSG, user-geometry
                  callbacks
    shading       the integrator's shading, finishes, lobes, surfaces
    pigments      pigments and noise
    lights        light sampling and shadow rays' set-up, the area light's lanes
    sampling      the tile loop, camera rays, samplers, film
    libm          the C maths library (called from all of the above)
    other         the rest (threads, kernel, allocation, output)

It also runs build/bench_throughput on the same frame and backend: the
render timed on one thread, its rays recorded and traced again through
the backend alone ("backend alone": Embree's calls, or the kd-tree's
walks, over the render's time: issue 34's traversal share; the analytic
shapes' tests are part of it). With --every-shadow-ray a second column
replays the rays of a render without shadow skips: every shadow ray the
frame needs, those LRay settles itself (an empty shaft, a few analytic
occluders tested directly) included, against the same render time.
--noise-threshold profiles adaptive sampling instead of -s (the runs
bench/time_vs_error matches against POV-Ray's levels).
A table (markdown) goes to stdout and --out/profile.md. See README.md in
this folder, and bench/README.md for the current figures.

    bench/throughput/profile.py                     # 640x360, -s 3, 1 thread, both backends
    bench/throughput/profile.py -w 320 -H 180 --backends embree --gallery
    bench/throughput/profile.py --scenes ring,pigments --noise-threshold 0.15 --min-samples 1
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
BENCH_SCENES = os.path.join(ROOT, "bench", "time_vs_error", "scenes")
# name -> extra lray options (bench/time_vs_error/run.py renders the same frames)
SCENES = {"arealight": [], "glass": [], "spheres16k": [], "mesh200k": [], "pigments": [],
          "ring": ["--frames", "10"]}

KINDS = ["traversal", "shape tests", "shading", "pigments", "lights", "sampling", "libm", "other"]
# First match wins; matched against "dso symbol".
RULES = [
    ("traversal", r"libembree3|KdTree|kdtree|Kd[A-Z]\w*::|traverse|Accelerator::intersect"),
    ("shape tests", r"::intersect\b|::occluded\b|intersectShape|occludedShape|TriangleHit|"
                    r"triangle|Triangle|Csg|csg|EmbreeCallbacks|solveQuartic|quartic|"
                    r"Sphere::|Cube::|Cylinder::|Cone::|Torus::|Plane::|Mesh::|"
                    r"float_frame|FloatFrame|fillLanes|fillAnalytic|wideObjectSpace|prefilter|"
                    r"Transform::apply"),
    ("pigments", r"Pigment|pigment|noise|Noise|perlin|Perlin|Marble|Wood|Checker|turbulence|"
                 r"TextureImage|Image(Cache|Map)"),
    ("lights", r"Light|light|shadow|Shadow|Emitter|emitter|"
               r"roundAvx2|roundScalar|placeAvx2|placeScalar|boundAxis|boundLanes|addLit"),
    ("shading", r"Integrator|shade|Shade|Finish|finish|Lobe|lobe|surface|Surface|fresnel|"
                r"Fresnel|refract|reflect|Ggx|ggx|Path|offsetRayOrigin"),
    ("sampling", r"sampleTile|renderTiles|Sampler|sampler|owenSobol|Sobol|sobol|mix64|Film|"
                 r"CameraRays|camera|pixelError|SampleBuffer|forEachTile|tbb"),
    ("libm", r"libm\.so|libm-"),
]


def lray_run(lray, scene, out, args, extra, stats, perf=None, delay_ms=0, frequency=2999):
    cmd = [lray, scene, out, "-q", "--stats", stats] + extra + args
    if perf:
        cmd = ["perf", "record", "-q", "-F", str(frequency), "-o", perf, "-D", str(delay_ms),
               "--"] + cmd
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(stats) as f:
        return json.load(f)


def bare(symbol):
    """The symbol without template arguments and parameter lists, so that
    Integrator<KdTreeAccelerator>::shade(Hit const*, ...) reads
    Integrator::shade: a function is sorted by its own name."""
    out, depth = [], 0
    for ch in symbol:
        if ch in "<(":
            depth += 1
        elif ch in ">)" and depth:
            depth -= 1
        elif not depth:
            out.append(ch)
    return "".join(out)


def classify(perf_data):
    text = subprocess.run(["perf", "report", "-i", perf_data, "--sort", "dso,symbol", "--stdio",
                           "--percent-limit", "0", "-t", "\t"],
                          check=True, capture_output=True, text=True).stdout
    shares = {k: 0.0 for k in KINDS}
    for line in text.splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        parts = [p.strip() for p in line.split("\t")]
        if len(parts) < 3 or not parts[0].endswith("%"):
            continue
        share = float(parts[0].rstrip("%"))
        name = parts[1] + " " + bare(parts[2])
        kind = next((k for k, pattern in RULES if re.search(pattern, name)), "other")
        shares[kind] += share
    total = sum(shares.values()) or 1
    return {k: 100 * v / total for k, v in shares.items()}


def replay_share(bench, path, args, frame, backend, flags):
    """bench_throughput's traversal share, "share (backend s / render s)"."""
    if not os.path.exists(bench):
        return "-"
    out_json = subprocess.run([bench, path] + args + ["--frame", frame, "--repeats", "3",
                                                     "--backend", backend] + flags,
                              check=True, capture_output=True, text=True).stdout
    replay = json.loads(out_json)
    return (f"{replay['traversal_share']:.2f} "
            f"({replay['raw_s']['total']:.3f} / {replay['render_s']:.3f} s)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lray", default=os.path.join(ROOT, "build", "lray"))
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "bench_throughput"))
    ap.add_argument("-w", "--width", type=int, default=640)
    ap.add_argument("-H", "--height", type=int, default=360)
    ap.add_argument("-s", "--samples", type=int, default=3)
    ap.add_argument("-t", "--threads", type=int, default=1)
    ap.add_argument("--noise-threshold", type=float, default=0,
                    help="adaptive sampling at this threshold instead of -s")
    ap.add_argument("--min-samples", type=int, default=16, help="with --noise-threshold")
    ap.add_argument("--max-samples", type=int, default=256, help="with --noise-threshold")
    ap.add_argument("--scenes", default=",".join(SCENES),
                    help="comma-separated subset of " + ",".join(SCENES))
    ap.add_argument("--every-shadow-ray", action="store_true",
                    help="also replay every shadow ray of the frame (memory: 72 bytes a ray; "
                         "arealight at the defaults records 124 M rays, 9 GB)")
    ap.add_argument("--frequency", type=int, default=2999, help="perf's samples per second")
    ap.add_argument("--backends", nargs="+", default=["embree", "kdtree"])
    ap.add_argument("--gallery", action="store_true", help="also scenes/*.lua, frame 0")
    ap.add_argument("--out", default=None, help="folder for profile.md (default: a temp folder)")
    a = ap.parse_args()
    out = a.out or tempfile.mkdtemp(prefix="lray_profile_")
    os.makedirs(out, exist_ok=True)
    chosen = a.scenes.split(",")
    unknown = [n for n in chosen if n not in SCENES]
    if unknown:
        ap.error("unknown scene(s) %s (known: %s)" % (",".join(unknown), ",".join(SCENES)))
    scenes = [(name, os.path.join(BENCH_SCENES, name + ".lua"), SCENES[name]) for name in chosen]
    if a.gallery:
        for f in sorted(os.listdir(os.path.join(ROOT, "scenes"))):
            if f.endswith(".lua") and f != "twins.lua":
                scenes.append((f[:-4], os.path.join(ROOT, "scenes", f), ["--frames", "0"]))
    sampling = ["-s", str(a.samples)]
    if a.noise_threshold > 0:
        sampling = ["--noise-threshold", str(a.noise_threshold), "--min-samples",
                    str(a.min_samples), "--max-samples", str(a.max_samples)]
    size = ["-w", str(a.width), "-H", str(a.height)]
    args = size + sampling + ["-t", str(a.threads)]
    every = ["every shadow ray alone"] if a.every_shadow_ray else []
    head = ("| scene | backend | render s | backend alone | " + " | ".join(every + KINDS) +
            " |")
    rows = [head, "|" + "---|" * (len(every + KINDS) + 4)]
    print(head, flush=True)
    for name, path, extra in scenes:
        for backend in a.backends:
            opts = args + ["--backend", backend]
            stats = os.path.join(out, f"{name}.{backend}.json")
            s = lray_run(a.lray, path, os.path.join(out, "img"), opts, extra, stats)
            t = s["times"]
            before = t["load_script"] + t["scene"] + t["images"] + t["build"]
            perf = os.path.join(out, f"{name}.{backend}.perf")
            lray_run(a.lray, path, os.path.join(out, "img"), opts, extra, stats, perf,
                     int(before * 1000) + 5, a.frequency)
            shares = classify(perf)
            frame = extra[1] if extra[:1] == ["--frames"] else "0"
            replays = [replay_share(a.bench, path, size + sampling, frame, backend, flags)
                       for flags in ([[]] + ([["--every-shadow-ray"]] if every else []))]
            row = (f"| {name} | {backend} | {t['render']:.3f} | " + " | ".join(replays) + " | " +
                   " | ".join(f"{shares[k]:.0f} %" for k in KINDS) + " |")
            rows.append(row)
            print(row, flush=True)
    with open(os.path.join(out, "profile.md"), "w") as f:
        f.write(f"{a.width}x{a.height}, {' '.join(sampling)}, {a.threads} thread(s)\n\n")
        f.write("\n".join(rows) + "\n")
    print(f"profile: {out}/profile.md", file=sys.stderr)


if __name__ == "__main__":
    main()
