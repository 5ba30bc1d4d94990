#include "compare/suite.h"

#include "compare/case_result.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <filesystem>
#include <optional>
#include <set>

namespace fs = std::filesystem;

namespace lray::compare {

namespace {

/// The keys of a case (and of [defaults]) and what each is.
struct CaseFields {
  std::optional<std::string> name, scene, approved, metric;
  std::optional<int64_t> frame, secondSeed;
  std::optional<std::vector<std::string>> options, approveOptions, backends;
  std::optional<double> threshold, allowed, timeout;
};

class SuiteReader {
public:
  explicit SuiteReader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const toml::node &at, const std::string &why) const {
    throw CompareError(fmt::format("{}:{}: {}", path_, at.source().begin.line, why));
  }

  std::string text(const toml::node &node, const std::string &key) const {
    if (auto s = node.value<std::string>()) return *s;
    fail(node, "'" + key + "' must be a string");
  }
  double number(const toml::node &node, const std::string &key) const {
    if (auto d = node.value<double>()) return *d; // integers convert too
    fail(node, "'" + key + "' must be a number");
  }
  std::vector<std::string> strings(const toml::node &node, const std::string &key) const {
    const toml::array *a = node.as_array();
    if (!a) fail(node, "'" + key + "' must be an array of strings");
    std::vector<std::string> out;
    for (const toml::node &e : *a)
      out.push_back(text(e, key + "[]"));
    return out;
  }

  CaseFields fields(const toml::table &table) const {
    CaseFields f;
    for (const auto &[key, node] : table) {
      const std::string k(key.str());
      if (k == "name")
        f.name = text(node, k);
      else if (k == "scene")
        f.scene = text(node, k);
      else if (k == "approved")
        f.approved = text(node, k);
      else if (k == "metric") {
        f.metric = text(node, k);
        if (!parseMetric(*f.metric))
          fail(node, "unknown metric '" + *f.metric + "' (pixel, psnr, ssim or noise)");
      } else if (k == "frame") {
        auto v = node.value<int64_t>();
        if (!v || *v < 0 || *v > 9999999) fail(node, "'frame' must be a whole number >= 0");
        f.frame = *v;
      } else if (k == "second_seed") {
        auto v = node.value<int64_t>();
        if (!v || *v < 0 || *v > 4294967295)
          fail(node, "'second_seed' must be a whole number >= 0");
        f.secondSeed = *v;
      } else if (k == "options")
        f.options = strings(node, k);
      else if (k == "approve_options")
        f.approveOptions = strings(node, k);
      else if (k == "backends")
        f.backends = strings(node, k);
      else if (k == "threshold")
        f.threshold = number(node, k);
      else if (k == "allowed")
        f.allowed = number(node, k);
      else if (k == "timeout") {
        f.timeout = number(node, k);
        if (!(*f.timeout > 0 && *f.timeout <= 86400))
          fail(node, "'timeout' must be 0 to 86400 seconds");
      } else
        fail(node, "unknown key '" + k +
                       "' (name, scene, approved, frame, options, approve_options, backends, "
                       "metric, threshold, allowed, timeout, second_seed)");
    }
    return f;
  }

  std::vector<SuiteCase> read() {
    toml::table root;
    try {
      root = toml::parse_file(path_);
    } catch (const toml::parse_error &e) {
      throw CompareError(fmt::format("{}:{}: {}", path_, e.source().begin.line, e.description()));
    }
    const fs::path base = fs::path(path_).parent_path();
    auto resolve = [&](const std::string &p) {
      return fs::path(p).is_absolute() || base.empty() ? p : (base / p).string();
    };
    CaseFields defaults;
    const toml::array *cases = nullptr;
    for (const auto &[key, node] : root) {
      if (key.str() == "defaults") {
        if (!node.is_table()) fail(node, "'defaults' must be a table");
        defaults = fields(*node.as_table());
        if (defaults.name || defaults.scene || defaults.approved)
          fail(node, "[defaults] cannot give a case's name, scene or approved image");
      } else if (key.str() == "case") {
        cases = node.as_array();
        if (!cases || !cases->is_array_of_tables()) fail(node, "'case' must be [[case]] tables");
      } else {
        fail(node, "unknown key '" + std::string(key.str()) + "' (defaults, case)");
      }
    }
    if (!cases || cases->empty()) throw CompareError(path_ + ": no [[case]] in the suite");
    std::vector<SuiteCase> out;
    std::set<std::string> names;
    for (const toml::node &node : *cases) {
      const CaseFields f = fields(*node.as_table());
      if (!f.name || !f.scene || !f.approved) fail(node, "a case needs name, scene and approved");
      SuiteCase c;
      c.name = *f.name;
      if (!plainCaseName(c.name))
        fail(node, "case name '" + c.name + "': give a plain file name (no '/', '..')");
      c.scene = resolve(*f.scene);
      c.approved = resolve(*f.approved);
      c.frame = static_cast<int>(f.frame.value_or(defaults.frame.value_or(0)));
      c.options = defaults.options.value_or(std::vector<std::string>{});
      for (const std::string &o : f.options.value_or(std::vector<std::string>{}))
        c.options.push_back(o);
      c.approveOptions = defaults.approveOptions.value_or(std::vector<std::string>{});
      for (const std::string &o : f.approveOptions.value_or(std::vector<std::string>{}))
        c.approveOptions.push_back(o);
      c.criteria.metric = *parseMetric(f.metric.value_or(defaults.metric.value_or("pixel")));
      if (f.threshold || defaults.threshold)
        c.criteria.threshold = f.threshold ? f.threshold : defaults.threshold;
      c.criteria.allowedPercent = f.allowed.value_or(defaults.allowed.value_or(0));
      if (std::string why = criteriaProblem(c.criteria); !why.empty()) fail(node, why);
      c.timeoutSeconds = f.timeout.value_or(defaults.timeout.value_or(600));
      c.secondSeed = f.secondSeed ? f.secondSeed : defaults.secondSeed;
      const auto backends = f.backends ? f.backends : defaults.backends;
      std::vector<SuiteCase> expanded;
      if (!backends || backends->empty()) {
        expanded.push_back(c);
      } else {
        for (const std::string &b : *backends) {
          SuiteCase one = c;
          one.name += "." + b;
          one.options.insert(one.options.begin(), {"--backend", b});
          expanded.push_back(std::move(one));
        }
      }
      for (SuiteCase &one : expanded) {
        if (!names.insert(one.name).second) fail(node, "a second case named '" + one.name + "'");
        out.push_back(std::move(one));
      }
    }
    return out;
  }

private:
  std::string path_;
};

} // namespace

std::vector<SuiteCase> readSuite(const std::string &path) { return SuiteReader(path).read(); }

} // namespace lray::compare
