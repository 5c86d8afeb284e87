#pragma once
// Order statistics of a sample: the one median and the one quantile of the tree, robot and world
// side alike. Every function takes its values by copy (it reorders them) and throws
// std::invalid_argument on empty input: what "no value" means (NaN in a report, 0 in a table, a
// gap in a filtered scan) is the caller's choice, made visibly at the call. Values must not be
// NaN (they have no order).

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace mopad {

/// The median: the middle of the sorted values for an odd count, the mean of the two middle
/// ones for an even count ({1, 2, 3, 4} gives 2.5). std::invalid_argument when empty.
double Median(std::vector<double> values);

/// The upper median: the element at index n / 2 of the sorted values, so for an even count the
/// higher of the two middle ones ({1, 2, 3, 4} gives 3), never a mean: the result is always one
/// of the values (a median filter's output, a measured depth). std::invalid_argument when empty.
template <class T>
T UpperMedian(std::vector<T> values) {
  static_assert(std::is_arithmetic_v<T>, "UpperMedian: arithmetic values only");
  if (values.empty()) throw std::invalid_argument("UpperMedian: no values");
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

/// The q-quantile as one of the values, without interpolation: the element at index
/// floor(q (n - 1)) of the sorted values (q = 0 the minimum, q = 1 the maximum; q = 0.5 the
/// lower median for an even count). q in [0, 1]; std::invalid_argument when `values` is empty
/// or q is outside [0, 1].
template <class T>
T Quantile(std::vector<T> values, double q) {
  static_assert(std::is_arithmetic_v<T>, "Quantile: arithmetic values only");
  if (values.empty()) throw std::invalid_argument("Quantile: no values");
  if (!(q >= 0.0 && q <= 1.0)) throw std::invalid_argument("Quantile: q outside [0, 1]");
  const auto at =
      values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace mopad
