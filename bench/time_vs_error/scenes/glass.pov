// time_vs_error bench scene "glass", POV-Ray 3.7 twin of glass.lua.
#version 3.7;
#include "lray.inc"

background { rgb <0.3, 0.45, 0.7> }
LRayCamera(<0, 2.5, -8>, <0, 1, 0>, 45, 16 / 9)

LRayCheckerFloor(rgb 0.9, rgb <0.2, 0.3, 0.2>)
// refraction 0.9 = transmit 0.9; POV scales ambient and diffuse by the
// opacity 0.1, so they are given x10.
sphere { 0, 1
  texture {
    pigment { rgbt <0.9, 1, 0.9, 0.9> }
    finish { ambient 0.02 / 0.1 diffuse 0.05 / 0.1 phong 0.9 phong_size 80 }
  }
  interior { ior 1.5 }
  translate <0, 1, -0.5>
}
// LRay's refracting objects cast full shadows: an opaque twin that only
// shadow rays see.
sphere { 0, 0.999 pigment { rgb 0 } no_image no_reflection translate <0, 1, -0.5> }
sphere { 0, 1
  texture { pigment { rgb 0.1 } finish { diffuse 0.1 phong 0.8 phong_size 60 reflection 0.8 } }
  translate <-2.4, 1, 0.8>
}
sphere { 0, 1
  texture { pigment { rgb <0.9, 0.5, 0.1> } finish { diffuse 0.8 } }
  translate <2.4, 1, 0.8>
}
box { -0.5, 0.5
  texture { pigment { rgb <0.7, 0.2, 0.6> } }
  scale 0.8 rotate y * 20 translate <0.6, 0.4, 2.5>
}
LRayPointLight(<-5, 8, -6>, rgb 1)
