-- A still life for examples/ci: three spheres on a checkered floor under
-- an area light, rendered by the Whitted integrator (deterministic: its
-- approved image is matched pixel for pixel).
scene_info = SceneInfo() { image_width = 160, image_height = 90, samples = 2 }

function scene(clock)
  local s = Scene() {
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 1.6, -5), Vector(0, 0.5, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() { pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.8)),
                                                         pigment2 = ColorPigment(grey(0.3)) } } })
  local colors = { Color(0.9, 0.3, 0.2), Color(0.2, 0.7, 0.3), Color(0.2, 0.4, 0.9) }
  for i = 1, 3 do
    s:add_entity(Sphere(Translate(Vector(1.3 * (i - 2), 0.5, 0)) * Scale(0.5)) {
      texture = Texture() { pigment = ColorPigment(colors[i]),
                            finish = Finish() { specular = 0.5, exponent = 40, reflection = 0.15 } } })
  end
  s:add_light(Light() { rows = 3, cols = 3, area = true,
                        transform = Translate(Vector(-3, 6, -4)) * Scale(2, 1, 2) })
  return s
end
