// Pipeline: acceleration (kd-tree backend). The surface area heuristic cost
// model, kept apart from the builder (as Mitsuba does) so it can be tuned or
// tested on its own. Costs follow Wald & Havran 2006, "On building fast
// kd-trees for ray tracing, and on doing that in O(N log N)".
#pragma once

#include <cstddef>

namespace lray {

/// Expected cost of a node, in units of one traversal step.
class SahCostModel {
public:
  /// Cost of descending one interior node.
  double traversalCost = 15;
  /// Cost of one primitive intersection test.
  double intersectionCost = 20;
  /// Factor (< 1) applied when a split cuts off an empty child: rewards
  /// separating empty space, which rays skip for free.
  double emptySpaceFactor = 0.8;

  /// Cost of making a leaf of n primitives.
  double leafCost(size_t n) const { return intersectionCost * static_cast<double>(n); }

  /// Cost of a split whose children are hit with probabilities pBelow,
  /// pAbove (surface-area ratios to the parent) and hold nBelow, nAbove primitives.
  double splitCost(double pBelow, double pAbove, size_t nBelow, size_t nAbove) const {
    double c = traversalCost + intersectionCost * (pBelow * static_cast<double>(nBelow) +
                                                   pAbove * static_cast<double>(nAbove));
    return (nBelow == 0 || nAbove == 0) ? c * emptySpaceFactor : c;
  }
};

} // namespace lray
