// lray-compare: the command (README.md, "Reference-image CI for your
// scenes"). Two images, or a suite of scenes rendered by lray and each
// compared with its approved image; a line per case, a JUnit XML file and
// an HTML report on request, --approve to take the new images.
// Exit status: 0 when every case passes, 1 when one fails or cannot be
// rendered or read, 2 for a usage error (options, the suite file).
#pragma once

namespace lray::compare {

int runCompare(int argc, const char *const *argv);

} // namespace lray::compare
