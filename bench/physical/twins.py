"""What bench/physical's twin scenes share: LRay's coordinates mapped to
each peer's, and geometry given by its vertices (so that all three
renderers get the same triangles).

LRay is left-handed with y up and +z into the screen. Mitsuba 3 is
right-handed with y up: a point (x, y, z) of LRay is (x, y, -z) there.
Blender is right-handed with z up: (x, z, y). Both maps are mirrors, so a
triangle's corners are listed in the other order to keep its normal on the
same side (LRay's face normal is (p2 - p1) x (p3 - p1) in its left-handed
frame; Mitsuba's and Blender's are the same product in right-handed ones).
"""

import importlib.util
import math
import os

import numpy as np


def to_mitsuba(p):
    p = np.asarray(p, dtype=np.float64)
    return p * np.array([1.0, 1.0, -1.0])


def to_blender(p):
    p = np.asarray(p, dtype=np.float64)
    return p[..., [0, 2, 1]]


def mirrored_faces(faces):
    """The same triangles with their corners in the other order."""
    faces = np.asarray(faces, dtype=np.int64)
    return faces[:, [0, 2, 1]]


def rotate_y(degrees):
    """LRay's Rotate(y, degrees) (Rodrigues' matrix, as src/math/transform.cpp)."""
    r = math.radians(degrees)
    c, s = math.cos(r), math.sin(r)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def cube(centre, size, degrees=0.0):
    """LRay's Cube(Translate(centre) * Rotate(y, degrees) * Scale(size)) as
    12 triangles (vertices, 0-based faces), normals out in LRay's frame."""
    size = np.broadcast_to(np.asarray(size, dtype=np.float64), (3,))
    corners = np.array([[x, y, z] for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)])
    verts = (corners * size) @ rotate_y(degrees).T + np.asarray(centre, dtype=np.float64)
    # Each face as a quad (a, b, c, d), then checked against the outward direction.
    quads = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    faces = []
    middle = verts.mean(axis=0)
    for a, b, c, d in quads:
        for tri in ((a, b, c), (a, c, d)):
            p = verts[list(tri)]
            normal = np.cross(p[1] - p[0], p[2] - p[0])  # LRay's face normal
            faces.append(tri if np.dot(normal, p.mean(axis=0) - middle) > 0 else tri[::-1])
    return verts, np.array(faces)


def quad(corners, facing):
    """Two triangles over four corners in order round the quad, turned so
    that LRay's face normal points along `facing`."""
    verts = np.asarray(corners, dtype=np.float64)
    faces = []
    for tri in ((0, 1, 2), (0, 2, 3)):
        p = verts[list(tri)]
        normal = np.cross(p[1] - p[0], p[2] - p[0])
        faces.append(tri if np.dot(normal, facing) > 0 else tri[::-1])
    return verts, np.array(faces)


def bumpy_torus(rings=400, sides=250, major=1.0, minor=0.35, bump=0.06):
    """The torus of bench/physical/scenes/mesh.lua, the same formula: rings x
    sides quads (2 triangles each; 400 x 250: 200,000) about the y axis,
    its tube's radius rippled by bump * sin(7u) * sin(5v). Normals out."""
    u = np.arange(rings) * (2 * math.pi / rings)
    v = np.arange(sides) * (2 * math.pi / sides)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    r = minor + bump * np.sin(7 * uu) * np.sin(5 * vv)
    x = (major + r * np.cos(vv)) * np.cos(uu)
    z = (major + r * np.cos(vv)) * np.sin(uu)
    y = r * np.sin(vv)
    verts = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32).astype(np.float64)
    i = np.arange(rings)[:, None]
    j = np.arange(sides)[None, :]
    a = i * sides + j
    b = ((i + 1) % rings) * sides + j
    c = ((i + 1) % rings) * sides + (j + 1) % sides
    d = i * sides + (j + 1) % sides
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    # Outward: the first face's normal against the tube's outward direction.
    p = verts[faces[0]]
    outward = p.mean(axis=0) - np.array([math.cos(u[0]), 0, math.sin(u[0])]) * major
    if np.dot(np.cross(p[1] - p[0], p[2] - p[0]), outward) < 0:
        faces = faces[:, [0, 2, 1]]
    return verts, faces


def write_ply(path, verts, faces):
    """A binary little-endian PLY of float vertices and int triangles."""
    verts = np.asarray(verts, dtype="<f4")
    faces = np.asarray(faces, dtype="<i4")
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(verts.tobytes())
        rows = np.zeros(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
        rows["n"] = 3
        rows["v"] = faces
        f.write(rows.tobytes())
    return path


def load_twin(name):
    """scenes/NAME.py, the peers' description of scenes/NAME.lua."""
    here = os.path.dirname(os.path.abspath(__file__))
    spec = importlib.util.spec_from_file_location(name, os.path.join(here, "scenes", name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def parse_args(extra=None):
    """The command line both twin runners take; `extra(parser)` adds more."""
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("name")
    ap.add_argument("out")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2)
    if extra:
        extra(ap)
    return ap.parse_args()
