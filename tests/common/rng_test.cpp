#include "common/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mopad {
namespace {

TEST(CounterRng, SameKeySameSequenceDifferentStreamsDiffer) {
  CounterRng a(42, "tls/noise", 7), b(42, "tls/noise", 7), c(42, "tls/noise", 8),
      d(42, "lrf/noise", 7);
  for (int i = 0; i < 100; ++i) {
    const auto x = a.NextU64();
    EXPECT_EQ(x, b.NextU64());
    EXPECT_NE(x, c.NextU64());
    EXPECT_NE(x, d.NextU64());
  }
}

TEST(CounterRng, PinnedValuesDoNotDriftAcrossBuilds) {
  // Pins the generator: a change here changes every seeded output of the project.
  CounterRng r(1, "pin", 0);
  EXPECT_EQ(Mix64(0), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(HashName(""), 0xCBF29CE484222325ull);
  const auto first = r.NextU64();
  CounterRng r2(1, "pin", 0);
  EXPECT_EQ(first, r2.NextU64());
}

TEST(CounterRng, UniformAndNormalMoments) {
  CounterRng r(7, "moments");
  const int n = 200000;
  double su = 0, sn = 0, sn2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    su += u;
    const double z = r.Normal();
    sn += z;
    sn2 += z * z;
  }
  EXPECT_NEAR(su / n, 0.5, 0.005);
  EXPECT_NEAR(sn / n, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sn2 / n), 1.0, 0.01);
}

TEST(CounterRng, BelowStaysInRange) {
  CounterRng r(3, "below");
  int counts[5] = {0};
  for (int i = 0; i < 50000; ++i) {
    const auto k = r.Below(5);
    ASSERT_LT(k, 5u);
    ++counts[k];
  }
  for (int c : counts) EXPECT_NEAR(c, 10000, 500);
}

}  // namespace
}  // namespace mopad
