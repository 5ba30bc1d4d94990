#!/usr/bin/python3
"""Run time against image error: LRay's sampling modes and POV-Ray 3.7.

For each bench scene (scenes/*.lua with a POV-Ray twin scenes/*.pov) this
renders LRay's converged reference once (embree, -s 16, every light cell),
then on each backend the ladders of fixed samples (--light-sampling all and
spread), adaptive sampling (--noise-threshold) and time limits
(--time-limit), and, when povray is on PATH, POV-Ray's reference and its
anti-aliasing ladder. Every image's RMSE and PSNR against its own
renderer's reference goes to results.csv, results.md and time_vs_error.png
in --out. See README.md in this folder.

    bench/time_vs_error/run.py --out /tmp/tve            # the whole ladder, 320x180
    bench/time_vs_error/run.py --quick -w 96 -H 54       # a short test run
"""

import argparse
import csv
import glob
import json
import math
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import time

# numpy and matplotlib come from Debian (python3-numpy, python3-matplotlib):
# a python3 found first on PATH (pyenv, a venv) may lack them, so fall back
# to the system interpreter once.
try:
    import numpy as np
    import matplotlib
except ImportError:
    if __name__ != "__main__":
        raise  # imported for its functions: no run in another interpreter
    if os.path.exists("/usr/bin/python3") and not os.environ.get("TVE_SYSTEM_PYTHON"):
        os.environ["TVE_SYSTEM_PYTHON"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3", os.path.abspath(__file__)] + sys.argv[1:])
    sys.exit("time_vs_error: needs numpy and matplotlib (apt-get install python3-numpy python3-matplotlib)")

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker as ticker  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE_DIR = os.path.join(HERE, "scenes")
ROOT = os.path.dirname(os.path.dirname(HERE))

# name -> what the runner needs to know beyond scenes/<name>.lua and .pov.
#   frame/frames: render one frame of an animation (LRay --frames, POV's
#   clock = frame / (frames - 1)); mesh: write mesh200k_mesh.inc first.
RING_FRAME, RING_FRAMES = 10, 20
SCENES = {
    "arealight": {},
    "glass": {},
    "spheres16k": {},
    "mesh200k": {"mesh": True},
    "pigments": {"note": "marble and wood use different noise in POV-Ray"},
    "ring": {"frame": RING_FRAME, "frames": RING_FRAMES},
}
POV_SUPPORT = ["lray.inc", "texture.png"]

REF_SAMPLES = 16
LADDER = {
    "samples": [1, 2, 3, 4, 6, 8],
    "thresholds": ["1", "0.7", "0.5", "0.3", "0.25", "0.2", "0.15", "0.12", "0.1", "0.085", "0.07",
                   "0.06", "0.05", "0.04", "0.03", "0.025", "0.02", "0.01", "0.005"],
    # --edge-lattice 5: the thresholds (its cells' contrast times their
    # area: lower than the Sobol passes' for the same error)
    "lattice_thresholds": ["1", "0.8", "0.6", "0.45", "0.3", "0.22", "0.15", "0.1", "0.07", "0.05",
                           "0.035", "0.025", "0.017", "0.012", "0.008", "0.005", "0.0035", "0.0025",
                           "0.0017"],
    # time limits as fractions of the LRay reference's render time
    "time_fractions": [1 / 32, 1 / 16, 1 / 8, 1 / 4],
    "pov": [("noaa", "-A", ["-A"]),
            ("adaptive", "+A0.3 +AM2 +R3", ["+A0.3", "+AM2", "+R3"]),
            ("adaptive", "+A0.1 +AM2 +R3", ["+A0.1", "+AM2", "+R3"]),
            ("adaptive", "+A0.03 +AM2 +R4", ["+A0.03", "+AM2", "+R4"]),
            ("forced", "+R2", ["+A0.0", "+AM1", "+R2"]),
            ("forced", "+R3", ["+A0.0", "+AM1", "+R3"]),
            ("forced", "+R4", ["+A0.0", "+AM1", "+R4"])],
}
# The sampler comparison of results.md: each renderer's adaptive modes
# against its own 16-rays-per-pixel fixed sampling (LRay -s 4 with every
# light cell; POV-Ray +AM1 +R4, 4 x 4 rays and the centre ray).
ADAPTIVE_BASE = {"lray": ("fixed-all", "4"), "povray": ("forced", "+R4")}
ADAPTIVE_MODES = {"lray": ("adaptive", "adaptive-min1", "lattice", "sparse"),
                  "povray": ("adaptive",)}
QUICK_LADDER = {
    "samples": [1, 2],
    "thresholds": ["0.05", "0.01"],
    "lattice_thresholds": ["0.01"],
    "time_fractions": [1 / 16, 1 / 4],
    "pov": LADDER["pov"][:3],
}
# POV-Ray's reference: one ray through each pixel of a -A render at 16 x the
# size, 16 x 16 rays a pixel averaged (pov_reference says why not +AM1).
POV_REF_SCALE = 16

# mesh200k's torus: the same formula as scenes/mesh200k.lua.
TORUS_NU, TORUS_NV = 500, 200
TORUS_MAJOR, TORUS_MINOR = 1.3, 0.45

CSV_FIELDS = ["scene", "renderer", "backend", "mode", "setting", "seconds", "rmse", "psnr",
              "render_seconds", "image", "command"]


class BenchError(Exception):
    pass


# --------------------------------------------------------------------------
# mesh200k: the POV-Ray mesh2, from the Lua scene's formula


def torus_vertex(i, j):
    """Vertex (i, j) of mesh200k.lua's torus, in double as Lua computes it."""
    u, v = 2 * math.pi * i / TORUS_NU, 2 * math.pi * j / TORUS_NV
    r = TORUS_MINOR * (1 + 0.12 * math.sin(9 * u) * math.cos(4 * v))
    w = TORUS_MAJOR + r * math.cos(v)
    return (w * math.cos(u), r * math.sin(v), w * math.sin(u))


def write_torus_mesh2(path):
    """Writes `#declare Torus = mesh2 {...}`: LRay's float positions, its
    area-weighted vertex normals (src/scene/mesh_builder.cpp) and faces."""
    nu, nv = TORUS_NU, TORUS_NV
    pos = np.array([torus_vertex(i, j) for i in range(nu) for j in range(nv)],
                   dtype=np.float32)  # LRay stores mesh vertices in single precision
    faces = []
    for i in range(nu):
        i1 = (i + 1) % nu
        for j in range(nv):
            j1 = (j + 1) % nv
            a, b, c, d = i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1
            faces.append((a, d, c))
            faces.append((a, c, b))
    faces = np.array(faces, dtype=np.int64)
    p = pos.astype(np.float64)
    n = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    sums = np.zeros_like(p)
    for k in range(3):
        np.add.at(sums, faces[:, k], n)
    normals = (sums / np.linalg.norm(sums, axis=1)[:, None]).astype(np.float32)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("// Written by bench/time_vs_error/run.py from mesh200k.lua's formula.\n")
        f.write("#declare Torus = mesh2 {\n  vertex_vectors { %d,\n" % len(pos))
        f.write(",\n".join("<%.9g,%.9g,%.9g>" % tuple(v) for v in pos.tolist()))
        f.write("\n  }\n  normal_vectors { %d,\n" % len(normals))
        f.write(",\n".join("<%.9g,%.9g,%.9g>" % tuple(v) for v in normals.tolist()))
        f.write("\n  }\n  face_indices { %d,\n" % len(faces))
        f.write(",\n".join("<%d,%d,%d>" % tuple(t) for t in faces.tolist()))
        f.write("\n  }\n}\n")
    os.replace(tmp, path)
    return len(faces)


# --------------------------------------------------------------------------
# images and errors


def read_rgb(path):
    """An 8-bit (or 16-bit) PNG as float RGB in [0, 1]: the sRGB-encoded
    values both renderers write, not linear light."""
    img = mpimg.imread(path)
    if img.dtype == np.uint8:
        img = img.astype(np.float64) / 255
    img = np.asarray(img, dtype=np.float64)
    if img.ndim == 2:
        img = np.stack([img] * 3, axis=-1)
    return img[..., :3]


def read_ppm16(path):
    """A binary PPM (P6) as float RGB in [0, 1] (POV-Ray's +FP16 output)."""
    with open(path, "rb") as f:
        data = f.read()
    fields, i = [], 0
    while len(fields) < 4:
        if data[i:i + 1] == b"#":
            i = data.index(b"\n", i) + 1
        elif data[i:i + 1].isspace():
            i += 1
        else:
            j = i
            while not data[j:j + 1].isspace():
                j += 1
            fields.append(data[i:j])
            i = j
    if fields[0] != b"P6":
        raise BenchError("%s: not a binary PPM" % path)
    w, h, maxval = (int(x) for x in fields[1:])
    dtype = ">u2" if maxval > 255 else "u1"
    count = w * h * 3
    pixels = np.frombuffer(data, dtype=dtype, count=count, offset=i + 1)
    return pixels.reshape(h, w, 3).astype(np.float64) / maxval


def srgb_to_linear(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v):
    return np.where(v <= 0.0031308, v * 12.92, 1.055 * np.maximum(v, 0) ** (1 / 2.4) - 0.055)


def box_downsample_srgb(img, scale):
    """Each scale x scale block of sRGB-encoded `img` averaged in linear light
    and encoded back, as POV-Ray averages its anti-aliasing rays, rounded to
    the 8-bit values its PNG output holds (the same rounding as its +FP16
    output's top bits)."""
    h, w = img.shape[0] // scale, img.shape[1] // scale
    out = np.empty((h, w, 3), dtype=np.uint8)
    for y in range(h):
        block = srgb_to_linear(img[y * scale:(y + 1) * scale])
        mean = block.reshape(scale, w, scale, 3).mean(axis=(0, 2))
        out[y] = np.clip(np.round(linear_to_srgb(mean) * 255), 0, 255)
    return out


def median_or_blank(values):
    """The median of a run's repeated render times ("" when none was read)."""
    return statistics.median(values) if values else ""


def pov_reference_setting(args):
    """How results.md names POV-Ray's reference."""
    return "-A x%d, %d x %d rays a pixel" % (args.pov_ref_scale, args.pov_ref_scale,
                                            args.pov_ref_scale)


def rmse(a, b):
    if a.shape != b.shape:
        raise BenchError("image sizes differ: %s and %s" % (a.shape, b.shape))
    return float(np.sqrt(np.mean((a - b) ** 2)))


def psnr(e):
    return math.inf if e == 0 else 20 * math.log10(1 / e)


# --------------------------------------------------------------------------
# running the renderers


def run_checked(cmd, cwd=None):
    """Runs cmd, returns (wall seconds, stdout+stderr); a non-zero exit is a
    BenchError with the command and its output."""
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, errors="replace")
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise BenchError("command failed with exit status %d (in %s):\n  %s\n%s"
                         % (proc.returncode, cwd or os.getcwd(), shlex.join(cmd), proc.stdout[-4000:]))
    return wall, proc.stdout


def lray_flags(lray):
    try:
        _, out = run_checked([lray, "--help"])
    except (OSError, BenchError) as e:
        raise BenchError("cannot run %s --help: %s" % (lray, e))
    return set(re.findall(r"(--[a-z][a-z0-9-]*)", out))


class Runner:
    def __init__(self, args):
        self.args = args
        self.out = os.path.abspath(args.out)
        self.rows = []
        # Per row timed again in the later passes: (row, timer, walls, renders).
        self.timings = []
        self.lray = os.path.abspath(args.lray)
        self.flags = lray_flags(self.lray)
        self.pov = shutil.which("povray") if not args.no_pov else None
        self.pov_dir = os.path.join(self.out, "pov")
        self.tmp_dir = os.path.join(self.out, "tmp")
        self.notes = []

    def note(self, text):
        if text not in self.notes:
            print("note: " + text, flush=True)
            self.notes.append(text)

    def has(self, *flags):
        return all(f in self.flags for f in flags)

    # ---- LRay

    def lray_render(self, scene, backend, name, extra):
        """Renders scenes/<scene>.lua with extra options into
        renders/<scene>/<name>.png; returns (wall s, render s, path, cmd, timer:
        another run's wall and render s)."""
        info = SCENES[scene]
        run_dir = os.path.join(self.tmp_dir, "lray")
        final = os.path.join(self.out, "renders", scene, name + ".png")
        stats = os.path.join(self.out, "stats", scene, name + ".json")
        os.makedirs(os.path.dirname(final), exist_ok=True)
        os.makedirs(os.path.dirname(stats), exist_ok=True)
        cmd = [self.lray, os.path.join(SCENE_DIR, scene + ".lua"), run_dir,
               "--backend", backend, "-t", str(self.args.threads),
               "-w", str(self.args.width), "-H", str(self.args.height),
               "--linear", "-q", "--stats", stats]
        if "frame" in info:
            cmd += ["--frames", str(info["frame"])]
        cmd += [str(a) for a in extra]
        def timed_run():
            """One run of cmd: (wall s, render s or None, the PNG it wrote)."""
            shutil.rmtree(run_dir, ignore_errors=True)
            wall, _ = run_checked(cmd)
            pngs = glob.glob(os.path.join(run_dir, "*.png"))
            if len(pngs) != 1:
                raise BenchError("%s wrote %d PNG files, expected 1:\n  %s"
                                 % (self.lray, len(pngs), shlex.join(cmd)))
            with open(stats) as f:
                return wall, json.load(f).get("times", {}).get("render"), pngs[0]

        wall, render_s, png = timed_run()
        shutil.move(png, final)  # the later passes only add timings (Runner.retime)
        return wall, render_s, final, cmd, lambda: timed_run()[:2]

    def lray_row(self, scene, backend, mode, setting, extra, ref):
        name = "lray-%s-%s-%s" % (backend, mode, setting)
        wall, render_s, path, cmd, timer = self.lray_render(scene, backend, name, extra)
        e = rmse(read_rgb(path), ref) if ref is not None else 0.0
        self.add_row(scene, "lray", backend, mode, setting, wall, e, render_s, path, cmd, timer)
        return render_s

    def lray_ladders(self, scene):
        a = self.args
        ladder = QUICK_LADDER if a.quick else LADDER
        ls = "--light-sampling" in self.flags
        ref_extra = ["-s", a.ref_samples] + (["--light-sampling", "all"] if ls else [])
        # The reference takes its own random stream: with the ladders' seed its
        # first samples would be theirs (the same Sobol points and light
        # jitter), and their error against it would come out too small.
        if "--seed" in self.flags:
            ref_extra += ["--seed", "1"]
        if not ls:
            self.note("%s has no --light-sampling: the reference and the 'fixed-all' ladder run "
                      "without it (every light cell, LRay's only mode then); 'fixed-spread' skipped"
                      % self.lray)
        wall, ref_render, ref_path, cmd, _ = self.lray_render(scene, "embree", "lray-reference",
                                                              ref_extra)
        self.add_row(scene, "lray", "embree", "reference", "-s %d" % a.ref_samples, wall, 0.0,
                     ref_render, ref_path, cmd)
        ref = read_rgb(ref_path)
        progressive = []
        if a.light_sampling != "default" and ls:
            progressive = ["--light-sampling", a.light_sampling]
        max_s = ["--max-samples", a.max_samples] if "--max-samples" in self.flags else []
        min_s = ["--min-samples", a.min_samples] if a.min_samples and "--min-samples" in self.flags else []
        if a.time_limits:
            limits = [float(s) for s in a.time_limits.split(",")]
        else:
            limits = [max(0.01, float("%.2g" % (ref_render * f))) for f in ladder["time_fractions"]]
        for backend in a.backends:
            for n in ladder["samples"]:
                extra = ["-s", n] + (["--light-sampling", "all"] if ls else [])
                self.lray_row(scene, backend, "fixed-all", str(n), extra, ref)
                if ls:
                    self.lray_row(scene, backend, "fixed-spread", str(n),
                                  ["-s", n, "--light-sampling", "spread"], ref)
            if self.has("--noise-threshold", "--max-samples"):
                for t in ladder["thresholds"]:
                    self.lray_row(scene, backend, "adaptive", t,
                                  ["--noise-threshold", t] + max_s + min_s + progressive, ref)
                # The centre-first pass (one sample per pixel, more only where
                # a pixel differs from a neighbour) for the low-quality end.
                if "--min-samples" in self.flags and not a.min_samples:
                    for t in ladder["thresholds"]:
                        self.lray_row(scene, backend, "adaptive-min1", t,
                                      ["--noise-threshold", t, "--min-samples", "1"] + max_s +
                                      progressive, ref)
                # The edge lattice: the centre-first pass, then each flagged
                # pixel refined on a lattice of its corners.
                if "--edge-lattice" in self.flags and not a.min_samples:
                    for t in ladder["lattice_thresholds"]:
                        self.lray_row(scene, backend, "lattice", t,
                                      ["--noise-threshold", t, "--min-samples", "1",
                                       "--edge-lattice", "5"] + max_s + progressive, ref)
                # The same with sparse centres: the centre-first pass fills
                # the centres between traced ones that agree.
                if "--sparse-centres" in self.flags and not a.min_samples:
                    for t in ladder["lattice_thresholds"]:
                        self.lray_row(scene, backend, "sparse", t,
                                      ["--noise-threshold", t, "--min-samples", "1",
                                       "--edge-lattice", "5", "--sparse-centres"] + max_s +
                                      progressive, ref)
            else:
                self.note("%s has no --noise-threshold/--max-samples: 'adaptive' skipped" % self.lray)
            if self.has("--time-limit"):
                for s in limits:
                    self.lray_row(scene, backend, "time", "%g" % s,
                                  ["--time-limit", "%g" % s] + max_s + progressive, ref)
            else:
                self.note("%s has no --time-limit: 'time' skipped" % self.lray)
        return ref_path

    # ---- POV-Ray

    def prepare_pov(self):
        os.makedirs(self.pov_dir, exist_ok=True)
        for f in POV_SUPPORT + [s + ".pov" for s in self.args.scenes]:
            shutil.copy(os.path.join(SCENE_DIR, f), self.pov_dir)
        if "mesh200k" in self.args.scenes:
            t0 = time.perf_counter()
            n = write_torus_mesh2(os.path.join(self.pov_dir, "mesh200k_mesh.inc"))
            print("wrote pov/mesh200k_mesh.inc (%d triangles, %.1f s)" % (n, time.perf_counter() - t0))

    def pov_render(self, scene, name, opts, scale=1):
        """Renders pov/<scene>.pov in pov/ (POV-Ray's I/O restrictions allow
        writing in its working folder) and moves the image to renders/; at
        `scale` x the size as a 16-bit PPM, for pov_reference. Returns as
        lray_render does, with POV-Ray's trace time."""
        info = SCENES[scene]
        a = self.args
        base = "%s-%s" % (scene, name)
        ext, fmt = ("png", "+FN") if scale == 1 else ("ppm", "+FP16")
        cmd = ["povray", "+I%s.pov" % scene, "+O%s.%s" % (base, ext), "+W%d" % (a.width * scale),
               "+H%d" % (a.height * scale), fmt, "-D", "-V", "+WT%d" % a.threads] + opts
        if "frame" in info:
            last, f = info["frames"] - 1, info["frame"]
            cmd += ["+KFI0", "+KFF%d" % last, "+KI0", "+KF1", "+SF%d" % f, "+EF%d" % f]
        final = os.path.join(self.out, "renders", scene, name + "." + ext)
        os.makedirs(os.path.dirname(final), exist_ok=True)
        def timed_run():
            """One run of cmd: (wall s, trace s or None, the image it wrote)."""
            for old in glob.glob(os.path.join(self.pov_dir, base + "*." + ext)):
                os.remove(old)
            wall, log = run_checked(cmd, cwd=self.pov_dir)
            if re.search(r"Fatal error|Parse Error|Render error", log) and "Possible Parse Error" not in log:
                raise BenchError("povray reported an error:\n  %s\n%s" % (shlex.join(cmd), log[-4000:]))
            images = glob.glob(os.path.join(self.pov_dir, base + "*." + ext))
            if len(images) != 1:
                raise BenchError("povray wrote %d images named %s*.%s, expected 1:\n  %s\n%s"
                                 % (len(images), base, ext, shlex.join(cmd), log[-4000:]))
            times = re.findall(r"Trace Time:.*\(\s*([\d.]+) seconds\)", log)
            return wall, sum(float(t) for t in times) if times else None, images[0]

        wall, trace_s, image = timed_run()
        shutil.move(image, final)
        return wall, trace_s, final, cmd, lambda: timed_run()[:2]

    def pov_reference(self, scene):
        """POV-Ray's reference: -A at --pov-ref-scale N times the size, each
        N x N block of rays averaged into a pixel (box_downsample_srgb). Its
        rays lie at odd multiples of 1/(2N) of a pixel (N even), none of them
        a ray of the runs it judges: the pixel centre (-A; and every +AM1
        run, which averages its centre ray with its grid, POV-Ray's
        TraceTask::SupersampleOnePixel), +AM1's grids at (i + 1/2) / depth
        (jittered by default), +AM2's corners and quarter points. POV-Ray's
        own +A0.0 +AM1 reference would hold the centre ray -A traces."""
        scale = self.args.pov_ref_scale
        wall, trace_s, ppm_path, cmd, _ = self.pov_render(scene, "pov-reference", ["-A"], scale)
        ref_path = ppm_path[:-len(".ppm")] + ".png"
        mpimg.imsave(ref_path, box_downsample_srgb(read_ppm16(ppm_path), scale))
        os.remove(ppm_path)
        self.add_row(scene, "povray", "", "reference", pov_reference_setting(self.args), wall, 0.0,
                     trace_s, ref_path, cmd)
        return ref_path

    def pov_ladder(self, scene):
        ladder = QUICK_LADDER if self.args.quick else LADDER
        ref_path = self.pov_reference(scene)
        ref = read_rgb(ref_path)
        for mode, setting, opts in ladder["pov"]:
            name = "pov-%s-%s" % (mode, re.sub(r"[^A-Za-z0-9.]+", "", setting))
            wall, trace_s, path, cmd, timer = self.pov_render(scene, name, opts)
            self.add_row(scene, "povray", "", mode, setting, wall, rmse(read_rgb(path), ref),
                         trace_s, path, cmd, timer)
        return ref_path

    # ---- results

    def add_row(self, scene, renderer, backend, mode, setting, seconds, e, render_s, path, cmd,
                timer=None):
        """One row of results; `timer` (a run's), timed again in the later passes."""
        row = {"scene": scene, "renderer": renderer, "backend": backend, "mode": mode,
               "setting": setting, "seconds": seconds, "rmse": e, "psnr": psnr(e),
               "render_seconds": render_s, "image": os.path.relpath(path, self.out) if path else "",
               "command": shlex.join(cmd) if cmd else ""}
        self.rows.append(row)
        if timer is not None:
            self.timings.append((row, timer, [seconds], [] if render_s is None else [render_s]))
        secs = "%8.3f s" % seconds if seconds is not None else " " * 10
        print("  %-10s %-11s %-7s %-12s %-16s %s  rmse %.5f  psnr %s"
              % (scene, renderer, backend, mode, setting, secs, e, fmt_psnr(row["psnr"])), flush=True)

    def run(self):
        os.makedirs(self.out, exist_ok=True)
        print("lray: %s" % self.lray)
        print("povray: %s" % (self.pov or "not used (not on PATH or --no-pov)"))
        if self.pov:
            self.prepare_pov()
        for scene in self.args.scenes:
            print("== %s" % scene, flush=True)
            lref = self.lray_ladders(scene)
            if self.pov:
                pref = self.pov_ladder(scene)
                e = rmse(read_rgb(lref), read_rgb(pref))
                self.add_row(scene, "lray-vs-pov", "", "reference",
                             "lray -s %d vs povray %s"
                             % (self.args.ref_samples, pov_reference_setting(self.args)),
                             None, e, "", None, None)
        self.retime()
        shutil.rmtree(self.tmp_dir, ignore_errors=True)
        self.write_csv()
        self.write_md()
        self.write_plot()
        print("wrote %s/results.csv, results.md, time_vs_error.png" % self.out)

    def retime(self):
        """--repeat N: N - 1 more passes, each timing every run of every
        ladder once (POV-Ray's and LRay's, scene after scene), then each
        row's medians. Interleaved, not N runs in a row: this machine's
        speed drifts over minutes, and a setting timed only in a slow
        minute, or POV-Ray's ladder in another minute than LRay's, would
        move the ratios by as much as the renderers differ."""
        for k in range(1, self.args.repeat):
            print("== timing pass %d of %d (%d runs)" % (k + 1, self.args.repeat,
                                                        len(self.timings)), flush=True)
            for _, timer, walls, renders in self.timings:
                wall, render_s = timer()
                walls.append(wall)
                if render_s is not None:
                    renders.append(render_s)
        for row, _, walls, renders in self.timings:
            row["seconds"] = statistics.median(walls)
            row["render_seconds"] = median_or_blank(renders)

    def write_csv(self):
        with open(os.path.join(self.out, "results.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=CSV_FIELDS)
            w.writeheader()
            for r in self.rows:
                r = dict(r)
                for k in ("seconds", "rmse", "render_seconds"):
                    if isinstance(r[k], float):
                        r[k] = "%.6g" % r[k]
                    elif r[k] is None:
                        r[k] = ""
                r["psnr"] = fmt_psnr(r["psnr"])
                w.writerow(r)

    def write_md(self):
        a = self.args
        lines = ["# LRay run time against image error", "",
                 "%dx%d, %d threads, `%s`%s; POV-Ray: %s. RMSE over R, G, B of the 8-bit sRGB-encoded "
                 "PNG values scaled to [0, 1], each image against its own renderer's reference "
                 "(LRay: `-s %d`, every light cell, embree; POV-Ray: `%s`); PSNR = 20 log10(1 / RMSE). "
                 "Seconds: wall time of the whole process; render s: LRay's "
                 "`--stats` `times.render`, POV-Ray's trace time (medians of %d runs, in passes that "
                 "each time every run of the ladders once; the references one run)."
                 % (a.width, a.height, a.threads, self.lray, " (--quick)" if a.quick else "",
                    self.pov or "not run", a.ref_samples, pov_reference_setting(a),
                    a.repeat), ""]
        for n in self.notes:
            lines.append("- Note: " + n)
        if self.notes:
            lines.append("")
        for scene in a.scenes:
            rows = [r for r in self.rows if r["scene"] == scene]
            lines += ["## %s" % scene, ""]
            if SCENES[scene].get("note"):
                lines += ["(%s)" % SCENES[scene]["note"], ""]
            cross = [r for r in rows if r["renderer"] == "lray-vs-pov"]
            if cross:
                lines += ["LRay reference against POV-Ray reference: RMSE %.5f (PSNR %s dB)."
                          % (cross[0]["rmse"], fmt_psnr(cross[0]["psnr"])), ""]
            lines += ["| renderer | backend | mode | setting | seconds | render s | RMSE | PSNR dB |",
                      "|---|---|---|---|---|---|---|---|"]
            for r in rows:
                if r["renderer"] == "lray-vs-pov":
                    continue
                rs = "%.3f" % r["render_seconds"] if isinstance(r["render_seconds"], float) else ""
                lines.append("| %s | %s | %s | %s | %.3f | %s | %.5f | %s |"
                             % (r["renderer"], r["backend"], r["mode"], r["setting"], r["seconds"], rs,
                                r["rmse"], fmt_psnr(r["psnr"])))
            lines.append("")
            povs = [r for r in rows if r["renderer"] == "povray" and r["mode"] != "reference"]
            if povs:
                lines += ["For each POV-Ray error level, the fastest LRay run (any mode but the reference) "
                          "with an RMSE no larger; ratio = POV-Ray seconds / LRay seconds (above 1: "
                          "LRay faster). The last two columns compare render time alone (POV-Ray's "
                          "trace time, LRay's frame time from --stats), without either renderer's "
                          "start-up and parsing: the fastest LRay run by render time and its "
                          "ratio, and the ratio to the render time read off LRay's quickest "
                          "ladder at POV-Ray's RMSE (log time against log RMSE between the two "
                          "runs of a mode that bracket it: the ladders' steps are coarse).", "",
                          "| POV-Ray run | POV s | POV RMSE | backend | fastest LRay run | LRay s | LRay RMSE | ratio "
                          "| fastest by render time | render ratio | interpolated render ratio |",
                          "|---|---|---|---|---|---|---|---|---|---|---|"]
                for p in povs:
                    for b in a.backends:
                        ok = [r for r in rows if r["renderer"] == "lray" and r["backend"] == b
                              and r["mode"] != "reference" and r["rmse"] <= p["rmse"]]
                        pov_cells = "%s %s | %.3f | %.5f" % (p["mode"], p["setting"], p["seconds"], p["rmse"])
                        if ok:
                            best = min(ok, key=lambda r: r["seconds"])
                            render = render_ratio(p, ok)
                            lines.append("| %s | %s | %s %s | %.3f | %.5f | %.2f | %s | %s |"
                                         % (pov_cells, b, best["mode"], best["setting"], best["seconds"],
                                            best["rmse"], p["seconds"] / best["seconds"], render,
                                            interpolated_render_ratio(p, rows, b)))
                        else:
                            lines.append("| %s | %s | none reaches it | | | | | | |"
                                         % (pov_cells, b))
                lines.append("")
        lines += self.adaptive_md()
        with open(os.path.join(self.out, "results.md"), "w") as f:
            f.write("\n".join(lines))

    def adaptive_md(self):
        """Each renderer's adaptive sampling against its own 16-ray fixed
        sampling: how long its adaptive runs take to reach the fixed run's
        RMSE, in wall time and in render time alone (POV-Ray's trace time;
        both renderers' fixed costs, start-up and parsing, are in the wall
        time: about 0.5 s a run for POV-Ray). 'fastest run' is the quickest
        ladder run whose RMSE is no larger; 'interpolated' reads the time off
        each adaptive ladder's curve, log time against log RMSE between the
        two runs that bracket the target (the ladder's steps are coarse), and
        takes the quickest ladder."""
        lines = ["## Adaptive against fixed 16-ray sampling", "",
                 "Per renderer: the fixed run (LRay `-s 4 --light-sampling all`, POV-Ray "
                 "`+A0.0 +AM1 +R4`) and the time its adaptive runs take to reach that RMSE; "
                 "ratio = fixed time / adaptive time, in wall seconds and in render seconds "
                 "(interpolated on each adaptive ladder's curve).", "",
                 "| scene | renderer | backend | fixed RMSE | fixed s | fastest adaptive run reaching it "
                 "| s | ratio | interpolated ratio | fixed render s | interpolated render ratio |",
                 "|---|---|---|---|---|---|---|---|---|---|---|"]
        for scene in self.args.scenes:
            for renderer, (base_mode, base_setting) in ADAPTIVE_BASE.items():
                for backend in (self.args.backends if renderer == "lray" else [""]):
                    rows = [r for r in self.rows if r["scene"] == scene and r["renderer"] == renderer
                            and r["backend"] == backend]
                    base = [r for r in rows if r["mode"] == base_mode and r["setting"] == base_setting]
                    if not base:
                        continue
                    base = base[0]
                    target = base["rmse"]
                    cells = "| %s | %s | %s | %.5f | %.3f |" % (scene, renderer, backend or "-", target,
                                                               base["seconds"])
                    ladders = [[r for r in rows if r["mode"] == m] for m in ADAPTIVE_MODES[renderer]]
                    reached = [r for ladder in ladders for r in ladder if r["rmse"] <= target]
                    if not reached:
                        lines.append(cells + " none reaches it | | | | |")
                        continue
                    best = min(reached, key=lambda r: r["seconds"])
                    wall = min(t for t in (interpolated_time(l, target, "seconds") for l in ladders)
                               if t is not None)
                    render = [t for t in (interpolated_time(l, target, "render_seconds") for l in ladders)
                              if t is not None]
                    base_render = base["render_seconds"]
                    render_cells = "| |"
                    if render and isinstance(base_render, float):
                        render_cells = "| %.3f | %.2f |" % (base_render, base_render / min(render))
                    lines.append(cells + " %s %s | %.3f | %.2f | %.2f %s"
                                 % (best["mode"], best["setting"], best["seconds"],
                                    base["seconds"] / best["seconds"], base["seconds"] / wall,
                                    render_cells))
        lines += ["", "Oracle: the samples per pixel an allocation that knew the reference would need "
                  "to reach LRay's fixed 4 x 4 RMSE, taking for each pixel the cheapest of the "
                  "`fixed-all` images (1 x 1 to 8 x 8; embree) that keeps the frame's squared error "
                  "at 4 x 4's (a lower bound for any adaptive sampler with these samples).", "",
                  "| scene | oracle samples per pixel | best possible ratio against 16 |", "|---|---|---|"]
        for scene in self.args.scenes:
            spp = self.oracle_samples(scene)
            if spp:
                lines.append("| %s | %.2f | %.2f |" % (scene, spp, 16 / spp))
        return lines + [""]

    def oracle_samples(self, scene):
        """Per pixel, the cheapest n x n of the embree fixed-all ladder, chosen
        with a Lagrange multiplier so that the frame's summed squared error
        is at most the 4 x 4 image's; the mean n^2. None without the images."""
        rows = [r for r in self.rows if r["scene"] == scene and r["renderer"] == "lray"
                and r["backend"] == "embree" and r["mode"] == "fixed-all"]
        ref = [r for r in self.rows if r["scene"] == scene and r["renderer"] == "lray"
               and r["mode"] == "reference"]
        paths = [os.path.join(self.out, r["image"]) for r in rows + ref]
        if not ref or not any(r["setting"] == "4" for r in rows) or not all(map(os.path.exists, paths)):
            return None
        reference = read_rgb(os.path.join(self.out, ref[0]["image"]))
        ns = [int(r["setting"]) for r in rows]
        errors = np.stack([((read_rgb(os.path.join(self.out, r["image"])) - reference) ** 2).sum(axis=2).ravel()
                           for r in rows])
        costs = np.array([n * n for n in ns], dtype=np.float64)[:, None]
        target = errors[ns.index(4)].sum()
        lo, hi = 1e-6, 1e12
        for _ in range(200):  # bisect the multiplier on a log scale
            lam = math.sqrt(lo * hi)
            pick = np.argmin(costs + lam * errors, axis=0)
            if errors[pick, np.arange(errors.shape[1])].sum() > target:
                lo = lam
            else:
                hi = lam
        pick = np.argmin(costs + hi * errors, axis=0)
        return float(costs[pick, 0].mean())

    def write_plot(self):
        a = self.args
        n = len(a.scenes)
        cols = min(3, n)
        rows_n = (n + cols - 1) // cols
        fig, axes = plt.subplots(rows_n, cols, figsize=(5.2 * cols, 4 * rows_n), squeeze=False)
        colours = {"fixed-all": "tab:blue", "fixed-spread": "tab:orange", "adaptive": "tab:green",
                   "adaptive-min1": "tab:olive", "lattice": "tab:purple", "sparse": "tab:pink",
                   "time": "tab:red"}
        styles = {"embree": "-", "kdtree": "--"}
        for ax, scene in zip(axes.flat, a.scenes):
            rows = [r for r in self.rows if r["scene"] == scene and math.isfinite(r["psnr"])
                    and r["mode"] != "reference"]
            for b in a.backends:
                for mode, colour in colours.items():
                    pts = [r for r in rows if r["renderer"] == "lray" and r["backend"] == b and r["mode"] == mode]
                    if pts:  # in ladder order: more samples, lower threshold, longer limit
                        ax.plot([r["seconds"] for r in pts], [r["psnr"] for r in pts], styles.get(b, ":"),
                                color=colour, marker="o", ms=3, label="LRay %s %s" % (b, mode))
            # POV-Ray: no anti-aliasing, then each mode's ladder from it (the
            # runs of one mode in ladder order, as LRay's).
            povs = [r for r in rows if r["renderer"] == "povray"]
            noaa = [r for r in povs if r["mode"] == "noaa"]
            for mode, style in (("adaptive", "-"), ("forced", ":")):
                pts = noaa + [r for r in povs if r["mode"] == mode]
                if len(pts) > len(noaa):
                    ax.plot([r["seconds"] for r in pts], [r["psnr"] for r in pts], style, color="black",
                            marker="s", ms=4, label="POV-Ray %s" % mode)
            for r in povs:
                    ax.annotate(r["setting"], (r["seconds"], r["psnr"]), fontsize=6,
                                textcoords="offset points", xytext=(3, 3))
            ax.set_xscale("log")
            ax.xaxis.set_major_formatter(ticker.FormatStrFormatter("%g"))
            ax.xaxis.set_minor_locator(ticker.LogLocator(subs=(2, 5)))
            ax.xaxis.set_minor_formatter(ticker.FormatStrFormatter("%g"))
            ax.tick_params(axis="x", which="minor", labelsize=7)
            ax.set_title(scene)
            ax.set_xlabel("wall seconds")
            ax.set_ylabel("PSNR (dB) against own reference")
            ax.grid(True, which="both", alpha=0.3)
        for ax in list(axes.flat)[n:]:
            ax.axis("off")
        handles, labels = {}, []
        for ax in axes.flat:
            for h, l in zip(*ax.get_legend_handles_labels()):
                if l not in handles:
                    handles[l] = h
                    labels.append(l)
        fig.legend([handles[l] for l in labels], labels, loc="lower center", ncol=min(5, len(labels)),
                   fontsize=7)
        fig.suptitle("LRay and POV-Ray 3.7: time against error, %dx%d, %d threads"
                     % (a.width, a.height, a.threads))
        fig.tight_layout(rect=(0, 0.04 + 0.02 * math.ceil(len(labels) / 5), 1, 0.97))
        fig.savefig(os.path.join(self.out, "time_vs_error.png"), dpi=120)
        plt.close(fig)


def render_ratio(pov, runs):
    """'run | ratio' cells: of the LRay runs `runs`, the one with the least
    render time, and POV-Ray's render time over its; blank cells when a
    render time is missing."""
    timed = [r for r in runs if isinstance(r["render_seconds"], float) and r["render_seconds"] > 0]
    if not timed or not isinstance(pov["render_seconds"], float):
        return " | "
    best = min(timed, key=lambda r: r["render_seconds"])
    return "%s %s | %.2f" % (best["mode"], best["setting"], pov["render_seconds"] / best["render_seconds"])


def interpolated_render_ratio(pov, rows, backend):
    """POV-Ray's render time over the least of LRay's ladders' render
    times interpolated at its RMSE (interpolated_time), one ladder a mode;
    blank without times."""
    lray = [r for r in rows if r["renderer"] == "lray" and r["backend"] == backend
            and r["mode"] != "reference"]
    times = [t for t in (interpolated_time([r for r in lray if r["mode"] == m], pov["rmse"],
                                           "render_seconds")
                         for m in sorted({r["mode"] for r in lray})) if t is not None]
    if not times or not isinstance(pov["render_seconds"], float):
        return ""
    return "%.2f" % (pov["render_seconds"] / min(times))


def interpolated_time(ladder, target, key):
    """The time (row field `key`) at which a ladder's runs (one adaptive
    mode) reach RMSE `target`: log-log interpolation between the quickest
    run that reaches it and the latest quicker run that misses it; the
    reaching run's own time when no quicker run misses. None if no run
    reaches it or a time is missing."""
    runs = [r for r in ladder if r["rmse"] > 0 and isinstance(r[key], float) and r[key] > 0]
    runs.sort(key=lambda r: r[key])
    for i, r in enumerate(runs):
        if r["rmse"] > target:
            continue
        misses = [p for p in runs[:i] if p["rmse"] > target]
        if not misses:
            return r[key]
        p = misses[-1]
        f = (math.log(target) - math.log(p["rmse"])) / (math.log(r["rmse"]) - math.log(p["rmse"]))
        return math.exp(math.log(p[key]) + f * (math.log(r[key]) - math.log(p[key])))
    return None


def fmt_psnr(p):
    return "inf" if math.isinf(p) else "%.2f" % p


def csv_list(choices):
    def parse(text):
        items = [s for s in text.split(",") if s]
        bad = [s for s in items if s not in choices]
        if bad or not items:
            raise argparse.ArgumentTypeError("expected a comma-separated subset of %s, got %r"
                                             % (",".join(choices), text))
        return items
    return parse


def rewrite_from_csv(args):
    """--from-csv: the tables and the plot again from a run's results.csv
    (after a change to how they are drawn; the scenes and backends are the
    CSV's own)."""
    path = os.path.join(args.out, "results.csv")
    if not os.path.exists(path):
        print("time_vs_error: error: no %s" % path, file=sys.stderr)
        return 1
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            for k in ("seconds", "rmse", "render_seconds"):
                r[k] = float(r[k]) if r[k] not in ("", None) else ("" if k == "render_seconds" else None)
            r["psnr"] = psnr(r["rmse"])
            rows.append(r)
    args.scenes = [s for s in SCENES if any(r["scene"] == s for r in rows)]
    args.backends = [b for b in ("embree", "kdtree") if any(r["backend"] == b for r in rows)]
    runner = Runner.__new__(Runner)
    runner.args, runner.out, runner.rows, runner.notes = args, args.out, rows, []
    runner.lray, runner.pov = args.lray, "povray" if any(r["renderer"] == "povray" for r in rows) else None
    runner.write_md()
    runner.write_plot()
    print("wrote %s/results.md, time_vs_error.png" % args.out)
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--lray", default=os.path.join(ROOT, "build", "lray"), help="lray binary (default build/lray)")
    p.add_argument("--out", default="/tmp/time_vs_error", help="output folder (default /tmp/time_vs_error)")
    p.add_argument("-w", "--width", type=int, default=320)
    p.add_argument("-H", "--height", type=int, default=180)
    p.add_argument("-t", "--threads", type=int, default=2)
    p.add_argument("--scenes", type=csv_list(list(SCENES)), default=list(SCENES),
                   help="comma-separated subset of %s" % ",".join(SCENES))
    p.add_argument("--backends", type=csv_list(["embree", "kdtree"]), default=["embree", "kdtree"],
                   help="comma-separated (default embree,kdtree)")
    p.add_argument("--quick", action="store_true", help="a shortened ladder, for testing the runner")
    p.add_argument("--ref-samples", type=int, default=REF_SAMPLES, help="LRay reference -s (default 16)")
    p.add_argument("--max-samples", type=int, default=256,
                   help="--max-samples for the adaptive and time-limit runs (default 256)")
    p.add_argument("--min-samples", type=int, default=0,
                   help="--min-samples for the adaptive runs (default: not given)")
    p.add_argument("--light-sampling", choices=["default", "all", "spread"], default="default",
                   help="--light-sampling for the adaptive and time-limit runs (default: not given)")
    p.add_argument("--time-limits", default="",
                   help="comma-separated --time-limit seconds (default: 1/32, 1/16, 1/8, 1/4 of the "
                        "reference's render time; --quick: 1/16, 1/4)")
    p.add_argument("--pov-ref-scale", type=int, default=POV_REF_SCALE,
                   help="POV-Ray reference: -A at N times the size, N x N rays averaged into a "
                        "pixel (an even N, default 16)")
    p.add_argument("--repeat", type=int, default=1,
                   help="runs per setting, in N passes over all the ladders (interleaved): medians "
                        "of the wall and render times (default 1; the references run once)")
    p.add_argument("--no-pov", action="store_true", help="skip POV-Ray even when it is on PATH")
    p.add_argument("--from-csv", action="store_true",
                   help="render nothing: rewrite results.md and the plot from --out's results.csv")
    args = p.parse_args()
    if args.from_csv:
        return rewrite_from_csv(args)
    if min(args.width, args.height, args.threads, args.repeat, args.ref_samples) < 1:
        p.error("--width, --height, --threads, --repeat and --ref-samples must be positive")
    if args.pov_ref_scale < 2 or args.pov_ref_scale % 2:
        p.error("--pov-ref-scale must be even (an odd N traces the pixel centres -A traces)")
    if not os.access(args.lray, os.X_OK):
        p.error("no lray binary at %s (build it, or give --lray)" % args.lray)
    try:
        Runner(args).run()
    except BenchError as e:
        print("time_vs_error: error: %s" % e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
