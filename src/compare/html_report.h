// lray-compare --html DIR: a report a person opens from a CI artifact.
// DIR/index.html (no external resources) lists every case, failures first:
// its verdict and figures, the new and approved images, a heat map of the
// difference (black to red to yellow to white as the difference grows, to
// the metric's failing level; failing pixels tinted cyan), and a slider
// and a flip button over the two images. Each case's pictures lie in
// DIR/<case>/ (new.png, approved.png, difference.png: values clamped to
// [0, 1], 8 bits, as lray writes a PNG).
#pragma once

#include "compare/case_result.h"
#include "compare/compare_image.h"

#include <string>
#include <vector>

namespace lray::compare {

/// Writes DIR/<r.name>/ pictures of a comparison that ran; sets r.hasImages.
void writeCaseImages(const std::string &dir, CaseResult &r, const CompareImage &fresh,
                     const CompareImage &approved);

/// Writes DIR/index.html for all results; throws CompareError.
void writeHtmlReport(const std::string &dir, const std::string &title,
                     const std::vector<CaseResult> &results);

} // namespace lray::compare
