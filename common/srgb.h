#pragma once
// The sRGB transfer function (IEC 61966-2-1): encoded value <-> linear light, both in [0, 1].
// The one home of the curve: the scene's materials (scenes/), the scanner's colours (sim/) and
// the recogniser's relit models (modelling/) all use it.

#include <algorithm>
#include <cmath>

namespace mopad {

/// Encoded sRGB value in [0, 1] -> linear light.
inline double SrgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Linear light -> encoded sRGB value in [0, 1]; light outside [0, 1] is clipped.
inline double LinearToSrgb(double l) {
  l = std::clamp(l, 0.0, 1.0);
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

}  // namespace mopad
