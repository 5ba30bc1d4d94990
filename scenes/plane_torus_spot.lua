-- Plane, Torus and SpotLight: two tori on an infinite checkered plane, lit
-- by a spot aimed at them (its soft-edged pool of light on the plane) and a
-- dim fill light; the far plane runs out to the horizon.
scene_info = SceneInfo() { image_width = 640, image_height = 480, samples = 2 }

local function shiny(pigment)
  return Texture() { pigment = pigment, finish = Finish() { specular = 0.5, exponent = 40 } }
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0.02, 0.02, 0.05),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 4, -9), Vector(0, 0.6, 0), y) },
  }
  s:add_entity(Plane() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.85)), pigment2 = ColorPigment(grey(0.25)),
                                     texture_map = UVMap() { scale_s = 0.5, scale_t = 0.5 } },
      finish = Finish() { ambient = grey(0.08) },
    },
  })
  -- A torus lying on the plane (its tube is 0.4 thick) and one standing up.
  s:add_entity(Torus(Translate(Vector(-1.4, 0.4, 0.3))) { minor = 0.4, texture = shiny(ColorPigment(Color(0.9, 0.25, 0.2))) })
  s:add_entity(Torus(Translate(Vector(1.5, 1.2, 0)) * Rotate(y, -30) * Rotate(x, 90)) {
    major = 0.9, minor = 0.3,
    texture = shiny(CheckerPigment2D() { texture_map = UVMap() { scale_s = 12, scale_t = 4 },
                                         pigment1 = ColorPigment(Color(0.25, 0.35, 0.9)), pigment2 = ColorPigment(white) }),
  })
  s:add_light(SpotLight() { transform = LookAt(Vector(-1, 8, -3), Vector(0, 0, 0.5), y), angle = 20, falloff = 27 })
  s:add_light(Light() { color = grey(0.12), transform = Translate(Vector(6, 5, -8)) })
  return s
end
