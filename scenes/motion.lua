-- Motion blur and depth of field (lua/README.md, "Motion blur"): a wheel
-- spins fast as it drifts to the right, a ball drifts the other way
-- behind it. The shutter stays open for half of each frame's interval:
-- the spokes sweep into a fan (a turn is interpolated as a turn, so the
-- spinning rim keeps its size), the rim, hub and ball smear a little along
-- their paths. The camera's thin lens pulls focus from the wheel (frame 0)
-- to the ball (frame 1).
scene_info = SceneInfo() { image_width = 640, image_height = 320, frames = 2, samples = 5,
                           shutter = 0.5, motion_steps = 3 }

local radius = 1
local eye = Vector(0, 1.8, -7)

local function solid(c, specular)
  return Texture() { pigment = ColorPigment(c),
                     finish = Finish() { specular = specular or 0.4, exponent = 30 } }
end

-- The wheel at `clock`: 90 degrees a clock unit (clockwise seen from the
-- camera) about its axle, which moves 0.3 to the right.
local function wheel(s, clock)
  local place = Translate(Vector(-1.6 + 0.3 * clock, radius + 0.05, 0)) * Rotate(z, -90 * clock)
  s:add_entity(Torus(place * Rotate(x, 90)) { major = radius - 0.1, minor = 0.1,
                                               texture = solid(grey(0.15), 0.2) })
  for i = 0, 2 do
    -- a spoke: a thin cylinder through the hub, turned by a third of a half turn each
    s:add_entity(Cylinder(place * Rotate(z, 60 * i) * Translate(Vector(0, -0.85, 0)) *
                          Scale(0.05, 1.7, 0.05)) { texture = solid(Color(0.9, 0.75, 0.2)) })
  end
  s:add_entity(Sphere(place * Scale(0.16)) { texture = solid(Color(0.85, 0.2, 0.15)) })
end

function scene(clock)
  local frame = math.floor(clock + 0.5)
  local ballAt = Vector(2.2 - 0.8 * clock, 1.0 + 0.6 * clock, 5)
  -- Focus on the wheel's hub, then on the ball (distances along the view axis
  -- are close to these straight-line ones at the image centre).
  local focus = frame == 0 and 7.0 or 12.0
  local s = Scene() {
    background_color = Color(0.55, 0.7, 0.9),
    camera = Perspective(40, 2) { transform = LookAt(eye, Vector(0, 1.1, 2), y),
                                  aperture = 0.12, focal_distance = focus },
  }
  s:add_entity(Floor() {
    texture = Texture() { pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.85)),
                                                         pigment2 = ColorPigment(grey(0.4)) } } })
  wheel(s, clock)
  s:add_entity(Sphere(Translate(ballAt) * Scale(0.5)) { texture = solid(Color(0.2, 0.45, 0.9), 0.6) })
  s:add_light(Light() { rows = 3, cols = 3, area = true,
                        transform = Translate(Vector(-4, 9, -4)) * Scale(2, 1, 2) })
  return s
end
