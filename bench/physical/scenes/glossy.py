"""The peers' twin of glossy.lua: m is mitsuba_twin or cycles_twin (bench/physical)."""
import twins


def scene(m):
    s = m.base(eye=(0, 1.6, -6.5), target=(0, 0.9, 0), fov=40, max_depth=8,
               background=(0.05, 0.06, 0.08))
    s["floor"] = m.mesh(*twins.quad([(-5, 0, -3), (-5, 0, 5), (5, 0, 5), (5, 0, -3)], (0, 1, 0)),
                        m.diffuse((0.5, 0.5, 0.5)))
    for i, alpha in enumerate((0.05, 0.2, 0.5)):
        s[f"sphere{i}"] = m.sphere((2 * (i - 1), 0.8, 0), 0.8, m.rough_mirror(alpha))
    s["lamp"] = m.sphere((1, 3.5, -2), 0.5, m.black(), emission=(30, 28, 25))
    return s
