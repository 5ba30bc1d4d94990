-- time_vs_error bench scene "spheres16k": a 160 x 100 grid of 16,000 small
-- spheres on a wavy height field over a checker floor, under a 4 x 4
-- jittered area light (many small objects: traversal and soft shadows).
-- POV-Ray twin: spheres16k.pov (the same loop as a #while).
scene_info = SceneInfo() { image_width = 320, image_height = 180 }

local NX, NZ = 160, 100

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 6, -7), Vector(0, 0, 2), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.8)), pigment2 = ColorPigment(grey(0.35)) },
    },
  })
  local finish = Finish() { specular = 0.4, exponent = 20 }
  for i = 0, NX - 1 do
    for j = 0, NZ - 1 do
      local px = (i - (NX - 1) / 2) * 0.1
      local pz = (j - (NZ - 1) / 2) * 0.1 + 2
      local py = 0.3 + 0.25 * math.sin(0.3 * i) * math.cos(0.4 * j)
      local c = Color(0.5 + 0.4 * math.sin(0.1 * i), 0.5 + 0.4 * math.sin(0.13 * j + 1), 0.5 + 0.4 * math.cos(0.07 * (i + j)))
      s:add_entity(Sphere(Translate(Vector(px, py, pz)) * Scale(0.045)) {
        texture = Texture() { pigment = ColorPigment(c), finish = finish },
      })
    end
  end
  s:add_light(Light() { rows = 4, cols = 4, area = true,
                        transform = Translate(Vector(-4, 9, -5)) * Scale(3, 1, 3) })
  return s
end
