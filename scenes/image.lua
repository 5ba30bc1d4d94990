-- Figure 5 of the LRay paper: ImagePigment2D. texture.png (made by
-- make_texture.sh) wrapped around a sphere and repeated on a cube's faces.
scene_info = SceneInfo() { image_width = 640, image_height = 480 }

function scene(clock)
  local s = Scene() {
    background_color = Color(0.05, 0.05, 0.1),
    camera = Perspective(45, 640 / 480) { transform = LookAt(Vector(0, 2.5, -7), Vector(0, 1, 0), y) },
  }
  local image = ImagePigment2D("texture.png")
  s:add_entity(Floor() { texture = Texture() { pigment = ColorPigment(grey(0.7)) } })
  s:add_entity(Sphere(Translate(Vector(-1.3, 1, 0)) * Rotate(y, 30 + 360 * clock)) {
    texture = Texture() { pigment = image },
  })
  s:add_entity(Cube(Translate(Vector(1.4, 0.8, 0)) * Rotate(y, -25) * Scale(1.6)) {
    texture = Texture() {
      pigment = ImagePigment2D("texture.png") { texture_map = UVMap() { scale_s = 2, scale_t = 2 } },
    },
  })
  s:add_light(Light() { transform = Translate(Vector(-4, 7, -6)) })
  return s
end
