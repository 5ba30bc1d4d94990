-- bench/physical: LRay's Light beside emission. A Light of colour Lc gives
-- irradiance pi * Lc * cos at any distance; no point light of the peers
-- does (theirs fall off as 1 / d^2). So the Light is put 10^4 units away
-- along one direction, where its direction is the same over the whole
-- scene to 1e-4 radians: the peers' directional light (Mitsuba's
-- `directional`, Cycles' Sun) of irradiance pi * Lc. Beside it, an emitting
-- square; a matte sphere, a GGX sphere (roughness 0.2, which sees the
-- Light through its lobe) and a matte cube on a floor. Its peers' twin:
-- mixed.py.
scene_info = SceneInfo() { image_width = 160, image_height = 120, integrator = "path", max_depth = 8 }

local T = dofile("twins.lua")
local matte, emitter, rough_mirror, glass, quad = T.matte, T.emitter, T.rough_mirror, T.glass, T.quad

function scene(clock)
  local s = Scene() {
    background_color = Color(0, 0, 0),
    camera = Perspective(45, 4 / 3) { transform = LookAt(Vector(0, 2.2, -5), Vector(0, 0.5, 0.5), y) },
  }
  s:add_entity(Mesh() { vertices = { { -6, 0, -4 }, { -6, 0, 6 }, { 6, 0, 6 }, { 6, 0, -4 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = matte(grey(0.6)) })
  s:add_entity(Sphere(Translate(Vector(-1.2, 0.7, 0.3)) * Scale(0.7)) { texture = matte(Color(0.8, 0.3, 0.2)) })
  s:add_entity(Sphere(Translate(Vector(1.2, 0.7, 0.3)) * Scale(0.7)) { texture = rough_mirror(0.2) })
  s:add_entity(Cube(Translate(Vector(0, 0.4, 1.5)) * Rotate(y, 25) * Scale(0.8)) { texture = matte(Color(0.3, 0.5, 0.8)) })
  -- A 1.2 x 1.2 square at y = 2.5 facing down.
  s:add_entity(Mesh() { vertices = { { -0.1, 2.5, -1.1 }, { 1.1, 2.5, -1.1 }, { 1.1, 2.5, 0.1 }, { -0.1, 2.5, 0.1 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = emitter(Color(2, 3, 5)) })
  local to_light = Vector(-0.5, 1, -0.6):normalized()
  s:add_light(Light() { color = Color(1, 0.95, 0.9), transform = Translate(to_light * 1e4) })
  return s
end
