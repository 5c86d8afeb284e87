// Every metric on hand-built cases with known answers.
#include "evaluation/metrics.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "common/error.h"
#include "common/params.h"
#include "evaluation/hungarian.h"
#include "evaluation/json_number.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"
#include "evaluation/report_tables.h"

namespace mopad::evaluation {
namespace {

constexpr double kX = 4.0, kY = 5.0, kZ = 2.5;  // box room [0,4] x [0,5] x [0,2.5]

// Normal from the polygon (Newell), so it always agrees with the winding.
Patch Make(const std::string& id, SurfaceClass cls, std::vector<Vec3> poly) {
  const Vec3 n = NewellVector(poly);
  return Patch{id, cls, std::move(poly), n.normalized()};
}

// Vertical wall from a to b (plan), z in [0, kZ]; normal (b - a) x z.
Patch Wall(const std::string& id, Vec2 a, Vec2 b) {
  return Make(id, SurfaceClass::kWall,
              {Vec3(a.x(), a.y(), 0), Vec3(b.x(), b.y(), 0), Vec3(b.x(), b.y(), kZ),
               Vec3(a.x(), a.y(), kZ)});
}

// The truth box room, walls facing inwards: 0 west (x=0), 1 south, 2 east, 3 north,
// 4 floor, 5 ceiling.
std::vector<Patch> BoxRoom() {
  return {Wall("wall_W", {0, 0}, {0, kY}),
          Wall("wall_S", {kX, 0}, {0, 0}),
          Wall("wall_E", {kX, kY}, {kX, 0}),
          Wall("wall_N", {0, kY}, {kX, kY}),
          Make("floor", SurfaceClass::kFloor, {{0, 0, 0}, {kX, 0, 0}, {kX, kY, 0}, {0, kY, 0}}),
          Make("ceiling", SurfaceClass::kCeiling,
               {{0, 0, kZ}, {0, kY, kZ}, {kX, kY, kZ}, {kX, 0, kZ}})};
}

IsprsParams FastIsprs() {
  IsprsParams p;
  p.sample_spacing = 0.01;
  return p;
}

TEST(Hungarian, FindsTheKnownOptimum) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3,  //
      2, 0, 5,   //
      3, 2, 2;
  EXPECT_EQ(SolveAssignment(c), (std::vector<int>{1, 0, 2}));  // 1 + 2 + 2 = 5
  Eigen::MatrixXd r(3, 2);  // more rows than columns: one row unassigned
  r << 1, 9,                //
      9, 1,                 //
      0.5, 0.5;
  EXPECT_EQ(SolveAssignment(r), (std::vector<int>{0, -1, 1}));  // 1 + 0.5 beats 1 + 1
  Eigen::MatrixXd f(1, 2);
  f << kForbiddenCost, kForbiddenCost;
  EXPECT_EQ(SolveAssignment(f), (std::vector<int>{-1}));
}

TEST(PolygonGeometry, ExactIntersectionOfNonConvexPolygons) {
  const std::vector<Vec2> ell = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // area 3
  const std::vector<Vec2> square2 = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  const std::vector<Vec2> notch = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  EXPECT_NEAR(SignedArea(ell), 3.0, 1e-12);
  EXPECT_NEAR(PolygonIoU(ell, square2), 0.75, 1e-12);
  EXPECT_NEAR(IntersectionArea(ell, notch), 0.0, 1e-12);
  // Winding does not matter.
  std::vector<Vec2> cw(square2.rbegin(), square2.rend());
  EXPECT_NEAR(IntersectionArea(ell, cw), 3.0, 1e-12);
}

TEST(PatchMetrics, IdenticalModelIsAllTruePositivesWithZeroErrors) {
  const auto truth = BoxRoom();
  const PatchEvaluation e = EvaluatePatches(truth, truth);
  EXPECT_EQ(e.pairs.size(), 6u);
  EXPECT_EQ(e.detection[0].tp, 4);
  EXPECT_EQ(e.detection[1].tp, 1);
  EXPECT_EQ(e.detection[2].tp, 1);
  for (const auto& d : e.detection) {
    EXPECT_EQ(d.fp, 0);
    EXPECT_EQ(d.fn, 0);
  }
  EXPECT_EQ(e.d_v.n, 8);  // 4 walls x 2 vertical edges
  EXPECT_EQ(e.d_h.n, 8);
  EXPECT_DOUBLE_EQ(e.d_v.max, 0.0);
  EXPECT_DOUBLE_EQ(e.d_h.max, 0.0);
  EXPECT_DOUBLE_EQ(e.phi_deg.max, 0.0);
  EXPECT_EQ(e.accuracy[1].d_h.n, 4);  // the floor's 4 horizontal edges, reported per class
  EXPECT_EQ(e.accuracy[1].d_v.n, 0);
  for (const auto& p : e.pairs) EXPECT_NEAR(p.iou, 1.0, 1e-12);
}

TEST(PatchMetrics, WallTenCentimetresShorterGivesDh010) {
  const auto truth = BoxRoom();
  auto model = truth;
  model[0] = Wall("wall_W", {0, 0}, {0, kY - 0.10});
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[0].tp, 4);
  const PatchPair* west = nullptr;
  for (const auto& p : e.pairs)
    if (p.truth_id == "wall_W") west = &p;
  ASSERT_NE(west, nullptr);
  EXPECT_NEAR(west->d_h.mean, 0.10, 1e-12);
  EXPECT_NEAR(west->d_h.max, 0.10, 1e-12);
  EXPECT_NEAR(west->d_v.max, 0.0, 1e-12);
  EXPECT_EQ(west->unpaired_edges, 0);
  EXPECT_NEAR(e.d_h.max, 0.10, 1e-12);
  EXPECT_NEAR(e.d_h.mean, 2 * 0.10 / 8, 1e-12);  // two of eight horizontal wall edges
  EXPECT_NEAR(e.d_v.max, 0.0, 1e-12);
}

TEST(PatchMetrics, LowerWallGivesDvAndCollinearSplitsAreMerged) {
  const auto truth = BoxRoom();
  auto model = truth;
  for (Vec3& p : model[1].polygon) p.z() = std::min(p.z(), kZ - 0.05);  // south wall 5 cm lower
  // West wall as a general polygon: its bottom edge split in three collinear pieces.
  model[0].polygon = {{0, 0, 0}, {0, 1, 0}, {0, 3.5, 0}, {0, kY, 0}, {0, kY, kZ}, {0, 0, kZ}};
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[0].tp, 4);
  for (const PatchPair& p : e.pairs) {
    EXPECT_EQ(p.unpaired_edges, 0) << p.truth_id;
    if (p.truth_id == "wall_S") {
      EXPECT_NEAR(p.d_v.mean, 0.05, 1e-12);
      EXPECT_NEAR(p.d_h.max, 0.0, 1e-12);
    } else if (p.cls == SurfaceClass::kWall) {
      EXPECT_NEAR(p.d_v.max, 0.0, 1e-12) << p.truth_id;
      EXPECT_NEAR(p.d_h.max, 0.0, 1e-12) << p.truth_id;
    }
  }
  EXPECT_NEAR(e.d_v.max, 0.05, 1e-12);
  EXPECT_NEAR(e.d_v.mean, 2 * 0.05 / 8, 1e-12);
}

TEST(PatchMetrics, WallTiltedHalfADegreeGivesPhi05) {
  const auto truth = BoxRoom();
  auto model = truth;
  const Eigen::AngleAxisd rot(DegToRad(0.5), Vec3::UnitZ());
  const Vec3 centre(0, kY / 2, 0);
  for (Vec3& p : model[0].polygon) p = centre + rot * (p - centre);
  model[0].normal = rot * model[0].normal;
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[0].tp, 4);
  EXPECT_NEAR(e.phi_deg.max, 0.5, 1e-9);
  EXPECT_NEAR(e.phi_deg.mean, 0.5 / 6, 1e-9);
  EXPECT_NEAR(e.accuracy[0].phi_deg.mean, 0.5 / 4, 1e-9);
  EXPECT_NEAR(e.d_h.max, 0.0, 1e-9);  // rotation keeps the lengths
  EXPECT_NEAR(e.d_v.max, 0.0, 1e-9);
}

TEST(PatchMetrics, MissingWallIsFalseNegativeAndExtraPatchFalsePositive) {
  const auto truth = BoxRoom();
  auto model = truth;
  model.erase(model.begin() + 2);                  // no east wall
  model.push_back(Wall("ghost", {1, 1}, {1, 3}));  // a wall in the middle of the room
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[0].tp, 3);
  EXPECT_EQ(e.detection[0].fn, 1);
  EXPECT_EQ(e.detection[0].fp, 1);
  EXPECT_NEAR(e.detection[0].Recall(), 0.75, 1e-12);
  ASSERT_EQ(e.unmatched_truth_ids.size(), 1u);
  EXPECT_EQ(e.unmatched_truth_ids[0], "wall_E");
  ASSERT_EQ(e.unmatched_model_ids.size(), 1u);
  EXPECT_EQ(e.unmatched_model_ids[0], "ghost");
}

TEST(PatchMetrics, ClassMismatchAndFlippedNormalDoNotMatch) {
  const auto truth = BoxRoom();
  auto model = truth;
  model[4].cls = SurfaceClass::kCeiling;  // floor labelled ceiling: FN floor, FP ceiling
  std::reverse(model[1].polygon.begin(), model[1].polygon.end());  // south wall facing out
  model[1].normal = -model[1].normal;
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[1].fn, 1);
  EXPECT_EQ(e.detection[2].fp, 1);
  EXPECT_EQ(e.detection[0].fn, 1);
  PatchMatchParams unoriented;
  unoriented.oriented_normals = false;
  const PatchEvaluation u = EvaluatePatches(model, truth, unoriented);
  EXPECT_EQ(u.detection[0].tp, 4);  // the flipped wall is the same plane
  EXPECT_NEAR(u.phi_deg.max, 0.0, 1e-9);
}

TEST(PatchMetrics, BadInputThrowsInputError) {
  auto truth = BoxRoom();
  auto bad = truth;
  bad[0].polygon[2].x() += 0.05;  // non-planar
  EXPECT_THROW(EvaluatePatches(bad, truth), InputError);
  bad = truth;
  bad[0].polygon.resize(2);
  EXPECT_THROW(EvaluatePatches(bad, truth), InputError);
  bad = truth;
  bad[3].polygon[1].z() = std::nan("");
  EXPECT_THROW(EvaluatePatches(truth, bad), InputError);
  bad = truth;
  bad[4].normal = -bad[4].normal;  // winding clockwise seen from the normal
  EXPECT_THROW(EvaluateIsprs(bad, truth), InputError);
  try {
    bad = truth;
    bad[0].polygon[2].x() += 0.05;
    EvaluatePatches(bad, truth);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model patch 0 'wall_W': polygon is not planar"),
              std::string::npos)
        << e.what();
  }
}

TEST(IsprsMetrics, IdenticalModelIsCompleteAndCorrect) {
  const auto truth = BoxRoom();
  const IsprsResult r = EvaluateIsprs(truth, truth, FastIsprs());
  ASSERT_EQ(r.buffers.size(), 16u);  // 0..15 cm in 1 cm steps
  EXPECT_NEAR(r.buffers.back(), 0.15, 1e-12);
  EXPECT_NEAR(r.all.reference_area, 2 * (kX + kY) * kZ + 2 * kX * kY, 1e-6);
  for (size_t k = 1; k < r.buffers.size(); ++k) {
    EXPECT_DOUBLE_EQ(r.all.completeness[k], 1.0);
    EXPECT_DOUBLE_EQ(r.all.correctness[k], 1.0);
  }
  EXPECT_NEAR(r.all.accuracy, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(r.per_class[3].completeness[5]));  // no columns
}

TEST(IsprsMetrics, IdenticalModelIsCompleteAtOneMillimetre) {
  IsprsParams p = FastIsprs();
  p.buffer_step = 0.001;
  p.buffer_max = 0.002;
  const IsprsResult r = EvaluateIsprs(BoxRoom(), BoxRoom(), p);
  ASSERT_EQ(r.buffers.size(), 3u);
  EXPECT_DOUBLE_EQ(r.all.completeness[1], 1.0);
  EXPECT_DOUBLE_EQ(r.all.correctness[1], 1.0);
}

TEST(IsprsMetrics, WallShiftedThreeCentimetres) {
  const auto truth = BoxRoom();
  auto model = truth;
  for (Vec3& p : model[0].polygon) p.x() -= 0.03;  // west wall 3 cm outwards
  const IsprsResult r = EvaluateIsprs(model, truth, FastIsprs());
  const int b2 = r.BufferIndex(0.02), b4 = r.BufferIndex(0.04);
  // The shifted wall: only its 2 cm strips along the adjacent (unshifted) walls are complete.
  const double strip = 2 * 0.02 / kY;
  EXPECT_NEAR(r.reference_patch_completeness[0][b2], strip, 1e-9);
  EXPECT_DOUBLE_EQ(r.reference_patch_completeness[0][b4], 1.0);
  EXPECT_DOUBLE_EQ(r.source_patch_correctness[0][b2], 0.0);  // 3 cm off everything
  EXPECT_DOUBLE_EQ(r.source_patch_correctness[0][b4], 1.0);
  // Walls, area-weighted: west 12.5 m^2 of 45 m^2.
  const double wall_area = 2 * (kX + kY) * kZ, west = kY * kZ;
  EXPECT_NEAR(r.per_class[0].completeness[b2], (wall_area - west + west * strip) / wall_area, 1e-9);
  EXPECT_NEAR(r.per_class[0].correctness[b2], (wall_area - west) / wall_area, 1e-9);
  EXPECT_DOUBLE_EQ(r.per_class[0].completeness[b4], 1.0);
  EXPECT_DOUBLE_EQ(r.per_class[1].completeness[0 + 1], 1.0);  // floor untouched
  // Accuracy of the shifted wall alone: every sample is 3 cm away.
  const IsprsResult w = EvaluateIsprs({model[0]}, {truth[0]}, FastIsprs());
  EXPECT_NEAR(w.all.accuracy, 0.03, 1e-12);
  IsprsParams tight = FastIsprs();
  tight.cutoff = 0.02;
  EXPECT_TRUE(std::isnan(EvaluateIsprs({model[0]}, {truth[0]}, tight).all.accuracy));
}

TEST(IsprsMetrics, SameBytesWithOneOrTwoThreads) {
  const auto truth = BoxRoom();
  auto model = truth;
  for (Vec3& p : model[2].polygon) p.x() += 0.017;
  std::string one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = ToJson(EvaluateIsprs(model, truth, FastIsprs())).dump();
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = ToJson(EvaluateIsprs(model, truth, FastIsprs())).dump();
  }
  EXPECT_EQ(one, two);
}

std::vector<Vec2> Rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

TEST(FloorplanMetrics, OffsetRoomsGiveIoUOneThird) {
  const std::vector<Room> truth = {{"A", Rect(0, 0, 1, 1)}};
  const std::vector<Room> pred = {{"a", Rect(0.5, 0, 1.5, 1)}};
  const FloorplanResult r = EvaluateFloorplan(pred, truth);
  ASSERT_EQ(r.room_pairs.size(), 1u);
  EXPECT_NEAR(r.room_pairs[0].iou, 1.0 / 3.0, 1e-12);
  EXPECT_FALSE(r.room_pairs[0].true_positive);
  EXPECT_EQ(r.rooms.tp, 0);
  EXPECT_EQ(r.corners[0].score.tp, 0);  // corners of non-TP rooms do not count
}

TEST(FloorplanMetrics, CornersOffsetSevenCentimetres) {
  const std::vector<Room> truth = {{"A", Rect(0, 0, 4, 5)}, {"B", Rect(4, 0, 7, 5)}};
  std::vector<Room> pred = {{"b", Rect(4.07, 0, 7.07, 5)}, {"a", Rect(0.07, 0, 4.07, 5)}};
  const FloorplanResult r = EvaluateFloorplan(pred, truth);
  EXPECT_EQ(r.rooms.tp, 2);
  EXPECT_NEAR(r.rooms.f1, 1.0, 1e-12);
  ASSERT_EQ(r.corners.size(), 3u);
  EXPECT_EQ(r.corners[0].score.n_truth, 8);
  EXPECT_DOUBLE_EQ(r.corners[0].score.recall, 0.0);  // 5 cm
  EXPECT_DOUBLE_EQ(r.corners[1].score.recall, 1.0);  // 10 cm
  EXPECT_DOUBLE_EQ(r.corners[2].score.precision, 1.0);
  EXPECT_DOUBLE_EQ(r.angles.recall, 1.0);
  EXPECT_NEAR(r.truth_room_iou[0], 3.93 / 4.07, 1e-12);
  // A skewed corner (angle off by atan(0.5/5) = 5.7 deg) fails the angle check only there.
  std::vector<Room> skew = {{"a", {{0, 0}, {4, 0}, {4.5, 5}, {0, 5}}}};
  const FloorplanResult s = EvaluateFloorplan(skew, {truth[0]});
  EXPECT_EQ(s.angles.tp, 2);  // corners (0,0) and (0,5) keep 90 deg
}

TEST(FloorplanMetrics, BadRoomThrows) {
  EXPECT_THROW(EvaluateFloorplan({{"x", {{0, 0}, {1, 0}}}}, {}), InputError);
  EXPECT_THROW(EvaluateFloorplan({}, {{"x", {{0, 0}, {1, std::nan("")}, {0, 1}}}}), InputError);
}

TEST(LabelMetrics, ConfusionOfAKnownLabelling) {
  using L = VoxelLabel;
  auto u = [](L l) { return static_cast<std::uint8_t>(l); };
  // truth:  4 structure, 2 empty, 1 clutter, 1 unseen
  // pred:   3 structure + 1 occluded, 1 empty + 1 structure, clutter, unseen
  const std::vector<std::uint8_t> truth = {u(L::kStructure), u(L::kStructure), u(L::kStructure),
                                           u(L::kStructure), u(L::kEmpty),     u(L::kEmpty),
                                           u(L::kClutter),   u(L::kUnseen)};
  const std::vector<std::uint8_t> pred = {
      u(L::kStructure), u(L::kStructure), u(L::kStructure), u(L::kOccludedStructure),
      u(L::kEmpty),     u(L::kStructure), u(L::kClutter),   u(L::kUnseen)};
  const ConfusionMatrix m = ComputeDsm3Confusion(truth, pred);
  EXPECT_EQ(m.total, 8);
  EXPECT_EQ(m.At(1, 1), 3);
  EXPECT_EQ(m.At(1, 2), 1);
  EXPECT_EQ(m.At(4, 1), 1);
  EXPECT_NEAR(m.accuracy, 6.0 / 8.0, 1e-12);
  EXPECT_NEAR(m.iou[1], 3.0 / 5.0, 1e-12);  // TP 3, FN 1, FP 1
  EXPECT_NEAR(m.iou[4], 0.5, 1e-12);
  EXPECT_NEAR(m.iou[2], 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(m.iou[0]));  // no openings anywhere
  EXPECT_NEAR(m.precision[1], 0.75, 1e-12);
  // SM1-style per-point labels with an ignore value.
  const ConfusionMatrix p =
      ComputeConfusion({0, 1, 1, 255}, {0, 1, 0, 1}, {"wall", "clutter"}, 255);
  EXPECT_EQ(p.total, 3);
  EXPECT_NEAR(p.accuracy, 2.0 / 3.0, 1e-12);
  EXPECT_THROW(ComputeConfusion({0, 7}, {0, 0}, {"a", "b"}), InputError);
  EXPECT_THROW(ComputeConfusion({0}, {0, 0}, {"a", "b"}), InputError);
}

TEST(JsonNumber, NonFiniteNumbersBecomeNullInEitherDocumentType) {
  EXPECT_EQ(Num(0.25).dump(), "0.25");
  EXPECT_TRUE(Num(std::nan("")).is_null());
  EXPECT_TRUE(Num(-INFINITY).is_null());
  const nlohmann::ordered_json j = {{"b", Num<nlohmann::ordered_json>(1.5)},
                                    {"a", Num<nlohmann::ordered_json>(NAN)}};
  EXPECT_EQ(j.dump(), R"({"b":1.5,"a":null})");
}

TEST(MetricParams, YamlRoundTripAndBounds) {
  PatchMatchParams pm;
  pm.max_normal_angle_deg = 7.5;
  pm.validation.planarity_tolerance = 0.002;
  const auto pm2 = LoadParams<PatchMatchParams>(SaveParams(pm), "test");
  EXPECT_EQ(pm2.max_normal_angle_deg, 7.5);
  EXPECT_EQ(pm2.validation.planarity_tolerance, 0.002);
  FloorplanParams fp;
  fp.corner_thresholds = {0.02, 0.3};
  EXPECT_EQ(LoadParams<FloorplanParams>(SaveParams(fp), "test").corner_thresholds,
            fp.corner_thresholds);
  const auto ip = LoadParams<IsprsParams>(SaveParams(IsprsParams{}), "test");
  EXPECT_EQ(ip.sample_spacing, 0.01);
  EXPECT_THROW(LoadParams<IsprsParams>(LoadYamlString("sample_spacin: 0.02", "t"), "t"),
               InputError);  // typo rejected
  IsprsParams bad;
  bad.sample_spacing = 0.0;
  EXPECT_THROW(EvaluateIsprs({}, {}, bad), InputError);
}

// A prism column's faces from a plan footprint (CCW), z in [0, kZ], normals pointing out.
std::vector<Patch> ColumnFaces(const std::string& prefix, const std::vector<Vec2>& fp) {
  std::vector<Patch> out;
  for (size_t k = 0; k < fp.size(); ++k) {
    const Vec2 a = fp[k], b = fp[(k + 1) % fp.size()];
    Patch p = Wall(prefix + std::to_string(k + 1), a, b);  // normal (b - a) x z: outward for CCW
    p.cls = SurfaceClass::kColumn;
    out.push_back(p);
  }
  return out;
}

std::vector<Vec2> Square(Vec2 c, double half) {
  return {c + Vec2(-half, -half), c + Vec2(half, -half), c + Vec2(half, half),
          c + Vec2(-half, half)};
}

std::vector<Vec2> Regular(Vec2 c, double r, int n, double phase) {
  std::vector<Vec2> v;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2.0 * kPi * i / n;
    v.push_back(c + r * Vec2(std::cos(a), std::sin(a)));
  }
  return v;
}

TEST(ColumnMetrics, GroupsModelFacesByIdPrefixIntoObjects) {
  std::vector<Patch> model = BoxRoom();
  for (const auto& f : ColumnFaces("column_1_face_", Square({1, 1}, 0.2))) model.push_back(f);
  for (const auto& f : ColumnFaces("column_2_face_", Regular({3, 3}, 0.2, 16, 0.0)))
    model.push_back(f);
  const auto cols = GroupModelColumns(model);
  ASSERT_EQ(cols.size(), 2u);
  EXPECT_EQ(cols[0].id, "column_1");
  EXPECT_EQ(cols[0].faces.size(), 4u);
  EXPECT_NEAR(cols[0].Area(), 0.16, 1e-12);
  EXPECT_NEAR((cols[0].Centre() - Vec2(1, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(cols[0].z_max - cols[0].z_min, kZ, 1e-12);
  EXPECT_EQ(cols[1].id, "column_2");
  EXPECT_EQ(cols[1].faces.size(), 16u);
  EXPECT_EQ(cols[1].footprint.size(), 16u);
  EXPECT_NEAR(cols[1].Area(), 8 * 0.04 * std::sin(kPi / 8), 1e-12);  // (n/2) r^2 sin(2 pi/n)
}

TEST(ColumnMetrics, ShiftedSquareColumnIsATruePositiveWithKnownErrors) {
  const ColumnObject truth = MakeColumnObject("C3", ColumnFaces("C3_", Square({2, 2}, 0.2)));
  // Model shifted 5 cm in x and 2.4 m tall instead of 2.5: IoU 0.35 / 0.45.
  auto faces = ColumnFaces("column_1_face_", Square({2.05, 2}, 0.2));
  for (auto& f : faces)
    for (auto& v : f.polygon) v.z() = std::min(v.z(), 2.4);
  const ColumnObject model = MakeColumnObject("column_1", faces);
  const ColumnEvaluation e = EvaluateColumns({model}, {truth});
  EXPECT_EQ(e.detection.tp, 1);
  EXPECT_EQ(e.detection.fp, 0);
  EXPECT_EQ(e.detection.fn, 0);
  ASSERT_EQ(e.pairs.size(), 1u);
  EXPECT_NEAR(e.pairs[0].plan_iou, 0.35 / 0.45, 1e-9);
  EXPECT_NEAR(e.pairs[0].centre_error, 0.05, 1e-9);
  EXPECT_NEAR(e.pairs[0].area_error, 0.0, 1e-9);
  EXPECT_NEAR(e.pairs[0].height_error, 0.1, 1e-9);
  // Square truth: faces are paired; the x faces are 5 cm off the plane, all parallel.
  EXPECT_TRUE(e.pairs[0].faces_compared);
  EXPECT_EQ(e.face_detection.tp, 4);
  EXPECT_NEAR(e.face_accuracy.phi_deg.max, 0.0, 1e-9);
  EXPECT_NEAR(e.face_accuracy.d_v.mean, 0.1, 1e-9);  // every vertical edge 0.1 m short
}

TEST(ColumnMetrics, RoundColumnIsScoredAsAnObjectWithoutFacePairs) {
  // Truth: 16 facets of radius 0.2; model: a 16-gon of radius 0.21 turned by half a facet,
  // 1 cm off centre. Equivalent diameter scales with the vertex radius.
  const ColumnObject truth =
      MakeColumnObject("C1", ColumnFaces("C1_", Regular({5, 3.8}, 0.2, 16, 0.0)));
  const ColumnObject model = MakeColumnObject(
      "column_1", ColumnFaces("column_1_face_", Regular({5.01, 3.8}, 0.21, 16, kPi / 16)));
  const ColumnEvaluation e = EvaluateColumns({model}, {truth});
  ASSERT_EQ(e.detection.tp, 1);
  EXPECT_FALSE(e.pairs[0].faces_compared);
  EXPECT_EQ(e.face_detection.n_truth, 0);
  EXPECT_NEAR(e.pairs[0].centre_error, 0.01, 1e-9);
  const double k = 2.0 * std::sqrt(8.0 * std::sin(kPi / 8) / kPi);
  EXPECT_NEAR(e.pairs[0].diameter_error, k * 0.01, 1e-9);
  EXPECT_GT(e.pairs[0].plan_iou, 0.85);
}

TEST(ColumnMetrics, FarOrSmallColumnsAreFalsePositivesAndNegatives) {
  const ColumnObject c1 = MakeColumnObject("C1", ColumnFaces("C1_", Square({1, 1}, 0.2)));
  const ColumnObject c2 = MakeColumnObject("C2", ColumnFaces("C2_", Square({3, 1}, 0.2)));
  // Model: one at C2 but 0.4 x 0.2 of it (IoU exactly 0.5: not > 0.5), one far away.
  const ColumnObject half = MakeColumnObject(
      "column_1", ColumnFaces("column_1_face_", {{2.8, 0.8}, {3.2, 0.8}, {3.2, 1.0}, {2.8, 1.0}}));
  const ColumnObject far =
      MakeColumnObject("column_2", ColumnFaces("column_2_face_", Square({6, 6}, 0.2)));
  const ColumnEvaluation e = EvaluateColumns({half, far}, {c1, c2});
  EXPECT_EQ(e.detection.tp, 0);
  EXPECT_EQ(e.detection.fp, 2);
  EXPECT_EQ(e.detection.fn, 2);
  EXPECT_EQ(e.unmatched_truth_ids, (std::vector<std::string>{"C1", "C2"}));
  ColumnMatchParams loose;
  loose.min_plan_iou = 0.4;
  const ColumnEvaluation l = EvaluateColumns({half, far}, {c1, c2}, loose);
  EXPECT_EQ(l.detection.tp, 1);
  EXPECT_EQ(l.pairs[0].truth_id, "C2");
  EXPECT_NEAR(l.pairs[0].plan_iou, 0.5, 1e-9);
  EXPECT_THROW(MakeColumnObject("x", {}), InputError);
}

TEST(Reports, JsonMarkdownAndSvgCarryTheNumbers) {
  const auto truth = BoxRoom();
  auto model = truth;
  model[0] = Wall("wall_W", {0, 0}, {0, kY - 0.10});
  const PatchEvaluation e = EvaluatePatches(model, truth);
  const nlohmann::json j = ToJson(e);
  EXPECT_EQ(j["classes"]["wall"]["tp"], 4);
  EXPECT_NEAR(j["d_h"]["max"].get<double>(), 0.10, 1e-12);
  const std::string md = MarkdownPatchTable(e);
  EXPECT_NE(md.find("| wall | 4 | 4 | 0 | 0 | 100.0 | 0.00 | 0.00 | 2.50 | 10.00 |"),
            std::string::npos)
      << md;
  const IsprsResult r = EvaluateIsprs(model, truth, FastIsprs());
  const nlohmann::json ji = ToJson(r);
  EXPECT_TRUE(ji["classes"]["column"]["completeness"][3].is_null());  // NaN -> null
  EXPECT_NE(MarkdownIsprsTable(r, 0.05).find("completeness @5 cm"), std::string::npos);
  const std::string svg = IsprsSvgPlot(r, "box <room>");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("box &lt;room&gt;"), std::string::npos);
  size_t lines = 0;
  for (size_t pos = 0; (pos = svg.find("<polyline", pos)) != std::string::npos; ++pos) ++lines;
  EXPECT_EQ(lines, 8u);  // wall, floor, ceiling, all x (completeness, correctness)
  EXPECT_EQ(svg.find("href"), std::string::npos);  // self-contained
  const ConfusionMatrix m = ComputeDsm3Confusion({1, 1}, {1, 4});
  EXPECT_NE(MarkdownConfusionTable(m).find("| structure | 0 | 1 | 0 | 0 | 1 | 0 |"),
            std::string::npos)
      << MarkdownConfusionTable(m);
  EXPECT_EQ(ToJson(m)["counts"][1][4], 1);
}

}  // namespace
}  // namespace mopad::evaluation
