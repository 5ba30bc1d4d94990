// time_vs_error bench scene "pigments", POV-Ray 3.7 twin of pigments.lua.
// Checker and image map the same; marble and wood have the same stripe
// direction, period, colours and |sin| profile but POV's own noise and
// turbulence (pov-mapping.md, "Noise").
#version 3.7;
#include "lray.inc"
#include "transforms.inc"

background { rgb <0.05, 0.05, 0.1> }
LRayCamera(<0, 3.2, -11>, <0, 0.8, 0>, 45, 16 / 9)

LRayFloor(texture { pigment { rgb 0.7 } })
// CheckerPigment3D + LinearMap { transform = Scale(3) }: the pattern scaled 1/3.
sphere { 0, 1
  texture { pigment { checker color rgb <0.9, 0.1, 0.1> color rgb <0.95, 0.95, 0.8> scale 1 / 3 } }
  translate <-3.3, 1, 0>
}
// Marble, frequency (5, 5, 5): |sin(5 (x + y + z) + 2 turb)|. scallop_wave is
// |sin(pi v)|, so the ramp along x is scaled by pi / |f| and turned onto f.
#declare MarbleF = <5, 5, 5>;
sphere { 0, 1
  texture {
    pigment {
      marble scallop_wave
      turbulence 0.6 octaves 3 omega 0.5 lambda 2
      color_map { [0 rgb <0.9, 0.9, 0.95>] [1 rgb <0.1, 0.1, 0.3>] }
      scale pi / vlength(MarbleF)
      Reorient_Trans(x, MarbleF)
    }
    finish { phong 0.6 phong_size 40 }
  }
  translate <-1.1, 1, 0>
}
// Wood, frequency (40, 40, 40), power 1, size 0.3: |sin(sqrt(40) r + turb)|,
// rings about z.
sphere { 0, 1
  texture {
    pigment {
      wood scallop_wave
      turbulence 0.1 octaves 2 omega 0.5 lambda 2
      color_map { [0 rgb <0.8, 0.6, 0.35>] [1 rgb <0.45, 0.25, 0.1>] }
      scale pi / sqrt(40)
    }
  }
  translate <1.1, 1, 0>
}
// ImagePigment2D on a sphere: u = (atan2(z, x) + pi) / 2 pi, v = (y + 1) / 2.
sphere { 0, 1
  texture {
    pigment {
      image_map { png "texture.png" map_type 2 interpolate 2 }
      rotate y * 180 scale <1, 2, 1> translate -y
    }
  }
  rotate y * 30 translate <3.3, 1, 0>
}
LRayPointLight(<-5, 8, -5>, rgb 1)
