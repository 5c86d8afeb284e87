// The U test and the bootstrap interval (suite/two_sample.h). Reference values: scipy 1.10's
// scipy.stats.mannwhitneyu (method "exact" on samples without ties, "asymptotic" otherwise; run
// once by hand with Debian's python3-scipy, not needed to run the tests), the textbook exact
// p = 2 / C(n, n_x) of completely separated samples, and a brute-force walk over every split of
// the pooled sample for tied ones.
#include "suite/two_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using mopad::suite::BootstrapMeanDifference;
using mopad::suite::MannWhitneyU;
using mopad::suite::MinimumTwoSidedP;

TEST(MannWhitneyU, SeparatedSamplesGiveTheTextbookExactP) {
  // All of x below all of y: U = 0, and only 2 of the C(7, 3) = 35 splits are as extreme.
  const auto r = MannWhitneyU({1.1, 2.2, 3.3}, {4.4, 5.5, 6.6, 7.7});
  EXPECT_TRUE(r.exact);
  EXPECT_DOUBLE_EQ(r.u, 0.0);
  EXPECT_NEAR(r.p, 2.0 / 35.0, 1e-15);
  EXPECT_NEAR(r.p, 0.05714285714285714, 1e-15);  // scipy, exact
  // The other way round: U = n_x n_y.
  const auto s = MannWhitneyU({0.9, 0.95, 0.91, 0.96, 0.93}, {0.85, 0.88, 0.86, 0.89, 0.84, 0.87});
  EXPECT_DOUBLE_EQ(s.u, 30.0);
  EXPECT_NEAR(s.p, 2.0 / 462.0, 1e-15);
}

TEST(MannWhitneyU, InterleavedSamplesMatchScipyExact) {
  const auto r =
      MannWhitneyU({0.8, 0.83, 0.89, 0.9, 0.92, 0.95}, {0.81, 0.85, 0.87, 0.91, 0.93, 0.97, 0.99});
  EXPECT_TRUE(r.exact);
  EXPECT_DOUBLE_EQ(r.u, 16.0);
  EXPECT_NEAR(r.p, 0.5337995337995338, 1e-12);
}

// Two-sided p by walking all C(n, n_x) splits of the pooled values: x's U against every split's.
double BruteForceP(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> all = x;
  all.insert(all.end(), y.begin(), y.end());
  const int n = static_cast<int>(all.size()), k = static_cast<int>(x.size());
  auto u_of = [&](unsigned mask) {
    double u = 0;
    for (int i = 0; i < n; ++i) {
      if (!(mask >> i & 1u)) continue;
      for (int j = 0; j < n; ++j) {
        if (mask >> j & 1u) continue;
        u += all[i] > all[j] ? 1.0 : (all[i] == all[j] ? 0.5 : 0.0);
      }
    }
    return u;
  };
  const double u_obs = u_of((1u << k) - 1u);
  double total = 0, at_most = 0, at_least = 0;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    if (__builtin_popcount(mask) != k) continue;
    const double u = u_of(mask);
    total += 1;
    at_most += u <= u_obs + 1e-9;
    at_least += u >= u_obs - 1e-9;
  }
  return std::min(1.0, 2.0 * std::min(at_most, at_least) / total);
}

TEST(MannWhitneyU, ExactPWithTiesIsThePermutationDistributionOfTheMidRanks) {
  // Discrete figures (rooms modelled, TP counts) tie a lot.
  const std::vector<std::vector<double>> xs = {
      {5, 5, 5, 4, 5, 5}, {0.9, 0.9, 0.8, 1.0}, {3, 3, 3}, {1, 2, 2, 3, 3, 3, 4}};
  const std::vector<std::vector<double>> ys = {
      {4, 4, 5, 4, 3, 4, 4}, {0.9, 0.8, 0.8, 0.7, 0.8}, {3, 3, 3, 3}, {2, 3, 4, 4, 5, 5}};
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const auto r = MannWhitneyU(xs[i], ys[i]);
    EXPECT_TRUE(r.exact);
    EXPECT_NEAR(r.p, BruteForceP(xs[i], ys[i]), 1e-12) << "case " << i;
  }
  EXPECT_DOUBLE_EQ(MannWhitneyU({3, 3, 3}, {3, 3, 3, 3}).p, 1.0);  // all tied: no evidence
}

TEST(MannWhitneyU, LargeSamplesUseScipysNormalApproximation) {
  // 56 distinct values (beyond the exact limit of 50).
  std::vector<double> x, y;
  for (int i = 0; i < 28; ++i) {
    x.push_back(std::round((0.5 + (i * 37 % 101) / 101.0) * 1e6) / 1e6);
    y.push_back(std::round(((i * 53 % 103) / 103.0) * 1e6) / 1e6);
  }
  const auto r = MannWhitneyU(x, y);
  EXPECT_FALSE(r.exact);
  EXPECT_DOUBLE_EQ(r.u, 694.0);
  EXPECT_NEAR(r.p, 7.786987555294009e-07, 1e-15);
  // 61 values in 8 tie blocks: the tie-corrected variance.
  std::vector<double> a, b;
  for (int i = 0; i < 30; ++i) a.push_back(i % 7);
  for (int i = 0; i < 31; ++i) b.push_back(i % 7 + 1);
  const auto t = MannWhitneyU(a, b);
  EXPECT_FALSE(t.exact);
  EXPECT_DOUBLE_EQ(t.u, 344.5);
  EXPECT_NEAR(t.p, 0.0806217168590505, 1e-12);
  EXPECT_DOUBLE_EQ(MannWhitneyU(std::vector<double>(30, 1.0), std::vector<double>(30, 1.0)).p, 1.0);
}

TEST(MannWhitneyU, EmptySampleIsRejected) {
  EXPECT_THROW(MannWhitneyU({}, {1.0}), std::invalid_argument);
}

TEST(MannWhitneyU, MinimumPSaysWhenSignificanceIsOutOfReach) {
  EXPECT_DOUBLE_EQ(MinimumTwoSidedP(1, 1), 1.0);
  EXPECT_NEAR(MinimumTwoSidedP(3, 3), 0.1, 1e-15);         // 2 / 20
  EXPECT_NEAR(MinimumTwoSidedP(4, 4), 2.0 / 70.0, 1e-15);  // below 0.05
  EXPECT_NEAR(MinimumTwoSidedP(10, 10), 2.0 / 184756.0, 1e-18);
  // It is what the exact test gives for separated samples.
  EXPECT_NEAR(MannWhitneyU({1, 2, 3, 4}, {5, 6, 7, 8}).p, MinimumTwoSidedP(4, 4), 1e-15);
}

TEST(Bootstrap, IntervalCoversTheShiftAndIsReproducible) {
  std::vector<double> x, y;
  for (int i = 0; i < 10; ++i) {
    x.push_back(1.0 + 0.01 * ((i * 7) % 10));
    y.push_back(1.5 + 0.01 * ((i * 3) % 10));
  }
  const auto a = BootstrapMeanDifference(x, y, 2000, 0.95, 42);
  const auto b = BootstrapMeanDifference(x, y, 2000, 0.95, 42);
  EXPECT_EQ(a.low, b.low);
  EXPECT_EQ(a.high, b.high);
  EXPECT_LT(a.low, 0.5);
  EXPECT_GT(a.high, 0.5);  // the true shift of the means
  EXPECT_GT(a.low, 0.4);   // the values spread by 0.09: the interval is narrow
  EXPECT_LT(a.high, 0.6);
  const auto c = BootstrapMeanDifference(x, y, 2000, 0.95, 43);
  EXPECT_TRUE(c.low != a.low || c.high != a.high);  // the key drives the draws
  const auto same = BootstrapMeanDifference({2.0}, {2.0, 2.0}, 100, 0.9, 1);
  EXPECT_EQ(same.low, 0.0);
  EXPECT_EQ(same.high, 0.0);
  EXPECT_THROW(BootstrapMeanDifference({}, {1.0}, 100, 0.9, 1), std::invalid_argument);
  EXPECT_THROW(BootstrapMeanDifference({1.0}, {1.0}, 100, 1.0, 1), std::invalid_argument);
}

TEST(Holm, StepDownAdjustmentByHand) {
  // Sorted 0.005, 0.01, 0.03, 0.04 -> 4 x 0.005 = 0.02, 3 x 0.01 = 0.03, 2 x 0.03 = 0.06,
  // max(0.06, 1 x 0.04) = 0.06; given back in the input's order.
  const std::vector<double> adj = mopad::suite::HolmAdjusted({0.01, 0.04, 0.03, 0.005});
  ASSERT_EQ(adj.size(), 4u);
  EXPECT_NEAR(adj[0], 0.03, 1e-15);
  EXPECT_NEAR(adj[1], 0.06, 1e-15);
  EXPECT_NEAR(adj[2], 0.06, 1e-15);
  EXPECT_NEAR(adj[3], 0.02, 1e-15);
  EXPECT_EQ(mopad::suite::HolmAdjusted({0.5, 0.9}), (std::vector<double>{1.0, 1.0}));
  EXPECT_TRUE(mopad::suite::HolmAdjusted({}).empty());
}

}  // namespace
