// lray-compare --junit FILE: the results as JUnit XML, the format GitLab,
// Jenkins and GitHub's test reporters read: one <testcase> per case, a
// <failure> for an image beyond its bound, an <error> for one that could
// not be rendered or read.
#pragma once

#include "compare/case_result.h"

#include <string>
#include <vector>

namespace lray::compare {

/// Writes the report (complete or not at all); throws CompareError.
void writeJunit(const std::string &path, const std::string &suite,
                const std::vector<CaseResult> &results);

} // namespace lray::compare
