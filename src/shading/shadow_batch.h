// Pipeline: shading. The shadow rays of several of one light's rounds over
// a tile's lit points (light_lanes.h), held to be traced together point
// by point. A point's rays to an area light's neighbouring cells start at
// one place and part slowly, so a packet of them (the kd-tree's four rays,
// Embree's eight) walks far fewer cells than a packet of neighbouring
// points' rays to one cell. What each round brings is held as well and
// added round by round once the batch is traced, in the order the rounds
// were taken, so the sums are the same bits as one round at a time.
#pragma once

#include "math/ray.h"
#include "shading/light_lanes.h"

#include <cstddef>
#include <cstdint>

namespace lray {

struct ShadowBatch {
  /// The most rounds a batch holds (all of a 4 x 4 light's after the first).
  static constexpr size_t kRounds = 16;
  /// A light of fewer rounds traces them one by one: after its first round
  /// (traced alone) a batch would hold too few rays a point for packets of
  /// one point's rays to pay for holding them (bench/README.md,
  /// "Throughput").
  static constexpr size_t kMinRounds = 8;
  static constexpr size_t kLanes = LightLanes::kMax;
  static constexpr size_t kRays = kRounds * kLanes;

  /// Leaves `rays` and `sorted` unmade (each in an anonymous union): as
  /// arrays of Ray they would take every ray's defaults when the batch is
  /// made, touching most of a megabyte of fresh pages at a thread's first
  /// tile (0.3-0.4 ms) where a light of few rounds uses the first few.
  /// Each ray is written whole before it is read.
  ShadowBatch() {}

  /// The rounds held: each one's colours (lightLanesRound's cr, cg, cb)
  /// and the lanes it lights (`add`: its clear rays; a waiting ray's flag
  /// is set when the batch is traced).
  size_t rounds = 0;
  alignas(32) double cr[kRounds][kLanes], cg[kRounds][kLanes], cb[kRounds][kLanes];
  alignas(32) uint8_t add[kRounds][kLanes];

  /// The rays waiting for the accelerator, rays[0, count) in the order
  /// taken, with each one's lane and round.
  size_t count = 0;
  union {
    Ray rays[kRays];
  };
  uint16_t lane[kRays];
  uint8_t round[kRays];

  /// The waiting rays point by point (sort): sorted[at[k]] is rays[k],
  /// and what the accelerator found for it, blocked[at[k]] and
  /// blocker[at[k]].
  union {
    Ray sorted[kRays];
  };
  uint32_t at[kRays];
  uint8_t blocked[kRays];
  uint32_t blocker[kRays];

  void clear() { rounds = count = 0; }
  bool full() const { return rounds == kRounds; }
  /// Holds the round just taken in `lanes` (lanes of `span`) as the
  /// batch's next: its colours and `add` flags (read to the end of the
  /// last group of four, as addLit reads them).
  void hold(const LightLanes &lanes, LaneSpan span, const uint8_t *add);
  /// Marks rays[count, count + n), whose lanes are lanes.rayLane[0, n), as
  /// round `r`'s, waiting.
  void wait(const LightLanes &lanes, size_t n, size_t r);
  /// The waiting rays by lane, each lane's in the order taken: `sorted`
  /// (and `at`), or `rays` as they are where they come from one round
  /// (one ray a lane, in lane order; at[k] is then k).
  const Ray *sort();
};

} // namespace lray
