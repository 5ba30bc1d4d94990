-- Finish in action: a mirror sphere, a glass sphere (refraction with
-- absorption) and a matte sphere over a checker floor.
scene_info = SceneInfo() { image_width = 640, image_height = 480, samples = 2 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.3, 0.45, 0.7),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 2.5, -8), Vector(0, 1, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(Color(0.9, 0.9, 0.9)),
                                     pigment2 = ColorPigment(Color(0.2, 0.3, 0.2)) },
      finish = Finish() { reflection = 0.15 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(-2.3, 1, 0.5))) {
    texture = Texture() {
      pigment = ColorPigment(grey(0.1)),
      finish = Finish() { diffuse = 0.1, specular = 0.8, exponent = 60, reflection = 0.85 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(0, 1, -0.5))) {
    texture = Texture() {
      pigment = ColorPigment(Color(0.85, 1, 0.9)),
      finish = Finish() { diffuse = 0.05, specular = 0.9, exponent = 80, reflection = 0.1,
                          refraction = 0.85, refraction_index = 1.5, absorption = 0.3 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(2.3, 1, 0.5))) {
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.5, 0.1)), finish = Finish() { diffuse = 0.8 } },
  })
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -6)) })
  return s
end
