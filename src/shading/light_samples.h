// Pipeline: shading. A light (SPEC 6) prepared once per frame for sampling:
// the 1 x 1 square in its local xz-plane, centred at its origin, split into
// rows x cols cells (cols along local x, rows along local z) and placed by
// worldFromLight. Each shading point takes one sample per cell.
#pragma once

#include "math/color.h"
#include "math/vec3.h"
#include "scene/scene.h"

namespace lray {

/// World-space cell grid of one light; sampling needs no matrix product.
struct LightSamples {
  Vec3 corner;         ///< world position of local (-0.5, 0, -0.5)
  Vec3 cellX;          ///< world step of one cell along local x (length/cols)
  Vec3 cellZ;          ///< world step of one cell along local z (length/rows)
  Color weightedColor; ///< colour * w, w = 1 / (rows * cols)
  int rows = 1;
  int cols = 1;
  bool area = false;   ///< jitter inside each cell instead of its centre

  static LightSamples fromLight(const Light &light) {
    LightSamples s;
    s.rows = light.rows;
    s.cols = light.cols;
    s.area = light.area;
    s.corner = light.worldFromLight.applyPoint({-0.5, 0, -0.5});
    s.cellX = light.worldFromLight.applyVector({1.0 / light.cols, 0, 0});
    s.cellZ = light.worldFromLight.applyVector({0, 0, 1.0 / light.rows});
    s.weightedColor = light.color / (static_cast<double>(light.rows) * light.cols);
    return s;
  }

  /// World position of the sample in cell (row, col) at fractional offset
  /// (fx, fz) in [0, 1) inside it; (0.5, 0.5) is the cell centre.
  Vec3 samplePoint(int row, int col, double fx, double fz) const {
    return corner + cellX * (col + fx) + cellZ * (row + fz);
  }
};

} // namespace lray
