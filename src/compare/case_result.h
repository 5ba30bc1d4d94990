// lray-compare: what became of one comparison, for the console line and
// the JUnit and HTML reports.
#pragma once

#include "compare/comparison.h"

#include <optional>
#include <string>

namespace lray::compare {

enum class CaseStatus { Pass, Fail, Error };

struct CaseResult {
  std::string name;
  CaseStatus status = CaseStatus::Error;
  std::string detail;          ///< the verdict line, or what went wrong
  double seconds = 0;          ///< rendering and comparing
  std::string fresh, approved; ///< the images compared (either may be missing)
  Metric metric = Metric::Pixel;
  std::optional<Outcome> outcome; ///< when the comparison ran
  bool hasImages = false;         ///< the HTML report has its pictures
};

/// Text safe inside XML/HTML element content and attribute values.
std::string escapeMarkup(const std::string &text);

/// Whether `name` can name a case: it becomes a folder of the renders and
/// of the HTML report, so nothing that leaves them ('/', '\\', '..', a
/// leading '.').
bool plainCaseName(const std::string &name);

/// Writes a report file whole or not at all (render/output_file.h), its
/// folder created first; throws CompareError naming the path and why.
void writeReportFile(const std::string &path, const std::string &text);

} // namespace lray::compare
