-- time_vs_error bench scene "glass": a refracting sphere (refraction 0.9,
-- index 1.5), a mirror sphere (reflection 0.8) and a matte sphere on a
-- checker floor under a point light: deep secondary rays, hard shadows, so
-- the only noise is the pixel sampling. POV-Ray twin: glass.pov.
scene_info = SceneInfo() { image_width = 320, image_height = 180 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.3, 0.45, 0.7),
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 2.5, -8), Vector(0, 1, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)), pigment2 = ColorPigment(Color(0.2, 0.3, 0.2)) },
    },
  })
  -- Glass: no absorption (POV-Ray applies it differently, pov-mapping.md item 5).
  s:add_entity(Sphere(Translate(Vector(0, 1, -0.5))) {
    texture = Texture() {
      pigment = ColorPigment(Color(0.9, 1, 0.9)),
      finish = Finish() { diffuse = 0.05, specular = 0.9, exponent = 80,
                          refraction = 0.9, refraction_index = 1.5, absorption = 0 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(-2.4, 1, 0.8))) {
    texture = Texture() {
      pigment = ColorPigment(grey(0.1)),
      finish = Finish() { diffuse = 0.1, specular = 0.8, exponent = 60, reflection = 0.8 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(2.4, 1, 0.8))) {
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.5, 0.1)), finish = Finish() { diffuse = 0.8 } },
  })
  s:add_entity(Cube(Translate(Vector(0.6, 0.4, 2.5)) * Rotate(y, 20) * Scale(0.8)) {
    texture = Texture() { pigment = ColorPigment(Color(0.7, 0.2, 0.6)) },
  })
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -6)) })
  return s
end
