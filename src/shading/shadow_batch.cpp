// Pipeline: shading. ShadowBatch (shadow_batch.h): holding rounds and
// ordering their waiting rays point by point.
#include "shading/shadow_batch.h"

#include <cstring>

namespace lray {

void ShadowBatch::hold(const LightLanes &lanes, LaneSpan span, const uint8_t *flags) {
  const size_t r = rounds++;
  const size_t end = (span.end + 3) & ~size_t{3};
  const size_t n = end - span.begin;
  std::memcpy(cr[r] + span.begin, lanes.cr + span.begin, n * sizeof(double));
  std::memcpy(cg[r] + span.begin, lanes.cg + span.begin, n * sizeof(double));
  std::memcpy(cb[r] + span.begin, lanes.cb + span.begin, n * sizeof(double));
  std::memcpy(add[r] + span.begin, flags + span.begin, n);
}

void ShadowBatch::wait(const LightLanes &lanes, size_t n, size_t r) {
  for (size_t k = 0; k < n; ++k) {
    lane[count + k] = static_cast<uint16_t>(lanes.rayLane[k]);
    round[count + k] = static_cast<uint8_t>(r);
  }
  count += n;
}

const Ray *ShadowBatch::sort() {
  // Taken round by round: the first and last rays' rounds bound them all.
  if (count == 0 || round[0] == round[count - 1]) {
    for (size_t k = 0; k < count; ++k) at[k] = static_cast<uint32_t>(k);
    return rays;
  }
  // A counting sort by lane: start[j] is where lane j's rays begin.
  uint32_t start[kLanes + 1] = {};
  for (size_t k = 0; k < count; ++k) ++start[lane[k] + 1];
  for (size_t j = 0; j < kLanes; ++j) start[j + 1] += start[j];
  for (size_t k = 0; k < count; ++k) {
    const uint32_t to = start[lane[k]]++;
    at[k] = to;
    sorted[to] = rays[k];
  }
  return sorted;
}

} // namespace lray
