"""The peers' twin of glass.lua: m is mitsuba_twin or cycles_twin (bench/physical)."""
import twins


def scene(m):
    s = m.base(eye=(0, 2, -5.5), target=(0, 0.8, 0), fov=45, max_depth=12,
               background=(0.9, 0.95, 1.0))
    s["floor"] = m.mesh(*twins.quad([(-6, 0, -4), (-6, 0, 8), (6, 0, 8), (6, 0, -4)], (0, 1, 0)),
                        m.diffuse((0.6, 0.6, 0.6)))
    s["glass"] = m.sphere((0, 1, 0), 1, m.glass(1.5))
    s["red"] = m.sphere((-1.6, 0.5, 1.8), 0.5, m.diffuse((0.8, 0.15, 0.1)))
    s["blue"] = m.mesh(*twins.cube((1.6, 0.5, 2), 1, 30), m.diffuse((0.1, 0.25, 0.8)))
    return s
