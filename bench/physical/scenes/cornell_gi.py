"""The peers' twin of scenes/cornell_gi.lua (the gallery's GI scene): m is
mitsuba_twin or cycles_twin (bench/physical). The box is cornell.py's."""
import twins


def scene(m):
    s = m.base(eye=(0, 1, -3.9), target=(0, 1, 0), fov=39.3, max_depth=8)
    twins.load_twin("cornell").box(m, s)
    s["glossy"] = m.sphere((-0.45, 0.4, 0.35), 0.4, m.rough_mirror(0.1))
    s["glass"] = m.sphere((0.45, 0.4, -0.3), 0.4, m.glass(1.5))
    return s
