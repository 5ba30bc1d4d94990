// One of LRay's own modules (a shared library built with the program, such
// as liblray_oiio.so), loaded on first use so that what it links costs only
// the runs that need it.
#pragma once

#include <string>

namespace lray {

/// dlopen()s the module from `buildPath`, where the build that made this
/// program put it, else `fileName` beside the executable (an installed or
/// copied build), and returns the address of its function `entry`. Returns
/// nullptr when no candidate has it, with `tried` naming each candidate and
/// why it failed. The module stays loaded, its symbols its own (RTLD_LOCAL).
void *loadModuleEntry(const std::string &buildPath, const std::string &fileName,
                      const char *entry, std::string &tried);

} // namespace lray
