// Test helper shared by the geometry and accel tests: two hit records must
// agree field for field, bit for bit.
#pragma once

#include "geometry/shape.h"

#include <gtest/gtest.h>

namespace lray::testing {

inline void expectSameHit(const Hit &a, const Hit &b) {
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.entity, b.entity);
  EXPECT_EQ(a.primitive, b.primitive);
  EXPECT_EQ(a.p, b.p);
  EXPECT_EQ(a.pObject, b.pObject);
  EXPECT_EQ(a.ng, b.ng);
  EXPECT_EQ(a.ns, b.ns);
  EXPECT_EQ(a.u, b.u);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.pError, b.pError);
}

} // namespace lray::testing
