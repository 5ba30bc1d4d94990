// lray-compare: one suite case rendered by the lray program, in a process
// of its own (a scene that fails, runs out of time or crashes is that
// case's failure, with lray's message, never the tool's).
#pragma once

#include "compare/suite.h"

#include <cstdint>
#include <optional>
#include <string>

namespace lray::compare {

struct CaseRender {
  bool ok = false;
  std::string image;   ///< the frame lray wrote (when ok)
  std::string message; ///< why not: lray's last lines, a timeout, a signal
  double seconds = 0;
  /// Samples that came out NaN or infinite, which lray leaves out of the
  /// image and counts (its --stats): a bug the image alone may not show.
  uint64_t nonFiniteSamples = 0;
};

/// Renders `c`'s frame with `lray` into `dir` (emptied first; lray's output
/// goes to dir/lray.log, its --stats to dir/stats.json), in the approved
/// image's format, with the case's options, plus its approve_options when
/// `forApproval`; with `seed`, at that --seed instead of any the options
/// give.
CaseRender renderCase(const std::string &lray, const SuiteCase &c, const std::string &dir,
                      bool forApproval, std::optional<int64_t> seed = std::nullopt);

} // namespace lray::compare
