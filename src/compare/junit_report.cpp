#include "compare/junit_report.h"

#include "render/output_file.h"

#include <fmt/format.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace lray::compare {

std::string escapeMarkup(const std::string &text) {
  std::string out;
  for (char c : text) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&#39;";
      break;
    default:
      // XML 1.0 allows no other control characters.
      if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t')
        out += ' ';
      else
        out += c;
    }
  }
  return out;
}

bool plainCaseName(const std::string &name) {
  return !name.empty() && name.find_first_of("/\\") == std::string::npos &&
         name.find("..") == std::string::npos && name.front() != '.';
}

void writeReportFile(const std::string &path, const std::string &text) {
  try {
    const fs::path target(path);
    if (target.has_parent_path()) fs::create_directories(target.parent_path());
    writeOutputFile(path, "report", text);
  } catch (const std::exception &e) {
    throw CompareError(e.what());
  }
}

void writeJunit(const std::string &path, const std::string &suite,
                const std::vector<CaseResult> &results) {
  size_t failures = 0, errors = 0;
  double total = 0;
  for (const CaseResult &r : results) {
    failures += r.status == CaseStatus::Fail;
    errors += r.status == CaseStatus::Error;
    total += r.seconds;
  }
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  xml += fmt::format("<testsuites name=\"lray-compare\" tests=\"{}\" failures=\"{}\" "
                     "errors=\"{}\" time=\"{:.3f}\">\n",
                     results.size(), failures, errors, total);
  xml += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" "
                     "skipped=\"0\" time=\"{:.3f}\">\n",
                     escapeMarkup(suite), results.size(), failures, errors, total);
  for (const CaseResult &r : results) {
    xml += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3f}\"",
                       escapeMarkup(suite), escapeMarkup(r.name), r.seconds);
    const std::string detail = escapeMarkup(r.detail);
    if (r.status == CaseStatus::Pass) {
      xml += ">\n      <system-out>" + detail + "</system-out>\n    </testcase>\n";
    } else {
      const char *tag = r.status == CaseStatus::Fail ? "failure" : "error";
      xml +=
          fmt::format(">\n      <{} message=\"{}\" type=\"{}\">{}\nnew: {}\napproved: {}</{}>\n"
                      "    </testcase>\n",
                      tag, detail, r.status == CaseStatus::Fail ? metricName(r.metric) : "render",
                      detail, escapeMarkup(r.fresh), escapeMarkup(r.approved), tag);
    }
  }
  xml += "  </testsuite>\n</testsuites>\n";
  writeReportFile(path, xml);
}

} // namespace lray::compare
