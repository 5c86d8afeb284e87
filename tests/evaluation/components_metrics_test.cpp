// SM5 components against the truth (evaluation/metrics_components.h) on hand-computed cases.

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "evaluation/metrics_components.h"

namespace mopad::evaluation {
namespace {

ComponentRecord Rec(const std::string& id, const std::string& cls, Vec3 c, double alpha = 0.5,
                    Vec3 n = Vec3(0, -1, 0)) {
  ComponentRecord r;
  r.id = id, r.class_name = cls, r.centre = c, r.normal = n, r.alpha = alpha;
  return r;
}

TEST(ComponentMetrics, Table3CountsSharesAndAlphaColumns) {
  // Truth: two switches and a socket on a wall facing -y, a smoke detector on the ceiling.
  const std::vector<ComponentRecord> truth{
      Rec("t1", "switch", {1, 0, 1}), Rec("t2", "switch", {3, 0, 1}),
      Rec("t3", "socket_x1", {2, 0, 0.3}), Rec("t4", "smoke_detector", {2, 2, 2.8}, 0, {0, 0, -1})};
  // Model: t1 found 3 mm right and 1 mm up (alpha 0.95); t2 found as a socket (wrong class: one
  // FN and one FP); t3 found 6 cm away (too far: FN + FP); t4 found 2 mm off in x (alpha 0.5).
  const std::vector<ComponentRecord> model{
      Rec("m1", "switch", {1.003, 0, 1.001}, 0.95), Rec("m2", "socket_x1", {3, 0, 1}),
      Rec("m3", "socket_x1", {2.06, 0, 0.3}), Rec("m4", "smoke_detector", {2.002, 2, 2.8}, 0.5)};
  const ComponentEvaluation e = EvaluateComponents(model, truth);
  EXPECT_EQ(e.total.n, 4);
  EXPECT_EQ(e.total.tp, 2);
  EXPECT_EQ(e.total.fn, 2);
  EXPECT_EQ(e.total.fp, 2);
  EXPECT_EQ(e.total.tp_alpha_high, 1);
  EXPECT_EQ(e.total.tp_alpha_half, 1);
  ASSERT_EQ(e.classes.size(), 3u);  // by name: smoke_detector, socket_x1, switch
  EXPECT_EQ(e.classes[1].class_name, "socket_x1");
  EXPECT_EQ(e.classes[1].n, 1);
  EXPECT_EQ(e.classes[1].fp, 2);
  EXPECT_DOUBLE_EQ(e.classes[1].Share(e.classes[1].fp), 2.0);
  EXPECT_EQ(e.classes[2].tp, 1);
  EXPECT_DOUBLE_EQ(e.classes[2].Share(e.classes[2].tp), 0.5);
  // Errors: t1 horizontal 3 mm, vertical 1 mm; t4 on the ceiling: horizontal (x) 2 mm.
  ASSERT_EQ(e.horizontal.size(), 2u);
  EXPECT_NEAR(e.horizontal[0], 0.003, 1e-9);
  EXPECT_NEAR(e.vertical[0], 0.001, 1e-9);
  EXPECT_NEAR(e.horizontal[1], 0.002, 1e-9);
  EXPECT_NEAR(e.vertical[1], 0.0, 1e-9);
  EXPECT_NEAR(e.horizontal_stats.mean, 0.0025, 1e-9);
  EXPECT_NEAR(e.horizontal_stats.max, 0.003, 1e-9);
  EXPECT_NEAR(e.horizontal_median, 0.0025, 1e-9);
  const std::string md = MarkdownComponentsTable(e);
  EXPECT_NE(md.find("| **all** | 4 | 50.0 | 50.0 | 50.0 | 50.0 | 50.0 | 2 / 2 / 2 |"),
            std::string::npos)
      << md;
  const auto j = ToJson(e);
  EXPECT_EQ(j["all"]["tp"], 2);
  EXPECT_EQ(j["pairs"].size(), 6u);
}

TEST(ComponentMetrics, MatchesOneToOneNearestFirstAndPools) {
  const std::vector<ComponentRecord> truth{Rec("t1", "switch", {1, 0, 1})};
  const std::vector<ComponentRecord> model{Rec("far", "switch", {1.04, 0, 1}),
                                           Rec("near", "switch", {1.01, 0, 1})};
  const ComponentEvaluation e = EvaluateComponents(model, truth);
  EXPECT_EQ(e.total.tp, 1);
  EXPECT_EQ(e.total.fp, 1);
  EXPECT_EQ(e.pairs[0].model_id, "near");
  const ComponentEvaluation pooled = PoolComponents({e, e});
  EXPECT_EQ(pooled.total.n, 2);
  EXPECT_EQ(pooled.total.tp, 2);
  EXPECT_EQ(pooled.total.fp, 2);
  EXPECT_EQ(pooled.horizontal.size(), 2u);
}

TEST(ComponentMetrics, RefusesNonFiniteCentres) {
  EXPECT_THROW(EvaluateComponents({Rec("m", "switch", {NAN, 0, 0})}, {}), InputError);
}

}  // namespace
}  // namespace mopad::evaluation
