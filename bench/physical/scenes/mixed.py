"""The peers' twin of mixed.lua: m is mitsuba_twin or cycles_twin (bench/physical)."""
import math

import numpy as np

import twins


def scene(m):
    s = m.base(eye=(0, 2.2, -5), target=(0, 0.5, 0.5), fov=45, max_depth=8)
    s["floor"] = m.mesh(*twins.quad([(-6, 0, -4), (-6, 0, 6), (6, 0, 6), (6, 0, -4)], (0, 1, 0)),
                        m.diffuse((0.6, 0.6, 0.6)))
    s["matte"] = m.sphere((-1.2, 0.7, 0.3), 0.7, m.diffuse((0.8, 0.3, 0.2)))
    s["glossy"] = m.sphere((1.2, 0.7, 0.3), 0.7, m.rough_mirror(0.2))
    s["cube"] = m.mesh(*twins.cube((0, 0.4, 1.5), 0.8, 25), m.diffuse((0.3, 0.5, 0.8)))
    s["panel"] = m.mesh(*twins.quad([(-0.1, 2.5, -1.1), (1.1, 2.5, -1.1), (1.1, 2.5, 0.1),
                                     (-0.1, 2.5, 0.1)], (0, -1, 0)),
                        m.black(), emission=(2, 3, 5))
    to_light = np.array([-0.5, 1, -0.6]) / math.sqrt(0.25 + 1 + 0.36)
    s["sun"] = m.sun(to_light, [math.pi * c for c in (1, 0.95, 0.9)])
    return s
