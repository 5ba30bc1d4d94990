-- time_vs_error bench scene "arealight": a sphere, a cube and a cylinder on a
-- checker floor under an 8 x 8 jittered area light (soft shadows: the light
-- sampling dominates the noise). POV-Ray twin: arealight.pov.
scene_info = SceneInfo() { image_width = 320, image_height = 180 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 3.5, -8), Vector(0, 0.8, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)), pigment2 = ColorPigment(grey(0.4)) },
    },
  })
  s:add_entity(Sphere(Translate(Vector(-1.5, 1, 0))) {
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.2, 0.2)),
                          finish = Finish() { specular = 0.5, exponent = 30 } },
  })
  s:add_entity(Cube(Translate(Vector(1.2, 0.75, 0.5)) * Rotate(y, 30) * Scale(1.5)) {
    texture = Texture() { pigment = ColorPigment(Color(0.2, 0.4, 0.9)) },
  })
  s:add_entity(Cylinder(Translate(Vector(0.2, 0, -1.6)) * Scale(0.5, 1.2, 0.5)) {
    texture = Texture() { pigment = ColorPigment(Color(0.3, 0.8, 0.3)) },
  })
  -- Up and to the left, so the shadows fall to the right.
  s:add_light(Light() { rows = 8, cols = 8, area = true,
                        transform = Translate(Vector(-5, 8, -4)) * Scale(2, 1, 2) })
  return s
end
