// See module_loader.h.
#include "util/module_loader.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace lray {

void *loadModuleEntry(const std::string &buildPath, const std::string &fileName,
                      const char *entry, std::string &tried) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path built(buildPath), beside = ec ? fs::path() : exe.parent_path() / fileName;
  for (const fs::path &candidate : {built, beside == built ? fs::path() : beside}) {
    if (candidate.empty()) continue;
    void *handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char *why = dlerror();
      tried += "\n  " + candidate.string() + ": " + (why ? why : "cannot load");
      continue;
    }
    if (void *function = dlsym(handle, entry)) return function;
    tried += "\n  " + candidate.string() + ": no " + entry;
  }
  return nullptr;
}

std::string probeModuleUnderLimit(const std::string &buildPath, const std::string &fileName,
                                  const char *entry, double seconds) {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return {};
  const pid_t child = fork();
  if (child < 0) return std::strerror(errno);
  if (child == 0) {
    // What the libraries print as they fail is the child's own business.
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
      dup2(null, 1);
      dup2(null, 2);
    }
    std::string tried;
    _exit(loadModuleEntry(buildPath, fileName, entry, tried) ? 0 : 1);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() >= deadline) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      return "it did not finish loading within " + std::to_string(int(seconds)) + " s";
    }
    usleep(5000);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {};
  return WIFSIGNALED(status) ? "it ended the process loading it (signal " +
                                   std::to_string(WTERMSIG(status)) + ")"
                             : "it could not be loaded";
}

bool moduleFailedForMemory(const std::string &tried) {
  return tried.find("failed to map segment") != std::string::npos ||
         tried.find("Cannot allocate memory") != std::string::npos ||
         tried.find("cannot allocate") != std::string::npos;
}

} // namespace lray
