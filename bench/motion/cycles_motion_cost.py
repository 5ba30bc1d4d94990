"""What motion blur costs Blender Cycles (which traces with Embree on the
CPU) on the twin of bench/motion/scenes/crowd.lua: the peer for issue 36's
target (a blurred frame at 16 samples per pixel within 1.5x of the sharp
one). See bench/README.md, "Motion blur".

The twin: the same 101 x 101-vertex cloth waving (a shape key from its
shape at clock 0 to the one at the shutter's close, as LRay's two motion
steps interpolate it), 450 spheres drifting and 450 cubes turning (one mesh
each, instanced: Cycles has no analytic sphere, so a 32 x 16 UV sphere),
one point light, direct light only (max_bounces 0, as LRay's shading
equation with no mirrors), 640 x 360, box filter, no adaptive sampling, no
denoising. The shutter stays open for half of the frame interval from the
frame on, as `--shutter 0.5` in LRay.

Each setting renders at 1 and at 16 samples per pixel (`--runs` times,
medians): the difference is what the 15 extra samples cost, without the
scene's sync and BVH build that Cycles times with its render. Prints a
markdown table.

    build/peers/bin/python bench/motion/cycles_motion_cost.py [--runs 3] [--threads 2]
"""

import argparse
import math
import statistics
import time

import bpy
import numpy as np


def to_blender(x, y, z):
    """LRay is y-up; Blender z-up (gi-peers mapping)."""
    return (x, -z, y)


def diffuse(name, rgb):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*rgb, 1)
    mat.node_tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def cloth(clock_end):
    n = 100
    def surface(clock):
        verts = []
        for j in range(n + 1):
            for i in range(n + 1):
                x, z = -10 + 20 * i / n, -2 + 20 * j / n
                y = 0.3 * math.sin(0.8 * x + 4 * clock) * math.cos(0.5 * z)
                verts.append(to_blender(x, y, z))
        return verts
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            faces.append((a, a + n + 1, a + 1))
            faces.append((a + 1, a + n + 1, a + n + 2))
    me = bpy.data.meshes.new("cloth")
    me.from_pydata(surface(0), [], faces)
    me.update()
    me.shade_smooth()
    ob = bpy.data.objects.new("cloth", me)
    bpy.context.scene.collection.objects.link(ob)
    ob.data.materials.append(diffuse("cloth", (0.7, 0.7, 0.7)))
    ob.shape_key_add(name="basis")
    key = ob.shape_key_add(name="close")
    key.data.foreach_set("co", np.array(surface(clock_end), dtype=np.float32).ravel())
    # The key's value follows the clock: 0 at frame 1 (clock 0), 1 at the
    # shutter's close (frame 1 + clock_end).
    key.value = 0
    key.keyframe_insert("value", frame=1)
    key.value = 1
    key.keyframe_insert("value", frame=1 + clock_end)


def crowd():
    sphere_mesh = bpy.data.meshes.new("sphere")
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=0.2)
    bm.to_mesh(sphere_mesh)
    bm.free()
    sphere_mesh.shade_smooth()
    sphere_mesh.materials.append(diffuse("red", (0.9, 0.3, 0.2)))
    cube_mesh = bpy.data.meshes.new("cube")
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=0.3)
    bm.to_mesh(cube_mesh)
    bm.free()
    cube_mesh.materials.append(diffuse("blue", (0.2, 0.4, 0.9)))
    for j in range(30):
        for i in range(30):
            x, z = -9 + 0.62 * i, -1 + 0.62 * j
            if (i + j) % 2 == 0:
                ob = bpy.data.objects.new(f"s{i}_{j}", sphere_mesh)
                ob.location = to_blender(x, 0.8, z)
                ob.keyframe_insert("location", frame=1)
                ob.location = to_blender(x + 0.6 * math.sin(i), 0.8, z)  # clock 1
                ob.keyframe_insert("location", frame=2)
            else:
                ob = bpy.data.objects.new(f"c{i}_{j}", cube_mesh)
                ob.location = to_blender(x, 0.8, z)
                ob.rotation_euler = (0, 0, math.radians(7 * j))
                ob.keyframe_insert("rotation_euler", frame=1)
                ob.rotation_euler = (0, 0, math.radians(7 * j + 120))
                ob.keyframe_insert("rotation_euler", frame=2)
            bpy.context.scene.collection.objects.link(ob)


def setup(threads, width, height):
    import mathutils
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Keys in straight lines between frames, as LRay's steps.
    bpy.context.preferences.edit.keyframe_new_interpolation_type = "LINEAR"
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = 0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.motion_blur_position = "START"
    scene.render.motion_blur_shutter = 0.5
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.frame_set(1)
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "HORIZONTAL"
    cam.angle = math.radians(50)
    ob = bpy.data.objects.new("camera", cam)
    scene.collection.objects.link(ob)
    eye, target = np.array([0, 6, -9.0]), np.array([0, 0, 6.0])
    ob.location = to_blender(*eye)
    ob.rotation_euler = mathutils.Vector(to_blender(*(target - eye))).to_track_quat(
        "-Z", "Y").to_euler()
    scene.camera = ob
    light = bpy.data.lights.new("light", "POINT")
    light.energy = 2000
    light.shadow_soft_size = 0
    lob = bpy.data.objects.new("light", light)
    lob.location = to_blender(-5, 10, -5)
    scene.collection.objects.link(lob)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.6, 0.8, 1)
    scene.world = world
    cloth(0.5)
    crowd()


def render_seconds(spp, blur):
    scene = bpy.context.scene
    scene.cycles.samples = spp
    scene.render.use_motion_blur = blur
    times = {}
    pre = lambda *_: times.setdefault("pre", time.perf_counter())  # noqa: E731
    post = lambda *_: times.setdefault("post", time.perf_counter())  # noqa: E731
    bpy.app.handlers.render_pre.append(pre)
    bpy.app.handlers.render_post.append(post)
    bpy.ops.render.render(write_still=False)
    bpy.app.handlers.render_pre.remove(pre)
    bpy.app.handlers.render_post.remove(post)
    return times["post"] - times["pre"]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--look", help="also write the blurred 16-spp frame to this PNG")
    args = ap.parse_args()
    setup(args.threads, 640, 360)
    print(f"Cycles {bpy.app.version_string}, {args.threads} threads, 640 x 360, "
          f"medians of {args.runs} runs\n")
    print("| setting | 1 spp (s) | 16 spp (s) | 15 samples (s) |")
    print("|---|---|---|---|")
    cost = {}
    for blur in (False, True):
        one = statistics.median(render_seconds(1, blur) for _ in range(args.runs))
        full = statistics.median(render_seconds(16, blur) for _ in range(args.runs))
        cost[blur] = full - one
        print(f"| {'blurred' if blur else 'sharp'} | {one:.3f} | {full:.3f} | {full - one:.3f} |",
              flush=True)
    print(f"\nblurred / sharp, the samples alone: {cost[True] / cost[False]:.2f}")
    if args.look:
        scene = bpy.context.scene
        scene.view_settings.view_transform = "Standard"
        scene.render.image_settings.file_format = "PNG"
        scene.render.filepath = args.look
        scene.cycles.samples = 16
        scene.render.use_motion_blur = True
        bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main()
