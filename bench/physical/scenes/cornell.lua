-- bench/physical: a Cornell box (after Mitsuba 3's cornell_box()): white
-- floor, ceiling and back wall, a red left and a green right wall, two
-- diffuse boxes, an emitting square under the ceiling, nothing outside.
-- Its twins: cornell_mitsuba.py and cornell_cycles.py, the same numbers.
scene_info = SceneInfo() { image_width = 128, image_height = 128, integrator = "path", max_depth = 8 }

local T = dofile("twins.lua")
local matte, emitter, rough_mirror, glass, quad = T.matte, T.emitter, T.rough_mirror, T.glass, T.quad

function scene(clock)
  local s = Scene() {
    background_color = Color(0, 0, 0),
    camera = Perspective(39.3, 1) { transform = LookAt(Vector(0, 1, -3.9), Vector(0, 1, 0), y) },
  }
  local white, red, green = Color(0.725, 0.71, 0.68), Color(0.63, 0.065, 0.05), Color(0.14, 0.45, 0.091)
  s:add_entity(quad({ { -1, 0, -1 }, { 1, 0, -1 }, { 1, 0, 1 }, { -1, 0, 1 } }, { 0, 1, 0 }, matte(white)))
  s:add_entity(quad({ { -1, 2, -1 }, { 1, 2, -1 }, { 1, 2, 1 }, { -1, 2, 1 } }, { 0, -1, 0 }, matte(white)))
  s:add_entity(quad({ { -1, 0, 1 }, { 1, 0, 1 }, { 1, 2, 1 }, { -1, 2, 1 } }, { 0, 0, -1 }, matte(white)))
  s:add_entity(quad({ { -1, 0, -1 }, { -1, 0, 1 }, { -1, 2, 1 }, { -1, 2, -1 } }, { 1, 0, 0 }, matte(red)))
  s:add_entity(quad({ { 1, 0, -1 }, { 1, 0, 1 }, { 1, 2, 1 }, { 1, 2, -1 } }, { -1, 0, 0 }, matte(green)))
  s:add_entity(Cube(Translate(Vector(-0.33, 0.6, 0.3)) * Rotate(y, 20) * Scale(0.6, 1.2, 0.6)) { texture = matte(white) })
  s:add_entity(Cube(Translate(Vector(0.35, 0.3, -0.3)) * Rotate(y, -20) * Scale(0.6)) { texture = matte(white) })
  s:add_entity(quad({ { -0.25, 1.98, -0.25 }, { 0.25, 1.98, -0.25 }, { 0.25, 1.98, 0.25 }, { -0.25, 1.98, 0.25 } },
                    { 0, -1, 0 }, emitter(Color(17, 12, 4))))
  return s
end
