#pragma once
// Figures pooled over a group's seeds: n, mean, sample standard deviation (n - 1; 0 for one
// case), min and max of each figure over the group's cases that have it, and the pooled checks
// (`mean(F) >= X`) on them. Cases that did not run to their figures (error, timeout, crashed)
// contribute nothing; a group whose figure no case has fails its pooled checks (value null).

#include <string>
#include <vector>

#include "suite/case_result.h"
#include "suite/manifest.h"

namespace mopad::suite {

struct PooledFigure {
  std::string group, figure;
  int n = 0;
  double mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;
};

/// Per group (first-appearance order of `cases`) and figure (name order).
std::vector<PooledFigure> Pool(const std::vector<CaseResult>& cases);

/// Each pooled check of `m` on each group.
std::vector<CheckOutcome> PooledChecks(const Manifest& m, const std::vector<PooledFigure>& pooled,
                                       const std::vector<std::string>& groups);

/// The groups of `cases` in first-appearance order.
std::vector<std::string> Groups(const std::vector<CaseResult>& cases);

}  // namespace mopad::suite
