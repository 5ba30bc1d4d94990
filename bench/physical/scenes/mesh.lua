-- bench/physical: a 200,000-triangle rippled torus (flat-shaded) on a
-- floor, lit only by an emitting sphere and an emitting square. The torus
-- is made here as twins.bumpy_torus makes it for the peers (same formula).
-- Its peers' twin: mesh.py.
scene_info = SceneInfo() { image_width = 160, image_height = 120, integrator = "path", max_depth = 8 }

local T = dofile("twins.lua")
local matte, emitter, rough_mirror, glass, quad = T.matte, T.emitter, T.rough_mirror, T.glass, T.quad

-- rings x sides quads about the y axis, the tube's radius rippled by
-- bump * sin(7u) * sin(5v); faces turned so that their normals point out.
local function bumpy_torus(rings, sides, major, minor, bump)
  local vertices, indices = {}, {}
  for i = 0, rings - 1 do
    local u = i * (2 * math.pi / rings)
    for j = 0, sides - 1 do
      local v = j * (2 * math.pi / sides)
      local r = minor + bump * math.sin(7 * u) * math.sin(5 * v)
      vertices[#vertices + 1] = { (major + r * math.cos(v)) * math.cos(u), r * math.sin(v),
                                  (major + r * math.cos(v)) * math.sin(u) }
    end
  end
  local function index(i, j) return (i % rings) * sides + (j % sides) + 1 end
  local second = {}
  for i = 0, rings - 1 do
    for j = 0, sides - 1 do
      local a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
      indices[#indices + 1] = { a, b, c }
      second[#second + 1] = { a, c, d }
    end
  end
  for _, f in ipairs(second) do indices[#indices + 1] = f end
  -- Outward: the first face's normal against the tube's outward direction.
  local f = indices[1]
  local p1, p2, p3 = vertices[f[1]], vertices[f[2]], vertices[f[3]]
  local e1 = { p2[1] - p1[1], p2[2] - p1[2], p2[3] - p1[3] }
  local e2 = { p3[1] - p1[1], p3[2] - p1[2], p3[3] - p1[3] }
  local n = { e1[2] * e2[3] - e1[3] * e2[2], e1[3] * e2[1] - e1[1] * e2[3], e1[1] * e2[2] - e1[2] * e2[1] }
  local out = { (p1[1] + p2[1] + p3[1]) / 3 - major, (p1[2] + p2[2] + p3[2]) / 3, (p1[3] + p2[3] + p3[3]) / 3 }
  if n[1] * out[1] + n[2] * out[2] + n[3] * out[3] < 0 then
    for _, face in ipairs(indices) do face[2], face[3] = face[3], face[2] end
  end
  return vertices, indices
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0, 0, 0),
    camera = Perspective(45, 4 / 3) { transform = LookAt(Vector(0, 2.6, -4), Vector(0, 0.3, 0), y) },
  }
  s:add_entity(Mesh() { vertices = { { -5, 0, -4 }, { -5, 0, 5 }, { 5, 0, 5 }, { 5, 0, -4 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = matte(grey(0.5)) })
  local vertices, indices = bumpy_torus(400, 250, 1.0, 0.35, 0.06)
  s:add_entity(Mesh(Translate(Vector(0, 0.45, 0))) { vertices = vertices, indices = indices,
                                                     texture = matte(Color(0.7, 0.55, 0.4)) })
  s:add_entity(Sphere(Translate(Vector(-1.5, 2.5, -1)) * Scale(0.3)) { texture = emitter(Color(20, 15, 10)) })
  -- A 1 x 1 square at y = 3 facing down.
  s:add_entity(Mesh() { vertices = { { 0.5, 3, 0 }, { 1.5, 3, 0 }, { 1.5, 3, 1 }, { 0.5, 3, 1 } },
                        indices = { { 1, 2, 3 }, { 1, 3, 4 } }, texture = emitter(Color(6, 8, 12)) })
  return s
end
