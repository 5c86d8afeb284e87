// Obstacle map: built from a height band of 3D points, updated by LRF ray tracing, inflated by
// a distance transform, written and read in ROS map_server conventions.
#include "perception/occupancy_grid.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "tests/perception/synthetic_world.h"

namespace mopad::perception {
namespace {

namespace fs = std::filesystem;
using testing::Box2;

fs::path TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("mopad_perception_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(OccupancyGrid, BuiltFromPointsOfTwoRoomsWithADoorGap) {
  const OccupancyGrid g = testing::BuildGrid(testing::TwoRooms());
  EXPECT_TRUE(g.IsOccupied({4.95, 1.0}));  // partition face (its inside is never seen)
  EXPECT_TRUE(g.IsOccupied({0.0, 3.0}));   // west wall
  EXPECT_TRUE(g.IsOccupied({2.0, 0.6}));   // edge of the table block
  EXPECT_TRUE(g.IsFree({5.0, 3.0}));       // the door gap
  EXPECT_TRUE(g.IsFree({2.5, 3.0}));       // west room
  EXPECT_TRUE(g.IsFree({7.5, 2.0}));       // east room
  EXPECT_EQ(g.StateAt({-0.4, -0.4}), CellState::kUnknown);  // never observed
  EXPECT_EQ(g.StateAt({2.0, 0.9}), CellState::kUnknown);    // inside the block: no returns
  EXPECT_EQ(g.StateAt({50.0, 50.0}), CellState::kUnknown);  // outside the grid
  EXPECT_GT(g.Count(CellState::kFree), 15000);
}

TEST(OccupancyGrid, EvidenceLaidOverABaseNeverClearsWhatTheCloudMarked) {
  OccupancyGridParams p;
  // The base: a wall of 3D band points at x = 1.0 m, free floor elsewhere around it.
  OccupancyGrid base = OccupancyGrid::Covering(p, Vec2(0.0, 0.0), Vec2(2.0, 2.0), 0.0);
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 40; ++k) {
    pts.emplace_back(1.02, 0.5 + 0.02 * k, 1.0);
    pts.emplace_back(0.52, 0.5 + 0.02 * k, 0.0);
  }
  base.InsertPoints(pts);
  ASSERT_TRUE(base.IsOccupied({1.02, 1.0}));
  ASSERT_TRUE(base.IsFree({0.52, 1.0}));
  // The evidence, on a larger grid of the same lattice: many misses over the wall cell and
  // the floor cell, hits on a cell the base left unknown.
  OccupancyGrid evidence = OccupancyGrid::Covering(p, Vec2(-1.0, -1.0), Vec2(3.0, 3.0), 0.0);
  OccupancyGrid beams(p, evidence.Origin(), evidence.Width(), evidence.Height());
  for (int k = 0; k < 10; ++k)
    beams.InsertScan(testing::SimulateScan({{{1.62, 1.5}, {1.72, 1.6}}}, {0.3, 1.02, 0.0}, 1, k,
                                           0.0),
                     {0.3, 1.02, 0.0});
  evidence = beams.Resized(Vec2(-1.0, -1.0), Vec2(3.0, 3.0));
  OccupancyGrid out = base;
  out.Compose(base, evidence, Vec2(0.0, 0.0), Vec2(2.0, 2.0));
  EXPECT_TRUE(out.IsOccupied({1.02, 1.0}));  // the beams crossed it: the cloud's wall stays
  EXPECT_TRUE(out.IsFree({0.52, 1.0}));
  EXPECT_TRUE(out.IsOccupied({1.63, 1.53}));  // the beams' own obstacle, unknown in the base
  EXPECT_EQ(base.StateAt({1.63, 1.53}), CellState::kUnknown);
  // Outside the box the base is kept as it was.
  OccupancyGrid part = base;
  part.Compose(base, evidence, Vec2(0.0, 0.0), Vec2(1.4, 2.0));
  EXPECT_EQ(part.StateAt({1.63, 1.53}), CellState::kUnknown);
  // A grid off the lattice cannot take lattice evidence.
  OccupancyGrid off(p, Vec2(0.013, 0.0), 10, 10);
  EXPECT_THROW(off.Compose(off, evidence, Vec2(0.0, 0.0), Vec2(0.5, 0.5)), InputError);
}

TEST(OccupancyGrid, PointsOutsideTheHeightBandAreNotObstacles) {
  OccupancyGridParams p;
  OccupancyGrid g(p, {0.0, 0.0}, 20, 20);
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 10; ++k) {
    pts.emplace_back(0.22, 0.22, 2.5);  // ceiling lamp, above the band
    pts.emplace_back(0.52, 0.52, 1.0);  // in the band
    pts.emplace_back(0.82, 0.82, 0.0);  // floor
  }
  pts.emplace_back(0.72, 0.22, 1.0);  // a single stray point: below min_points_per_cell
  g.InsertPoints(pts);
  EXPECT_EQ(g.StateAt({0.22, 0.22}), CellState::kUnknown);
  EXPECT_EQ(g.StateAt({0.52, 0.52}), CellState::kOccupied);
  EXPECT_EQ(g.StateAt({0.82, 0.82}), CellState::kFree);
  EXPECT_EQ(g.StateAt({0.72, 0.22}), CellState::kUnknown);
}

TEST(OccupancyGrid, LrfScanClearsAlongBeamsAndMarksReturns) {
  OccupancyGridParams p;
  OccupancyGrid g(p, {-1.0, -1.0}, 140, 100);  // unknown, 7 m x 5 m
  const std::vector<Box2> world = {{{-0.6, -0.6}, {5.6, -0.5}},
                                   {{-0.6, 3.5}, {5.6, 3.6}},
                                   {{-0.6, -0.6}, {-0.5, 3.6}},
                                   {{5.5, -0.6}, {5.6, 3.6}}};
  for (int k = 0; k < 5; ++k) {
    g.InsertScan(testing::SimulateScan(world, {2.0, 1.5, 0.0}, 1, k, 0.0), {2.0, 1.5, 0.0});
    g.InsertScan(testing::SimulateScan(world, {2.0, 1.5, kPi}, 1, k, 0.0), {2.0, 1.5, kPi});
  }
  EXPECT_EQ(g.StateAt({3.0, 1.5}), CellState::kFree);
  EXPECT_EQ(g.StateAt({0.5, 2.5}), CellState::kFree);
  EXPECT_EQ(g.StateAt({5.52, 1.5}), CellState::kOccupied);
  EXPECT_EQ(g.StateAt({2.0, 3.52}), CellState::kOccupied);
  EXPECT_EQ(g.StateAt({5.8, 1.5}), CellState::kUnknown);  // behind the wall
}

// A desk top seen by the 3D scan (band points at 0.74 m) stays an obstacle although the base
// LRF's beams pass under it (the LRF world here has no desk); with the old rule they cleared it.
TEST(OccupancyGrid, LrfBeamsDoNotClearObstaclesSeenIn3D) {
  const std::vector<Box2> walls = {{{-0.6, -0.6}, {5.6, -0.5}},
                                   {{-0.6, 3.5}, {5.6, 3.6}},
                                   {{-0.6, -0.6}, {-0.5, 3.6}},
                                   {{5.5, -0.6}, {5.6, 3.6}}};
  std::vector<Eigen::Vector3d> desk_top;
  for (double x = 3.5; x <= 4.0; x += 0.02)
    for (double y = 1.2; y <= 1.8; y += 0.02) desk_top.emplace_back(x, y, 0.74);
  for (const bool clears : {false, true}) {
    OccupancyGridParams p;
    p.lrf_clears_cloud_obstacles = clears;
    OccupancyGrid g(p, {-1.0, -1.0}, 140, 100);
    g.InsertPoints(desk_top);
    EXPECT_EQ(g.StateAt({3.75, 1.5}), CellState::kOccupied);
    for (int k = 0; k < 5; ++k)
      g.InsertScan(testing::SimulateScan(walls, {2.0, 1.5, 0.0}, 1, k, 0.0), {2.0, 1.5, 0.0});
    EXPECT_EQ(g.StateAt({3.75, 1.5}), clears ? CellState::kFree : CellState::kOccupied) << clears;
    EXPECT_EQ(g.StateAt({3.0, 1.5}), CellState::kFree);  // the floor in front is still cleared
  }
}

// TLS beams clear the floor they cross low: a scanner at 1.6 m in a 10 m
// room whose floor returns are thinned to one every 2 m leaves most far cells unknown with
// InsertPoints alone; InsertRays fills them, stops a cell short of a wall, keeps a low box
// that band points marked, and does not clear the cells a beam crosses above ray_clear_z_max.
TEST(OccupancyGrid, TlsRaysClearTheFloorTheyCrossLowButNeverABandCell) {
  const Eigen::Vector3d o(0.0, 0.0, 1.6);
  std::vector<Eigen::Vector3d> pts;
  // Wall at x = 10.02 from 0.1 to 1.8 m (band returns), for y in [-2, 2].
  for (double y = -2.0; y <= 2.0; y += 0.01)
    for (double z = 0.1; z <= 1.8; z += 0.1) pts.emplace_back(10.02, y, z);
  // Sparse floor returns along +x: every 2 m, for y in [-2, 2] every 1 cm (azimuths).
  for (double x = 2.0; x <= 9.0; x += 2.0)
    for (double y = -2.0; y <= 2.0; y += 0.01) pts.emplace_back(x, y, 0.0);
  // A low box (0.3 m high) at x 6..6.3, y 1..1.3: band points on its top.
  for (double x = 6.0; x <= 6.3; x += 0.02)
    for (double y = 1.0; y <= 1.3; y += 0.02) pts.emplace_back(x, y, 0.3);
  OccupancyGridParams p;
  OccupancyGrid only_points(p, {-1.0, -3.0}, 240, 120);
  only_points.InsertPoints(pts);
  OccupancyGrid g = only_points;
  g.InsertRays(o, pts);
  EXPECT_EQ(only_points.StateAt({7.0, 0.5}), CellState::kUnknown);  // between floor rows
  EXPECT_EQ(g.StateAt({7.0, 0.5}), CellState::kFree);
  EXPECT_EQ(g.StateAt({9.0, -1.5}), CellState::kFree);
  EXPECT_EQ(g.StateAt({9.93, 0.0}), CellState::kFree);       // up to the cell before the wall
  EXPECT_EQ(g.StateAt({10.02, 0.0}), CellState::kOccupied);  // the wall
  EXPECT_EQ(g.StateAt({10.5, 0.0}), CellState::kUnknown);    // behind it
  EXPECT_EQ(g.StateAt({6.15, 1.15}), CellState::kOccupied);  // the low box stays
  // Near the scanner every beam runs above 0.4 m (the nearest floor return, 2 m out, is
  // crossed below 0.4 m only from 1.5 m on): no clearing there.
  EXPECT_EQ(g.StateAt({0.5, 0.0}), CellState::kUnknown);
  // Disabled: nothing changes.
  p.ray_clear_z_max = 0.0;
  OccupancyGrid off(p, {-1.0, -3.0}, 240, 120);
  off.InsertPoints(pts);
  off.InsertRays(o, pts);
  EXPECT_EQ(off.LogOddsData(), only_points.LogOddsData());
}

// A door leaf seen edge-on by one scan (floor returns in its cells only) and face-on by
// another (band returns) is an obstacle whatever the scan order; before, +2 and -2 cancelled.
TEST(OccupancyGrid, BandPointsBeatFloorPointsOfAnotherScan) {
  std::vector<Eigen::Vector3d> floor_only, leaf;
  for (double x = 1.0; x <= 1.9; x += 0.01) {
    floor_only.emplace_back(x, 0.51, 0.0);
    for (double z = 0.2; z <= 1.8; z += 0.2) leaf.emplace_back(x, 0.52, z);
  }
  for (const bool leaf_first : {false, true}) {
    OccupancyGrid g(OccupancyGridParams{}, {0.0, 0.0}, 60, 40);
    g.InsertPoints(leaf_first ? leaf : floor_only);
    g.InsertPoints(leaf_first ? floor_only : leaf);
    EXPECT_EQ(g.StateAt({1.5, 0.52}), CellState::kOccupied) << leaf_first;
  }
}

// Driving sweeps are traced only up to max_range: a return beyond it clears up to it, no hit.
TEST(OccupancyGrid, LrfScanWithARangeCapClearsOnlyUpToIt) {
  const std::vector<Box2> world = {{{-0.6, -0.6}, {5.6, -0.5}},
                                   {{-0.6, 3.5}, {5.6, 3.6}},
                                   {{-0.6, -0.6}, {-0.5, 3.6}},
                                   {{5.5, -0.6}, {5.6, 3.6}}};
  OccupancyGrid g(OccupancyGridParams{}, {-1.0, -1.0}, 140, 100);
  for (int k = 0; k < 5; ++k)
    g.InsertScan(testing::SimulateScan(world, {2.0, 1.5, 0.0}, 1, k, 0.0), {2.0, 1.5, 0.0}, 2.0);
  EXPECT_EQ(g.StateAt({3.5, 1.5}), CellState::kFree);      // 1.5 m out
  EXPECT_EQ(g.StateAt({4.6, 1.5}), CellState::kUnknown);   // beyond 2 m
  EXPECT_EQ(g.StateAt({5.52, 1.5}), CellState::kUnknown);  // the wall 3.5 m out: no hit
}

// A door gap whose jamb faces lie just past a 5 cm cell boundary: on the 5 cm map each jamb
// reads 4.5 cm into the gap; refined three times around the returns, 1.2 cm.
TEST(OccupancyGrid, RefinedPutsObstaclesWhereTheReturnsAre) {
  std::vector<Box2> world = testing::TwoRooms();
  world[4].hi.y() = 2.655;  // partition south of the gap: face at 2.655, in cell [2.65, 2.70)
  world[5].lo.y() = 3.295;  // north of it: face at 3.295, in cell [3.25, 3.30)
  const OccupancyGrid g = testing::BuildGrid(world);
  const OccupancyGrid fine = g.Refined(3);
  EXPECT_DOUBLE_EQ(fine.Resolution(), 0.05 / 3);
  EXPECT_EQ(fine.Width(), 3 * g.Width());
  EXPECT_EQ(fine.Origin(), g.Origin());
  EXPECT_TRUE(g.IsOccupied({5.0, 2.69}));       // 3.5 cm into the gap on the 5 cm map
  EXPECT_TRUE(fine.IsFree({5.0, 2.69}));        // free at 1.7 cm
  EXPECT_TRUE(fine.IsOccupied({5.0, 2.66}));    // the face's sub-cell
  EXPECT_TRUE(fine.IsOccupied({5.0, 3.29}));
  EXPECT_EQ(fine.StateAt({2.0, 0.9}), CellState::kUnknown);  // unknown stays unknown
  EXPECT_TRUE(fine.IsFree({2.5, 3.0}));
  // The gap's clearance: 0.275 m on the 5 cm map, 0.308 m refined (true 0.32).
  const double coarse = DistanceField(g, true).Clearance({5.0, 2.975});
  const double refined = DistanceField(fine, true).Clearance({5.0, 2.975});
  EXPECT_LE(coarse, 0.28);
  EXPECT_GE(refined, 0.30);
  EXPECT_LE(refined, 0.32);  // never past the true faces
  // A cell occupied without returns (a map from a PNG, an added obstacle) stays solid.
  OccupancyGrid marked = g;
  marked.SetState(marked.CellOf({2.5, 3.0}), CellState::kOccupied);
  const OccupancyGrid marked_fine = marked.Refined(3);
  const Vec2 c = marked.CentreOf(marked.CellOf({2.5, 3.0}));
  for (double dx : {-0.02, 0.0, 0.02})
    for (double dy : {-0.02, 0.0, 0.02})
      EXPECT_TRUE(marked_fine.IsOccupied({c.x() + dx, c.y() + dy}));
  EXPECT_THROW(g.Refined(0), InputError);
  EXPECT_THROW(g.Refined(9), InputError);
}

TEST(DistanceField, ClearanceInTheDoorGapAndInflation) {
  const OccupancyGrid g = testing::BuildGrid(testing::TwoRooms());
  const DistanceField f(g, true);
  EXPECT_NEAR(f.Clearance(Vec2(5.0, 3.0)), 0.45, 0.03);  // half the 0.9 m gap
  EXPECT_NEAR(f.Clearance(Vec2(2.5, 3.0)), 1.8, 0.05);   // 1.8 m to the block
  EXPECT_EQ(f.Clearance(Vec2(5.0, 1.0)), 0.0);
  EXPECT_TRUE(f.IsFree({5.0, 3.0}, 0.3));
  EXPECT_FALSE(f.IsFree({5.0, 3.0}, 0.5));
  EXPECT_FALSE(f.IsFree({-0.4, -0.4}, 0.0));  // unknown counts as obstacle here
  const OccupancyGrid inflated = g.Inflated(0.3, true);
  EXPECT_TRUE(inflated.IsFree({5.0, 3.0}));
  EXPECT_TRUE(inflated.IsOccupied({5.0, 2.75}));  // 0.2 m from the frame
  EXPECT_TRUE(inflated.IsOccupied({0.2, 3.0}));
  EXPECT_TRUE(inflated.IsFree({0.4, 3.0}));
  EXPECT_LT(inflated.Count(CellState::kFree), g.Count(CellState::kFree));
  // The interpolated centre distance is continuous across cells.
  const double a = f.CentreDistance({2.5, 3.0}, -1.0), b = f.CentreDistance({2.52, 3.0}, -1.0);
  EXPECT_NEAR(a, b, 0.03);
  EXPECT_EQ(f.CentreDistance({100.0, 0.0}, -1.0), -1.0);
}

TEST(DistanceField, ObstacleDistanceIsPerpendicularToTheWallWhateverTheCellAlignment) {
  // A wall along y at x = wall_x, sampled densely; the grid's cell boundaries fall at
  // multiples of 5 cm, so wall_x = 1.0 lies on a boundary and 1.0125 inside a cell.
  for (double wall_x : {1.0, 1.0125, 1.025}) {
    OccupancyGrid g(OccupancyGridParams{}, {0.0, 0.0}, 40, 40);
    std::vector<Eigen::Vector3d> pts;
    for (double y = 0.2; y <= 1.8; y += 0.01) pts.emplace_back(wall_x, y, 1.0);
    g.InsertPoints(pts);
    const DistanceField f(g, false, 2.0);
    for (double y : {0.5, 0.51, 0.525, 0.549, 1.2}) {
      for (double dx : {-0.2, -0.03, 0.0, 0.03, 0.2}) {
        EXPECT_NEAR(f.ObstacleDistance({wall_x + dx, y}, -1.0), std::abs(dx), 2e-3)
            << "wall at " << wall_x << ", query (" << wall_x + dx << ", " << y << ")";
      }
    }
    EXPECT_EQ(f.ObstacleDistance({-1.0, 0.5}, -1.0), -1.0);
  }
}

TEST(MapIo, PngYamlRoundTripKeepsEveryCell) {
  const OccupancyGrid g = testing::BuildGrid(testing::TwoRooms());
  const fs::path dir = TempDir("roundtrip");
  WriteMap(g, (dir / "map.yaml").string());
  ASSERT_TRUE(fs::exists(dir / "map.png"));
  const OccupancyGrid r = ReadMap((dir / "map.yaml").string());
  ASSERT_EQ(r.Width(), g.Width());
  ASSERT_EQ(r.Height(), g.Height());
  EXPECT_DOUBLE_EQ(r.Resolution(), g.Resolution());
  EXPECT_DOUBLE_EQ(r.Origin().x(), g.Origin().x());
  EXPECT_DOUBLE_EQ(r.Origin().y(), g.Origin().y());
  int differ = 0;
  for (int j = 0; j < g.Height(); ++j)
    for (int i = 0; i < g.Width(); ++i) differ += g.State(Cell{i, j}) != r.State(Cell{i, j});
  EXPECT_EQ(differ, 0);
  // map_server conventions: top image row is the highest y; free 254, occupied 0.
  const cv::Mat img = cv::imread((dir / "map.png").string(), cv::IMREAD_GRAYSCALE);
  const Cell wall = g.CellOf({4.95, 1.0});
  EXPECT_EQ(img.at<std::uint8_t>(g.Height() - 1 - wall.j, wall.i), 0);
  const Cell room = g.CellOf({2.5, 3.0});
  EXPECT_EQ(img.at<std::uint8_t>(g.Height() - 1 - room.j, room.i), 254);
}

TEST(MapIo, ReadsAHandWrittenMapServerFileWithNegate) {
  const fs::path dir = TempDir("negate");
  cv::Mat img(2, 3, CV_8U);
  // negate 1: occupancy = value / 255. Row 0 is the top (y = 1).
  img.at<std::uint8_t>(0, 0) = 255;  // occupied
  img.at<std::uint8_t>(0, 1) = 0;    // free
  img.at<std::uint8_t>(0, 2) = 100;  // unknown (0.39)
  img.at<std::uint8_t>(1, 0) = 0;
  img.at<std::uint8_t>(1, 1) = 0;
  img.at<std::uint8_t>(1, 2) = 240;
  cv::imwrite((dir / "tiny.pgm").string(), img);
  std::ofstream(dir / "tiny.yaml") << "image: tiny.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0]\n"
                                      "negate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const OccupancyGrid g = ReadMap((dir / "tiny.yaml").string());
  EXPECT_EQ(g.Width(), 3);
  EXPECT_EQ(g.Height(), 2);
  EXPECT_EQ(g.State(Cell{0, 1}), CellState::kOccupied);
  EXPECT_EQ(g.State(Cell{1, 1}), CellState::kFree);
  EXPECT_EQ(g.State(Cell{2, 1}), CellState::kUnknown);
  EXPECT_EQ(g.State(Cell{2, 0}), CellState::kOccupied);
  EXPECT_EQ(g.StateAt(Vec2(1.2, 2.2)), CellState::kFree);  // cell (0, 0)
}

TEST(MapIo, MalformedFilesFailWithFileAndLine) {
  const fs::path dir = TempDir("errors");
  auto expect_error = [&](const std::string& yaml, const std::string& needle) {
    std::ofstream(dir / "bad.yaml") << yaml;
    try {
      ReadMap((dir / "bad.yaml").string());
      ADD_FAILURE() << "no error for: " << yaml;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  };
  const std::string ok_tail = "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  expect_error("image: none.png\nresolution: 0.05\norigin: [0, 0, 0]\n" + ok_tail,
               "cannot read map image");
  expect_error("image: m.png\nresolution: 0.05\norigin: [0, 0, 0.5]\n" + ok_tail, "rotated maps");
  expect_error("image: m.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegat: 1\n" + ok_tail, "negat");
  expect_error("image: m.png\nresolution: fine\norigin: [0, 0, 0]\n" + ok_tail, ":2:");
  expect_error("image: m.png\norigin: [0, 0, 0]\n" + ok_tail, "resolution");
}

TEST(OccupancyGridParams, RoundTripAndValidation) {
  OccupancyGridParams p;
  p.resolution = 0.025;
  const auto q = LoadParams<OccupancyGridParams>(SaveParams(p), "t.yaml");
  EXPECT_EQ(q.resolution, 0.025);
  OccupancyGridParams bad;
  bad.obstacle_z_max = 0.0;
  EXPECT_THROW(bad.Validate(), InputError);
  EXPECT_THROW(OccupancyGrid(OccupancyGridParams{}, {0, 0}, 0, 5), InputError);
}

}  // namespace
}  // namespace mopad::perception
