-- Global illumination: a Cornell box lit only by the emitting square under
-- its ceiling, with a GGX mirror sphere (roughness 0.1) and a Fresnel glass
-- sphere, rendered by the path tracer (lua/README.md, "Light transport"):
-- colour bleeding from the walls, a soft glossy reflection, light focused
-- through the glass. The twin of bench/physical's peers renders it too
-- (bench/physical/scenes/cornell_gi.py; README.md shows all three).
scene_info = SceneInfo() { image_width = 400, image_height = 400, samples = 16,
                           integrator = "path", max_depth = 8 }

local function matte(albedo)
  return Texture() { pigment = ColorPigment(albedo),
                     finish = Finish() { ambient = grey(0), diffuse = 1, specular = 0 } }
end

-- Two triangles over four corners in order round the square; the face
-- normal (p2 - p1) x (p3 - p1) is turned to point along `facing`.
local function quad(p, facing, texture)
  local e1 = { p[2][1] - p[1][1], p[2][2] - p[1][2], p[2][3] - p[1][3] }
  local e2 = { p[3][1] - p[1][1], p[3][2] - p[1][2], p[3][3] - p[1][3] }
  local n = { e1[2] * e2[3] - e1[3] * e2[2], e1[3] * e2[1] - e1[1] * e2[3], e1[1] * e2[2] - e1[2] * e2[1] }
  local along = n[1] * facing[1] + n[2] * facing[2] + n[3] * facing[3] > 0
  return Mesh() { vertices = p, indices = along and { { 1, 2, 3 }, { 1, 3, 4 } } or { { 1, 3, 2 }, { 1, 4, 3 } },
                  texture = texture }
end

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
  s:add_entity(Sphere(Translate(Vector(-0.45, 0.4, 0.35)) * Scale(0.4)) {
    texture = Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                              reflection = 1, roughness = 0.1 } } })
  s:add_entity(Sphere(Translate(Vector(0.45, 0.4, -0.3)) * Scale(0.4)) {
    texture = Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                              reflection = 1, refraction = 1, refraction_index = 1.5,
                                              absorption = 0, fresnel = true } } })
  s:add_entity(quad({ { -0.25, 1.98, -0.25 }, { 0.25, 1.98, -0.25 }, { 0.25, 1.98, 0.25 }, { -0.25, 1.98, 0.25 } },
                    { 0, -1, 0 },
                    Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                                    emission = Color(17, 12, 4) } }))
  return s
end
