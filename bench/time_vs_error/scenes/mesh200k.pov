// time_vs_error bench scene "mesh200k", POV-Ray 3.7 twin of mesh200k.lua.
// mesh200k_mesh.inc (#declare Torus = mesh2 {...}) is written by the runner
// from the Lua file's formula.
#version 3.7;
#include "lray.inc"
#include "mesh200k_mesh.inc"

background { rgb <0.05, 0.05, 0.1> }
LRayCamera(<0, 3.5, -9>, <0, 1.4, 0>, 45, 16 / 9)

LRayCheckerFloor(rgb 0.85, rgb 0.4)
object { Torus
  texture { pigment { rgb <0.85, 0.6, 0.2> } finish { diffuse 0.7 phong 0.6 phong_size 40 } }
  rotate x * -60 translate <0, 1.75, 0.5>
}
LRayPointLight(<-4, 7, -5>, rgb 0.7)
LRayAreaLight(<5, 6, -3>, rgb 0.4, 2, 2, 2, 2)
