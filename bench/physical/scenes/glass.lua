-- bench/physical: a smooth glass sphere (index 1.5, Fresnel, no
-- absorption) over a diffuse floor, a red sphere and a blue cube behind it,
-- lit by a constant sky alone. Its peers' twin: glass.py.
scene_info = SceneInfo() { image_width = 160, image_height = 120, integrator = "path", max_depth = 12 }

local T = dofile("twins.lua")
local matte, emitter, rough_mirror, glass, quad = T.matte, T.emitter, T.rough_mirror, T.glass, T.quad

function scene(clock)
  local s = Scene() {
    background_color = Color(0.9, 0.95, 1.0),
    camera = Perspective(45, 4 / 3) { transform = LookAt(Vector(0, 2, -5.5), Vector(0, 0.8, 0), y) },
  }
  s:add_entity(Mesh() { vertices = { { -6, 0, -4 }, { -6, 0, 8 }, { 6, 0, 8 }, { 6, 0, -4 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = matte(grey(0.6)) })
  s:add_entity(Sphere(Translate(Vector(0, 1, 0))) { texture = glass(1.5) })
  s:add_entity(Sphere(Translate(Vector(-1.6, 0.5, 1.8)) * Scale(0.5)) { texture = matte(Color(0.8, 0.15, 0.1)) })
  s:add_entity(Cube(Translate(Vector(1.6, 0.5, 2)) * Rotate(y, 30)) { texture = matte(Color(0.1, 0.25, 0.8)) })
  return s
end
