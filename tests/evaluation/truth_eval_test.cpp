// Truth-side figures on rooms built in code with known answers: structural surface
// cells, reachable positions, observable area, coverage, registration error, SM1 label truth.

#include "evaluation/truth_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "common/error.h"
#include "common/polygon.h"
#include "evaluation/coverage.h"
#include "evaluation/observability.h"
#include "evaluation/scan_eval.h"
#include "evaluation/truth_surfaces.h"
#include "io/scan_io.h"
#include "scenes/generator.h"
#include "scenes/geometry.h"
#include "scenes/scene_spec.h"
#include "sim/threads.h"
#include "sim/tls_params.h"
#include "sim/tls_scanner.h"
#include "tests/sim/test_scenes.h"

namespace mopad::evaluation {
namespace {

using scenes::ElementClass;
using sim::testing::AddRoomBox;
using sim::testing::AddRoomWithOpening;
using V = Eigen::Vector3f;

#ifndef MOPAD_TRUTH_FIGURES  // unit tests; the figures binary builds only the #else part

constexpr double kW = 5.0, kD = 4.0, kH = 2.8;

/// Ground truth of a box room "R" [0,W]x[0,D] with the six elements of AddRoomBox.
scenes::GroundTruth BoxTruth(double W, double D, double H) {
  scenes::GroundTruth t;
  scenes::Room r;
  r.id = "R";
  r.polygon = {{0, 0}, {W, 0}, {W, D}, {0, D}};
  r.floor_z = 0;
  r.ceiling_z = H;
  t.rooms.push_back(r);
  const std::pair<const char*, ElementClass> els[] = {
      {"floor", ElementClass::kFloor}, {"ceiling", ElementClass::kCeiling},
      {"wall_s", ElementClass::kWall}, {"wall_e", ElementClass::kWall},
      {"wall_n", ElementClass::kWall}, {"wall_w", ElementClass::kWall}};
  for (const auto& [id, cls] : els) {
    scenes::StructuralElement e;
    e.id = id;
    e.element_class = cls;
    e.rooms = {"R"};
    t.elements.push_back(e);
  }
  return t;
}

scenes::Scene BoxScene(double W, double D, double H) {
  scenes::Scene s;
  s.source = "box";
  AddRoomBox(s, V(0, 0, 0), V(W, D, H));
  return s;
}

/// A closed box of furniture [lo, hi] (faces outward).
void AddFurnitureBox(scenes::Scene& s, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                     const std::string& id) {
  scenes::MeshPart p;
  p.name = p.element_id = id;
  p.element_class = ElementClass::kFurniture;
  scenes::PartBuilder(&p).AddBox(Eigen::Isometry3d::Identity(), lo, hi);
  s.parts.push_back(std::move(p));
}

double AreaOf(const StructuralSurfaces& s, const std::vector<std::uint8_t>& flags,
              ElementClass cls) {
  double a = 0;
  for (std::size_t k = 0; k < s.cells.size(); ++k)
    if (flags[k] && s.cells[k].element_class == cls) a += s.cells[k].area;
  return a;
}

// ---------------------------------------------------------------- structural surfaces

TEST(TruthSurfaces, BoxRoomAreaIsAnalyticPerElement) {
  const StructuralSurfaces s =
      SampleStructuralSurfaces(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R");
  const double total = 2 * kW * kD + 2 * (kW + kD) * kH;  // 90.4 m^2
  EXPECT_NEAR(s.TotalArea(), total, 0.01 * total);
  EXPECT_NEAR(s.TotalArea(), total, 1e-4);  // in fact exact up to float vertices
  ASSERT_EQ(s.elements.size(), 6u);
  EXPECT_NEAR(s.elements[0].area, kW * kD, 1e-4);
  EXPECT_NEAR(s.elements[2].area, kW * kH, 1e-4);  // wall_s
  EXPECT_NEAR(s.elements[3].area, kD * kH, 1e-4);  // wall_e
  // 5 cm cells: the 5 x 4 floor is exactly 100 x 80 whole cells.
  std::size_t floor_cells = 0;
  for (const SurfaceCell& c : s.cells) {
    if (c.element == 0) {
      ++floor_cells;
      EXPECT_NEAR(c.area, 0.0025, 1e-9);
      EXPECT_NEAR(c.normal.z(), 1.0, 1e-9);
    }
  }
  EXPECT_EQ(floor_cells, 8000u);
}

TEST(TruthSurfaces, OpeningIsCutOutAndCellsLieOnTheirSurface) {
  scenes::Scene scene;
  scene.source = "opening";
  AddRoomWithOpening(scene, 5.f, 4.f, 2.8f, 1.03f, 2.0f, 0.0f, 2.1f);  // door 0.97 x 2.1 in wall_e
  const StructuralSurfaces s = SampleStructuralSurfaces(scene, BoxTruth(5, 4, 2.8), "R");
  EXPECT_NEAR(s.elements[3].area, 4 * 2.8 - 0.97 * 2.1, 1e-4);
  EXPECT_NEAR(s.TotalArea(), 90.4 - 0.97 * 2.1, 1e-4);
  for (std::size_t k = 0; k < s.cells.size(); ++k) {
    const SurfaceCell& c = s.cells[k];
    if (c.element != 3) continue;
    EXPECT_NEAR(c.centre.x(), 5.0, 1e-6);
    // Centres are on the wall, never inside the door hole.
    EXPECT_FALSE(c.centre.y() > 1.03 + 1e-6 && c.centre.y() < 2.0 - 1e-6 &&
                 c.centre.z() < 2.1 - 1e-6)
        << k << " " << c.centre.transpose() << " a=" << c.area;
    EXPECT_EQ(s.FindCell(c.centre + 0.01 * c.normal, 0.03), static_cast<std::int32_t>(k));
  }
  EXPECT_EQ(s.FindCell(Eigen::Vector3d(5.0, 1.5, 1.0), 0.03), -1);  // in the hole
  EXPECT_THROW(SampleStructuralSurfaces(scene, BoxTruth(5, 4, 2.8), "nope"), InputError);
}

// ---------------------------------------------------------------- reachable and observable

TEST(Observability, ReachableLatticeOfAnEmptyBoxIsTheShrunkRectangle) {
  const ReachableArea r = ComputeReachable(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R");
  // Centres with clearance > 0.35 m: x in (0.35, 4.65), y in (0.35, 3.65); 0.2 m lattice:
  // x = 0.4 .. 4.6 (22 values), y = 0.4 .. 3.6 (17 values).
  EXPECT_EQ(r.positions.size(), 22u * 17u);
  EXPECT_NEAR(r.free_area, 4.3 * 3.3, 0.05 * 4.3 * 3.3);
  for (const auto& p : r.positions) {
    EXPECT_GT(p.x(), 0.35);
    EXPECT_LT(p.x(), 4.65);
    EXPECT_GT(p.y(), 0.35);
    EXPECT_LT(p.y(), 3.65);
  }
}

TEST(Observability, EmptyBoxIsFullyObservable) {
  // Every wall point has a position 0.4-4.6 m away within -40..+60 deg; every floor point one
  // more than 1.4 / tan 40 = 1.67 m away; every ceiling point one more than 0.81 m away.
  const scenes::Scene scene = BoxScene(kW, kD, kH);
  const scenes::GroundTruth truth = BoxTruth(kW, kD, kH);
  const StructuralSurfaces s = SampleStructuralSurfaces(scene, truth, "R");
  const sim::EmbreeWorld world(scene, &truth);
  const Observability o = ComputeObservability(world, s, ComputeReachable(scene, truth, "R"));
  EXPECT_NEAR(o.total_area, 90.4, 1e-4);
  EXPECT_NEAR(o.observable_area, o.total_area, 1e-9);
}

TEST(Observability, UnseenFloorAndCeilingMatchTheElevationLimits) {
  // A fat robot (radius 1.7 m) in a 4 x 4 room can stand only on the 9 lattice points
  // {1.8, 2.0, 2.2}^2. A floor point is visible from a position >= 1.4 / tan 40 deg away
  // (elevation limit -40), a ceiling point from one >= 1.4 / tan 60 deg away (+60). Walls are
  // >= 1.8 m away: always within -37.9..+37.9 deg. The area never seen is computed here by plain
  // integration, independent of ray casting.
  const double W = 4, D = 4, H = 2.8;
  const scenes::Scene scene = BoxScene(W, D, H);
  const scenes::GroundTruth truth = BoxTruth(W, D, H);
  ObservabilityParams p;
  p.robot_radius = 1.7;
  const ReachableArea r = ComputeReachable(scene, truth, "R", p);
  ASSERT_EQ(r.positions.size(), 9u);
  const StructuralSurfaces s = SampleStructuralSurfaces(scene, truth, "R");
  const sim::EmbreeWorld world(scene, &truth);
  const Observability o = ComputeObservability(world, s, r, p);

  const auto unseen_disc_area = [&](double min_h) {
    const double step = 0.002;
    double a = 0;
    for (double y = step / 2; y < D; y += step)
      for (double x = step / 2; x < W; x += step) {
        bool seen = false;
        for (const auto& q : r.positions)
          seen = seen || (Eigen::Vector2d(x, y) - q).norm() >= min_h;
        if (!seen) a += step * step;
      }
    return a;
  };
  const double floor_unseen = unseen_disc_area(1.4 / std::tan(DegToRad(40.0)));
  const double ceiling_unseen = unseen_disc_area(1.4 / std::tan(DegToRad(60.0)));
  EXPECT_GT(floor_unseen, 5.0);  // ~ a disc of radius 1.67 - 0.28
  EXPECT_GT(ceiling_unseen, 0.7);
  // Cells are classified by their centre: allow half a cell row around the ~9 m and ~3.3 m rims.
  EXPECT_NEAR(AreaOf(s, o.observable, ElementClass::kFloor), W * D - floor_unseen, 0.05);
  EXPECT_NEAR(AreaOf(s, o.observable, ElementClass::kCeiling), W * D - ceiling_unseen, 0.03);
  EXPECT_NEAR(AreaOf(s, o.observable, ElementClass::kWall), 4 * W * H, 1e-6);
}

TEST(Observability, CabinetAgainstAWallHidesItsFootprintOnWallAndFloor) {
  const scenes::GroundTruth truth = BoxTruth(kW, kD, kH);
  const scenes::Scene empty = BoxScene(kW, kD, kH);
  scenes::Scene with = empty;
  // 1.0 m wide, 0.5 m deep, 1.0 m high, flush with the south wall. (With a gap of 1 cm, the
  // wall cells next to its sides are seen through the gap at grazing angles.)
  AddFurnitureBox(with, {2.0, 0.0, 0.0}, {3.0, 0.5, 1.0}, "cabinet_1");
  const auto observable = [&](const scenes::Scene& scene) {
    const StructuralSurfaces s = SampleStructuralSurfaces(scene, truth, "R");
    const sim::EmbreeWorld world(scene, &truth);
    const Observability o = ComputeObservability(world, s, ComputeReachable(scene, truth, "R"));
    return std::make_pair(o, s);
  };
  const auto [o0, s0] = observable(empty);
  const auto [o1, s1] = observable(with);
  EXPECT_NEAR(o1.total_area, o0.total_area, 1e-9);  // the truth surfaces do not change
  const double wall_drop = AreaOf(s0, o0.observable, ElementClass::kWall) -
                           AreaOf(s1, o1.observable, ElementClass::kWall);
  const double floor_drop = AreaOf(s0, o0.observable, ElementClass::kFloor) -
                            AreaOf(s1, o1.observable, ElementClass::kFloor);
  // Wall behind it: 1.0 x 1.0; floor under it 1.0 x 0.5.
  std::printf("cabinet: wall drop %.4f m2, floor drop %.4f m2\n", wall_drop, floor_drop);
  EXPECT_NEAR(wall_drop, 1.0, 0.03);
  EXPECT_NEAR(floor_drop, 0.5, 0.05);
  EXPECT_NEAR(AreaOf(s1, o1.observable, ElementClass::kCeiling), kW * kD, 1e-6);
}

TEST(Observability, SameBytesWithOneAndTwoThreads) {
  const scenes::GroundTruth truth = BoxTruth(kW, kD, kH);
  scenes::Scene scene = BoxScene(kW, kD, kH);
  AddFurnitureBox(scene, {1.0, 1.0, 0.0}, {1.8, 1.6, 0.75}, "desk_1");
  const StructuralSurfaces s = SampleStructuralSurfaces(scene, truth, "R");
  const sim::EmbreeWorld world(scene, &truth);
  const ReachableArea r = ComputeReachable(scene, truth, "R");
  Observability a, b;
  sim::RunWithThreads(1, [&] { a = ComputeObservability(world, s, r); });
  sim::RunWithThreads(2, [&] { b = ComputeObservability(world, s, r); });
  EXPECT_EQ(a.observable, b.observable);
  EXPECT_EQ(a.rays, b.rays);
  EXPECT_LT(a.observable_area, a.total_area);  // the floor under the desk top near its legs
}

TEST(Observability, AgreesWithABruteForceSingleRayCheck) {
  // Every (cell, position) pair traced with Intersect, no early exit, no packets.
  const scenes::GroundTruth truth = BoxTruth(kW, kD, kH);
  scenes::Scene scene = BoxScene(kW, kD, kH);
  AddFurnitureBox(scene, {1.0, 1.0, 0.0}, {1.8, 1.6, 0.75}, "desk_1");
  AddFurnitureBox(scene, {3.5, 0.0, 0.0}, {4.5, 0.4, 1.8}, "shelf_1");
  SurfaceSamplingParams sp;
  sp.cell_size = 0.1;
  ObservabilityParams p;
  p.grid_step = 0.5;
  p.range_max = 4.0;  // makes the far corners depend on position too
  const StructuralSurfaces s = SampleStructuralSurfaces(scene, truth, "R", sp);
  // Robust (watertight) traversal: the fast one may, rarely, let a ray aimed exactly at a shared
  // edge slip through to the surface behind (here the floor under a closed box).
  sim::WorldOptions wo;
  wo.robust = true;
  const sim::EmbreeWorld world(scene, &truth, wo);
  const ReachableArea r = ComputeReachable(scene, truth, "R", p);
  ASSERT_GT(r.positions.size(), 20u);
  const Observability o = ComputeObservability(world, s, r, p);
  std::size_t seen = 0;
  for (std::size_t k = 0; k < s.cells.size(); ++k) {
    const SurfaceCell& c = s.cells[k];
    bool visible = false;
    for (const Eigen::Vector2d& q : r.positions) {
      const Eigen::Vector3d o3(q.x(), q.y(), p.mast_height);
      const Eigen::Vector3d d = c.centre - o3;
      const double L = d.norm();
      const double el = RadToDeg(std::asin(d.z() / L));
      if (c.normal.dot(d) >= 0 || L < p.range_min || L > p.range_max || el > p.elevation_max_deg ||
          el < p.elevation_min_deg)
        continue;
      const sim::RayHit h = world.Intersect(o3.cast<float>(), (d / L).cast<float>());
      if (h.hit() && scene.parts[h.part].element_id == s.elements[c.element].id &&
          std::abs(h.t - L) <= p.hit_tolerance) {
        visible = true;
        break;
      }
    }
    EXPECT_EQ(o.observable[k], visible ? 1 : 0)
        << k << " centre " << c.centre.transpose() << " el " << s.elements[c.element].id;
    seen += visible;
  }
  EXPECT_GT(seen, s.cells.size() / 2);
  EXPECT_LT(seen, s.cells.size());
}

TEST(Observability, BadParamsThrow) {
  ObservabilityParams p;
  p.body_z_max = 0.01;
  EXPECT_THROW(ComputeReachable(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R", p), InputError);
  p = {};
  p.grid_step = 0;
  EXPECT_THROW(ComputeReachable(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R", p), InputError);
}

TEST(TruthEvalParams, EveryFieldIsInTheFieldList) {
  for (const auto& m : FieldsMissingFromVisit(TruthEvalParams{}, "eval.")) ADD_FAILURE() << m;
}

TEST(TruthEvalParams, YamlRoundTripAndUnknownKeys) {
  TruthEvalParams p;
  p.observability.robot_radius = 0.4;
  p.surfaces.cell_size = 0.1;
  p.coverage.distance_tolerance = 0.02;
  p.labels.outside_margin = 0.05;
  const TruthEvalParams q = LoadParams<TruthEvalParams>(SaveParams(p), "saved");
  EXPECT_EQ(q.observability.robot_radius, 0.4);
  EXPECT_EQ(q.surfaces.cell_size, 0.1);
  EXPECT_EQ(q.coverage.distance_tolerance, 0.02);
  EXPECT_EQ(q.labels.outside_margin, 0.05);
  EXPECT_EQ(YAML::Dump(SaveParams(q)), YAML::Dump(SaveParams(p)));
  EXPECT_THROW(LoadParams<TruthEvalParams>(
                   LoadYamlString("observability: {robot_radus: 0.3}", "x.yaml"), "x.yaml"),
               InputError);
  EXPECT_THROW(
      LoadParams<TruthEvalParams>(LoadYamlString("surfaces: {cell_size: 0}", "x.yaml"), "x.yaml"),
      InputError);
}

// ---------------------------------------------------------------- coverage

TEST(TruthSurfaces, ABuildingAsBuiltIsSampledOnItsDesignSurfaces) {
  // The as-built walls bow by millimetres: sampled as triangles they would fall into many
  // planes; taken back through the field they are the design's planes and cells again.
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  const auto design = scenes::Generate(spec);
  spec.as_built.flatness_mm = 4.0;
  spec.as_built.lean_sigma_deg = 0.1;
  const auto built = scenes::Generate(spec);
  const StructuralSurfaces a = SampleStructuralSurfaces(design.scene, design.truth, "R1");
  const StructuralSurfaces b = SampleStructuralSurfaces(built.scene, built.truth, "R1");
  EXPECT_EQ(b.planes.size(), a.planes.size());
  // Cells: the same squares, up to slivers where a design edge falls on a square's side and the
  // field's inverse leaves it micrometres off (under 1 %).
  EXPECT_NEAR(static_cast<double>(b.cells.size()), static_cast<double>(a.cells.size()),
              0.01 * static_cast<double>(a.cells.size()));
  EXPECT_NEAR(b.TotalArea(), a.TotalArea(), 1e-3 * a.TotalArea());
  for (std::size_t k = 0; k < a.planes.size(); ++k)
    EXPECT_NEAR(b.planes[k].offset, a.planes[k].offset, 1e-5);
  // ... while without the field's record the same mesh falls apart into partial planes.
  scenes::GroundTruth unrecorded = built.truth;
  unrecorded.as_built = {};
  EXPECT_GT(SampleStructuralSurfaces(built.scene, unrecorded, "R1").planes.size(),
            3 * a.planes.size());
}

TEST(Coverage, PointsOnOneWallCoverExactlyThatWallsShare) {
  const StructuralSurfaces s =
      SampleStructuralSurfaces(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R");
  // The map frame is the world moved by 10 m and turned by 30 deg.
  Pose3 X_WM = Pose3::Identity();
  X_WM.translation() = Eigen::Vector3d(10, -3, 0.5);
  X_WM.linear() = Eigen::AngleAxisd(DegToRad(30), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> p_M;
  for (double x = 0.01; x < kW; x += 0.02)
    for (double z = 0.01; z < kH; z += 0.02) {
      p_M.push_back((X_WM.inverse() * Eigen::Vector3d(x, 0.0, z)).cast<float>());  // on wall_s
      p_M.push_back((X_WM.inverse() * Eigen::Vector3d(0.5 + 0.8 * x, 0.5, 0.2 + 0.8 * z))
                        .cast<float>());  // air
    }
  const CoverageReport rep = ComputeCoverage(s, {}, p_M, X_WM);
  const double wall = kW * kH, total = s.TotalArea();
  EXPECT_NEAR(rep.room.sensed_area, wall, 1e-6);
  EXPECT_NEAR(rep.room.ShareOfTotal(), wall / total, 1e-6);
  EXPECT_NEAR(rep.room.ShareOfObservable(), wall / total, 1e-6);
  EXPECT_EQ(rep.points_on_cells, p_M.size() / 2);
  ASSERT_EQ(rep.per_element.size(), 6u);
  EXPECT_EQ(rep.per_element[2].name, "wall_s");
  EXPECT_NEAR(rep.per_element[2].ShareOfTotal(), 1.0, 1e-9);
  EXPECT_NEAR(rep.per_element[3].ShareOfTotal(), 0.0, 1e-9);
  ASSERT_EQ(rep.per_class.size(), 3u);  // wall, floor, ceiling
  EXPECT_EQ(rep.per_class[0].name, "wall");
  EXPECT_NEAR(rep.per_class[0].ShareOfTotal(), wall / (2 * (kW + kD) * kH), 1e-6);
  // Observable share: if half the wall were unobservable, the other half counts alone.
  std::vector<std::uint8_t> obs(s.cells.size(), 1);
  for (std::size_t k = 0; k < s.cells.size(); ++k)
    if (s.cells[k].element == 2 && s.cells[k].centre.x() > 2.5) obs[k] = 0;
  const CoverageReport half = ComputeCoverage(s, obs, p_M, X_WM);
  EXPECT_NEAR(half.room.observable_area, total - wall / 2, 1e-6);
  EXPECT_NEAR(half.room.sensed_observable_area, wall / 2, 1e-6);
  EXPECT_NEAR(half.room.sensed_area, wall, 1e-6);
  EXPECT_NEAR(half.room.ShareOfTotal(), wall / 2 / total, 1e-6);  // unobservable cells never count
  EXPECT_NE(CoverageToJson(rep).find("\"name\": \"wall_s\""), std::string::npos);
  // Through a PLY file, same answer.
  io::PointCloud cloud;
  cloud.points = p_M;
  const std::string path =
      (std::filesystem::temp_directory_path() / "mopad_truth_eval_cov.ply").string();
  io::WritePly(path, cloud);
  EXPECT_EQ(CoverageToJson(ComputeCoverageFromPly(s, {}, path, X_WM)), CoverageToJson(rep));
  std::remove(path.c_str());
}

TEST(Coverage, PointsBeyondTheToleranceDoNotCount) {
  const StructuralSurfaces s =
      SampleStructuralSurfaces(BoxScene(kW, kD, kH), BoxTruth(kW, kD, kH), "R");
  std::vector<Eigen::Vector3f> p = {Eigen::Vector3f(2.5f, 2.0f, 0.04f)};  // 4 cm above the floor
  EXPECT_EQ(ComputeCoverage(s, {}, p, Pose3::Identity()).room.sensed_area, 0.0);
  CoverageParams wide;
  wide.distance_tolerance = 0.05;
  EXPECT_NEAR(ComputeCoverage(s, {}, p, Pose3::Identity(), wide).room.sensed_area, 0.0025, 1e-9);
}

// ---------------------------------------------------------------- registration error

TEST(ScanEval, RegistrationErrorOfAKnownOffset) {
  Pose3 X_WS = Pose3::Identity();
  X_WS.translation() = Eigen::Vector3d(3, 2, 1.4);
  X_WS.linear() =
      Eigen::AngleAxisd(1.0, Eigen::Vector3d(0.1, 0.2, 1).normalized()).toRotationMatrix();
  Pose3 X_WM = Pose3::Identity();
  X_WM.translation() = Eigen::Vector3d(-1, 4, 0);
  X_WM.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  sim::TlsTruth truth;
  truth.X_WS = X_WS;
  const Pose3 X_MS = X_WM.inverse() * X_WS;
  EXPECT_TRUE(TrueScannerPoseInMap(X_WM, truth).isApprox(X_MS, 1e-12));
  Pose3 offset = Pose3::Identity();
  offset.translation() = Eigen::Vector3d(0.003, 0.004, 0);  // 5 mm
  offset.linear() =
      Eigen::AngleAxisd(DegToRad(0.07), Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const PoseError e = ScanRegistrationError(X_MS * offset, X_WM, truth);
  EXPECT_NEAR(e.translation, 0.005, 1e-12);
  EXPECT_NEAR(e.rotation_deg, 0.07, 1e-9);
  const PoseError big =
      RegistrationError(X_MS * Eigen::AngleAxisd(DegToRad(179.0), Eigen::Vector3d::UnitZ()), X_MS);
  EXPECT_NEAR(big.rotation_deg, 179.0, 1e-9);
  EXPECT_NEAR(big.translation, 0.0, 1e-12);
}

// ---------------------------------------------------------------- SM1 label truth

TEST(ScanEval, TruthLabelsOfHandMadeReturns) {
  // Room R = [0,5]x[0,4]; scanner at (2, 2, 1.4) looking along +x (identity rotation).
  const scenes::GroundTruth gt = BoxTruth(kW, kD, kH);
  interfaces::TlsScan scan;
  sim::TlsTruth truth;
  scan.rows = truth.rows = 1;
  scan.columns = truth.columns = 7;
  truth.X_WS.translation() = Eigen::Vector3d(2, 2, 1.4);
  truth.element_ids = {"wall_e", "desk_R_1", "wall_x_R2", "D1", "floor"};
  struct Case {
    Eigen::Vector3d p_S;  // measured, scanner frame
    int element;
    ElementClass cls;
    std::uint8_t flags;
    Sm1Label expected;
  };
  const Case cases[] = {
      {{3.0, 0, 0}, 0, ElementClass::kWall, 0, Sm1Label::kInlier},           // own wall at x = 5
      {{1.0, 0, -0.6}, 1, ElementClass::kFurniture, 0, Sm1Label::kClutter},  // desk in the room
      {{6.0, 0, 0}, 2, ElementClass::kWall, 0, Sm1Label::kOutlier},  // next room's wall, x = 8
      {{3.1, 0, 0},
       3,
       ElementClass::kDoorLeaf,
       0,
       Sm1Label::kOutlier},  // closed leaf 10 cm in the wall
      {{2.99, 0, 0},
       3,
       ElementClass::kDoorFrame,
       0,
       Sm1Label::kClutter},  // casing 1 cm proud of it
      {{1.0, 0, -1.4},
       4,
       ElementClass::kFloor,
       sim::kTruthTransmitted,
       Sm1Label::kOutlier},                                         // via glass
      {{0, 0, 0}, -1, ElementClass::kUnknown, 0, Sm1Label::kNone},  // no return
  };
  for (const Case& c : cases) {
    interfaces::TlsPoint p;
    p.x = static_cast<float>(c.p_S.x());
    p.y = static_cast<float>(c.p_S.y());
    p.z = static_cast<float>(c.p_S.z());
    p.range = static_cast<float>(c.p_S.norm());
    scan.points.push_back(p);
    sim::TlsPointTruth t;
    t.element = c.element;
    t.element_class = static_cast<std::uint8_t>(c.cls);
    t.flags = c.flags;
    t.true_range = static_cast<float>(c.p_S.norm());
    truth.points.push_back(t);
  }
  const std::vector<Sm1Label> labels = TruthLabels(scan, truth, gt, "R");
  for (std::size_t i = 0; i < labels.size(); ++i) EXPECT_EQ(labels[i], cases[i].expected) << i;

  // One estimate wrong (the leaf called clutter), one unlabelled (the desk): 4 of 6 right.
  const std::vector<std::uint8_t> est = {1, 0, 2, 3, 3, 2, 0};
  const LabelAccuracy acc = CompareLabels(labels, est);
  EXPECT_EQ(acc.points, 6u);
  EXPECT_EQ(acc.correct, 4u);
  EXPECT_EQ(acc.unlabelled, 1u);
  EXPECT_NEAR(acc.Accuracy(), 4.0 / 6.0, 1e-12);
  EXPECT_EQ(acc.confusion[0][0], 1u);  // inlier -> inlier
  EXPECT_EQ(acc.confusion[1][1], 2u);  // outlier -> outlier
  EXPECT_EQ(acc.confusion[1][2], 1u);  // outlier -> clutter
  EXPECT_EQ(acc.confusion[2][2], 1u);  // clutter -> clutter
  EXPECT_NE(LabelAccuracyToJson(acc).find("\"accuracy\": 0.666667"), std::string::npos)
      << LabelAccuracyToJson(acc);
  const std::vector<std::uint8_t> bad = {1, 0, 2, 3, 3, 7, 0};
  EXPECT_THROW(CompareLabels(labels, bad), InputError);
  EXPECT_THROW(TruthLabels(scan, truth, gt, "nope"), InputError);
}

TEST(ScanEval, SimulatedScanOfABoxRoomWithAnOpeningIsLabelledFromItsTruth) {
  // Room [0,5]x[0,4] whose east wall has a 1 x 2 m hole; behind it a wall of another room at
  // x = 7 and a desk-sized box inside. Real scanner, real truth sidecar.
  scenes::Scene scene;
  scene.source = "opening";
  AddRoomWithOpening(scene, 5.f, 4.f, 2.8f, 1.5f, 2.5f, 0.0f, 2.0f);
  sim::testing::AddQuad(scene, V(7, 0, 0), V(7, 0, 2.8f), V(7, 4, 2.8f), V(7, 4, 0),
                        ElementClass::kWall, "wall_far");
  AddFurnitureBox(scene, {1.0, 2.8, 0.0}, {2.0, 3.5, 0.75}, "desk_R_1");
  const scenes::GroundTruth gt = BoxTruth(5, 4, 2.8);
  const sim::EmbreeWorld world(scene, &gt);
  sim::TlsParams tp;
  tp.step_deg = 1.0;
  const sim::TlsScanner scanner(world, tp);
  sim::ScanRequest req;
  req.X_WB.translation() = Eigen::Vector3d(2.5, 1.5, 0);
  sim::TlsTruth truth;
  const interfaces::TlsScan scan = scanner.Scan(req, &truth);
  const std::vector<Sm1Label> labels = TruthLabels(scan, truth, gt, "R");
  std::size_t n[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < labels.size(); ++i) {
    ++n[static_cast<int>(labels[i])];
    const sim::TlsPointTruth& t = truth.points[i];
    if (labels[i] == Sm1Label::kNone) continue;
    const std::string& id = truth.element_ids[t.element];
    if (id == "wall_far") {
      EXPECT_EQ(labels[i], Sm1Label::kOutlier);
    } else if (id == "desk_R_1") {
      EXPECT_EQ(labels[i], Sm1Label::kClutter);
    } else if (id == "wall_e" || id == "floor") {
      EXPECT_EQ(labels[i], Sm1Label::kInlier);
    }
  }
  EXPECT_GT(n[1], 10000u);
  EXPECT_GT(n[2], 50u);
  EXPECT_GT(n[3], 50u);
  // The same labels through the PLY order, compared with themselves, are all right.
  const std::vector<Sm1Label> ply = InPlyOrder(scan, labels);
  EXPECT_EQ(ply.size(), n[1] + n[2] + n[3]);
  EXPECT_EQ(CompareLabels(ply, ply).Accuracy(), 1.0);
}

#else  // MOPAD_TRUTH_FIGURES
// ---------------------------------------------------------------- figures (LABELS long)

/// Area of room `room`'s structural elements from the truth alone: element polygons (Newell)
/// minus the opening rectangles their walls host.
double AnalyticStructuralArea(const scenes::GroundTruth& t, const std::string& room) {
  double a = 0;
  for (const scenes::StructuralElement& e : t.elements) {
    if (!scenes::IsStructural(e.element_class) ||
        std::find(e.rooms.begin(), e.rooms.end(), room) == e.rooms.end())
      continue;
    for (const auto& poly : e.polygons) a += PolygonArea3d(poly);
    for (const scenes::Opening& o : t.openings)
      if (std::find(o.host_walls.begin(), o.host_walls.end(), e.id) != o.host_walls.end())
        a -= (o.u1 - o.u0) * (o.v1 - o.v0);
  }
  return a;
}

TEST(TruthFigures, Office5RoomsObservableAreaPerRoom) {
  const scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
  sim::WorldOptions wo;
  wo.robust =
      std::getenv("MOPAD_FAST_WORLD") == nullptr;  // watertight: no ray slips through an edge
  const sim::EmbreeWorld world(g.scene, &g.truth, wo);
  std::printf(
      "room  cells    analytic_m2  total_m2  observable_m2  share   positions  rays       "
      "seconds\n");
  for (const scenes::Room& room : g.truth.rooms) {
    const auto t0 = std::chrono::steady_clock::now();
    const RoomTruth rt = ComputeRoomTruth(world, g.truth, room.id);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Observability& o = rt.observability;
    const double analytic = AnalyticStructuralArea(g.truth, room.id);
    std::printf("%-4s  %-7zu  %11.2f  %8.2f  %13.2f  %5.3f   %-9zu  %-9llu  %.2f\n",
                room.id.c_str(), rt.surfaces.cells.size(), analytic, o.total_area,
                o.observable_area, o.observable_area / o.total_area, o.positions,
                static_cast<unsigned long long>(o.rays), sec);
    const CoverageReport by_class = SummariseCoverage(rt.surfaces, {}, o.observable);
    for (const CoverageFigures& f : by_class.per_class)
      std::printf("      %-8s total %7.2f m2  observable %7.2f m2  (%5.3f)\n", f.name.c_str(),
                  f.total_area, f.sensed_area, f.ShareOfTotal());
    EXPECT_NEAR(o.total_area, analytic, 0.01 * analytic) << room.id;
    EXPECT_GT(o.observable_area, 0.9 * o.total_area) << room.id;
    EXPECT_LE(o.observable_area, o.total_area) << room.id;
  }
}

TEST(TruthFigures, Office5RoomsScansSenseOnlyObservableCells) {
  // Three simulated scans (riegl_vz400 profile, noise on) from reachable positions of R1: the
  // cells they sense are observable by definition, up to partial occlusion of a cell.
  const scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
  const sim::EmbreeWorld world(g.scene, &g.truth);
  const RoomTruth rt = ComputeRoomTruth(world, g.truth, "R1");
  const sim::TlsScanner scanner(world, sim::TlsParams{});
  std::vector<Eigen::Vector3f> p_W;
  const auto& pos = rt.reachable.positions;
  double scan_seconds = 0;
  for (int k = 1; k <= 3; ++k) {
    sim::ScanRequest req;
    req.seed = 5;
    req.scan_id = static_cast<std::uint64_t>(k);
    const Eigen::Vector2d xy = pos[pos.size() * k / 4];
    req.X_WB.translation() = Eigen::Vector3d(xy.x(), xy.y(), 0);
    sim::TlsTruth truth;
    const auto t0 = std::chrono::steady_clock::now();
    const interfaces::TlsScan scan = scanner.Scan(req, &truth);
    scan_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const interfaces::TlsPoint& q : scan.points)
      if (q.valid()) p_W.push_back((truth.X_WS * Eigen::Vector3d(q.x, q.y, q.z)).cast<float>());
  }
  const auto t0 = std::chrono::steady_clock::now();
  const CoverageReport rep =
      ComputeCoverage(rt.surfaces, rt.observability.observable, p_W, Pose3::Identity());
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "R1, 3 scans (%.1f s), %zu points: coverage %.2f s; sensed %.2f m2, %.3f of observable, %.3f "
      "of total; "
      "sensed but not observable %.3f m2\n",
      scan_seconds, p_W.size(), sec, rep.room.sensed_area, rep.room.ShareOfObservable(),
      rep.room.ShareOfTotal(), rep.room.sensed_area - rep.room.sensed_observable_area);
  EXPECT_GT(rep.room.ShareOfObservable(), 0.5);
  // Points of door and window casings, shelf backs and BSCs lie within the tolerance of the
  // wall they hide (~1.5 % here); shares count only observable cells (coverage.h).
  EXPECT_LT(rep.room.sensed_area - rep.room.sensed_observable_area, 0.025 * rep.room.sensed_area);
  EXPECT_NEAR(rep.room.ShareOfTotal(), rep.room.sensed_observable_area / rep.room.total_area,
              1e-12);
}
#endif

}  // namespace
}  // namespace mopad::evaluation
