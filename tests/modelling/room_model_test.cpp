// RoomModel (paper §3.1 steps (3)-(5)) and the stopping rule (step (6)) on simulated scans of
// rooms built in code and generated from scenes/*.yaml, with known answers.

#include "modelling/room_model.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/error.h"
#include "common/frames.h"
#include "modelling/stopping.h"
#include "modelling/structural_model.h"
#include "tests/modelling/sim_scans.h"
#include "tests/sim/test_scenes.h"

namespace mopad::modelling {
namespace {

using testing::AddBox;
using testing::SimScan;
using testing::TakeScan;
using testing::TestTls;

double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double u = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + u * ab)).norm();
}

// Largest distance from any vertex of `poly` to the outline `truth` and vice versa.
double OutlineDistance(const std::vector<Vec2>& poly, const std::vector<Vec2>& truth) {
  auto one_way = [](const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
    double worst = 0.0;
    for (const auto& p : a) {
      double d = 1e300;
      for (std::size_t i = 0; i < b.size(); ++i)
        d = std::min(d, DistanceToSegment(p, b[i], b[(i + 1) % b.size()]));
      worst = std::max(worst, d);
    }
    return worst;
  };
  return std::max(one_way(poly, truth), one_way(truth, poly));
}

struct DoorRoom {
  sim::EmbreeWorld world{testing::RoomWithDoorScene()};
};

const DoorRoom& Door() {
  static const DoorRoom d;
  return d;
}

TEST(RoomModel, FloorCeilingAndPerimeterOfABoxRoomWithAnOpenDoor) {
  const SimScan s = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  RoomModel model;
  model.AddScan(s.scan, s.X_MS);
  EXPECT_NEAR(model.FloorZ(), 0.0, 0.01);
  EXPECT_NEAR(model.CeilingZ(), 2.7, 0.01);
  const std::vector<Vec2> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  ASSERT_EQ(model.Perimeter().size(), 4u) << model.FiguresJson();
  EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.03) << model.FiguresJson();
  EXPECT_TRUE(model.Columns().empty());
  EXPECT_TRUE(model.GetRoi().slopes.empty());  // a level ceiling, no slope
  EXPECT_TRUE(model.GetRoi().level_ceiling);
}

// An attic 8 m x 6 m under a gable roof: knee walls 1 m high along y = 0 and y = 6, the roof
// rising 35 deg from them towards the ridge at y = 3 (3.10 m), gables at x = 0 and x = 8. With
// `collar` > 0 a level ceiling at that height cuts the roof off (a collar-beam ceiling): the
// slopes end where they reach it. Two scans along the middle.
struct Attic {
  float W = 8.0f, D = 6.0f, knee = 1.0f, ridge = 0.0f, top = 0.0f, y_collar = 0.0f;
  scenes::Scene scene;
  explicit Attic(float collar) {
    using scenes::ElementClass;
    using sim::testing::AddQuad;
    using testing::V3;
    const float t = std::tan(static_cast<float>(DegToRad(35.0)));
    ridge = knee + 0.5f * D * t;
    top = collar > 0.0f ? collar : ridge;
    y_collar = (top - knee) / t;  // where a slope reaches the top
    const float y0 = y_collar, y1 = D - y_collar;
    AddQuad(scene, V3(0, 0, 0), V3(W, 0, 0), V3(W, D, 0), V3(0, D, 0), ElementClass::kFloor,
            "floor");
    AddQuad(scene, V3(0, 0, knee), V3(0, y0, top), V3(W, y0, top), V3(W, 0, knee),
            ElementClass::kCeiling, "roof_s");
    AddQuad(scene, V3(0, y1, top), V3(0, D, knee), V3(W, D, knee), V3(W, y1, top),
            ElementClass::kCeiling, "roof_n");
    if (y1 > y0)
      AddQuad(scene, V3(0, y0, top), V3(0, y1, top), V3(W, y1, top), V3(W, y0, top),
              ElementClass::kCeiling, "collar");
    AddQuad(scene, V3(0, 0, 0), V3(0, 0, knee), V3(W, 0, knee), V3(W, 0, 0), ElementClass::kWall,
            "knee_s");
    AddQuad(scene, V3(W, D, 0), V3(W, D, knee), V3(0, D, knee), V3(0, D, 0), ElementClass::kWall,
            "knee_n");
    for (float x : {0.0f, W}) {
      const std::string id = x == 0.0f ? "gable_w" : "gable_e";
      AddQuad(scene, V3(x, 0, 0), V3(x, y0, 0), V3(x, y0, top), V3(x, 0, knee), ElementClass::kWall,
              id);
      if (y1 > y0)
        AddQuad(scene, V3(x, y0, 0), V3(x, y1, 0), V3(x, y1, top), V3(x, y0, top),
                ElementClass::kWall, id);
      AddQuad(scene, V3(x, y1, 0), V3(x, D, 0), V3(x, D, knee), V3(x, y1, top), ElementClass::kWall,
              id);
    }
  }
};

// The roof is two sloped ceilings (and the collar a level one), the outline reaches the knee
// walls, and SM3 has the slopes (and the collar) for ceilings and the gables ended under them:
// pentagons under a ridge, hexagons under a collar.
TEST(RoomModel, AnAtticsRoofIsTwoSlopedCeilingsAndItsWallsEndUnderThem) {
  for (float collar : {0.0f, 2.5f}) {
    const Attic a(collar);
    const sim::EmbreeWorld world(a.scene);
    RoomModel model;
    for (int k = 0; k < 2; ++k) {
      const SimScan s = TakeScan(world, TestTls(), 2.5 + 3.0 * k, 3.0, k);
      model.AddScan(s.scan, s.X_MS);
    }
    const Roi& roi = model.GetRoi();
    ASSERT_EQ(roi.slopes.size(), 2u) << collar << " " << model.FiguresJson();
    EXPECT_EQ(roi.level_ceiling, collar > 0.0f) << collar;
    for (const auto& p : roi.slopes) {
      EXPECT_NEAR(RadToDeg(std::acos(-p.n.z())), 35.0, 0.3) << collar;
      EXPECT_NEAR(p.ZAt(Vec2(4.0, 3.0)), a.ridge, 0.02) << collar;
    }
    const std::vector<Vec2> truth = {{0, 0}, {a.W, 0}, {a.W, a.D}, {0, a.D}};
    ASSERT_EQ(model.Perimeter().size(), 4u) << collar << " " << model.FiguresJson();
    EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.03) << model.FiguresJson();
    const StructuralModel sm3 = BuildRoomSm3(model, Sm3Params{}, "attic");
    int slopes = 0, level = 0, gables = 0, knees = 0;
    for (const auto& p : sm3.patches) {
      if (p.patch_class == PatchClass::kCeiling) {
        if (p.id == "ceiling") {
          ++level;
          double area = 0.0;
          for (std::size_t i = 0; i < p.polygon.size(); ++i)
            area += p.polygon[i].head<2>().x() * p.polygon[(i + 1) % p.polygon.size()].y() -
                    p.polygon[(i + 1) % p.polygon.size()].x() * p.polygon[i].y();
          EXPECT_NEAR(std::abs(area) / 2.0, a.W * (a.D - 2.0 * a.y_collar), 0.1) << collar;
        } else {
          ++slopes;
        }
      }
      if (p.patch_class != PatchClass::kWall) continue;
      double top = 0.0;
      for (const auto& v : p.polygon) top = std::max(top, v.z());
      if (p.polygon.size() == (collar > 0.0f ? 6u : 5u)) {
        ++gables;
        EXPECT_NEAR(top, a.top, 0.02) << collar << " " << p.id;
      } else if (p.polygon.size() == 4) {
        ++knees;
        EXPECT_NEAR(top, a.knee, 0.02) << collar << " " << p.id;
      }
    }
    EXPECT_EQ(slopes, 2) << collar;
    EXPECT_EQ(level, collar > 0.0f ? 1 : 0) << collar;
    EXPECT_EQ(gables, 2) << collar;
    EXPECT_EQ(knees, 2) << collar;
  }
}

// An 8 x 6 m room under a hip roof: knee walls 1 m high on all four sides, four planes rising
// 35 deg from them to a 2 m ridge along x at y = 3 (3.10 m). Four sloped ceilings, no level one,
// the outline the room's, and every wall a 1 m strip.
TEST(RoomModel, AHipRoofIsFourSlopedCeilingsOverFourKneeWalls) {
  using scenes::ElementClass;
  using sim::testing::AddQuad;
  using testing::V3;
  const float W = 8.0f, D = 6.0f, k = 1.0f;
  const float r = k + 3.0f * std::tan(static_cast<float>(DegToRad(35.0)));
  scenes::Scene scene;
  AddQuad(scene, V3(0, 0, 0), V3(W, 0, 0), V3(W, D, 0), V3(0, D, 0), ElementClass::kFloor, "floor");
  AddQuad(scene, V3(0, 0, k), V3(3, 3, r), V3(5, 3, r), V3(W, 0, k), ElementClass::kCeiling, "s");
  AddQuad(scene, V3(3, 3, r), V3(0, D, k), V3(W, D, k), V3(5, 3, r), ElementClass::kCeiling, "n");
  AddQuad(scene, V3(0, 0, k), V3(0, D, k), V3(3, 3, r), V3(3, 3, r), ElementClass::kCeiling, "w");
  AddQuad(scene, V3(W, 0, k), V3(5, 3, r), V3(5, 3, r), V3(W, D, k), ElementClass::kCeiling, "e");
  AddQuad(scene, V3(0, 0, 0), V3(0, 0, k), V3(W, 0, k), V3(W, 0, 0), ElementClass::kWall, "ws");
  AddQuad(scene, V3(W, 0, 0), V3(W, 0, k), V3(W, D, k), V3(W, D, 0), ElementClass::kWall, "we");
  AddQuad(scene, V3(W, D, 0), V3(W, D, k), V3(0, D, k), V3(0, D, 0), ElementClass::kWall, "wn");
  AddQuad(scene, V3(0, D, 0), V3(0, D, k), V3(0, 0, k), V3(0, 0, 0), ElementClass::kWall, "ww");
  const sim::EmbreeWorld world(scene);
  RoomModel model;
  for (int i = 0; i < 2; ++i) {
    const SimScan s = TakeScan(world, TestTls(), 2.5 + 3.0 * i, 3.0, i);
    model.AddScan(s.scan, s.X_MS);
  }
  ASSERT_EQ(model.GetRoi().slopes.size(), 4u) << model.FiguresJson();
  EXPECT_FALSE(model.GetRoi().level_ceiling);
  const std::vector<Vec2> truth = {{0, 0}, {W, 0}, {W, D}, {0, D}};
  ASSERT_EQ(model.Perimeter().size(), 4u) << model.FiguresJson();
  EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.03) << model.FiguresJson();
  const StructuralModel sm3 = BuildRoomSm3(model, Sm3Params{}, "hip");
  int ceilings = 0, strips = 0;
  for (const auto& p : sm3.patches) {
    ceilings += p.patch_class == PatchClass::kCeiling;
    if (p.patch_class != PatchClass::kWall) continue;
    double top = 0.0;
    for (const auto& v : p.polygon) top = std::max(top, v.z());
    EXPECT_EQ(p.polygon.size(), 4u) << p.id;
    EXPECT_NEAR(top, k, 0.02) << p.id;
    ++strips;
  }
  EXPECT_EQ(ceilings, 4);
  EXPECT_EQ(strips, 4);
}

// A 6 x 4 m room under a level 2.7 m ceiling with a stair flight along its south wall: its
// underside 1 m wide, rising 33 deg from 0.4 m at x = 1 to the ceiling at x = 4.5, and the
// stairwell's wall standing on its edge (y = 1) up to the ceiling, so that nothing above the
// underside is seen: the underside is the top surface there, tilted and 3.5 m2 in plan, but a
// flight's width, no roof. Without the width rule it is taken for one.
TEST(RoomModel, AStairFlightsUndersideIsNoSlopedCeiling) {
  using scenes::ElementClass;
  using sim::testing::AddQuad;
  using testing::V3;
  scenes::Scene scene;
  sim::testing::AddRoomBox(scene, V3(0, 0, 0), V3(6, 4, 2.7f));
  AddQuad(scene, V3(1, 0, 0.4f), V3(1, 1, 0.4f), V3(4.5f, 1, 2.7f), V3(4.5f, 0, 2.7f),
          ElementClass::kOther, "flight");
  AddQuad(scene, V3(1, 1, 0.4f), V3(1, 1, 2.7f), V3(4.5f, 1, 2.7f), V3(4.5f, 1, 2.7f),
          ElementClass::kOther, "stairwell");
  const sim::EmbreeWorld world(scene);
  for (double width : {1.5, 0.0}) {
    RoomModelParams p;
    p.slopes.min_width = width;
    RoomModel model(p);
    for (int k = 0; k < 2; ++k) {
      const SimScan s = TakeScan(world, TestTls(), 2.0 + 2.5 * k, 2.6, k);
      model.AddScan(s.scan, s.X_MS);
    }
    EXPECT_EQ(model.GetRoi().slopes.size(), width > 0.0 ? 0u : 1u) << width;
  }
}

// A low ceiling (2.5 m: 1.1 m above the scanner centre) lies inside the scanner's 1.5 m minimum
// range in the top rows of every column, so each column's first return follows a gap. That gap
// is the ceiling, not a wall too close to return: the outline must still be traced (random
// floors with 2.6-2.7 m ceilings got no perimeter and no model at all).
TEST(RoomModel, PerimeterUnderACeilingInsideTheMinimumRange) {
  const sim::EmbreeWorld world(testing::RoomWithDoorScene(6, 4, 2.5f));
  ASSERT_GE(TestTls().range_min, 1.5);
  const SimScan s = TakeScan(world, TestTls(), 2.0, 1.8, 0);
  RoomModel model;
  model.AddScan(s.scan, s.X_MS);
  EXPECT_NEAR(model.CeilingZ(), 2.5, 0.01);
  const std::vector<Vec2> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  ASSERT_EQ(model.Perimeter().size(), 4u) << model.FiguresJson();
  EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.03) << model.FiguresJson();
}

// A room model of one scan, with the default rule for the ceiling over the scanner or with any
// strong peak counting as over it (the rule switched off).
RoomModel ModelOfOneScan(const SimScan& s, bool any_peak_over_scanner) {
  RoomModelParams p;
  if (any_peak_over_scanner) p.heights.ceiling_over_scanner = 100.0, p.heights.ceiling_sectors = 1;
  RoomModel model(p);
  model.AddScan(s.scan, s.X_MS);
  return model;
}

// A narrow corridor under a low ceiling (2.65 m, 1.25 m above the scanner centre: inside the
// 1.5 m minimum range within 0.83 m of it) beside a hall under a higher one (2.75 m) seen
// through a 1.6 m door 0.6 m away: the hall's ceiling is the highest strong peak of the heights
// histogram, but it is not over the scanner; the corridor's is. (Nearer a door the hall's
// ceiling starts within reach: ACeilingSeenThroughADoorBesideTheScannerIsNotTheRooms.)
TEST(RoomModel, TheCeilingIsTheOneOverTheScannerNotTheNextRoomsSeenThroughADoor) {
  const sim::EmbreeWorld world(testing::RoomWithDoorScene(6, 2.2f, 2.65f, 0.3f, 1.9f, 2.1f, 2.75f));
  const SimScan s = TakeScan(world, TestTls(), 5.4, 1.1, 0);
  const RoomModel any_peak = ModelOfOneScan(s, /*any_peak_over_scanner=*/true);
  const RoomModel model = ModelOfOneScan(s, false);
  // The outline is traced at the ceiling's height: at the hall's, the corridor has none.
  EXPECT_GE(model.Perimeter().size(), 3u) << model.FiguresJson();
  std::printf("[ HEIGHTS  ] ceiling %.3f m with any peak, %.3f m over the scanner\n",
              any_peak.CeilingZ(), model.CeilingZ());
  EXPECT_NEAR(any_peak.CeilingZ(), 2.75, 0.01);  // the case the rule is for
  EXPECT_NEAR(model.CeilingZ(), 2.65, 0.01);
}

// A small office under a 2.9 m ceiling (1.5 m above the scanner centre: beyond its minimum
// range everywhere, but above the top of its field of view, 60 deg, within 0.87 m of it) beside
// a deep hall under 3.9 m, seen through a 2.3 m high door 1.1 m away: the office's ceiling is
// over the scanner although no return of it lies within 0.5 m of the minimum range's (empty)
// disc; the hall's is seen from 3 m on, under the door's head. (The rooms of a random hall
// floor took the hall's ceiling for theirs and traced their perimeter at its height.)
TEST(RoomModel, TheCeilingOverTheScannerStartsWhereItsFieldOfViewEnds) {
  const sim::EmbreeWorld world(
      testing::RoomWithDoorScene(3.0f, 3.2f, 2.9f, 1.0f, 2.2f, 2.3f, 3.9f, 16.0f));
  ASSERT_NEAR(TestTls().elevation_max_deg, 60.0, 1e-9);
  const SimScan s = TakeScan(world, TestTls(), 1.9, 1.6, 0);
  // The hall's is the highest strong peak.
  EXPECT_NEAR(ModelOfOneScan(s, /*any_peak_over_scanner=*/true).CeilingZ(), 3.9, 0.01);
  EXPECT_NEAR(ModelOfOneScan(s, false).CeilingZ(), 2.9, 0.01);
}

// A 1.6 m x 2.4 m washroom with a bathtub (top 0.44 m) along its far wall: the floor lies
// outside the scanner's -40 deg field of view up to 1.7 m from it and under the tub beyond, so
// the lowest strong height peak is the tub's top (the KIT Jasmin-Sun house's WC and shower:
// floors 0.44 m up). The robot stands on the floor: with the scan's mount (1.4 m over
// base_link, which lies on the floor) the floor is that floor; without a mount (a scan read
// from a file) the floor is the lowest strong peak.
TEST(RoomModel, TheFloorIsTheOneTheRobotStandsOnWhereTheScannerCannotSeeIt) {
  scenes::Scene scene;
  sim::testing::AddRoomBox(scene, testing::V3(0, 0, 0), testing::V3(1.6f, 2.4f, 2.6f));
  AddBox(scene, testing::V3(0.001f, 1.65f, 0.0f), testing::V3(1.599f, 2.399f, 0.44f),
         scenes::ElementClass::kFurniture, "bathtub", "R");
  const sim::EmbreeWorld world{std::move(scene)};
  const SimScan s = TakeScan(world, TestTls(), 0.8, 0.55, 0);
  ASSERT_NEAR(s.scan.X_BS.translation().z(), 1.4, 1e-9);
  RoomModel with_mount;
  with_mount.AddScan(s.scan, s.X_MS);
  EXPECT_NEAR(with_mount.FloorZ(), 0.0, 0.01);
  EXPECT_NEAR(with_mount.CeilingZ(), 2.6, 0.01);
  interfaces::TlsScan no_mount = s.scan;
  no_mount.X_BS = Eigen::Isometry3d::Identity();
  RoomModel without;
  without.AddScan(no_mount, s.X_MS);
  EXPECT_NEAR(without.FloorZ(), 0.44, 0.02) << "the lowest strong peak is the tub's top";
}

TEST(RoomModel, PerimeterDoesNotLeakThroughADoorBesideTheScanner) {
  // 0.6 m from the door wall (a 2 m hall is always < 1 m from one): the lintel over the door
  // is closer than the scanner's 1.5 m minimum range below ~66 deg elevation, so it returns
  // only its top rows; the next return up the column is the neighbour's ceiling beyond the
  // door. The missing rows end the trace there (before: the outline ran on into the hall).
  ASSERT_GE(TestTls().range_min, 1.5);
  for (const double y : {1.95, 2.2}) {
    const SimScan s = TakeScan(Door().world, TestTls(0.2), 5.4, y, 0);
    RoomModel model;
    model.AddScan(s.scan, s.X_MS);
    const std::vector<Vec2> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
    EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.05)
        << "y " << y << ": " << model.FiguresJson();
    double xmax = -1e300;
    for (const auto& v : model.Perimeter()) xmax = std::max(xmax, v.x());
    EXPECT_LT(xmax, 6.05) << "y " << y;
    EXPECT_NEAR(model.Coverage().total_area, 2 * 24.0 + 2 * (6 + 4) * 2.7 - 0.9 * 2.1, 3.0);
  }
}

// A corridor under 2.55 m, 0.68 m from its door wall: the whole lintel (2.1-2.55 m) lies inside
// the 1.5 m minimum range, and in the door's columns the first return is the next room's ceiling
// 6 cm higher, beyond the ceiling tolerance (5 cm). Above the ceiling, it is not a wall beside
// the scanner: the outline must not follow it into the next room (a random corridor floor's
// corridor grew a 0.9 m notch through an open door, hid that door and never entered its room).
TEST(RoomModel, PerimeterDoesNotTakeTheNextRoomsHigherCeilingForAWallBesideTheScanner) {
  const sim::EmbreeWorld world(
      testing::RoomWithDoorScene(6.0f, 2.35f, 2.55f, 0.7f, 1.6f, 2.1f, 2.61f));
  ASSERT_GE(TestTls().range_min, 1.5);
  for (const double y : {1.0, 1.15, 1.3}) {
    const SimScan s = TakeScan(world, TestTls(0.2), 6.0 - 0.68, y, 0);
    RoomModel model;
    model.AddScan(s.scan, s.X_MS);
    double xmax = -1e300;
    for (const auto& v : model.Perimeter()) xmax = std::max(xmax, v.x());
    EXPECT_LT(xmax, 6.05) << "y " << y << ": " << model.FiguresJson();
  }
}

// A 2.2 m corridor under 2.55 m, 0.55-0.75 m from a door into a room under 2.65 m (a random
// corridor floor: the second scan stood 0.63 m from an office's door). Through the door the
// room's ceiling begins about 0.8 m out, within the disc the scanner's minimum range hides
// plus ceiling_over_scanner, so it passed as "over the scanner"; being the higher strong peak
// it became the ceiling, no outline was traced at it, and the corridor lost its perimeter
// (SM3 refused the room, the mission ended in it). A ceiling is over the scanner where it surrounds
// it: its points near the disc span ceiling_sectors of its eight azimuth sectors; a ceiling seen
// through a door spans one or two.
TEST(RoomModel, ACeilingSeenThroughADoorBesideTheScannerIsNotTheRooms) {
  // The corridor x 0-2.2 m, y 0-15 m; the door in its east wall at y 6.0-6.9 m.
  const sim::EmbreeWorld world(
      testing::RoomWithDoorScene(2.2f, 15.0f, 2.55f, 6.0f, 6.9f, 2.1f, 2.65f));
  ASSERT_GE(TestTls().range_min, 1.5);
  for (const double from_wall : {0.55, 0.65, 0.75}) {
    const SimScan s = TakeScan(world, TestTls(0.2), 2.2 - from_wall, 6.45, 0);
    RoomModel model;
    model.AddScan(s.scan, s.X_MS);
    EXPECT_NEAR(model.CeilingZ(), 2.55, 0.02) << from_wall << " m from the door's wall";
    EXPECT_GE(model.Perimeter().size(), 4u) << from_wall << " m from the door's wall";
  }
}

// A 0.24 m wall standing into the room from its west wall (x 0-3.5 m), its line continued to
// the east wall by a beam 0.24 m deep under a 2.5 m ceiling, and the scanner under the beam
// 1.55 m from the wall's end (the imported FZK-Haus: the wall between its hall and dining area,
// the beam over the open passage). The beam's underside lies within the scanner's 1.5 m minimum
// range up to ~1.2 m out, so in the columns towards the wall's end the first return follows
// rows without one and no point is accepted; such a column was bridged by its neighbours'
// vertices on the west wall on either side of the standing wall, and the wall vanished from the
// outline. A column that returned something but accepted nothing was stopped within the minimum
// range: the bridge across it may claim no more than a column without any return.
TEST(RoomModel, AWallEndingUnderABeamBesideTheScannerStaysOutOfTheOutline) {
  scenes::Scene scene;
  sim::testing::AddRoomBox(scene, testing::V3(0, 0, 0), testing::V3(7.0f, 5.0f, 2.5f));
  AddBox(scene, testing::V3(0.001f, 2.38f, 0.0f), testing::V3(3.5f, 2.62f, 2.5f),
         scenes::ElementClass::kWall, "standing_wall", "R");
  AddBox(scene, testing::V3(3.3f, 2.40f, 2.26f), testing::V3(6.999f, 2.60f, 2.5f),
         scenes::ElementClass::kOther, "beam", "R");
  const sim::EmbreeWorld world{std::move(scene)};
  ASSERT_GE(TestTls().range_min, 1.5);
  auto inside = [](const std::vector<Vec2>& poly, const Vec2& p) {  // even-odd rule
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
          p.x() <
              (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) +
                  poly[i].x())
        in = !in;
    }
    return in;
  };
  for (const double y : {2.45, 2.5, 2.55}) {
    const SimScan s = TakeScan(world, TestTls(0.2), 3.5 + 1.55, y, 0);
    RoomModel model;
    model.AddScan(s.scan, s.X_MS);
    ASSERT_GE(model.Perimeter().size(), 3u) << "y " << y;
    for (const double x : {0.5, 1.5, 2.5, 3.3})
      EXPECT_FALSE(inside(model.Perimeter(), Vec2(x, 2.5)))
          << "y " << y << ": the standing wall at x " << x << " is inside the outline "
          << model.FiguresJson();
    EXPECT_TRUE(inside(model.Perimeter(), Vec2(1.5, 4.0))) << "y " << y;
    EXPECT_TRUE(inside(model.Perimeter(), Vec2(1.5, 1.0))) << "y " << y;
  }
}

// A box hanging from the ceiling down to 1.6 m (a duct, a bulkhead; a spiral stair's flights
// do the same) 1.6 m in front of the east wall: from the scanner the ceiling behind it is
// hidden, and the outline has a wedge of unfitted edges from the box to the wall (SM3 made them
// walls: on the imported FZK-Haus, 5 false walls and the wall behind split in three, d_h 1.8
// m). The wall was seen behind it, under the box: it goes on, and the room is its rectangle.
// The same box down to the floor hides the wall behind it at every height: the outline keeps
// the notch (nothing says the room goes on there).
TEST(RoomModel, TheShadowOfSomethingStandingInTheRoomIsNoPartOfItsOutline) {
  const std::vector<Vec2> truth = {{0, 0}, {8, 0}, {8, 5}, {0, 5}};
  for (const float bottom : {1.6f, 0.0f}) {
    scenes::Scene scene;
    sim::testing::AddRoomBox(scene, testing::V3(0, 0, 0), testing::V3(8.0f, 5.0f, 2.5f));
    AddBox(scene, testing::V3(6.0f, 1.5f, bottom), testing::V3(6.4f, 3.0f, 2.499f),
           scenes::ElementClass::kOther, "box", "R");
    const sim::EmbreeWorld world{std::move(scene)};
    const SimScan s = TakeScan(world, TestTls(0.2), 2.5, 2.5, 0);
    RoomModel model;
    model.AddScan(s.scan, s.X_MS);
    if (bottom > 0.0f) {
      EXPECT_EQ(model.Perimeter().size(), 4u) << model.FiguresJson();
      EXPECT_LT(OutlineDistance(model.Perimeter(), truth), 0.05) << model.FiguresJson();
    } else {
      EXPECT_GT(model.Perimeter().size(), 4u) << model.FiguresJson();
      EXPECT_GT(OutlineDistance(model.Perimeter(), truth), 1.0) << model.FiguresJson();
    }
  }
}

// The imported FZK-Haus (IFC4) living room: its spiral stair stands against the south wall
// beside the 2 m window, hides the wall at every height from every scan the robot made, and
// shows no wall face (no edge of its detour was fitted: steps at every depth and height). The
// outline ran around it (5 false walls, the wall split at the stair, d_h 4.2 m). Faceless
// clutter more than refit_band and up to shadow_depth deep is bridged, the window's reveal
// beside it part of the run. With a face fitted in front (a cupboard, a wall standing into the
// room), deeper than shadow_depth (the single-scan shadow of a standing wall), or a jog within
// refit_band, it stays, unless it stays in front of the line and wall points lie on the line
// behind it.
TEST(RoomModel, AFacelessShadowAgainstAWallIsBridged) {
  const RoomModelParams params;
  // The room 12 m x 6 m, its south wall y = 0, the stair's detour at x 7.4-8.7 m standing
  // `depth` into the room, and with `reveal` the window's reveal 0.3 m deep at x 5-7 m. Every
  // edge's line is fitted but the window's glass, the wall piece between window and stair and
  // the detour's; with `face`, the detour's first edge into the room is fitted (a face).
  struct Outline {
    std::vector<Vec2> poly;
    std::vector<PerimeterLine> lines;
  };
  auto room = [](double depth, bool reveal, bool face) {
    Outline o;
    std::vector<bool> fitted;
    auto add = [&](const Vec2& v, bool fit) { o.poly.push_back(v), fitted.push_back(fit); };
    add({0, 0}, true);
    if (reveal) {
      add({5, 0}, true), add({5, -0.3}, false), add({7, -0.3}, true), add({7, 0}, false);
    } else {
      add({5, 0}, true);
    }
    add({7.4, 0}, face), add({7.45, depth}, false);
    for (const Vec2& v : {Vec2(8.7, 0), Vec2(12, 0), Vec2(12, 6), Vec2(0, 6)}) add(v, true);
    for (std::size_t i = 0; i < o.poly.size(); ++i) {
      const Vec2 a = o.poly[i], b = o.poly[(i + 1) % o.poly.size()], t = (b - a).normalized();
      o.lines.push_back({0.5 * (a + b), t, fitted[i], t});
    }
    return o;
  };
  std::vector<Vec2> behind;  // the wall seen behind the stair, beside it, over the window
  for (double x = 5.0; x <= 8.7; x += 0.01) behind.emplace_back(x, 0.003);
  struct Case {
    double depth;
    bool reveal, face, wall_seen, bridged;
    const char* what;
  };
  for (const Case& c : {Case{1.4, true, false, false, true, "faceless stair beside a window"},
                        Case{1.4, false, false, false, true, "faceless stair"},
                        Case{1.4, true, true, false, false, "a face in front"},
                        Case{2.5, true, false, false, false, "deeper than shadow_depth"},
                        Case{0.08, false, false, false, false, "a jog within refit_band"},
                        Case{1.4, false, true, true, true, "a face, the wall seen behind"},
                        Case{2.5, false, false, true, true, "deep, the wall seen behind"},
                        Case{1.4, true, true, true, false, "a face, behind a window's reveal"}}) {
    Outline o = room(c.depth, c.reveal, c.face);
    std::vector<Vec2>& poly = o.poly;
    const std::size_t n = poly.size();
    BridgeShadows(poly, o.lines, c.wall_seen ? behind : std::vector<Vec2>{}, params);
    ASSERT_EQ(poly.size(), o.lines.size()) << c.what;
    if (c.bridged) {
      const std::vector<Vec2> truth = {{0, 0}, {12, 0}, {12, 6}, {0, 6}};
      ASSERT_EQ(poly.size(), 4u) << c.what;
      for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((poly[i] - truth[i]).norm(), 1e-9) << c.what;
    } else {
      EXPECT_EQ(poly.size(), n) << c.what;
    }
  }
}

// Jasmin-Sun's basement (the imported KIT house): the stair down from the ground floor stands
// in the corner of its hall, 1.4 m x 1.3 m, hides both walls there at every height from every
// scan and shows no wall face (steps). The outline ran around it (5 false walls, d_h 1.4 m).
// A faceless run between two fitted walls that turn left by corner_min_deg or more, in front of
// both and at most shadow_depth from each, hides their corner: the walls meet there. With a
// face (a cupboard, a room's re-entrant corner) or deeper than shadow_depth it stays, unless
// both walls are seen going on behind it.
TEST(RoomModel, AFacelessShadowInACornerIsBridgedToTheCorner) {
  const RoomModelParams params;
  // The room 6 m x 4 m; the stair's detour from (4.6, 0) on the south wall to (6, depth) on the
  // east wall; with `face` its second edge is fitted.
  auto room = [](double depth, bool face, std::vector<PerimeterLine>* lines) {
    std::vector<Vec2> poly = {
        {0, 0}, {4.6, 0}, {5.0, 0.45 * depth}, {5.4, 0.55 * depth}, {5.0, 0.8 * depth}, {6, depth},
        {6, 4}, {0, 4}};
    const std::vector<bool> fitted = {true, false, face, false, false, true, true, true};
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()], t = (b - a).normalized();
      lines->push_back({0.5 * (a + b), t, fitted[i], t});
    }
    return poly;
  };
  std::vector<Vec2> behind;  // both walls seen going on behind the stair
  for (double x = 4.6; x <= 6.0; x += 0.01) behind.emplace_back(x, 0.003);
  for (double y = 0.0; y <= 2.5; y += 0.01) behind.emplace_back(5.997, y);
  struct Case {
    double depth;
    bool face, wall_seen, bridged;
    const char* what;
  };
  for (const Case& c : {Case{1.3, false, false, true, "faceless stair in the corner"},
                        Case{1.3, true, false, false, "a face in front"},
                        Case{1.3, true, true, true, "a face, both walls seen behind"},
                        Case{2.5, false, false, false, "deeper than shadow_depth"},
                        Case{2.5, false, true, true, "deeper, the walls seen behind"}}) {
    std::vector<PerimeterLine> lines;
    std::vector<Vec2> poly = room(c.depth, c.face, &lines);
    const std::size_t n = poly.size();
    BridgeShadows(poly, lines, c.wall_seen ? behind : std::vector<Vec2>{}, params);
    ASSERT_EQ(poly.size(), lines.size()) << c.what;
    if (c.bridged) {
      const std::vector<Vec2> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
      ASSERT_EQ(poly.size(), 4u) << c.what;
      for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((poly[i] - truth[i]).norm(), 1e-9) << c.what;
      EXPECT_TRUE(lines[0].fitted && lines[1].fitted) << c.what;
    } else {
      EXPECT_EQ(poly.size(), n) << c.what;
    }
  }
}

TEST(RoomModel, PointsThroughTheDoorAreOutliersAndTheDeskIsClutter) {
  const SimScan s = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  RoomModel model;
  model.AddScan(s.scan, s.X_MS);
  int beyond = 0, beyond_outlier = 0, desk = 0, desk_clutter = 0, wall = 0, wall_inlier = 0;
  for (std::size_t i = 0; i < model.PointCount(); ++i) {
    const Eigen::Vector3f& p = model.Points()[i];
    const PointLabel l = model.Labels()[i];
    if (p.x() > 6.1f) {
      ++beyond;
      beyond_outlier += l == PointLabel::kOutlier;
    }
    if (p.x() > 2.45f && p.x() < 3.55f && p.y() > 3.15f && p.y() < 3.65f && p.z() > 0.1f &&
        p.z() < 0.8f) {
      ++desk;
      desk_clutter += l == PointLabel::kClutter;
    }
    if (p.y() < 0.01f && p.z() > 0.1f && p.z() < 2.6f) {
      ++wall;
      wall_inlier += l == PointLabel::kInlier;
    }
  }
  ASSERT_GT(beyond, 1000);  // the hall floor, walls, ceiling and cabinet through the door
  EXPECT_EQ(beyond_outlier, beyond);
  ASSERT_GT(desk, 200);
  EXPECT_GT(desk_clutter, 0.99 * desk);
  ASSERT_GT(wall, 1000);
  EXPECT_GT(wall_inlier, 0.999 * wall);
  EXPECT_EQ(model.Classify(Vec3(8.0, 2.0, 0.0)), PointLabel::kOutlier);
  EXPECT_EQ(model.Classify(Vec3(3.0, 3.4, 0.75)), PointLabel::kClutter);
  EXPECT_EQ(model.Classify(Vec3(3.0, 2.0, 0.0)), PointLabel::kInlier);
  EXPECT_EQ(model.Classify(Vec3(0.0, 2.0, 1.0)), PointLabel::kInlier);
}

TEST(RoomModel, LabelsAgreeWithTruthInTheDoorRoom) {
  RoomModel model;
  std::vector<SimScan> scans;
  scans.push_back(TakeScan(Door().world, TestTls(), 2.0, 1.8, 0));
  scans.push_back(TakeScan(Door().world, TestTls(), 4.5, 1.2, 1));
  for (const auto& s : scans) model.AddScan(s.scan, s.X_MS);
  const std::vector<Eigen::Vector2d> polygon = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  std::size_t agree = 0, total = 0;
  for (const auto& s : scans) {
    const auto truth = testing::TruthLabels(s, Door().world.scene(), "R", polygon);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      agree += static_cast<std::uint8_t>(model.Labels()[total + k]) == truth[k];
    }
    total += truth.size();
  }
  ASSERT_EQ(total, model.PointCount());
  EXPECT_GT(static_cast<double>(agree) / total, 0.99);
}

TEST(RoomModel, CoverageGrowsWithScansAndReachesNinetyPercent) {
  RoomModel model;
  const double xy[3][2] = {{1.5, 1.5}, {4.5, 1.5}, {3.0, 2.4}};
  for (int k = 0; k < 3; ++k) {
    const SimScan s = TakeScan(Door().world, TestTls(), xy[k][0], xy[k][1], k);
    model.AddScan(s.scan, s.X_MS);
  }
  const auto& h = model.CoverageHistory();
  ASSERT_EQ(h.size(), 3u);
  EXPECT_GT(h[1].sensed_area, h[0].sensed_area + 1.0);
  EXPECT_GT(h[1].ratio, h[0].ratio);
  EXPECT_GT(h[1].increment, 0.01);
  EXPECT_GE(h[2].ratio, 0.9) << model.FiguresJson();
  // Room: floor 24 + ceiling 24 + walls 54 m^2 minus the door (0.9 x 2.1).
  EXPECT_NEAR(h[2].total_area, 102.0 - 1.89, 2.0);
  EXPECT_NEAR(h[2].opening_area, 1.89, 0.5);
}

TEST(RoomModel, RoiIsAValidBrepAndVoxelsAreLabelled) {
  RoomModel model;
  const SimScan s = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  model.AddScan(s.scan, s.X_MS);
  const Roi& roi = model.GetRoi();
  ASSERT_EQ(roi.faces.size(), 6u);
  // Euler-Poincare for a box: V - E + F = 2.
  EXPECT_EQ(static_cast<int>(roi.vertices.size()) - static_cast<int>(roi.edges.size()) +
                static_cast<int>(roi.faces.size()),
            2);
  for (const auto& adj : roi.face_adjacency) EXPECT_EQ(adj.size(), 4u);
  EXPECT_NEAR(roi.Volume(), 6 * 4 * 2.7, 0.6);
  for (const auto& f : roi.faces) {
    EXPECT_TRUE(f.structural) << ToString(f.kind) << " " << f.element;
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-9);
  }
  // Outward normals: a point just beyond a wall face along its normal is outside the room.
  for (std::size_t i = 2; i < roi.faces.size(); ++i) {
    const RoiFace& f = roi.faces[i];
    const Vec3 c = f.CellCentre(f.nu / 2, f.nv / 2) + 0.2 * f.normal;
    EXPECT_FALSE(roi.ContainsPlan(c.head<2>()));
  }
  const VoxelSpace& v = model.Voxels();
  auto label_at = [&](const Vec3& p) {
    const Eigen::Vector3i q = v.VoxelOf(p);
    return v.Label(v.Index(q.x(), q.y(), q.z()));
  };
  EXPECT_EQ(label_at(Vec3(3.0, 3.4, 0.72)), VoxelLabel::kClutter);           // desk top
  EXPECT_EQ(label_at(Vec3(3.0, 1.0, 1.2)), VoxelLabel::kEmpty);              // open air
  EXPECT_EQ(label_at(Vec3(3.0, 3.4, 0.0)), VoxelLabel::kOccludedStructure);  // floor under the desk
  EXPECT_EQ(label_at(Vec3(5.0, 0.0, 1.2)), VoxelLabel::kStructure);          // south wall
  // The door in the east wall (x = 6, on a voxel boundary): its layer is the room-side one.
  EXPECT_EQ(label_at(Vec3(5.99, 1.95, 1.0)), VoxelLabel::kOpening);
  EXPECT_EQ(label_at(Vec3(6.01, 1.95, 1.0)), VoxelLabel::kEmpty);  // beams through the door
  const auto counts = v.LabelCounts();
  for (int l = 0; l < kVoxelLabelCount; ++l)
    EXPECT_GT(counts[l], 0) << ToString(static_cast<VoxelLabel>(l));
}

// Issue 6: structural voxels are the single layer containing a RoI face (the truth DSM3's rule);
// the layer behind it (centres ~0.1 m outside the room) used to be labelled too.
// The 14 m room of the two tests below, scanned from (3.5, 2.4) and (10.5, 2.4): how far the
// ends of its refit south wall line (y = 0) lie off the wall, and how many such long edges the
// perimeter has.
struct SouthWallFit {
  double worst = 0.0;
  int edges = 0;
  std::string figures;
};
SouthWallFit FitSouthWall(scenes::Scene scene) {
  const sim::EmbreeWorld world(std::move(scene));
  RoomModel model;
  for (const double x : {3.5, 10.5}) {
    const SimScan s = TakeScan(world, TestTls(), x, 2.4, 1);
    model.AddScan(s.scan, s.X_MS);
  }
  SouthWallFit fit;
  const auto& per = model.Perimeter();
  for (std::size_t i = 0; i < per.size(); ++i) {
    const Vec2 a = per[i], b = per[(i + 1) % per.size()];
    if (std::abs(a.y()) > 0.05 || std::abs(b.y()) > 0.05 || (b - a).norm() < 10.0) continue;
    ++fit.edges;
    fit.worst = std::max({fit.worst, std::abs(a.y()), std::abs(b.y())});
  }
  fit.figures = model.FiguresJson();
  return fit;
}

// A 14 m room whose south wall (y = 0) carries a 1.2 cm panel over half its length (x in
// [7, 13.8]; cladding, a whiteboard row, a closed door's casing): the refit keeps the wall line
// on the wall, anchored at the outermost strong peak of the offsets. A least-squares line over
// the band ended 1.1 cm into the room at the panel's end (1.3 cm when tightened about itself);
// anchored: 2.4 mm.
TEST(RoomModel, WallRefitIsNotTiltedByAPanelOnPartOfTheWall) {
  scenes::Scene scene = testing::RoomWithDoorScene(14.0f, 4.0f);
  AddBox(scene, testing::V3(7.0f, 0.0f, 0.05f), testing::V3(13.8f, 0.012f, 2.3f),
         scenes::ElementClass::kFurniture, "panel", "R");
  const SouthWallFit fit = FitSouthWall(std::move(scene));
  const double worst = fit.worst;
  ASSERT_EQ(fit.edges, 1) << fit.figures;
  std::printf("south wall line: ends at most %.4f m off the wall\n", worst);
  EXPECT_LT(worst, 0.006) << fit.figures;
}

// The same wall, now behind a 2.5 cm proud panel 2.1 m high over nearly all its length (a
// closed door filling most of a short end wall, as D13 in office_5rooms' hall): below door
// heads the panel outnumbers the wall, so the whole-band outermost strong peak was the panel
// (the line 2.5 cm into the room); above door heads only the wall remains and anchors the fit.
TEST(RoomModel, WallRefitStaysOnTheWallBehindADoorHighPanelCoveringMostOfIt) {
  scenes::Scene scene = testing::RoomWithDoorScene(14.0f, 4.0f);
  AddBox(scene, testing::V3(0.6f, 0.0f, 0.0f), testing::V3(13.4f, 0.025f, 2.1f),
         scenes::ElementClass::kFurniture, "door_panel", "R");
  const SouthWallFit fit = FitSouthWall(std::move(scene));
  const double worst = fit.worst;
  ASSERT_EQ(fit.edges, 1) << fit.figures;
  std::printf("south wall line behind the panel: ends at most %.4f m off the wall\n", worst);
  EXPECT_LT(worst, 0.006) << fit.figures;
}

// The perimeter's last pass: a vertex between two on a wall line, behind it by up to
// jog_tolerance, is a jog (dropped); deeper, up to seal_depth, a view through an opening (cut
// across). The two rules meet: a vertex between the two thresholds (jog 4 cm, seal from 5 cm)
// used to stay and split its wall in three SM3 faces (docs/floor-mission.md).
TEST(RoomModel, PerimeterDropsADetourBehindAWallLineAtAnyDepthUpToSealDepth) {
  const RoomModelParams p;
  for (const double depth : {0.02, 0.039, 0.045, 0.049, 0.1, 0.5}) {
    std::vector<Vec2> poly = {{0, 0}, {2.8, 0}, {3.0, -depth}, {3.3, 0}, {6, 0}, {6, 4}, {0, 4}};
    TidyPerimeter(poly, p);
    EXPECT_EQ(poly.size(), 4u) << "depth " << depth;
    for (const Vec2& v : poly) EXPECT_GE(v.y(), -1e-9) << "depth " << depth;
  }
  // Deeper than seal_depth: room (a niche, an alcove), kept.
  std::vector<Vec2> alcove = {{0, 0},   {2.5, 0}, {2.5, -1.0}, {3.5, -1.0},
                              {3.5, 0}, {6, 0},   {6, 4},      {0, 4}};
  TidyPerimeter(alcove, p);
  EXPECT_EQ(alcove.size(), 8u);
}

// A scanner 0.6 m from a corridor wall, beside a door in it: the lintel over the door lies inside
// the minimum range, so the first return up the door's azimuths is the next room's ceiling and
// the outline runs 0.9 m into that room through a 0.2 m mouth on the wall line (random corridor
// floor 8104: the room behind the door was never entered). Where other scans saw the wall's
// face go on above the mouth (a lintel), the detour is a view through an opening at any depth
// and is cut across; without a lintel (an alcove whose ceiling goes on) it is room, kept.
TEST(RoomModel, PerimeterCutsAcrossADeepViewThroughADoorWhoseLintelOtherScansSaw) {
  const RoomModelParams p;
  const std::vector<Vec2> spike = {{0, 0},       {15, 0},    {15, 2.25},  {11.43, 2.25},
                                   {10.71, 3.15}, {10.43, 3.15}, {11.21, 2.25}, {0, 2.25}};
  std::vector<Vec2> lintel;  // the wall's face over the 1 m door at x 10.85-11.85, y 2.25
  for (double x = 10.86; x < 11.85; x += 0.02) lintel.emplace_back(x, 2.25 + 0.003);
  std::vector<Vec2> sealed = spike;
  TidyPerimeter(sealed, p, lintel);
  EXPECT_EQ(sealed.size(), 4u);
  for (const Vec2& v : sealed) EXPECT_LE(v.y(), 2.25 + 1e-9);
  // No lintel points, or points off the wall's line (the next room's far wall): kept.
  for (const double off : {-1.0, 0.05}) {
    std::vector<Vec2> kept = spike, pts;
    if (off > 0)
      for (const Vec2& q : lintel) pts.emplace_back(q.x(), q.y() + off);
    TidyPerimeter(kept, p, pts);
    EXPECT_EQ(kept.size(), spike.size()) << "offset " << off;
  }
  // The lintel over part of the mouth only (a third of a 0.6 m mouth): kept.
  std::vector<Vec2> wide = {{0, 0},      {15, 0},      {15, 2.25}, {11.8, 2.25},
                            {11.5, 3.15}, {11.3, 3.15}, {11.2, 2.25}, {0, 2.25}};
  std::vector<Vec2> third;
  for (double x = 11.6; x < 11.8; x += 0.02) third.emplace_back(x, 2.25);
  TidyPerimeter(wide, p, third);
  EXPECT_EQ(wide.size(), 8u);
}

// A corner the tracer cut with a 0.39 m edge 11 deg off the wall it ends (office_5rooms, R1's
// corner at the room east of it): the refit kept the cut's direction but moved it onto the
// wall, whose points are the only ones in its band and run along the wall. It is no face: the
// room keeps its four corners. A cut whose points run 30 deg off (a diagonal face of its own)
// or lie 5 cm in front of the wall stays an edge; a 0.21 m cut no wall carried collapses.
TEST(RoomModel, ACornerCutFittedOntoItsNeighboursWallCollapsesIntoTheCorner) {
  const RoomModelParams params;
  const std::vector<Vec2> poly = {{0, 0}, {6, 0}, {6, 3.62}, {5.925, 4}, {0, 4}};
  const Vec2 cut = (poly[3] - poly[2]).normalized();
  auto lines_with_cut = [&](double support_deg, double offset, bool fitted) {
    const double a = DegToRad(support_deg);
    return std::vector<PerimeterLine>{{{3, 0}, {1, 0}, true, {1, 0}},
                                      {{6, 2}, {0, 1}, true, {0, 1}},
                                      {{6 - offset, 3.8}, cut, fitted, {-std::sin(a), std::cos(a)}},
                                      {{3, 4}, {-1, 0}, true, {-1, 0}},
                                      {{0, 2}, {0, -1}, true, {0, -1}}};
  };
  const std::vector<Vec2> truth = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  auto expect_truth = [&](const std::vector<Vec2>& out, const char* what) {
    ASSERT_EQ(out.size(), truth.size()) << what;
    for (std::size_t i = 0; i < truth.size(); ++i)
      EXPECT_LT((out[i] - truth[i]).norm(), 1e-3) << what << " corner " << i;
  };
  expect_truth(JoinPerimeterLines(poly, lines_with_cut(0.5, 0.003, true), params), "on the wall");
  EXPECT_EQ(JoinPerimeterLines(poly, lines_with_cut(30.0, 0.003, true), params).size(), 5u);
  EXPECT_EQ(JoinPerimeterLines(poly, lines_with_cut(0.5, 0.05, true), params).size(), 5u);
  const std::vector<Vec2> short_cut = {{0, 0}, {6, 0}, {6, 3.79}, {5.96, 4}, {0, 4}};
  expect_truth(JoinPerimeterLines(short_cut, lines_with_cut(0.5, 0.003, false), params),
               "unfitted");
}

// An L-shaped room scanned from both legs: the perimeter is the six corners of the L to 1 cm,
// the re-entrant one included. (Scanned from (1, 2), (8.5, 1) and (9, 9) instead, the wall
// x = 7 comes out 0.33 deg tilted and that corner 4 cm off: a known limit, docs/room-scanning.md.)
TEST(RoomModel, LRoomPerimeterHasTheSixCornersOfTheL) {
  const sim::EmbreeWorld world(testing::LRoomScene());
  RoomModel model;
  for (const auto& xy : {Vec2(2.0, 1.5), Vec2(8.5, 1.5), Vec2(8.5, 7.0)}) {
    const SimScan s = TakeScan(world, TestTls(), xy.x(), xy.y(), 1);
    model.AddScan(s.scan, s.X_MS);
  }
  const std::vector<Vec2> truth = {{0, 0}, {10, 0}, {10, 10}, {7, 10}, {7, 3}, {0, 3}};
  const auto& per = model.Perimeter();
  ASSERT_EQ(per.size(), truth.size()) << model.FiguresJson();
  for (const Vec2& c : truth) {
    double best = 1e9;
    for (const Vec2& p : per) best = std::min(best, (p - c).norm());
    EXPECT_LT(best, 0.01) << "corner " << c.transpose() << "\n" << model.FiguresJson();
  }
}

// A frozen structure (the detail pass's scans: data quality, never structure) keeps heights,
// perimeter, columns and faces when a scan sees a part of the room no earlier scan saw; the
// scan's points still join the cloud and are labelled against the frozen RoI (and its rays
// still mark where a face is an opening: a face cell's state is data). The same scan
// moves the perimeter of a model that is not frozen (so the check can fail).
TEST(RoomModel, AFrozenStructureTakesAScansPointsButKeepsItsPerimeter) {
  const sim::EmbreeWorld world(testing::LRoomScene());
  RoomModel frozen, open;
  for (RoomModel* m : {&frozen, &open}) {
    const SimScan s = TakeScan(world, TestTls(), 2.0, 1.5, 1);
    m->AddScan(s.scan, s.X_MS);
  }
  const std::vector<Vec2> perimeter = frozen.Perimeter();
  const double ceiling = frozen.CeilingZ();
  const std::size_t points = frozen.PointCount(), faces = frozen.GetRoi().faces.size();
  frozen.FreezeStructure();
  EXPECT_TRUE(frozen.StructureFrozen());
  EXPECT_FALSE(open.StructureFrozen());
  const SimScan s = TakeScan(world, TestTls(), 8.5, 7.0, 2);  // up the L's leg
  frozen.AddScan(s.scan, s.X_MS);
  open.AddScan(s.scan, s.X_MS);
  EXPECT_GT(OutlineDistance(open.Perimeter(), perimeter), 0.5) << open.FiguresJson();
  EXPECT_EQ(frozen.Perimeter(), perimeter) << frozen.FiguresJson();
  EXPECT_EQ(frozen.GetRoi().faces.size(), faces);
  EXPECT_EQ(frozen.CeilingZ(), ceiling);
  EXPECT_EQ(frozen.ScanCount(), 2);
  EXPECT_GT(frozen.PointCount(), points);
  EXPECT_EQ(frozen.Labels().size(), frozen.PointCount());
  EXPECT_GT(frozen.Coverage().sensed_area, 0.0);
}

// An exterior door 2.55 m high under a 2.7 m ceiling in a 0.3 m wall, nothing beyond (FZK-Haus'
// front door): its head soffit is within the trace's hanging tolerance of the ceiling, so the
// trace walks into the reveal up to the wall's outer face. That notch is a view through an
// opening, not room: the perimeter cuts straight across it (seal_depth), the 4 corners to 3 cm.
// Without the seal the notch stays (the check below that it exists keeps this test honest).
TEST(RoomModel, PerimeterCutsAcrossTheRevealOfADoorWhoseHeadIsNearTheCeiling) {
  const float W = 6, D = 4, H = 2.7f, oy0 = 1.5f, oy1 = 2.4f, door_h = 2.55f, e = 0.001f;
  scenes::Scene scene;
  sim::testing::AddRoomWithOpening(scene, W, D, H, oy0, oy1, 0.0f, door_h);
  AddBox(scene, testing::V3(W + e, 0.0f, door_h + e), testing::V3(W + 0.3f, D, H),
         scenes::ElementClass::kOther, "lintel");
  AddBox(scene, testing::V3(W + e, 0.0f, 0.0f), testing::V3(W + 0.3f, oy0 - e, door_h),
         scenes::ElementClass::kOther, "wall_e_a");
  AddBox(scene, testing::V3(W + e, oy1 + e, 0.0f), testing::V3(W + 0.3f, D, door_h),
         scenes::ElementClass::kOther, "wall_e_b");
  for (auto& part : scene.parts) part.room = "R";
  const sim::EmbreeWorld world(std::move(scene));
  const std::vector<Vec2> truth = {{0, 0}, {W, 0}, {W, D}, {0, D}};
  auto perimeter = [&](double seal_depth) {
    RoomModelParams params;
    params.seal_depth = seal_depth;
    RoomModel model(params);
    for (const auto& xy : {Vec2(2.0, 1.8), Vec2(4.5, 3.0)}) {
      const SimScan s = TakeScan(world, TestTls(), xy.x(), xy.y(), 0);
      model.AddScan(s.scan, s.X_MS);
    }
    return std::make_pair(model.Perimeter(), model.FiguresJson());
  };
  const auto [sealed, figures] = perimeter(RoomModelParams{}.seal_depth);
  ASSERT_EQ(sealed.size(), 4u) << figures;
  EXPECT_LT(OutlineDistance(sealed, truth), 0.03) << figures;
  const auto [open, open_figures] = perimeter(0.0);
  double xmax = -1e300;
  for (const auto& v : open) xmax = std::max(xmax, v.x());
  EXPECT_GT(xmax, W + 0.1) << "no notch to cut: " << open_figures;
}

// A 0.24 m wall standing 3.5 m out of the west wall of an open room (FZK-Haus' hall): seen past
// its end, a scan's ceiling reach jumps from the end face to the far ceiling, and the straight
// outline edge between them claimed the shadow behind the end (the end came out 0.2 m short
// and slanted). The outline steps radially at such jumps: the end face's corners to 3 cm.
TEST(RoomModel, PerimeterKeepsTheEndOfAWallStandingIntoTheRoom) {
  scenes::Scene scene;
  sim::testing::AddRoomWithOpening(scene, 8.0f, 6.0f, 2.5f, 0.0f, 0.0f, 0.0f, 0.0f);
  AddBox(scene, testing::V3(0.0f, 2.88f, 0.0f), testing::V3(3.5f, 3.12f, 2.5f),
         scenes::ElementClass::kWall, "stub");
  for (auto& part : scene.parts) part.room = "R";
  const sim::EmbreeWorld world(std::move(scene));
  RoomModel model;
  for (const auto& xy : {Vec2(5.5, 1.5), Vec2(5.5, 4.5), Vec2(2.0, 1.2), Vec2(2.0, 4.8)}) {
    const SimScan s = TakeScan(world, TestTls(), xy.x(), xy.y(), 0);
    model.AddScan(s.scan, s.X_MS);
  }
  const std::vector<Vec2> truth = {{0, 0},    {8, 0},      {8, 6},      {0, 6},
                                   {0, 3.12}, {3.5, 3.12}, {3.5, 2.88}, {0, 2.88}};
  const auto& per = model.Perimeter();
  for (const Vec2& c : {Vec2(3.5, 3.12), Vec2(3.5, 2.88)}) {
    double best = 1e9;
    for (const Vec2& p : per) best = std::min(best, (p - c).norm());
    EXPECT_LT(best, 0.03) << "corner " << c.transpose() << "\n" << model.FiguresJson();
  }
  EXPECT_LT(OutlineDistance(per, truth), 0.03) << model.FiguresJson();
  // The end face is fitted across its own points, squared to the wall: traced askew, its fit
  // came out 1.4 cm inside the end (FZK-Haus: 2.4 cm, d_h of the wall's faces).
  int at_end = 0;
  for (const Vec2& p : per)
    if (p.x() > 3.0 && p.x() < 4.0) {
      EXPECT_NEAR(p.x(), 3.5, 0.01) << p.transpose() << "\n" << model.FiguresJson();
      ++at_end;
    }
  EXPECT_EQ(at_end, 2);
}

// The same wall with one scan standing 0.7 m from its end, inside the scanner's minimum
// range of it: that scan's azimuths towards the end return nothing, and its outline must not
// bridge them with a straight edge across the end.
TEST(RoomModel, PerimeterKeepsTheEndOfAWallAScanStandsTooCloseTo) {
  scenes::Scene scene;
  sim::testing::AddRoomWithOpening(scene, 8.0f, 6.0f, 2.5f, 0.0f, 0.0f, 0.0f, 0.0f);
  AddBox(scene, testing::V3(0.0f, 2.88f, 0.0f), testing::V3(3.5f, 3.12f, 2.5f),
         scenes::ElementClass::kWall, "stub");
  for (auto& part : scene.parts) part.room = "R";
  const sim::EmbreeWorld world(std::move(scene));
  RoomModel model;
  for (const auto& xy :
       {Vec2(5.5, 1.5), Vec2(5.5, 4.5), Vec2(2.0, 1.2), Vec2(2.0, 4.8), Vec2(4.15, 2.7)}) {
    const SimScan s = TakeScan(world, TestTls(), xy.x(), xy.y(), 0);
    model.AddScan(s.scan, s.X_MS);
  }
  const auto& per = model.Perimeter();
  for (const Vec2& c : {Vec2(3.5, 3.12), Vec2(3.5, 2.88)}) {
    double best = 1e9;
    for (const Vec2& p : per) best = std::min(best, (p - c).norm());
    EXPECT_LT(best, 0.03) << "corner " << c.transpose() << "\n" << model.FiguresJson();
  }
}

TEST(RoomModel, StructuralVoxelsAreTheSingleLayerContainingEachFace) {
  RoomModel model;
  const SimScan s = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  model.AddScan(s.scan, s.X_MS);
  const Roi& roi = model.GetRoi();
  const VoxelSpace& v = model.Voxels();
  const double h = v.Size();
  auto structural = [&](int i, int j, int k) {
    return v.Contains(i, j, k) && (v.Flags(v.Index(i, j, k)) & VoxelSpace::kStructural);
  };
  auto outside_by = [&](const Vec2& c) {  // plan distance outside the RoI perimeter (0 inside)
    if (roi.ContainsPlan(c)) return 0.0;
    double d = 1e300;
    const auto& p = roi.perimeter;
    for (std::size_t e = 0; e < p.size(); ++e)
      d = std::min(d, DistanceToSegment(c, p[e], p[(e + 1) % p.size()]));
    return d;
  };
  int n_struct = 0;
  for (int k = 0; k < v.Nz(); ++k)
    for (int j = 0; j < v.Ny(); ++j)
      for (int i = 0; i < v.Nx(); ++i) {
        if (!structural(i, j, k)) continue;
        ++n_struct;
        const Vec3 c = v.Centre(i, j, k);
        // Half a voxel behind a face's plane at most (so up to sqrt(2)/2 at a corner).
        EXPECT_LE(outside_by(c.head<2>()), 0.5 * std::sqrt(2.0) * h + 1e-9) << c.transpose();
        EXPECT_GE(c.z(), model.FloorZ() - 0.5 * h - 1e-9);
        EXPECT_LE(c.z(), model.CeilingZ() + 0.5 * h + 1e-9);
      }
  EXPECT_GT(n_struct, 0);
  // One layer across each wall: at mid-height along lines crossing the south (y = 0) and the
  // west (x = 0) walls, and one floor and one ceiling layer above an inside point.
  const int km = v.VoxelOf(Vec3(0, 0, 1.2)).z();
  for (double x : {1.05, 3.05, 5.05}) {
    const Eigen::Vector3i q = v.VoxelOf(Vec3(x, 0.0, 1.2));
    int n = 0;
    for (int j = q.y() - 4; j <= q.y() + 4; ++j) n += structural(q.x(), j, km);
    EXPECT_EQ(n, 1) << "south wall at x " << x;
  }
  for (double y : {1.05, 3.05}) {
    const Eigen::Vector3i q = v.VoxelOf(Vec3(0.0, y, 1.2));
    int n = 0;
    for (int i = q.x() - 4; i <= q.x() + 4; ++i) n += structural(i, q.y(), km);
    EXPECT_EQ(n, 1) << "west wall at y " << y;
  }
  const Eigen::Vector3i q = v.VoxelOf(Vec3(3.05, 1.05, 1.2));
  int n = 0;
  for (int k = 0; k < v.Nz(); ++k) n += structural(q.x(), q.y(), k);
  EXPECT_EQ(n, 2);  // the floor's layer and the ceiling's
  EXPECT_TRUE(structural(q.x(), q.y(), v.VoxelOf(Vec3(0, 0, model.FloorZ())).z()));
  EXPECT_TRUE(structural(q.x(), q.y(), v.VoxelOf(Vec3(0, 0, model.CeilingZ() - 1e-6)).z()));
}

// DSM3's layers keep the floor and the ceiling at least a quarter of a voxel from a layer
// boundary, so that the estimate and the truth of each fall in the same layer whatever the
// room's height. With the floor centred in its layer, a 2.65 m ceiling under a 0.1 m grid lay on
// a boundary and a 0.3 mm difference in the estimates moved the whole ceiling layer (random
// corridor floor 8104's R2: structure IoU 0.99 on one run, 0.74 on the next).
TEST(RoomModel, FloorAndCeilingLieInsideTheirVoxelLayersAtAnyRoomHeight) {
  for (const float H : {2.6f, 2.65f, 2.7f, 2.72f, 2.78f}) {
    sim::EmbreeWorld world{testing::RoomWithDoorScene(6, 4, H)};
    RoomModel model;
    const SimScan s = TakeScan(world, TestTls(), 2.0, 1.8, 0);
    model.AddScan(s.scan, s.X_MS);
    const VoxelSpace& v = model.Voxels();
    const double oz = v.Origin().z(), size = v.Size();
    for (const double z : {model.FloorZ(), model.CeilingZ(), 0.0, static_cast<double>(H)}) {
      const double f = (z - oz) / size - std::floor((z - oz) / size);
      EXPECT_GE(std::min(f, 1.0 - f), 0.2) << "H " << H << ", z " << z;
    }
    EXPECT_EQ(v.VoxelOf(Vec3(2.0, 1.8, model.CeilingZ())).z(), v.VoxelOf(Vec3(2.0, 1.8, H)).z())
        << "H " << H;
    EXPECT_EQ(v.VoxelOf(Vec3(2.0, 1.8, model.FloorZ())).z(), 1) << "H " << H;
  }
}

TEST(RoomModel, ColumnIsDetectedAndItsSurfaceIsStructural) {
  scenes::Scene scene;
  sim::testing::AddRoomBox(scene, testing::V3(0, 0, 0), testing::V3(8, 5, 2.8f));
  AddBox(scene, testing::V3(3.8f, 2.3f, 0.0f), testing::V3(4.2f, 2.7f, 2.8f),
         scenes::ElementClass::kColumn, "C1");
  const sim::EmbreeWorld world(std::move(scene));
  RoomModel model;
  const SimScan a = TakeScan(world, TestTls(), 1.5, 1.5, 0);
  const SimScan b = TakeScan(world, TestTls(), 6.5, 3.5, 1);
  model.AddScan(a.scan, a.X_MS);
  model.AddScan(b.scan, b.X_MS);
  ASSERT_EQ(model.Columns().size(), 1u) << model.FiguresJson();
  Vec2 c = Vec2::Zero();
  for (const auto& p : model.Columns()[0]) c += p;
  c /= static_cast<double>(model.Columns()[0].size());
  EXPECT_NEAR(c.x(), 4.0, 0.1);
  EXPECT_NEAR(c.y(), 2.5, 0.1);
  EXPECT_NEAR(std::abs(SignedArea(model.Columns()[0])), 0.16, 0.06);
  EXPECT_EQ(model.Classify(Vec3(3.8, 2.5, 1.5)), PointLabel::kInlier);
  EXPECT_EQ(model.Classify(Vec3(3.5, 2.5, 1.5)), PointLabel::kClutter);
  // B-rep with a through hole: V - E + F - (inner loops) = 2 (shells - genus) = 0.
  const Roi& roi = model.GetRoi();
  int inner = 0;
  for (const auto& f : roi.faces) inner += static_cast<int>(f.holes.size());
  EXPECT_EQ(static_cast<int>(roi.vertices.size()) - static_cast<int>(roi.edges.size()) +
                static_cast<int>(roi.faces.size()) - inner,
            0);
}

TEST(RoomModel, SameInputSameBytesWithOneOrTwoThreads) {
  const SimScan a = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  const SimScan b = TakeScan(Door().world, TestTls(), 4.5, 1.2, 1);
  const auto dir = std::filesystem::temp_directory_path();
  std::string bytes[2];
  std::string json[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    RoomModel model;
    model.AddScan(a.scan, a.X_MS);
    model.AddScan(b.scan, b.X_MS);
    std::string name = "mopad_sm1_";
    name += std::to_string(threads);
    name += ".ply";
    const std::string path = (dir / name).string();
    model.WriteSm1(path);
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    bytes[threads - 1] = ss.str();
    json[threads - 1] = model.FiguresJson();
    std::filesystem::remove(path);
  }
  EXPECT_EQ(json[0], json[1]);
  EXPECT_TRUE(bytes[0] == bytes[1]);
}

TEST(RoomModel, Sm1PlyHasTheLabelledColouredCloud) {
  const SimScan a = TakeScan(Door().world, TestTls(), 2.0, 1.8, 0);
  RoomModel model;
  model.AddScan(a.scan, a.X_MS);
  const std::string path =
      (std::filesystem::temp_directory_path() / "mopad_sm1_fields.ply").string();
  model.WriteSm1(path);
  const io::PointCloud c = io::ReadPly(path);
  std::filesystem::remove(path);
  ASSERT_EQ(c.points.size(), model.PointCount());
  ASSERT_EQ(c.colors.size(), model.PointCount());
  const io::ScalarField* label = c.Field("scalar_label");
  const io::ScalarField* scan = c.Field("scalar_scan");
  ASSERT_NE(c.Field("scalar_intensity"), nullptr);
  ASSERT_NE(label, nullptr);
  ASSERT_NE(scan, nullptr);
  for (std::size_t i = 0; i < c.points.size(); i += 997) {
    EXPECT_EQ(label->values[i], static_cast<double>(model.Labels()[i]));
    EXPECT_EQ(scan->values[i], 0.0);
  }
}

TEST(RoomModel, BadInputAndParamsThrow) {
  RoomModel model;
  interfaces::TlsScan bad;
  bad.rows = 2;
  bad.columns = 2;
  EXPECT_THROW(model.AddScan(bad, Pose3::Identity()), InputError);
  bad.points.resize(4);
  EXPECT_THROW(model.AddScan(bad, Pose3::Identity()), InputError);  // no valid return
  RoomModelParams p;
  p.voxel_size = 0.0;
  EXPECT_THROW(RoomModel{p}, InputError);
  const RoomModelParams q = LoadParams<RoomModelParams>(
      LoadYamlString("wall_tolerance: 0.02\nray_stride: 3\n", "t.yaml"), "t.yaml");
  EXPECT_EQ(q.wall_tolerance, 0.02);
  EXPECT_EQ(q.ray_stride, 3);
  const RoomModelParams r = LoadParams<RoomModelParams>(SaveParams(q), "saved");
  EXPECT_EQ(r.ray_stride, 3);
  EXPECT_THROW(LoadParams<RoomModelParams>(LoadYamlString("wall_tol: 1\n", "t.yaml"), "t.yaml"),
               InputError);
}

TEST(RoomModelParams, VisitReachesEveryFieldAndNestedKeysRoundTrip) {
  for (const auto& m : FieldsMissingFromVisit(RoomModelParams{}, "room_model.")) ADD_FAILURE() << m;
  const RoomModelParams q = LoadParams<RoomModelParams>(
      LoadYamlString("refit:\n  high_band: 2.4\ncolumns:\n  slices: 6\nvoxel_growth: 0.5\n",
                     "t.yaml"),
      "t.yaml");
  EXPECT_EQ(q.refit.high_band, 2.4);
  EXPECT_EQ(q.columns.slices, 6);
  EXPECT_EQ(q.voxel_growth, 0.5);
  EXPECT_EQ(q.refit.offset_bin, RoomModelParams{}.refit.offset_bin);  // the rest keep defaults
  const RoomModelParams r = LoadParams<RoomModelParams>(SaveParams(q), "saved");
  EXPECT_EQ(YAML::Dump(SaveParams(r)), YAML::Dump(SaveParams(q)));
  EXPECT_THROW(
      LoadParams<RoomModelParams>(LoadYamlString("outline:\n  gap_row: 3\n", "t.yaml"), "t.yaml"),
      InputError);
  RoomModelParams bad;
  bad.columns.slices = 17;  // the column mask holds 16 slices
  EXPECT_THROW(RoomModel{bad}, InputError);
}

// Coverage after `scans` scans: `sensed` of `total` m^2, nothing estimated hidden.
CoverageFigures Figures(int scans, double sensed, double total, double increment) {
  CoverageFigures f;
  f.scans = scans;
  f.sensed_area = sensed;
  f.total_area = total;
  f.ratio = sensed / total;
  f.increment = increment;
  f.SetHiddenArea(0.0);
  return f;
}

TEST(Stopping, EachCriterionStopsWithItsReason) {
  CoverageFigures f = Figures(3, 93.0, 100.0, 0.05);
  StoppingParams paper;
  paper.epsilon1 = 0.90;
  StopDecision d = CheckStopping(f, paper);
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.reason, StopReason::kCoverageReached);
  EXPECT_NE(d.message.find("coverage 0.930 >= epsilon1 0.900"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("93.00 m2 of 100.00 m2"), std::string::npos) << d.message;

  f = Figures(3, 80.0, 100.0, 0.004);
  d = CheckStopping(f, {});
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.reason, StopReason::kIncrementTooSmall);
  EXPECT_NE(d.message.find("increment 0.004 < epsilon2 0.010"), std::string::npos) << d.message;

  f.increment = 0.2;
  d = CheckStopping(f, {});
  EXPECT_FALSE(d.stop);
  EXPECT_EQ(d.reason, StopReason::kContinue);

  f.scans = 1;  // the first scan's increment is not a stopping reason
  f.increment = 0.0;
  EXPECT_FALSE(CheckStopping(f, {}).stop);

  StoppingParams p;
  p.max_scans = 3;
  f.scans = 3;
  f.increment = 0.2;
  d = CheckStopping(f, p);
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.reason, StopReason::kMaxScans);

  p.epsilon1 = 1.5;
  EXPECT_THROW(CheckStopping(f, p), InputError);
}

TEST(Stopping, Epsilon1IsAShareOfTheObservableStructure) {
  // 88 of 100 m^2 sensed; 6 m^2 of what is missing no reachable position can see: 88 / 94.
  CoverageFigures f = Figures(3, 88.0, 100.0, 0.05);
  StoppingParams p;
  p.epsilon1 = 0.93;
  EXPECT_DOUBLE_EQ(f.observable_ratio, 0.88);
  EXPECT_FALSE(CheckStopping(f, p).stop);
  f.SetHiddenArea(6.0);
  EXPECT_NEAR(f.observable_ratio, 88.0 / 94.0, 1e-12);
  const StopDecision d = CheckStopping(f, p);
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.reason, StopReason::kCoverageReached);
  EXPECT_NE(d.message.find("coverage 0.936 >= epsilon1 0.930"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("6.00 m2 hidden"), std::string::npos) << d.message;
  // Hidden area cannot exceed what is unsensed, nor be negative.
  f.SetHiddenArea(50.0);
  EXPECT_DOUBLE_EQ(f.hidden_area, 12.0);
  EXPECT_DOUBLE_EQ(f.observable_ratio, 1.0);
  f.SetHiddenArea(-1.0);
  EXPECT_DOUBLE_EQ(f.hidden_area, 0.0);
}

}  // namespace
}  // namespace mopad::modelling
