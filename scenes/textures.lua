-- Figure 6 of the LRay paper: CheckerPigment3D, MarblePigment3D and
-- WoodPigment3D spheres on a CheckerPigment2D floor.
scene_info = SceneInfo() { image_width = 640, image_height = 480 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 3.2, -9.5), Vector(0, 0.9, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(white), pigment2 = ColorPigment(grey(0.25)) },
    },
  })
  s:add_entity(Sphere(Translate(Vector(-2.4, 1, 0))) {
    texture = Texture() {
      pigment = CheckerPigment3D() {
        pigment1 = ColorPigment(Color(0.9, 0.1, 0.1)),
        pigment2 = ColorPigment(Color(0.95, 0.95, 0.8)),
        texture_map = LinearMap() { transform = Scale(3) },
      },
    },
  })
  s:add_entity(Sphere(Translate(Vector(0, 1, 0))) {
    texture = Texture() {
      pigment = MarblePigment3D() { color1 = Color(0.1, 0.1, 0.3), color2 = Color(0.9, 0.9, 0.95) },
      finish = Finish() { specular = 0.6, exponent = 40 },
    },
  })
  s:add_entity(Sphere(Translate(Vector(2.4, 1, 0))) {
    texture = Texture() {
      pigment = WoodPigment3D() {
        color1 = Color(0.45, 0.25, 0.1), color2 = Color(0.8, 0.6, 0.35),
        period = Vector(40, 40, 40), power = 1, size = 0.3,
      },
    },
  })
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -5)) })
  return s
end
