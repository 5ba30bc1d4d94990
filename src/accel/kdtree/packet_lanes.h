// Pipeline: acceleration (kd-tree backend). The lanes of math/lanes.h for
// a packet's rays (KdTree::walkPacket, clipPacket) or a few entities'
// boxes (FlatInstances), and the slab test they share. Each lane's
// operations are the scalar code's, so its decisions are the same bit for
// bit.
#pragma once

#include "math/lanes.h"

namespace lray::packet_lanes {

using lanes::bits;
using lanes::clearSigns;
using lanes::kWidth;
using lanes::Lanes;
using lanes::load;
using lanes::Mask;
using lanes::splat;

/// One axis of KdTree::clipToBounds' slab test, lane by lane with the same
/// operations: (tEnter, tExit) cut to where the line o + t d lies between
/// lo and hi, with invD = 1 / d (no component 0) and the test's slack
/// (KdTree::kSlack) in every lane of `slack`.
[[gnu::always_inline]] inline void clipToSlab(const Lanes &lo, const Lanes &hi, const Lanes &o,
                                              const Lanes &invD, const Lanes &slack,
                                              Lanes &tEnter, Lanes &tExit) {
  const Lanes tLo = (lo - o) * invD, tHi = (hi - o) * invD;
  const Mask swap = tLo > tHi;
  const Lanes tNear = swap ? tHi : tLo, tFar = swap ? tLo : tHi;
  Lanes absNear = tNear, absFar = tFar;
  clearSigns(absNear);
  clearSigns(absFar);
  const Lanes nearSlack = tNear - absNear * slack, farSlack = tFar + absFar * slack;
  // std::max(tEnter, nearSlack), std::min(tExit, farSlack).
  tEnter = tEnter < nearSlack ? nearSlack : tEnter;
  tExit = farSlack < tExit ? farSlack : tExit;
}

} // namespace lray::packet_lanes
