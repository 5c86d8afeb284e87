#pragma once
// printf-style formatting into a std::string: the one helper for messages and figures.

#include <cstdio>
#include <string>

namespace mopad {

/// `format` (printf conversions for doubles only: %f, %e, %g with their flags) applied to up
/// to four numbers, into a string of any length.
inline std::string FormatNumbers(const char* format, double a = 0, double b = 0, double c = 0,
                                 double d = 0) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof buf, format, a, b, c, d);
  if (n < static_cast<int>(sizeof buf)) return buf;
  std::string out(static_cast<std::size_t>(n) + 1, '\0');
  std::snprintf(out.data(), out.size(), format, a, b, c, d);
  out.resize(static_cast<std::size_t>(n));
  return out;
}

}  // namespace mopad
