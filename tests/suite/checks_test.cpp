#include <gtest/gtest.h>

#include "common/error.h"
#include "suite/checks.h"
#include "suite/pooled.h"

namespace mopad::suite {
namespace {

TEST(SuiteChecks, ParsesFigureOpBoundUnitAndStat) {
  const Check a = ParseCheck("d_h_mean <= 1 cm", "m.yaml:3");
  EXPECT_EQ(a.figure, "d_h_mean");
  EXPECT_EQ(a.op, "<=");
  EXPECT_DOUBLE_EQ(a.bound, 0.01);
  EXPECT_EQ(a.stat, "");
  const Check b = ParseCheck("mean(sm5_tp_rate)>=95 %", "m.yaml:4");
  EXPECT_EQ(b.stat, "mean");
  EXPECT_DOUBLE_EQ(b.bound, 0.95);
  const Check c = ParseCheck("rooms_modelled >= rooms_reachable", "x");
  EXPECT_EQ(c.bound_figure, "rooms_reachable");
  const Check d = ParseCheck("eval.summary.openings.precision > 0.9", "x");
  EXPECT_EQ(d.figure, "eval.summary.openings.precision");
  EXPECT_THROW(ParseCheck("a => 3", "x"), InputError);
  EXPECT_THROW(ParseCheck("a >= 3 furlong", "x"), InputError);
  EXPECT_THROW(ParseCheck("mean(a) >= b", "x"), InputError);
  EXPECT_THROW(ParseCheck("median(a) >= 1", "x"), InputError);
}

TEST(SuiteChecks, EvaluateComparesAndAMissingFigureFails) {
  const Figures f = {{"a", 0.5}, {"b", 0.7}};
  EXPECT_TRUE(Evaluate(ParseCheck("a >= 0.5", "x"), f).passed);
  EXPECT_FALSE(Evaluate(ParseCheck("a > 0.5", "x"), f).passed);
  EXPECT_TRUE(Evaluate(ParseCheck("a < b", "x"), f).passed);
  EXPECT_FALSE(Evaluate(ParseCheck("a != 0.5", "x"), f).passed);
  const Check missing = ParseCheck("c >= 0", "x");
  const CheckResult r = Evaluate(missing, f);
  EXPECT_FALSE(r.passed);
  EXPECT_FALSE(r.value.has_value());
  EXPECT_EQ(Describe(r), "check 'c >= 0': figure c missing");
  const Check low = ParseCheck("a >= 0.6", "x");
  EXPECT_EQ(Describe(Evaluate(low, f)), "check 'a >= 0.6': 0.5 not >= 0.6");
}

TEST(SuitePooled, MeanSampleSdMinMaxPerGroupAndPooledChecks) {
  std::vector<CaseResult> cases(4);
  const double v[] = {1.0, 2.0, 4.0, 10.0};
  for (int i = 0; i < 4; ++i) {
    cases[i].group = i < 3 ? "g1" : "g2";
    cases[i].figures["x"] = v[i];
  }
  cases[2].figures.erase("x");  // a case without the figure contributes nothing
  const std::vector<PooledFigure> p = Pool(cases);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].group, "g1");
  EXPECT_EQ(p[0].n, 2);
  EXPECT_DOUBLE_EQ(p[0].mean, 1.5);
  EXPECT_DOUBLE_EQ(p[0].sd, std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(p[0].min, 1.0);
  EXPECT_DOUBLE_EQ(p[0].max, 2.0);
  EXPECT_DOUBLE_EQ(p[1].sd, 0.0);  // one case
  Manifest m;
  m.pooled_checks = {ParseCheck("mean(x) >= 2", "x"), ParseCheck("max(y) <= 1", "x")};
  const std::vector<CheckOutcome> c = PooledChecks(m, p, Groups(cases));
  ASSERT_EQ(c.size(), 4u);
  EXPECT_FALSE(c[0].passed);  // g1 mean 1.5
  EXPECT_EQ(c[0].group, "g1");
  EXPECT_EQ(c[0].stat, "mean");
  EXPECT_FALSE(c[1].passed);  // y missing
  EXPECT_TRUE(c[2].passed);   // g2 mean 10
}

}  // namespace
}  // namespace mopad::suite
