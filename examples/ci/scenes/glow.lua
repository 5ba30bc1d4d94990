-- A path-traced scene for examples/ci: a matte sphere and floor lit by an
-- emitting panel. Its renders are noisy, so the suite compares it with the
-- noise-aware test against an approved render with other samples.
scene_info = SceneInfo() { image_width = 96, image_height = 64, samples = 6,
                           integrator = "path", max_depth = 4 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.08),
    camera = Perspective(45, 1.5) { transform = LookAt(Vector(0, 1.5, -4), Vector(0, 0.5, 0), y) },
  }
  local matte = Finish() { ambient = grey(0), diffuse = 1, specular = 0 }
  s:add_entity(Floor() { texture = Texture() { pigment = ColorPigment(grey(0.7)), finish = matte } })
  s:add_entity(Sphere(Translate(Vector(0, 0.6, 0)) * Scale(0.6)) {
    texture = Texture() { pigment = ColorPigment(Color(0.8, 0.4, 0.2)), finish = matte } })
  s:add_entity(Mesh() {
    vertices = { { -1, 3, -1 }, { 1, 3, -1 }, { 1, 3, 1 }, { -1, 3, 1 } },
    indices = { { 1, 2, 3 }, { 1, 3, 4 } },
    texture = Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                              emission = Color(6, 5.5, 5) } } })
  return s
end
