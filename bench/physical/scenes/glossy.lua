-- bench/physical: GGX mirrors of roughness 0.05, 0.2 and 0.5 (no Fresnel)
-- on a grey floor under an emitting sphere and a dim constant sky.
-- Its peers' twin: glossy.py, the same numbers.
scene_info = SceneInfo() { image_width = 160, image_height = 120, integrator = "path", max_depth = 8 }

local T = dofile("twins.lua")
local matte, emitter, rough_mirror, glass, quad = T.matte, T.emitter, T.rough_mirror, T.glass, T.quad

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.06, 0.08),
    camera = Perspective(40, 4 / 3) { transform = LookAt(Vector(0, 1.6, -6.5), Vector(0, 0.9, 0), y) },
  }
  -- The floor: y = 0, x in [-5, 5], z in [-3, 5], facing up.
  s:add_entity(Mesh() { vertices = { { -5, 0, -3 }, { -5, 0, 5 }, { 5, 0, 5 }, { 5, 0, -3 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = matte(grey(0.5)) })
  for i, alpha in ipairs({ 0.05, 0.2, 0.5 }) do
    s:add_entity(Sphere(Translate(Vector(2 * (i - 2), 0.8, 0)) * Scale(0.8)) { texture = rough_mirror(alpha) })
  end
  s:add_entity(Sphere(Translate(Vector(1, 3.5, -2)) * Scale(0.5)) { texture = emitter(Color(30, 28, 25)) })
  return s
end
