#include "suite/two_sample.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "common/rng.h"
#include "common/statistics.h"

namespace mopad::suite {
namespace {

// The pooled sample's mid-ranks, doubled so that they are integers (a tie block over sorted
// positions i..j, 1-based, has mid-rank (i + j) / 2), with x's values first; and the tie term
// sum(t^3 - t) over tie blocks of size t.
struct PooledRanks {
  std::vector<long> doubled;  // one per value: x's, then y's
  double tie_term = 0.0;
};

PooledRanks RankPooled(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<std::pair<double, std::size_t>> all;
  for (std::size_t i = 0; i < x.size(); ++i) all.emplace_back(x[i], i);
  for (std::size_t i = 0; i < y.size(); ++i) all.emplace_back(y[i], x.size() + i);
  std::sort(all.begin(), all.end());
  PooledRanks r;
  r.doubled.assign(all.size(), 0);
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    while (j + 1 < all.size() && all[j + 1].first == all[i].first) ++j;
    for (std::size_t k = i; k <= j; ++k) r.doubled[all[k].second] = static_cast<long>(i + j + 2);
    const double t = static_cast<double>(j - i + 1);
    r.tie_term += t * t * t - t;
    i = j + 1;
  }
  return r;
}

// Exact two-sided p of the doubled rank sum `w2` of a subset of size `k` of `doubled`: counts of
// the subsets of each size and doubled sum (a knapsack over the values), then both tails.
double ExactP(const std::vector<long>& doubled, std::size_t k, long w2) {
  const long max_sum = std::accumulate(doubled.begin(), doubled.end(), 0L);
  // count[m][s]: subsets of size m of the values seen so far with doubled rank sum s.
  std::vector<std::vector<double>> count(k + 1, std::vector<double>(max_sum + 1, 0.0));
  count[0][0] = 1.0;
  std::size_t seen = 0;
  for (const long r : doubled) {
    ++seen;
    for (std::size_t m = std::min(k, seen); m >= 1; --m)
      for (long s = max_sum; s >= r; --s) count[m][s] += count[m - 1][s - r];
  }
  double total = 0.0, at_most = 0.0, at_least = 0.0;
  for (long s = 0; s <= max_sum; ++s) {
    const double c = count[k][s];
    total += c;
    if (s <= w2) at_most += c;
    if (s >= w2) at_least += c;
  }
  return std::min(1.0, 2.0 * std::min(at_most, at_least) / total);
}

}  // namespace

MannWhitneyResult MannWhitneyU(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.empty() || y.empty()) throw std::invalid_argument("MannWhitneyU: an empty sample");
  const PooledRanks ranks = RankPooled(x, y);
  const double nx = static_cast<double>(x.size()), ny = static_cast<double>(y.size());
  const long w2 = std::accumulate(ranks.doubled.begin(),
                                  ranks.doubled.begin() + static_cast<long>(x.size()), 0L);
  MannWhitneyResult r;
  r.u = 0.5 * static_cast<double>(w2) - nx * (nx + 1.0) / 2.0;
  if (x.size() + y.size() <= static_cast<std::size_t>(kExactMaxTotal)) {
    r.exact = true;
    r.p = ExactP(ranks.doubled, x.size(), w2);
    return r;
  }
  // Normal approximation: the larger of the two U against its mean, continuity-corrected.
  const double n = nx + ny;
  const double u_max = std::max(r.u, nx * ny - r.u);
  const double var = nx * ny / 12.0 * ((n + 1.0) - ranks.tie_term / (n * (n - 1.0)));
  if (var <= 0.0) return r;  // every value tied: no evidence of a shift, p = 1
  const double z = (u_max - nx * ny / 2.0 - 0.5) / std::sqrt(var);
  r.p = std::clamp(std::erfc(z / std::sqrt(2.0)), 0.0, 1.0);  // 2 P(Z > z)
  return r;
}

double MinimumTwoSidedP(int n_x, int n_y) {
  // C(n_x + n_y, n_x) as a product of ratios (exact enough for any suite size).
  double c = 1.0;
  for (int i = 1; i <= n_x; ++i) c = c * static_cast<double>(n_y + i) / static_cast<double>(i);
  return std::min(1.0, 2.0 / c);
}

double Mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (const double a : v) s += a;
  return s / static_cast<double>(v.size());
}

double SampleSd(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = Mean(v);
  double ss = 0.0;
  for (const double a : v) ss += (a - m) * (a - m);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

Interval BootstrapMeanDifference(const std::vector<double>& x, const std::vector<double>& y,
                                 int resamples, double confidence, std::uint64_t key) {
  if (x.empty() || y.empty())
    throw std::invalid_argument("BootstrapMeanDifference: an empty sample");
  if (resamples < 1) throw std::invalid_argument("BootstrapMeanDifference: resamples < 1");
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("BootstrapMeanDifference: confidence outside (0, 1)");
  CounterRng rng(key);
  auto resampled_mean = [&rng](const std::vector<double>& v) {
    double s = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) s += v[rng.Below(v.size())];
    return s / static_cast<double>(v.size());
  };
  std::vector<double> diffs(static_cast<std::size_t>(resamples));
  for (double& d : diffs) {
    const double mx = resampled_mean(x);
    d = resampled_mean(y) - mx;
  }
  return {Quantile(diffs, (1.0 - confidence) / 2.0), Quantile(diffs, (1.0 + confidence) / 2.0)};
}

std::vector<double> HolmAdjusted(const std::vector<double>& p) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&p](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> out(p.size());
  double running = 0.0;
  for (std::size_t j = 0; j < order.size(); ++j) {
    const double scaled = static_cast<double>(p.size() - j) * p[order[j]];
    running = std::max(running, std::min(1.0, scaled));
    out[order[j]] = running;
  }
  return out;
}

}  // namespace mopad::suite
