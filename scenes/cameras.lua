-- The camera kinds (lua/README.md, "Perspective", "Orthographic",
-- "Spherical"), one per frame, on one scene: a row of spheres running away
-- from the viewer over a checkered floor.
--   frame 0: Perspective, a pinhole: everything sharp
--   frame 1: Perspective with a thin lens (aperture 0.3) focused on the
--            third sphere: nearer and farther ones blur
--   frame 2: Orthographic, 14 units wide, from high up: no perspective,
--            the far spheres as large as the near ones
--   frame 3: Spherical: the whole surroundings, longitude across the image
-- Every frame is 2:1, the shape a spherical panorama needs.
scene_info = SceneInfo() { image_width = 640, image_height = 320, frames = 4, samples = 4 }

local target = Vector(0.7, 0.6, 5.5) -- the third sphere's centre
local eye = LookAt(Vector(-1, 1.5, -5), target, y)

local function camera(frame)
  if frame == 0 then
    return Perspective(50, 2) { transform = eye }
  elseif frame == 1 then
    -- the eye looks at the third sphere: focus at its distance
    return Perspective(50, 2) { transform = eye, aperture = 0.3,
                                     focal_distance = math.sqrt(1.7 ^ 2 + 0.9 ^ 2 + 10.5 ^ 2) }
  elseif frame == 2 then
    return Orthographic(14, 2) { transform = LookAt(Vector(-8, 10, -6), target, y) }
  end
  return Spherical() { transform = Translate(Vector(1.6, 1.0, 3.0)) }
end

function scene(clock)
  local frame = math.floor(clock * 3 + 0.5)
  local s = Scene() { background_color = Color(0.55, 0.7, 0.9), camera = camera(frame) }
  s:add_entity(Floor() {
    texture = Texture() { pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.85)),
                                                         pigment2 = ColorPigment(grey(0.35)) } } })
  local hues = { Color(0.9, 0.25, 0.2), Color(0.95, 0.6, 0.15), Color(0.3, 0.75, 0.3),
                 Color(0.2, 0.5, 0.9), Color(0.6, 0.3, 0.8) }
  for i = 1, 5 do
    s:add_entity(Sphere(Translate(Vector(-2.6 + 1.1 * i, 0.6, -2 + 2.5 * i)) * Scale(0.6)) {
      texture = Texture() { pigment = ColorPigment(hues[i]),
                            finish = Finish() { specular = 0.6, exponent = 40, reflection = 0.1 } } })
  end
  s:add_light(Light() { transform = Translate(Vector(-4, 8, -3)) })
  return s
end
