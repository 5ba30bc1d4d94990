-- time_vs_error bench scene "mesh200k": a bumpy torus as one smooth
-- 200,000-triangle mesh (500 x 200 quads), tilted over a checker floor,
-- under a point light and a 2 x 2 area light. POV-Ray twin: mesh200k.pov,
-- whose mesh2 (mesh200k_mesh.inc) the runner writes from the same formula
-- (bench/time_vs_error/run.py: torus_vertex).
scene_info = SceneInfo() { image_width = 320, image_height = 180 }

local NU, NV = 500, 200       -- quads around the ring and around the tube
local MAJOR, MINOR = 1.3, 0.45

local function vertex(i, j)
  local u, v = 2 * math.pi * i / NU, 2 * math.pi * j / NV
  local r = MINOR * (1 + 0.12 * math.sin(9 * u) * math.cos(4 * v))
  local w = MAJOR + r * math.cos(v)
  return { w * math.cos(u), r * math.sin(v), w * math.sin(u) }
end

-- Built once at the top level; vertex (i, j) is number i * NV + j + 1.
local vertices, indices = {}, {}
for i = 0, NU - 1 do
  for j = 0, NV - 1 do
    vertices[#vertices + 1] = vertex(i, j)
  end
end
for i = 0, NU - 1 do
  local i1 = (i + 1) % NU
  for j = 0, NV - 1 do
    local j1 = (j + 1) % NV
    local a, b = i * NV + j + 1, i1 * NV + j + 1
    local c, d = i1 * NV + j1 + 1, i * NV + j1 + 1
    indices[#indices + 1] = { a, d, c }
    indices[#indices + 1] = { a, c, b }
  end
end
local torus = Mesh() { vertices = vertices, indices = indices, smooth = true }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 16 / 9) { transform = LookAt(Vector(0, 3.5, -9), Vector(0, 1.4, 0), y) },
  }
  s:add_entity(Floor() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.85)), pigment2 = ColorPigment(grey(0.4)) },
    },
  })
  torus.transform = Translate(Vector(0, 1.75, 0.5)) * Rotate(x, -60)
  torus.texture = Texture() {
    pigment = ColorPigment(Color(0.85, 0.6, 0.2)),
    finish = Finish() { diffuse = 0.7, specular = 0.6, exponent = 40 },
  }
  s:add_entity(torus)
  s:add_light(Light() { color = grey(0.7), transform = Translate(Vector(-4, 7, -5)) })
  s:add_light(Light() { color = grey(0.4), rows = 2, cols = 2, area = true,
                        transform = Translate(Vector(5, 6, -3)) * Scale(2, 1, 2) })
  return s
end
