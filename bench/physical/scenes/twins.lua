-- What bench/physical's LRay scenes share (each loads it with dofile): the
-- finishes that have a twin in the peers (bench/physical/README.md maps
-- each) and two triangles over four corners.
local M = {}

-- Pigment albedo, diffuse 1: a Lambertian surface, nothing else.
function M.matte(albedo)
  return Texture() { pigment = ColorPigment(albedo),
                     finish = Finish() { ambient = grey(0), diffuse = 1, specular = 0 } }
end

-- Radiance leaving the side the normal points to, and nothing reflected.
function M.emitter(radiance)
  return Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0, emission = radiance } }
end

-- A GGX mirror of roughness alpha, no Fresnel.
function M.rough_mirror(alpha)
  return Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                         reflection = 1, roughness = alpha } }
end

-- Smooth glass of index ior with Fresnel, no absorption.
function M.glass(ior)
  return Texture() { finish = Finish() { ambient = grey(0), diffuse = 0, specular = 0,
                                         reflection = 1, refraction = 1, refraction_index = ior,
                                         absorption = 0, fresnel = true } }
end

-- Two triangles over four corners in order round the square; the face
-- normal (p2 - p1) x (p3 - p1) is turned to point along `facing`.
function M.quad(p, facing, texture)
  local e1 = { p[2][1] - p[1][1], p[2][2] - p[1][2], p[2][3] - p[1][3] }
  local e2 = { p[3][1] - p[1][1], p[3][2] - p[1][2], p[3][3] - p[1][3] }
  local n = { e1[2] * e2[3] - e1[3] * e2[2], e1[3] * e2[1] - e1[1] * e2[3], e1[1] * e2[2] - e1[2] * e2[1] }
  local along = n[1] * facing[1] + n[2] * facing[2] + n[3] * facing[3] > 0
  return Mesh() { vertices = p, indices = along and { { 1, 2, 3 }, { 1, 3, 4 } } or { { 1, 3, 2 }, { 1, 4, 3 } },
                  texture = texture }
end

return M
