-- time_vs_error bench scene "pigments": the 3-D and image pigments, one per
-- sphere (CheckerPigment3D, MarblePigment3D, WoodPigment3D, ImagePigment2D
-- with texture.png), on a plain floor under a point light. POV-Ray twin:
-- pigments.pov (marble and wood only approximate: POV's noise differs,
-- ../shared/pov-mapping.md).
scene_info = SceneInfo() { image_width = 320, image_height = 180 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 3.2, -11), Vector(0, 0.8, 0), y) },
  }
  s:add_entity(Floor() { texture = Texture() { pigment = ColorPigment(grey(0.7)) } })
  s:add_entity(Sphere(Translate(Vector(-3.3, 1, 0))) {
    texture = Texture() {
      pigment = CheckerPigment3D() {
        pigment1 = ColorPigment(Color(0.9, 0.1, 0.1)),
        pigment2 = ColorPigment(Color(0.95, 0.95, 0.8)),
        texture_map = LinearMap() { transform = Scale(3) },
      },
    },
  })
  s:add_entity(Sphere(Translate(Vector(-1.1, 1, 0))) {
    texture = Texture() {
      pigment = MarblePigment3D() { color1 = Color(0.1, 0.1, 0.3), color2 = Color(0.9, 0.9, 0.95) },
      finish = Finish() { specular = 0.6, exponent = 40 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(1.1, 1, 0))) {
    texture = Texture() {
      pigment = WoodPigment3D() {
        color1 = Color(0.45, 0.25, 0.1), color2 = Color(0.8, 0.6, 0.35),
        frequency = Vector(40, 40, 40), power = 1, size = 0.3,
      },
    },
  })
  s:add_entity(Sphere(Translate(Vector(3.3, 1, 0)) * Rotate(y, 30)) {
    texture = Texture() { pigment = ImagePigment2D("texture.png") },
  })
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -5)) })
  return s
end
