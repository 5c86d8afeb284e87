// SM4 openings against the truth: Precision and Recall of areas, e_abs, e_r,
// door states and angles on hand-built cases whose answers are computed by hand in comments.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "evaluation/metrics_openings.h"

namespace mopad::evaluation {
namespace {

// A rectangle on the wall y = 0 (normal +y into the room): x in [x0, x1], z in [z0, z1], CCW
// seen from +y.
OpeningRecord Rect(const std::string& id, double x0, double x1, double z0, double z1,
                   const std::string& type = "door", const std::string& state = "",
                   double angle = std::nan("")) {
  OpeningRecord r;
  r.id = id, r.type = type, r.host = "wall_1", r.state = state, r.angle_deg = angle;
  r.normal = Vec3::UnitY();
  r.corners = {{x1, 0, z0}, {x0, 0, z0}, {x0, 0, z1}, {x1, 0, z1}};
  if (type == "door" && state.empty()) r.state = "closed", r.angle_deg = 0.0;
  return r;
}

TEST(OpeningMetrics, IdenticalOpeningsScorePerfectly) {
  const auto t = Rect("D1", 1, 2, 0, 2);
  const OpeningEvaluation e = EvaluateOpenings({t}, {t});
  EXPECT_EQ(e.matched, 1);
  EXPECT_DOUBLE_EQ(e.precision, 1.0);
  EXPECT_DOUBLE_EQ(e.recall, 1.0);
  EXPECT_NEAR(e.e_abs.max, 0.0, 1e-12);
  EXPECT_NEAR(e.e_r.max, 0.0, 1e-12);
  EXPECT_EQ(e.door_state_right, 1);
}

TEST(OpeningMetrics, ShiftedRectangleGivesHandComputedAreas) {
  // Truth 1 x 2 m; recognised shifted 0.1 m along the wall: tp = 0.9 * 2 = 1.8, fp = fn = 0.2;
  // Precision = Recall = 0.9, e_abs = 0.4 m^2, e_r = 0.4 / (1.8 + 0.2) = 0.2.
  const OpeningEvaluation e =
      EvaluateOpenings({Rect("o1", 1.1, 2.1, 0, 2)}, {Rect("D1", 1, 2, 0, 2)});
  ASSERT_EQ(e.rows.size(), 1u);
  EXPECT_NEAR(e.rows[0].tp, 1.8, 1e-9);
  EXPECT_NEAR(e.rows[0].fp, 0.2, 1e-9);
  EXPECT_NEAR(e.rows[0].fn, 0.2, 1e-9);
  EXPECT_NEAR(e.precision, 0.9, 1e-9);
  EXPECT_NEAR(e.recall, 0.9, 1e-9);
  EXPECT_NEAR(e.e_abs.mean, 0.4, 1e-9);
  EXPECT_NEAR(e.e_r.mean, 0.2, 1e-9);
  EXPECT_NEAR(e.fn_max, 0.2, 1e-9);
  EXPECT_NEAR(e.fp_max, 0.2, 1e-9);
}

TEST(OpeningMetrics, MissedAndFalseOpeningsCountAsWholeAreas) {
  // Truth D1 (1 m^2) missed; W9 (0.5 m^2) recognised on another wall (x = 0, normal +x): false.
  OpeningRecord f = Rect("W9", 0, 1, 1, 1.5, "window");
  for (auto& c : f.corners) c = Vec3(0.0, c.x() + 1.0, c.z());
  f.normal = Vec3::UnitX();
  f.corners = {f.corners[1], f.corners[0], f.corners[3], f.corners[2]};  // CCW seen from +x
  const OpeningEvaluation e = EvaluateOpenings({f}, {Rect("D1", 1, 2, 0, 1)});
  EXPECT_EQ(e.missed, 1);
  EXPECT_EQ(e.false_openings, 1);
  EXPECT_DOUBLE_EQ(e.precision, 0.0);     // 0 / (0 + 0.5)
  EXPECT_DOUBLE_EQ(e.recall, 0.0);        // 0 / (0 + 1)
  EXPECT_NEAR(e.e_abs.mean, 0.75, 1e-9);  // rows 1.0 and 0.5
  EXPECT_NEAR(e.e_abs.max, 1.0, 1e-9);
  EXPECT_EQ(e.e_r.n, 1);  // false openings have no e_r
  EXPECT_NEAR(e.e_r.max, 1.0, 1e-9);
  EXPECT_NEAR(e.fn_max, 1.0, 1e-9);
  EXPECT_NEAR(e.fp_max, 0.5, 1e-9);
  EXPECT_EQ(e.state_confusion[0][3], 1);  // the closed truth door was missed
}

TEST(OpeningMetrics, OppositeWallOrDistantPlaneDoesNotMatch) {
  OpeningRecord back = Rect("o1", 1, 2, 0, 2);
  back.normal = -Vec3::UnitY();
  std::reverse(back.corners.begin(), back.corners.end());
  EXPECT_EQ(EvaluateOpenings({back}, {Rect("D1", 1, 2, 0, 2)}).matched, 0);
  OpeningRecord far = Rect("o2", 1, 2, 0, 2);
  for (auto& c : far.corners) c.y() = 0.5;
  EXPECT_EQ(EvaluateOpenings({far}, {Rect("D1", 1, 2, 0, 2)}).matched, 0);
  for (auto& c : far.corners) c.y() = 0.2;  // a wall refit 20 cm off still matches
  EXPECT_EQ(EvaluateOpenings({far}, {Rect("D1", 1, 2, 0, 2)}).matched, 1);
}

TEST(OpeningMetrics, DoorStatesAndAngleErrors) {
  // Truth closed 0, semi_open 30, open 95; recognised closed 2, semi_open 36, semi_open 80:
  // states right 2 of 3, angle errors 2, 6, 15 -> mean 23/3, median 6, max 15.
  const std::vector<OpeningRecord> truth = {Rect("D1", 0, 1, 0, 2, "door", "closed", 0),
                                            Rect("D2", 2, 3, 0, 2, "door", "semi_open", 30),
                                            Rect("D3", 4, 5, 0, 2, "door", "open", 95)};
  const std::vector<OpeningRecord> model = {Rect("o3", 4, 5, 0, 2, "door", "semi_open", 80),
                                            Rect("o1", 0, 1, 0, 2, "door", "closed", 2),
                                            Rect("o2", 2, 3, 0, 2, "door", "semi_open", 36)};
  const OpeningEvaluation e = EvaluateOpenings(model, truth);
  EXPECT_EQ(e.matched, 3);
  EXPECT_EQ(e.rows[0].model_id, "o1");
  EXPECT_EQ(e.doors, 3);
  EXPECT_EQ(e.door_state_right, 2);
  EXPECT_EQ(e.state_confusion[0][0], 1);
  EXPECT_EQ(e.state_confusion[1][1], 1);
  EXPECT_EQ(e.state_confusion[2][1], 1);
  EXPECT_NEAR(e.angle_error.mean, 23.0 / 3.0, 1e-9);
  EXPECT_NEAR(e.angle_error_median, 6.0, 1e-9);
  EXPECT_NEAR(e.angle_error.max, 15.0, 1e-9);
}

TEST(OpeningMetrics, LargestOverlapWinsWhenTwoRecognisedOpeningsCoverOneTruth) {
  const OpeningEvaluation e = EvaluateOpenings(
      {Rect("small", 1.0, 1.3, 0, 2), Rect("big", 1.2, 2.0, 0, 2)}, {Rect("D1", 1, 2, 0, 2)});
  ASSERT_EQ(e.rows.size(), 2u);
  EXPECT_EQ(e.rows[0].model_id, "big");
  EXPECT_EQ(e.false_openings, 1);
  // tp = 1.6, fp = 0 + 0.6 (the small one, whole), fn = 0.4.
  EXPECT_NEAR(e.precision, 1.6 / 2.2, 1e-9);
  EXPECT_NEAR(e.recall, 0.8, 1e-9);
}

TEST(OpeningMetrics, PoolingTwoRoomsSumsAreasAndRecomputesRatios) {
  // Room A: the shifted case (tp 1.8, fp 0.2, fn 0.2, angle error 0); room B: a missed 1 m^2
  // door. Pooled: P = 1.8 / 2.0 = 0.9, R = 1.8 / 3.0 = 0.6, e_abs rows 0.4 and 1.0.
  const OpeningEvaluation a =
      EvaluateOpenings({Rect("o1", 1.1, 2.1, 0, 2)}, {Rect("D1", 1, 2, 0, 2)});
  const OpeningEvaluation b = EvaluateOpenings({}, {Rect("D2", 1, 2, 0, 1)});
  const OpeningEvaluation p = PoolOpenings({a, b});
  EXPECT_EQ(p.truth_count, 2);
  EXPECT_EQ(p.missed, 1);
  EXPECT_NEAR(p.precision, 0.9, 1e-9);
  EXPECT_NEAR(p.recall, 0.6, 1e-9);
  EXPECT_NEAR(p.e_abs.mean, 0.7, 1e-9);
  EXPECT_NEAR(p.e_abs.max, 1.0, 1e-9);
  EXPECT_EQ(p.doors, 2);
  EXPECT_EQ(p.door_state_right, 1);
  EXPECT_EQ(p.state_confusion[0][3], 1);
  EXPECT_EQ(p.angle_error.n, 1);
}

TEST(OpeningMetrics, NoOpeningsOnEitherSideIsPerfect) {
  const OpeningEvaluation e = EvaluateOpenings({}, {});
  EXPECT_DOUBLE_EQ(e.precision, 1.0);
  EXPECT_DOUBLE_EQ(e.recall, 1.0);
}

TEST(OpeningMetrics, BadRecordsAreInputErrors) {
  OpeningRecord r = Rect("o1", 1, 2, 0, 2);
  r.corners.pop_back();
  EXPECT_THROW(EvaluateOpenings({r}, {}), InputError);
  r = Rect("o1", 1, 2, 0, 2);
  r.type = "hatch";
  EXPECT_THROW(EvaluateOpenings({}, {r}), InputError);
  r = Rect("o1", 1, 2, 0, 2);
  r.state = "ajar";
  EXPECT_THROW(EvaluateOpenings({r}, {}), InputError);
}

TEST(OpeningMetrics, JsonAndMarkdownCarryTheFigures) {
  const OpeningEvaluation e =
      EvaluateOpenings({Rect("o1", 1.1, 2.1, 0, 2)}, {Rect("D1", 1, 2, 0, 2)});
  const auto j = ToJson(e);
  EXPECT_NEAR(j["precision"].get<double>(), 0.9, 1e-9);
  EXPECT_NEAR(j["e_abs_m2"]["mean"].get<double>(), 0.4, 1e-9);
  EXPECT_EQ(j["door_states"]["matrix"][0][0], 1);
  EXPECT_EQ(j["openings"][0]["truth_id"], "D1");
  EXPECT_TRUE(j["openings"][0]["angle_error_deg"].is_number());
  const std::string md = MarkdownOpeningsTable(e);
  EXPECT_NE(md.find("| 0.9000 | 0.9000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| D1 | o1 | door |"), std::string::npos) << md;
}

TEST(OpeningMetrics, TruthOpeningsComeFromTheSidecarWithStateAndAngle) {
  scenes::GroundTruth t;
  t.rooms.push_back({"R1", "", {{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0.0, 2.5});
  scenes::StructuralElement w;
  w.id = "wall_s", w.element_class = scenes::ElementClass::kWall, w.rooms = {"R1"};
  w.origin = {0, 0, 0}, w.u_axis = Vec3::UnitX(), w.length = 4, w.height = 2.5;
  w.normal = Vec3::UnitY();
  t.elements.push_back(w);
  scenes::Opening d;
  d.id = "D1", d.type = scenes::OpeningType::kDoor, d.host_walls = {"wall_s"}, d.rooms = {"R1"};
  d.corners = {{1, 0, 0}, {2, 0, 0}, {2, 0, 2.1}, {1, 0, 2.1}};
  d.opening_angle = 30.0 * 3.14159265358979323846 / 180.0;
  d.state = scenes::DoorState::kSemiOpen;
  t.openings.push_back(d);
  const auto r = TruthOpenings(t, "R1");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].type, "door");
  EXPECT_EQ(r[0].state, "semi_open");
  EXPECT_NEAR(r[0].angle_deg, 30.0, 1e-9);
  EXPECT_NEAR(PolygonArea3d(r[0].corners), 2.1, 1e-9);
  const Vec3 n = (r[0].corners[1] - r[0].corners[0]).cross(r[0].corners[3] - r[0].corners[0]);
  EXPECT_GT(n.dot(Vec3::UnitY()), 0.0);  // CCW seen from the room
  EXPECT_THROW(TruthOpenings(t, "R9"), InputError);
  // The robot's file in its map frame, 1 m along x from the world: the same rectangle matches.
  modelling::Sm4Model m;
  modelling::DetectedOpening o;
  o.id = "opening_1", o.host = "wall_1", o.state = modelling::DoorState::kSemiOpen;
  o.opening_angle_deg = 33.0;
  o.corners = {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 2.1), Vec3(1, 0, 2.1)};
  m.openings.push_back(o);
  Pose3 X_WM = Pose3::Identity();
  X_WM.translation() = Vec3(1, 0, 0);
  const OpeningEvaluation e = EvaluateOpenings(ModelOpenings(m, X_WM), r);
  EXPECT_EQ(e.matched, 1);
  EXPECT_NEAR(e.recall, 1.0, 1e-9);
  EXPECT_NEAR(e.angle_error.max, 3.0, 1e-9);
}

}  // namespace
}  // namespace mopad::evaluation
