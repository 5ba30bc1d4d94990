-- bench/motion: what motion blur costs when much of a scene moves. 900
-- spheres drift and 900 cubes spin over a 20,000-triangle cloth whose
-- vertices wave; the camera and light stay. With shutter 0 the same frame
-- renders sharp (the baseline of bench/motion/motion_cost.py).
scene_info = SceneInfo() { image_width = 640, image_height = 360, samples = 4, shutter = 0.5 }

local function cloth(clock)
  local n = 100
  local vertices, indices = {}, {}
  for j = 0, n do
    for i = 0, n do
      local x, z = -10 + 20 * i / n, -2 + 20 * j / n
      vertices[#vertices + 1] = { x, 0.3 * math.sin(0.8 * x + 4 * clock) * math.cos(0.5 * z), z }
    end
  end
  for j = 0, n - 1 do
    for i = 0, n - 1 do
      local a = j * (n + 1) + i + 1
      indices[#indices + 1] = { a, a + n + 1, a + 1 }
      indices[#indices + 1] = { a + 1, a + n + 1, a + n + 2 }
    end
  end
  return Mesh() { vertices = vertices, indices = indices, smooth = true,
                  texture = Texture() { pigment = ColorPigment(grey(0.7)) } }
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0.5, 0.6, 0.8),
    camera = Perspective(50, 16 / 9) { transform = LookAt(Vector(0, 6, -9), Vector(0, 0, 6), y) },
  }
  s:add_entity(cloth(clock))
  for j = 0, 29 do
    for i = 0, 29 do
      local x, z = -9 + 0.62 * i, -1 + 0.62 * j
      if (i + j) % 2 == 0 then
        s:add_entity(Sphere(Translate(Vector(x + 0.6 * clock * math.sin(i), 0.8, z)) * Scale(0.2)) {
          texture = Texture() { pigment = ColorPigment(Color(0.9, 0.3, 0.2)) } })
      else
        s:add_entity(Cube(Translate(Vector(x, 0.8, z)) * Rotate(y, 120 * clock + 7 * j) * Scale(0.3)) {
          texture = Texture() { pigment = ColorPigment(Color(0.2, 0.4, 0.9)) } })
      end
    end
  end
  s:add_light(Light() { transform = Translate(Vector(-5, 10, -5)) })
  return s
end
