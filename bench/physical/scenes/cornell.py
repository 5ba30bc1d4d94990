"""The peers' twin of cornell.lua: m is mitsuba_twin or cycles_twin (bench/physical)."""
import twins

WHITE, RED, GREEN = (0.725, 0.71, 0.68), (0.63, 0.065, 0.05), (0.14, 0.45, 0.091)


def box(m, s):
    """The walls and the emitting square (cornell_gi.py has them too)."""
    s["floor"] = m.mesh(*twins.quad([(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)], (0, 1, 0)),
                        m.diffuse(WHITE))
    s["ceiling"] = m.mesh(*twins.quad([(-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1)], (0, -1, 0)),
                          m.diffuse(WHITE))
    s["back"] = m.mesh(*twins.quad([(-1, 0, 1), (1, 0, 1), (1, 2, 1), (-1, 2, 1)], (0, 0, -1)),
                       m.diffuse(WHITE))
    s["left"] = m.mesh(*twins.quad([(-1, 0, -1), (-1, 0, 1), (-1, 2, 1), (-1, 2, -1)], (1, 0, 0)),
                       m.diffuse(RED))
    s["right"] = m.mesh(*twins.quad([(1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1)], (-1, 0, 0)),
                        m.diffuse(GREEN))
    s["light"] = m.mesh(*twins.quad([(-0.25, 1.98, -0.25), (0.25, 1.98, -0.25), (0.25, 1.98, 0.25),
                                     (-0.25, 1.98, 0.25)], (0, -1, 0)),
                        m.black(), emission=(17, 12, 4))


def scene(m):
    s = m.base(eye=(0, 1, -3.9), target=(0, 1, 0), fov=39.3, max_depth=8)
    box(m, s)
    s["tall"] = m.mesh(*twins.cube((-0.33, 0.6, 0.3), (0.6, 1.2, 0.6), 20), m.diffuse(WHITE))
    s["short"] = m.mesh(*twins.cube((0.35, 0.3, -0.3), 0.6, -20), m.diffuse(WHITE))
    return s
