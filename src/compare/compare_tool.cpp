#include "compare/compare_tool.h"

#include "compare/case_render.h"
#include "compare/html_report.h"
#include "compare/junit_report.h"
#include "compare/suite.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>
#include <unistd.h>

namespace fs = std::filesystem;

namespace lray::compare {

namespace {

struct ToolOptions {
  std::string fresh, approved, suite, html, junit, out = "lray-compare-out", lray, name, second;
  std::vector<std::string> only;
  std::string metric = "pixel";
  std::optional<double> threshold;
  double allowed = 0;
  bool approve = false, quiet = false;
};

/// The lray program beside this one (both are built into one folder).
std::string besideMe(const char *program) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(program) : (self.parent_path() / program).string();
}

/// Compares two files into `r` (and the HTML pictures when asked); with
/// `second`, a second new render for the noise test.
void compareFiles(CaseResult &r, const Criteria &criteria, const std::string &htmlDir,
                  const std::string &second = "") {
  r.metric = criteria.metric;
  try {
    const CompareImage fresh = readCompareImage(r.fresh);
    std::optional<CompareImage> other;
    if (!second.empty()) other = readCompareImage(second);
    CompareImage approved;
    try {
      approved = readCompareImage(r.approved);
    } catch (const CompareError &e) {
      throw CompareError(std::string(e.what()) + (fs::exists(r.approved)
                                                      ? ""
                                                      : " (no approved image yet: look at the "
                                                        "new one and run with --approve)"));
    }
    r.outcome = compareImages(fresh, approved, criteria, other ? &*other : nullptr);
    r.status = r.outcome->pass ? CaseStatus::Pass : CaseStatus::Fail;
    r.detail = r.outcome->verdict;
    if (!htmlDir.empty()) writeCaseImages(htmlDir, r, fresh, approved);
  } catch (const std::exception &e) {
    r.status = CaseStatus::Error;
    r.detail = e.what();
  }
}

void approve(CaseResult &r) {
  std::error_code ec;
  const fs::path target(r.approved);
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const fs::path tmp = target.string() + ".approving";
  fs::copy_file(r.fresh, tmp, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::rename(tmp, target, ec);
  if (ec) {
    r.status = CaseStatus::Error;
    r.detail = "cannot approve '" + r.approved + "': " + ec.message();
    return;
  }
  r.status = CaseStatus::Pass;
  r.detail = "approved (" + r.detail + ")";
}

void printLine(const CaseResult &r) {
  const char *word = r.status == CaseStatus::Pass   ? "PASS"
                     : r.status == CaseStatus::Fail ? "FAIL"
                                                    : "ERROR";
  std::FILE *to = r.status == CaseStatus::Pass ? stdout : stderr;
  std::fflush(stdout); // keep the lines in order when both streams go to one place
  std::fprintf(to, "%-5s %s: %s (%.2f s)\n", word, r.name.c_str(), r.detail.c_str(), r.seconds);
  std::fflush(to);
}

std::vector<CaseResult> runSuite(const ToolOptions &o) {
  std::vector<SuiteCase> cases = readSuite(o.suite);
  if (!o.only.empty()) {
    for (const std::string &name : o.only) {
      bool found = false;
      for (const SuiteCase &c : cases)
        found = found || c.name == name;
      if (!found) throw CompareError("--only " + name + ": no such case in " + o.suite);
    }
    std::erase_if(cases, [&](const SuiteCase &c) {
      return std::find(o.only.begin(), o.only.end(), c.name) == o.only.end();
    });
  }
  const std::string lray = o.lray.empty() ? besideMe("lray") : o.lray;
  if (access(lray.c_str(), X_OK) != 0)
    throw CompareError("cannot run lray at '" + lray + "' (give its path with --lray)");
  std::vector<CaseResult> results;
  // With --approve, a second case of one approved image (another backend)
  // is compared with the image the first case just approved.
  std::set<std::string> approvedNow;
  for (const SuiteCase &c : cases) {
    CaseResult r;
    r.name = c.name;
    r.approved = c.approved;
    r.metric = c.criteria.metric;
    const auto start = std::chrono::steady_clock::now();
    const CaseRender render = renderCase(lray, c, (fs::path(o.out) / c.name).string(), o.approve);
    if (!render.ok) {
      r.status = CaseStatus::Error;
      r.detail = "render failed: " + render.message;
    } else {
      r.fresh = render.image;
      std::string second;
      if (c.secondSeed && c.criteria.metric == Metric::Noise && !o.approve) {
        const CaseRender again = renderCase(
            lray, c, (fs::path(o.out) / (c.name + ".second")).string(), false, c.secondSeed);
        if (!again.ok) r.detail = "second render failed: " + again.message;
        second = again.image;
      }
      if (r.detail.empty()) compareFiles(r, c.criteria, o.html, second);
      // lray leaves NaN and infinite samples out of the image: a bug that
      // a matching image would hide. Never approved.
      if (render.nonFiniteSamples > 0) {
        // The comparison's verdict follows, unless it is only that there
        // is no approved image yet (which would suggest --approve).
        const bool compared = fs::exists(r.approved);
        r.status = CaseStatus::Fail;
        r.detail = fmt::format("{} samples were not finite (NaN or infinite; lray left them "
                               "out of the image){}",
                               render.nonFiniteSamples,
                               compared && !r.detail.empty() ? "; " + r.detail : "");
      }
      // An approved image the new one matches pixel for pixel stays as it
      // is (another PNG encoder's bytes are no change to commit).
      const bool same = r.outcome && r.outcome->maxDifference == 0;
      if (o.approve && render.nonFiniteSamples == 0 &&
          approvedNow.insert(fs::weakly_canonical(r.approved).string()).second && !same) {
        if (!fs::exists(r.approved)) r.detail = "new";
        approve(r);
      }
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!o.quiet || r.status != CaseStatus::Pass) printLine(r);
    results.push_back(std::move(r));
  }
  return results;
}

} // namespace

int runCompare(int argc, const char *const *argv) {
  CLI::App app{"lray-compare compares rendered images with approved ones: two files\n"
               "(NEW APPROVED), or every case of a suite file (--suite), which it renders\n"
               "with lray first. Exit status 0: all pass; 1: a case fails or cannot be\n"
               "rendered; 2: usage error.",
               "lray-compare"};
  ToolOptions o;
  app.add_option("new", o.fresh, "The new image (PNG, TGA, EXR)");
  app.add_option("approved", o.approved, "The approved image it should match");
  auto *suite = app.add_option("--suite", o.suite,
                               "A suite file (TOML) of scenes to render and "
                               "compare")
                    ->check(CLI::ExistingFile);
  app.add_option("--only", o.only, "Only these cases of the suite (repeatable)")->needs(suite);
  app.add_option("--out", o.out, "Where the suite's renders go (default lray-compare-out)")
      ->needs(suite);
  app.add_option("--lray", o.lray, "The lray program (default: the one beside lray-compare)")
      ->needs(suite);
  app.add_option("--metric", o.metric, "Two images: pixel, psnr, ssim or noise (default pixel)")
      ->check(CLI::IsMember({"pixel", "psnr", "ssim", "noise"}));
  app.add_option("--threshold", o.threshold,
                 "Two images: the metric's bound (pixel 0.004, psnr 40 dB, ssim 0.99, noise: "
                 "false-alarm rate 0.01)");
  app.add_option("--allowed", o.allowed, "Two images, pixel: % of pixels that may differ (0)");
  app.add_option("--name", o.name, "Two images: the case's name in reports (default: NEW's)");
  app.add_option("--second", o.second,
                 "Two images, noise: another render of NEW at another --seed (for files "
                 "without variance, e.g. PNG)")
      ->check(CLI::ExistingFile);
  app.add_option("--html", o.html, "Write an HTML report into this folder");
  app.add_option("--junit", o.junit, "Write the results as JUnit XML to this file");
  app.add_flag("--approve", o.approve, "Copy each new image over its approved one");
  app.add_flag("-q,--quiet", o.quiet, "Print only the cases that do not pass");
  try {
    app.parse(argc, argv);
    if (o.suite.empty() == (o.fresh.empty() || o.approved.empty()))
      throw CLI::ValidationError("give NEW and APPROVED images, or --suite FILE (not both)");
  } catch (const CLI::ParseError &e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    std::vector<CaseResult> results;
    std::string title;
    if (!o.suite.empty()) {
      title = fs::path(o.suite).stem().string();
      results = runSuite(o);
    } else {
      Criteria criteria;
      criteria.metric = *parseMetric(o.metric);
      criteria.threshold = o.threshold;
      criteria.allowedPercent = o.allowed;
      if (std::string why = criteriaProblem(criteria); !why.empty()) {
        std::fprintf(stderr, "lray-compare: %s\n", why.c_str());
        return 2;
      }
      CaseResult r;
      r.name = o.name.empty() ? fs::path(o.fresh).stem().string() : o.name;
      // The name is a folder of the HTML report: nothing that leaves it.
      if (!plainCaseName(r.name)) {
        std::fprintf(stderr, "lray-compare: --name '%s': give a plain file name\n", r.name.c_str());
        return 2;
      }
      r.fresh = o.fresh;
      r.approved = o.approved;
      title = "lray-compare";
      const auto start = std::chrono::steady_clock::now();
      compareFiles(r, criteria, o.html, o.second);
      if (o.approve && r.outcome) approve(r);
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!o.quiet || r.status != CaseStatus::Pass) printLine(r);
      results.push_back(std::move(r));
    }
    if (!o.junit.empty()) writeJunit(o.junit, title, results);
    if (!o.html.empty()) writeHtmlReport(o.html, title, results);
    size_t bad = 0;
    for (const CaseResult &r : results)
      bad += r.status != CaseStatus::Pass;
    if (results.size() > 1 || bad)
      std::printf("lray-compare: %zu of %zu cases pass%s\n", results.size() - bad, results.size(),
                  o.html.empty() ? "" : fmt::format("; report: {}/index.html", o.html).c_str());
    return bad ? 1 : 0;
  } catch (const CompareError &e) {
    std::fprintf(stderr, "lray-compare: %s\n", e.what());
    return 2;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "lray-compare: error: %s\n", e.what());
    return 1;
  }
}

} // namespace lray::compare
