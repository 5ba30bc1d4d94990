// Tests for src/accel/kdtree/sah_cost_model.h.
#include "accel/kdtree/sah_cost_model.h"

#include <gtest/gtest.h>

namespace lray {
namespace {

TEST(SahCostModel, SplitCostWeighsChildrenByProbability) {
  SahCostModel m;
  m.traversalCost = 10;
  m.intersectionCost = 2;
  m.emptySpaceFactor = 0.5;
  EXPECT_DOUBLE_EQ(m.leafCost(7), 14);
  EXPECT_DOUBLE_EQ(m.splitCost(0.5, 0.75, 4, 2), 10 + 2 * (0.5 * 4 + 0.75 * 2));
}

TEST(SahCostModel, EmptyChildGetsTheBonus) {
  SahCostModel m;
  m.traversalCost = 10;
  m.intersectionCost = 2;
  m.emptySpaceFactor = 0.5;
  EXPECT_DOUBLE_EQ(m.splitCost(0.5, 0.75, 0, 8), 0.5 * (10 + 2 * 0.75 * 8));
  EXPECT_DOUBLE_EQ(m.splitCost(0.5, 0.75, 8, 0), 0.5 * (10 + 2 * 0.5 * 8));
}

} // namespace
} // namespace lray
