"""Builds and renders the Mitsuba 3 twin of a bench/physical scene
(scenes/NAME.py defines scene(m), m being this module: its functions map
each LRay term to Mitsuba's, as bench/physical/README.md lists them).

  build/peers/bin/python bench/physical/mitsuba_twin.py NAME OUT.exr \\
      --width W --height H --spp N --seed S [--variant scalar_rgb]

Prints one JSON line: render seconds (mi.render alone) and wall seconds.
"""

import json
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import twins  # noqa: E402

mi = None
_tmp = tempfile.mkdtemp(prefix="lray-mitsuba-")
_count = 0


def rgb(c):
    return {"type": "rgb", "value": [float(x) for x in c]}


def diffuse(albedo):
    """LRay: pigment albedo, diffuse 1 (shaded from both sides)."""
    return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(albedo)}}


def black():
    return {"type": "diffuse", "reflectance": rgb((0, 0, 0))}


def rough_mirror(alpha):
    """LRay: reflection 1, roughness alpha, no Fresnel."""
    return {"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "material": "none"}


def glass(ior):
    """LRay: reflection 1, refraction 1, fresnel, absorption 0."""
    return {"type": "dielectric", "int_ior": ior, "ext_ior": 1.0}


def emitter(radiance):
    return {"type": "area", "radiance": rgb(radiance)}


def mesh(verts, faces, bsdf, emission=None):
    """Triangles given in LRay's frame (twins.py), flat-shaded."""
    global _count
    _count += 1
    path = twins.write_ply(os.path.join(_tmp, f"mesh{_count}.ply"), twins.to_mitsuba(verts),
                           twins.mirrored_faces(faces))
    shape = {"type": "ply", "filename": path, "face_normals": True, "bsdf": bsdf}
    if emission is not None:
        shape["emitter"] = emitter(emission)
    return shape


def sphere(centre, radius, bsdf, emission=None):
    shape = {"type": "sphere", "center": [float(x) for x in twins.to_mitsuba(centre)],
             "radius": float(radius), "bsdf": bsdf}
    if emission is not None:
        shape["emitter"] = emitter(emission)
    return shape


def sun(to_light, irradiance):
    """LRay: a Light so far along `to_light` that its direction is the same
    everywhere, of colour Lc = irradiance / pi."""
    travel = -twins.to_mitsuba(np.asarray(to_light, dtype=np.float64))
    return {"type": "directional", "direction": [float(x) for x in travel],
            "irradiance": rgb(irradiance)}


def base(eye, target, fov, max_depth, background=None):
    """The camera (LRay's Perspective: horizontal fov) and path depth (LRay's
    max_depth scattering events are Mitsuba's max_depth + 1)."""
    s = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": int(max_depth) + 1},
        "sensor": {
            "type": "perspective", "fov": float(fov), "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[float(x) for x in twins.to_mitsuba(eye)],
                target=[float(x) for x in twins.to_mitsuba(target)], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": SPP, "seed": SEED},
        },
    }
    if background is not None:
        s["sky"] = {"type": "constant", "radiance": rgb(background)}
    return s


def main():
    global mi, WIDTH, HEIGHT, SPP, SEED
    start = time.perf_counter()
    a = twins.parse_args(
        lambda ap: ap.add_argument("--variant", default="scalar_rgb"))
    WIDTH, HEIGHT, SPP, SEED = a.width, a.height, a.spp, a.seed
    import drjit as dr
    import mitsuba
    mi = mitsuba
    mi.set_variant(a.variant)
    dr.set_thread_count(a.threads)
    scene = mi.load_dict(twins.load_twin(a.name).scene(sys.modules[__name__]))
    t0 = time.perf_counter()
    image = mi.render(scene, spp=SPP, seed=SEED)
    dr.eval(image)
    render = time.perf_counter() - t0
    mi.Bitmap(image).write(a.out)
    print(json.dumps({"render_s": render, "wall_s": time.perf_counter() - start}), flush=True)
    os._exit(0)  # drjit may hang at exit with few threads (gi-peers notes)


if __name__ == "__main__":
    main()
