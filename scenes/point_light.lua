-- Figure 3 of the LRay paper: a small scene lit by a point light (sharp
-- shadows). area_light.lua is the same scene under a 10 x 10 area light.
scene_info = SceneInfo() { image_width = 640, image_height = 480 }

local function objects(s)
  local floor_texture = Texture() {
    pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)), pigment2 = ColorPigment(grey(0.4)) },
  }
  s:add_entity(Floor() { texture = floor_texture })
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
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 3.5, -8), Vector(0, 0.8, 0), y) },
  }
  objects(s)
  -- Up and to the left, so the shadows fall to the right.
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -4)) })
  return s
end
