// time_vs_error bench scene "arealight", POV-Ray 3.7 twin of arealight.lua.
#version 3.7;
#include "lray.inc"

background { rgb <0.05, 0.05, 0.1> }
LRayCamera(<0, 3.5, -8>, <0, 0.8, 0>, 45, 16 / 9)

LRayCheckerFloor(rgb 0.9, rgb 0.4)
sphere { 0, 1
  texture { pigment { rgb <0.9, 0.2, 0.2> } finish { phong 0.5 phong_size 30 } }
  translate <-1.5, 1, 0>
}
box { -0.5, 0.5
  texture { pigment { rgb <0.2, 0.4, 0.9> } }
  scale 1.5 rotate y * 30 translate <1.2, 0.75, 0.5>
}
cylinder { 0, y, 1
  texture { pigment { rgb <0.3, 0.8, 0.3> } }
  scale <0.5, 1.2, 0.5> translate <0.2, 0, -1.6>
}
LRayAreaLight(<-5, 8, -4>, rgb 1, 2, 2, 8, 8)
