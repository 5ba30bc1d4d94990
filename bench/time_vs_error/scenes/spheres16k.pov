// time_vs_error bench scene "spheres16k", POV-Ray 3.7 twin of spheres16k.lua.
#version 3.7;
#include "lray.inc"

#declare NX = 160;
#declare NZ = 100;

background { rgb <0.05, 0.05, 0.1> }
LRayCamera(<0, 6, -7>, <0, 0, 2>, 45, 16 / 9)

LRayCheckerFloor(rgb 0.8, rgb 0.35)
#declare I = 0;
#while (I < NX)
  #declare J = 0;
  #while (J < NZ)
    sphere { 0, 1
      texture {
        pigment { rgb <0.5 + 0.4 * sin(0.1 * I), 0.5 + 0.4 * sin(0.13 * J + 1), 0.5 + 0.4 * cos(0.07 * (I + J))> }
        finish { phong 0.4 phong_size 20 }
      }
      scale 0.045
      translate <(I - (NX - 1) / 2) * 0.1, 0.3 + 0.25 * sin(0.3 * I) * cos(0.4 * J), (J - (NZ - 1) / 2) * 0.1 + 2>
    }
    #declare J = J + 1;
  #end
  #declare I = I + 1;
#end
LRayAreaLight(<-4, 9, -5>, rgb 1, 3, 3, 4, 4)
