// Pipeline: shading. Pigment evaluation (lua/README.md, "Textures, finishes and pigments"): the
// colour of a surface point before lighting, through the one dispatch on Pigment::pattern
// (pigments/pigment_list.h); no virtual calls, no allocation, no Lua.
#pragma once

#include "scene/scene.h"
#include "shading/pigments/pigment_context.h"
