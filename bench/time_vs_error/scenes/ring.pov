// time_vs_error bench scene "ring", POV-Ray 3.7 twin of ring.lua. Rendered
// as frame F of 20 with +KFI0 +KFF19 +KI0 +KF1 +SF<F> +EF<F>, so that clock
// = F / 19 as in LRay.
#version 3.7;
#include "lray.inc"

background { rgb 0 }
camera {
  perspective location 0 right x * 16 / 9 up y angle 45
  translate -5 * z rotate y * 360 * clock
}
#declare I = 1;
#while (I <= 20)
  sphere { 0, 1 scale 0.1 translate x rotate z * (I / 20) * 360 }
  #declare I = I + 1;
#end
LRayPointLight(x - 3 * z, rgb 1)
