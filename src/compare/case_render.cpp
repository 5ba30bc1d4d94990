#include "compare/case_render.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char **environ;

namespace fs = std::filesystem;

namespace lray::compare {

namespace {

/// What lray said last: its last "lray: " line (its error message, which
/// a Lua stack traceback may follow), else the last `lines` lines, joined
/// by "; ".
std::string lastLines(const fs::path &path, size_t lines) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) all.push_back(line);
  for (size_t i = all.size(); i-- > 0;)
    if (all[i].rfind("lray: ", 0) == 0) return all[i].substr(6);
  std::string out;
  for (size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i)
    out += (out.empty() ? "" : "; ") + all[i];
  return out;
}

/// Removes option `name` (with its value, or as name=value) from
/// args[from..]: the tool gives its own.
void dropOption(std::vector<std::string> &args, size_t from, const std::string &name) {
  for (size_t i = from; i < args.size();) {
    if (args[i] == name && i + 1 < args.size())
      args.erase(args.begin() + i, args.begin() + i + 2);
    else if (args[i].rfind(name + "=", 0) == 0)
      args.erase(args.begin() + i);
    else
      ++i;
  }
}

/// The non-finite sample count of lray's --stats file (0 when unreadable:
/// a missing count is not a failure of the render).
uint64_t nonFiniteSamples(const fs::path &stats) {
  std::ifstream in(stats);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("non_finite_samples")) return 0;
  return j["non_finite_samples"].is_number_unsigned() ? j["non_finite_samples"].get<uint64_t>()
                                                      : 0;
}

} // namespace

CaseRender renderCase(const std::string &lray, const SuiteCase &c, const std::string &dir,
                      bool forApproval, std::optional<int64_t> seed) {
  CaseRender r;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(fs::path(dir) / "frames", ec);
  if (ec) {
    r.message = "cannot create '" + dir + "': " + ec.message();
    return r;
  }
  std::string ext = fs::path(c.approved).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char &ch : ext)
    ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != "png" && ext != "tga" && ext != "exr") {
    r.message = "the approved image '" + c.approved + "' is not .png, .tga or .exr";
    return r;
  }
  std::vector<std::string> args = {
      lray, c.scene, (fs::path(dir) / "frames").string(), "--frames", std::to_string(c.frame), "-f",
      ext,  "-q"};
  const size_t fixed = args.size();
  args.insert(args.end(), c.options.begin(), c.options.end());
  if (forApproval) args.insert(args.end(), c.approveOptions.begin(), c.approveOptions.end());
  // lray takes one --seed and one --stats: drop the options' own.
  if (seed) {
    dropOption(args, fixed, "--seed");
    args.insert(args.end(), {"--seed", std::to_string(*seed)});
  }
  const fs::path stats = fs::path(dir) / "stats.json";
  dropOption(args, fixed, "--stats");
  args.insert(args.end(), {"--stats", stats.string()});
  std::vector<char *> argv;
  for (std::string &a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  const std::string log = (fs::path(dir) / "lray.log").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const auto start = std::chrono::steady_clock::now();
  const int spawned = posix_spawn(&pid, lray.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    r.message = "cannot run '" + lray + "': " + std::strerror(spawned);
    return r;
  }
  int status = 0;
  bool timedOut = false;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      r.message = std::string("waiting for lray: ") + std::strerror(errno);
      return r;
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!timedOut && elapsed > c.timeoutSeconds) {
      kill(pid, SIGKILL);
      timedOut = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string said = lastLines(log, 3);
  if (timedOut) {
    r.message = fmt::format("the render took longer than {} s and was stopped", c.timeoutSeconds);
    return r;
  }
  if (WIFSIGNALED(status)) {
    r.message = fmt::format("lray died of signal {} ({}){}", WTERMSIG(status),
                            strsignal(WTERMSIG(status)), said.empty() ? "" : ": " + said);
    return r;
  }
  if (WEXITSTATUS(status) != 0) {
    r.message = fmt::format("lray exited with status {}{}", WEXITSTATUS(status),
                            said.empty() ? "" : ": " + said);
    return r;
  }
  std::vector<fs::path> images;
  for (const auto &e : fs::directory_iterator(fs::path(dir) / "frames", ec))
    if (e.path().extension() == "." + ext) images.push_back(e.path());
  if (images.size() != 1) {
    r.message =
        fmt::format("lray wrote {} .{} images for frame {}, not one", images.size(), ext, c.frame);
    return r;
  }
  r.ok = true;
  r.image = images.front().string();
  r.nonFiniteSamples = nonFiniteSamples(stats);
  return r;
}

} // namespace lray::compare
