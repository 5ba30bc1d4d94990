#!/bin/sh
# Regenerates scenes/texture.png (64x64, used by image.lua and textures.lua):
# a colour gradient over a checkerboard, made with OpenImageIO's oiiotool so
# no downloaded image is needed.
set -e
cd "$(dirname "$0")"
oiiotool --pattern fill:topleft=1,0.2,0.2:topright=0.2,1,0.2:bottomleft=0.2,0.2,1:bottomright=1,1,0.2 64x64 3 \
         --pattern checker:width=8:height=8:color1=1,1,1:color2=0.35,0.35,0.35 64x64 3 \
         --mul -d uint8 -o texture.png
