#pragma once
// Two-sample statistics for comparing a figure between two suites (suite/compare.h): the
// Mann-Whitney U rank test, a bootstrap interval of the change of the mean, and Holm's
// correction of many tests' p-values. Both samples are
// a figure's values over the seed repetitions of one scene group; they need not have the same
// size or the same seeds. Values must be finite.

#include <cstdint>
#include <vector>

namespace mopad::suite {

/// The largest n_a + n_b for which MannWhitneyU uses the exact permutation distribution: the
/// subset counts, at most C(50, 25) ~ 1.3e14, stay exact in a double (< 2^53).
inline constexpr int kExactMaxTotal = 50;

/// A two-sided Mann-Whitney U test (Mann & Whitney 1947; Wilcoxon's rank sum).
struct MannWhitneyResult {
  double u = 0.0;      ///< U of the first sample x: pairs with x_i > y_j plus half the ties
                       ///< (scipy.stats.mannwhitneyu's statistic); in [0, n_x n_y]
  double p = 1.0;      ///< two-sided p-value, in (0, 1]
  bool exact = false;  ///< p from the exact permutation distribution (else normal approximation)
};

/// Tests whether x and y come from one distribution, against a shift either way.
/// Exact for n_x + n_y <= kExactMaxTotal: the permutation distribution of x's rank sum over
/// all C(n, n_x) splits of the pooled mid-ranks (conditional on the ties, so it stays exact with
/// tied values), p = 2 min(P(W <= w), P(W >= w)) capped at 1; without ties this is
/// scipy's method="exact". Larger samples: the normal approximation with the tie correction of
/// the variance and a continuity correction of 0.5 (scipy's method="asymptotic"). When every
/// value is tied p = 1. std::invalid_argument when a sample is empty.
MannWhitneyResult MannWhitneyU(const std::vector<double>& x, const std::vector<double>& y);

/// The smallest two-sided p the exact test can give for these sample sizes: 2 / C(n_x + n_y,
/// n_x) (all of one sample above all of the other), capped at 1. When it exceeds the
/// significance level no data can be significant: 3 seeds a side give 0.1, 4 a side 0.029.
double MinimumTwoSidedP(int n_x, int n_y);

/// Arithmetic mean; NaN when empty.
double Mean(const std::vector<double>& v);
/// Sample standard deviation (n - 1 in the denominator); 0 for fewer than two values.
double SampleSd(const std::vector<double>& v);

struct Interval {
  double low = 0.0;
  double high = 0.0;
};

/// Percentile bootstrap interval (Efron & Tibshirani 1993, ch. 13) of mean(y) - mean(x): both
/// samples resampled with replacement, each at its own size, `resamples` times; the interval
/// between the (1 - confidence) / 2 and (1 + confidence) / 2 quantiles of the differences
/// (mopad::Quantile, no interpolation). Deterministic: the draws come from CounterRng(`key`),
/// so the same data and key give the same bytes on any machine. resamples >= 1, confidence in
/// (0, 1), both samples non-empty (std::invalid_argument otherwise).
Interval BootstrapMeanDifference(const std::vector<double>& x, const std::vector<double>& y,
                                 int resamples, double confidence, std::uint64_t key);

/// Holm's step-down adjustment (Holm 1979) of m p-values, in their order: with the p sorted
/// ascending, the i-th (1-based) becomes max over j <= i of min(1, (m - j + 1) p_(j)). Rejecting
/// where the adjusted p < alpha keeps the chance of any false rejection below alpha, whatever
/// the dependence between the tests. Empty in, empty out.
std::vector<double> HolmAdjusted(const std::vector<double>& p);

}  // namespace mopad::suite
