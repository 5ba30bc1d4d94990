// Text from outside LRay (a script's error message, a path, a value) made
// safe for a terminal and bounded before it is printed: a scene file must
// not be able to send escape sequences to the terminal of the person who
// renders it, nor flood it (README.md, "Security").
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace lray {

/// The most bytes of one message LRay prints.
constexpr size_t kMaxMessageBytes = 4096;

/// `text` with every control character but newline and tab, DEL, C1
/// control and byte that is not valid UTF-8 written as an escape (\x1b,
/// \u009b), cut after `maxBytes` with a note of how much was left out.
std::string printableText(std::string_view text, size_t maxBytes = kMaxMessageBytes);

/// A number in at most about a dozen characters ("1e+300", "0.5", "2.5e-07").
std::string readableNumber(double value);

/// A non-negative count exactly while it is below 10^15, else as
/// readableNumber (a product of limits can exceed any integer type).
std::string readableCount(long double value);

} // namespace lray
