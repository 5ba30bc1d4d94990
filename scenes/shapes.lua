-- Figure 2 of the LRay paper: the four primitive shapes in their default
-- sizes (moved apart), standing on a Floor mesh.
scene_info = SceneInfo() { image_width = 640, image_height = 480 }

local function solid(c)
  return Texture() { pigment = ColorPigment(c), finish = Finish() { specular = 0.3, exponent = 20 } }
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 4.5, -12), Vector(0, 0.6, 0), y) },
  }
  s:add_entity(Floor() { texture = solid(grey(0.8)) })
  -- Sphere and Cube are centred on the origin: lift them onto the floor.
  s:add_entity(Sphere(Translate(Vector(-3.3, 1, 0))) { texture = solid(Color(0.9, 0.3, 0.3)) })
  s:add_entity(Cylinder(Translate(Vector(-1.1, 0, 0))) { texture = solid(Color(0.3, 0.9, 0.3)) })
  s:add_entity(Cone(Translate(Vector(1.1, 0, 0))) { texture = solid(Color(0.3, 0.4, 0.9)) })
  s:add_entity(Cube(Translate(Vector(3.3, 0.5, 0))) { texture = solid(Color(0.9, 0.8, 0.3)) })
  s:add_light(Light() { transform = Translate(Vector(-6, 10, -6)) })
  return s
end
