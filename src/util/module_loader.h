// One of LRay's own modules (a shared library built with the program, such
// as liblray_oiio.so), loaded on first use so that what it links costs only
// the runs that need it.
#pragma once

#include <cstddef>
#include <string>

namespace lray {

/// dlopen()s the module from `buildPath`, where the build that made this
/// program put it, else `fileName` beside the executable (an installed or
/// copied build), and returns the address of its function `entry`. Returns
/// nullptr when no candidate has it, with `tried` naming each candidate and
/// why it failed. The module stays loaded, its symbols its own (RTLD_LOCAL).
void *loadModuleEntry(const std::string &buildPath, const std::string &fileName,
                      const char *entry, std::string &tried);

/// Under an address-space limit (ulimit -v), loading a large module can
/// fail inside a library's own initialisation, which then aborts or hangs
/// instead of reporting (OpenImageIO's dependencies do both). Where such a
/// limit is set, this loads the module in a child process first: "" when
/// it loaded there (or no limit is set), else why not. At most `seconds`.
std::string probeModuleUnderLimit(const std::string &buildPath, const std::string &fileName,
                                  const char *entry, double seconds);

/// Whether `tried` (loadModuleEntry's account) says a candidate failed for
/// want of memory (address space), not for a missing or broken file.
bool moduleFailedForMemory(const std::string &tried);

} // namespace lray
