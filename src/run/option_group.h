// Pipeline: run. lray's command line (README.md, "Command line") in groups,
// each in its own file next to the settings it fills: output, sampling,
// limits, farm and preview. options.cpp puts the groups on one parser.
#pragma once

#include "run/options.h"

#include <memory>
#include <string>

namespace CLI {
class App;
}

namespace lray {

/// One group of options. `add` registers them on the parser, writing into
/// `o` (or into the group's own text fields for what CLI11 cannot convert);
/// `finish`, once everything is parsed, converts that text and checks the
/// group's rules, returning a usage error without the "lray: error: "
/// prefix ("" when all is well). Groups finish in the order of
/// optionGroups(), so a later group may read an earlier one's results.
class OptionGroup {
public:
  virtual ~OptionGroup() = default;
  virtual void add(CLI::App &app, Options &o) = 0;
  virtual std::string finish(Options &o) = 0;
};

std::unique_ptr<OptionGroup> makeOutputOptions();   ///< output_options.cpp
std::unique_ptr<OptionGroup> makeSamplingOptions(); ///< sampling_options.cpp
std::unique_ptr<OptionGroup> makeLimitOptions();    ///< limit_options.cpp
std::unique_ptr<OptionGroup> makeFarmOptions();     ///< farm_options.cpp
std::unique_ptr<OptionGroup> makePreviewOptions();  ///< preview_options.cpp

} // namespace lray
