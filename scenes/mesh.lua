-- Meshes: an OBJ model loaded natively with mesh_from_obj, drawn three
-- times with copy() (one shared set of arrays, rendered as instances), and a
-- smooth hand-written mesh.
scene_info = SceneInfo() { image_width = 640, image_height = 480 }

local pyramid = mesh_from_obj("models/pyramid.obj") -- loaded once, reused every frame

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 4, -9), Vector(0, 0.7, 0), y) },
  }
  s:add_entity(Floor() { texture = Texture() { pigment = ColorPigment(grey(0.8)) } })
  local colours = { Color(0.9, 0.3, 0.2), Color(0.3, 0.8, 0.3), Color(0.3, 0.4, 0.9) }
  for i = 1, 3 do
    s:add_entity(pyramid:copy() {
      transform = Translate(Vector(3 * (i - 2), 0, 1.5)) * Rotate(y, 20 * i),
      texture = Texture() { pigment = ColorPigment(colours[i]) },
    })
  end
  -- An octahedron with shared vertices; smooth shading interpolates normals.
  s:add_entity(Mesh(Translate(Vector(1.5, 0.8, -1.8)) * Scale(0.8)) {
    vertices = { {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1} },
    indices = { {1, 3, 5}, {5, 3, 2}, {2, 3, 6}, {6, 3, 1}, {1, 5, 4}, {5, 2, 4}, {2, 6, 4}, {6, 1, 4} },
    smooth = true,
    texture = Texture() { pigment = ColorPigment(Color(0.9, 0.8, 0.3)), finish = Finish() { specular = 0.5, exponent = 30 } },
  })
  s:add_light(Light() { transform = Translate(Vector(-5, 8, -6)) })
  return s
end
