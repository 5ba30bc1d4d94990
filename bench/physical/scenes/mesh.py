"""The peers' twin of mesh.lua: m is mitsuba_twin or cycles_twin (bench/physical)."""
import twins


def scene(m):
    s = m.base(eye=(0, 2.6, -4), target=(0, 0.3, 0), fov=45, max_depth=8)
    s["floor"] = m.mesh(*twins.quad([(-5, 0, -4), (-5, 0, 5), (5, 0, 5), (5, 0, -4)], (0, 1, 0)),
                        m.diffuse((0.5, 0.5, 0.5)))
    verts, faces = twins.bumpy_torus(400, 250, 1.0, 0.35, 0.06)
    s["torus"] = m.mesh(verts + [0, 0.45, 0], faces, m.diffuse((0.7, 0.55, 0.4)))
    s["lamp"] = m.sphere((-1.5, 2.5, -1), 0.3, m.black(), emission=(20, 15, 10))
    panel = twins.quad([(0.5, 3, 0), (1.5, 3, 0), (1.5, 3, 1), (0.5, 3, 1)], (0, -1, 0))
    s["panel"] = m.mesh(*panel, m.black(), emission=(6, 8, 12))
    return s
