#pragma once
// printf-style formatting into a std::string: the one helper for messages and figures.

#include <charconv>
#include <cmath>
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

/// The shortest text that reads back as the same double (std::to_chars): file formats.
inline std::string FormatShortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

/// Fixed-point with `digits` decimals ("%.*f"); "-" for NaN and infinities (tables).
inline std::string FormatFixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace mopad
