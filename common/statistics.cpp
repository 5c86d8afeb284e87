#include "common/statistics.h"

namespace mopad {

double Median(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("Median: no values");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace mopad
