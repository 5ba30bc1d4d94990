-- CSG: the classic tree (a cube intersected with a sphere, minus three
-- cylinders along the axes), a glass Merge of two spheres (no inner
-- surface: refraction sees one solid) and a bowl carved from a Difference
-- of spheres and cut flat by a Plane, on a checkered floor.
scene_info = SceneInfo() { image_width = 640, image_height = 400, samples = 2 }

local function matte(color, specular)
  return Texture() {
    pigment = ColorPigment(color),
    finish = Finish() { specular = specular or 0.4, exponent = 30, ambient = grey(0.06) },
  }
end

-- A cylinder of radius r, 3 long, centred on the origin along the y axis
-- turned by `turn`.
local function rod(r, turn)
  return Cylinder(turn * Scale(r, 3, r) * Translate(Vector(0, -0.5, 0)))
end

function scene(clock)
  local s = Scene() {
    background_color = Color(0.55, 0.65, 0.8),
    camera = Perspective(40, 640 / 400) { transform = LookAt(Vector(0.4, 3.2, -7.5), Vector(0, 0.7, 0), y) },
  }
  s:add_entity(Plane() {
    texture = Texture() {
      pigment = CheckerPigment2D() { pigment1 = ColorPigment(grey(0.9)), pigment2 = ColorPigment(grey(0.35)),
                                     texture_map = UVMap() { scale_s = 0.5, scale_t = 0.5 } },
      finish = Finish() { ambient = grey(0.1) },
    },
  })

  -- The classic: (cube and sphere) minus (three rods), turned to show it.
  local rods = Union { rod(0.42, Identity()), rod(0.42, Rotate(x, 90)), rod(0.42, Rotate(z, 90)) }
  s:add_entity(Difference {
    Intersection {
      Cube() { texture = matte(Color(0.85, 0.15, 0.1)) },
      Sphere(Scale(0.68, 0.68, 0.68)) { texture = matte(Color(0.15, 0.3, 0.85)) },
    },
    rods,
    texture = matte(Color(0.2, 0.7, 0.3)),
    transform = Translate(Vector(-2.1, 0.9, 0.3)) * Rotate(y, 30) * Rotate(x, -20) * Scale(1.5, 1.5, 1.5),
  })

  -- Glass: two overlapping spheres merged, so the light bends at the outer
  -- surface only.
  local glass = Texture() {
    pigment = ColorPigment(Color(0.95, 0.97, 1)),
    finish = Finish() { ambient = grey(0), diffuse = 0.05, specular = 0.8, exponent = 120,
                        reflection = 0.08, refraction = 0.9, refraction_index = 1.5, absorption = 0.1 },
  }
  s:add_entity(Merge {
    Sphere(Translate(Vector(-0.35, 0, 0)) * Scale(0.7, 0.7, 0.7)),
    Sphere(Translate(Vector(0.35, 0, 0)) * Scale(0.7, 0.7, 0.7)),
    texture = glass,
    transform = Translate(Vector(0.3, 0.7, -1.2)) * Rotate(y, -25),
  })

  -- A bowl: a sphere minus a smaller one, cut flat at the rim by a Plane.
  s:add_entity(Intersection {
    Difference {
      Sphere(),
      Sphere(Scale(0.9, 0.9, 0.9)) { texture = matte(Color(0.95, 0.85, 0.3), 0.2) },
    },
    Plane(Translate(Vector(0, 0.35, 0))),
    texture = matte(Color(0.3, 0.5, 0.85), 0.6),
    transform = Translate(Vector(2.2, 1, 0.8)) * Rotate(x, -25),
  })

  s:add_light(Light() { transform = Translate(Vector(-5, 9, -7)), color = grey(0.9) })
  s:add_light(Light() { transform = Translate(Vector(6, 4, -6)), color = grey(0.35) })
  return s
end
