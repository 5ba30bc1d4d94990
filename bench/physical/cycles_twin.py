"""Builds and renders the Blender Cycles twin of a bench/physical scene
(scenes/NAME.py defines scene(m), m being this module: its functions map
each LRay term to Cycles', as bench/physical/README.md lists them).

  build/peers/bin/python bench/physical/cycles_twin.py NAME OUT.exr \\
      --width W --height H --spp N --seed S [--adaptive THRESHOLD]

Prints one JSON line: render seconds (between Cycles' render_pre and
render_post handlers) and wall seconds.
"""

import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import twins  # noqa: E402

bpy = None
_count = 0


def _material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    return mat, nodes, mat.node_tree.links, out


def diffuse(albedo):
    """LRay: pigment albedo, diffuse 1. Roughness 0 (more is Oren-Nayar)."""
    mat, nodes, links, out = _material("diffuse")
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*[float(x) for x in albedo], 1)
    bsdf.inputs["Roughness"].default_value = 0
    links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def black():
    return None  # an emitter reflects nothing: its material is the emission alone


def rough_mirror(alpha):
    """LRay: reflection 1, roughness alpha, no Fresnel: Glossy BSDF, GGX
    (not multiscatter), Cycles' roughness being sqrt(alpha)."""
    mat, nodes, links, out = _material("glossy")
    bsdf = nodes.new("ShaderNodeBsdfGlossy")
    bsdf.distribution = "GGX"
    bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    bsdf.inputs["Roughness"].default_value = math.sqrt(alpha)
    links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def glass(ior):
    """LRay: reflection 1, refraction 1, fresnel, absorption 0."""
    mat, nodes, links, out = _material("glass")
    bsdf = nodes.new("ShaderNodeBsdfGlass")
    bsdf.distribution = "GGX"
    bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    bsdf.inputs["Roughness"].default_value = 0
    bsdf.inputs["IOR"].default_value = ior
    links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def _emission(radiance):
    """Radiance L from the front side only, as LRay's and Mitsuba's: the
    strength times (1 - Backfacing), and only the front sampled."""
    mat, nodes, links, out = _material("emitter")
    strength = max(float(x) for x in radiance)
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (*[float(x) / strength for x in radiance], 1)
    geometry = nodes.new("ShaderNodeNewGeometry")
    front = nodes.new("ShaderNodeMath")
    front.operation = "SUBTRACT"
    front.inputs[0].default_value = 1
    links.new(geometry.outputs["Backfacing"], front.inputs[1])
    scaled = nodes.new("ShaderNodeMath")
    scaled.operation = "MULTIPLY"
    scaled.inputs[1].default_value = strength
    links.new(front.outputs[0], scaled.inputs[0])
    links.new(scaled.outputs[0], emit.inputs["Strength"])
    links.new(emit.outputs[0], out.inputs["Surface"])
    mat.cycles.emission_sampling = "FRONT"
    return mat


def _object(name, mesh, material):
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    if material is not None:
        ob.data.materials.append(material)
    return ob


def mesh(verts, faces, bsdf, emission=None):
    """Triangles given in LRay's frame (twins.py), flat-shaded."""
    global _count
    _count += 1
    verts = twins.to_blender(verts).astype(np.float32)
    faces = twins.mirrored_faces(faces).astype(np.int32)
    me = bpy.data.meshes.new(f"mesh{_count}")
    me.vertices.add(len(verts))
    me.vertices.foreach_set("co", verts.ravel())
    me.loops.add(faces.size)
    me.loops.foreach_set("vertex_index", faces.ravel())
    me.polygons.add(len(faces))
    me.polygons.foreach_set("loop_start", np.arange(0, faces.size, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(len(faces), 3, dtype=np.int32))
    me.update()
    me.validate()
    me.shade_flat()  # meshes made here are smooth-shaded unless told
    return _object(me.name, me, _emission(emission) if emission is not None else bsdf)


def sphere(centre, radius, bsdf, emission=None):
    """Cycles has no analytic sphere: a smooth-shaded UV sphere of 256 x 128
    segments (its polygon lies within 8e-5 of the radius)."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=float(radius),
                                         location=[float(x) for x in twins.to_blender(centre)])
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    ob.data.materials.append(_emission(emission) if emission is not None else bsdf)
    return ob


def sun(to_light, irradiance):
    """LRay: a Light so far along `to_light` that its direction is the same
    everywhere, of colour Lc = irradiance / pi. A Sun lamp's strength is its
    irradiance; angle 0 (a point on the sky)."""
    import mathutils
    strength = max(float(x) for x in irradiance)
    light = bpy.data.lights.new("sun", "SUN")
    light.energy = strength
    light.color = [float(x) / strength for x in irradiance]
    light.angle = 0
    ob = bpy.data.objects.new("sun", light)
    travel = -twins.to_blender(np.asarray(to_light, dtype=np.float64))
    ob.rotation_euler = mathutils.Vector(travel).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(ob)
    return ob


def base(eye, target, fov, max_depth, background=None):
    """Camera, film and path depth: LRay's max_depth scattering events are
    Cycles' max_depth - 1 bounces (every kind), and every default that
    would bias a reference is set (gi-peers: clamping, glossy blur, light
    threshold, denoising, filter, view transform)."""
    import mathutils
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = SPP
    c.seed = SEED
    c.use_adaptive_sampling = ADAPTIVE > 0
    if ADAPTIVE > 0:
        c.adaptive_threshold = ADAPTIVE
    c.use_denoising = False
    c.sample_clamp_direct = 0
    c.sample_clamp_indirect = 0
    c.blur_glossy = 0
    c.light_sampling_threshold = 0
    bounces = int(max_depth) - 1
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.volume_bounces = 0
    c.transparent_max_bounces = bounces
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x = WIDTH
    scene.render.resolution_y = HEIGHT
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = THREADS
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "HORIZONTAL"
    cam.angle = math.radians(fov)
    ob = bpy.data.objects.new("camera", cam)
    scene.collection.objects.link(ob)
    ob.location = [float(x) for x in twins.to_blender(eye)]
    look = twins.to_blender(np.asarray(target, dtype=np.float64) - np.asarray(eye, np.float64))
    ob.rotation_euler = mathutils.Vector(look).to_track_quat("-Z", "Y").to_euler()
    scene.camera = ob
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    if background is None:
        bg.inputs["Strength"].default_value = 0
    else:
        bg.inputs["Color"].default_value = (*[float(x) for x in background], 1)
        bg.inputs["Strength"].default_value = 1
    scene.world = world
    return {}


def main():
    global bpy, WIDTH, HEIGHT, SPP, SEED, THREADS, ADAPTIVE
    start = time.perf_counter()
    a = twins.parse_args(
        lambda ap: ap.add_argument("--adaptive", type=float, default=0,
                                   help="Cycles' adaptive threshold (0: off)"))
    WIDTH, HEIGHT, SPP, SEED, THREADS, ADAPTIVE = (a.width, a.height, a.spp, a.seed, a.threads,
                                                   a.adaptive)
    import bpy as blender
    bpy = blender
    bpy.ops.wm.read_factory_settings(use_empty=True)
    twins.load_twin(a.name).scene(sys.modules[__name__])
    times = {}
    bpy.app.handlers.render_pre.append(lambda *_: times.setdefault("pre", time.perf_counter()))
    bpy.app.handlers.render_post.append(lambda *_: times.setdefault("post", time.perf_counter()))
    bpy.context.scene.render.filepath = os.path.abspath(a.out)
    bpy.ops.render.render(write_still=True)
    print(json.dumps({"render_s": times["post"] - times["pre"],
                      "wall_s": time.perf_counter() - start}), flush=True)


if __name__ == "__main__":
    main()
