// Next best scan (paper §3.1 step (1)) on rooms built in code where the answer is known.

#include "autonomy/next_best_scan.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <fstream>

#include "autonomy/detail_pass.h"
#include "common/error.h"
#include "modelling/stopping.h"
#include "tests/modelling/sim_scans.h"

namespace mopad::autonomy {
namespace {

using modelling::RoomModel;
using modelling::testing::SimScan;
using modelling::testing::TakeScan;
using modelling::testing::TestTls;

std::vector<Eigen::Vector3d> MapPoints(const RoomModel& model) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(model.PointCount());
  for (const auto& p : model.Points()) out.push_back(p.cast<double>());
  return out;
}

// The robot's obstacle map from its own registered points (as the mission builds it).
perception::OccupancyGrid MapOf(const RoomModel& model) {
  const auto pts = MapPoints(model);
  perception::OccupancyGrid grid = perception::OccupancyGrid::Covering({}, pts, 1.0);
  grid.InsertPoints(pts);
  return grid;
}

struct LRoom {
  sim::EmbreeWorld world{modelling::testing::LRoomScene()};
  SimScan first = TakeScan(world, TestTls(0.2), 1.5, 1.5, 0);
  RoomModel model;
  LRoom() { model.AddScan(first.scan, first.X_MS); }
};

const LRoom& L() {
  static const LRoom l;
  return l;
}

TEST(NextBestScan, LRoomChoosesAPositionThatSeesTheHiddenLeg) {
  const RoomModel& model = L().model;
  // After the first scan at the far end of leg A, most of leg B (y > 4) is unseen.
  EXPECT_FALSE(model.GetRoi().ContainsPlan(Vec2(8.5, 7.0)));
  const perception::OccupancyGrid map = MapOf(model);
  const auto t0 = std::chrono::steady_clock::now();
  const NbsResult r = NextBestScan(model, map, Pose2{1.5, 1.5, 0.0}, 0.2);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[figures] L-room NBS: %s (%.3f s)\n", r.message.c_str(), dt);
  ASSERT_TRUE(r.found) << r.message;
  ASSERT_GT(r.candidates.size(), 20u);
  // Known answer: leg B is visible only from the junction square x in [7, 10] (from x < 7 the
  // inner corner (7, 3) hides it).
  EXPECT_GT(r.goal.x, 7.0) << r.message;
  EXPECT_GT(r.expected_gain, 0.0);
  EXPECT_EQ(r.expected_gain, r.candidates[r.chosen].gain);
  double face_sum = 0.0;
  for (double g : r.candidates[r.chosen].face_certainty) face_sum += g;
  EXPECT_NEAR(face_sum, r.expected_gain, 1e-9 * r.expected_gain);
  // Every candidate west of the corner gains less than the chosen one.
  for (const auto& c : r.candidates) {
    if (c.position.x() < 6.0) {
      EXPECT_LT(c.gain, r.expected_gain);
    }
  }
  // Scanning there reveals the hidden leg.
  RoomModel next = model;
  const SimScan s = TakeScan(L().world, TestTls(0.2), r.goal.x, r.goal.y, 1);
  next.AddScan(s.scan, s.X_MS);
  EXPECT_TRUE(next.GetRoi().ContainsPlan(Vec2(8.5, 7.0)));
  EXPECT_GT(next.Coverage().sensed_area, model.Coverage().sensed_area + 30.0);
  std::printf(
      "[figures] L-room coverage: scan 1 %.3f (%.1f m2), scan 2 at (%.2f, %.2f) %.3f (%.1f m2)\n",
      model.Coverage().ratio, model.Coverage().sensed_area, r.goal.x, r.goal.y,
      next.Coverage().ratio, next.Coverage().sensed_area);
}

TEST(NextBestScan, ANearTieGoesToTheCandidateThatSeesMoreFrontier) {
  // Known answer: A and B are 0.25 % apart (well inside the estimate's error); B sees more of
  // the open boundary, so B wins; C has the most frontier but 25 % less gain and stays out.
  auto cand = [](double x, double gain, double frontier) {
    NbsCandidate c;
    c.position = Vec2(x, 0.0);
    c.gain = gain;
    c.frontier_gain = frontier;
    return c;
  };
  const std::vector<NbsCandidate> cs{cand(1.0, 20.25, 2.0), cand(2.0, 20.20, 8.0),
                                     cand(3.0, 15.0, 15.0), cand(4.0, 0.0, 0.0)};
  EXPECT_EQ(ChooseNextBestScan(cs, Vec2::Zero(), 0.05), 1);
  EXPECT_EQ(ChooseNextBestScan(cs, Vec2::Zero(), 0.0), 0);  // the largest gain only
  EXPECT_EQ(ChooseNextBestScan(cs, Vec2::Zero(), 0.3), 2);
  // A frontier difference smaller than the estimate's error (0.5 < 0.05 x 20.25) is a tie too:
  // the larger gain wins.
  const std::vector<NbsCandidate> close{cand(1.0, 20.25, 8.5), cand(2.0, 20.0, 9.0)};
  EXPECT_EQ(ChooseNextBestScan(close, Vec2::Zero(), 0.05), 0);
  EXPECT_EQ(ChooseNextBestScan(close, Vec2::Zero(), 0.01), 0);  // 20.0 is not within 1 %
  // Without frontier (a closed room) the largest gain wins; an exact tie goes to the nearer.
  const std::vector<NbsCandidate> closed{cand(5.0, 10.0, 0.0), cand(1.0, 9.9, 0.0),
                                         cand(-1.0, 10.0, 0.0)};
  EXPECT_EQ(ChooseNextBestScan(closed, Vec2::Zero(), 0.05), 2);
  EXPECT_EQ(ChooseNextBestScan({cand(1.0, 0.0, 0.0)}, Vec2::Zero(), 0.05), -1);
  EXPECT_EQ(ChooseNextBestScan({}, Vec2::Zero(), 0.05), -1);
}

TEST(NextBestScan, FrontierGainIsThePartOfTheGainFromFacesWithoutStructuralData) {
  const RoomModel& model = L().model;
  const NbsResult r = NextBestScan(model, MapOf(model), Pose2{1.5, 1.5, 0.0}, 0.2);
  ASSERT_TRUE(r.found) << r.message;
  const auto& faces = model.GetRoi().faces;
  double best = 0.0;
  for (const auto& c : r.candidates) {
    double frontier = 0.0;
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (!faces[f].structural) frontier += c.face_certainty[f];
    EXPECT_NEAR(c.frontier_gain, frontier, 1e-9 * std::max(1.0, c.gain));
    EXPECT_LE(c.frontier_gain, c.gain + 1e-9);
    best = std::max(best, c.gain);
  }
  // The L-room's leg is behind a frontier: the choice sees some of it, and no candidate in
  // the near-tie sees clearly more.
  const NbsCandidate& chosen = r.candidates[r.chosen];
  EXPECT_GT(chosen.frontier_gain, 0.0);
  const double slack = NextBestScanParams{}.tie_tolerance * best;
  for (const auto& c : r.candidates) {
    if (c.gain >= best - slack) {
      EXPECT_LE(c.frontier_gain, chosen.frontier_gain + slack);
    }
  }
}

TEST(NextBestScan, PatchesAnEarlierScanShouldHaveSensedAreDiscounted) {
  // Known answer: at the first scan position every patch it sees was already looked at, so
  // each keeps 1 - (1 - revisit_factor) x chance of its weight: the candidate there loses a
  // larger share of its gain than the junction (which sees the hidden leg) and expects little.
  const perception::OccupancyGrid map = MapOf(L().model);
  NextBestScanParams off;
  off.revisit_factor = 1.0;
  NextBestScanParams on;
  const NbsResult a = NextBestScan(L().model, map, Pose2{1.5, 1.5, 0.0}, 0.2, off);
  const NbsResult b = NextBestScan(L().model, map, Pose2{1.5, 1.5, 0.0}, 0.2, on);
  ASSERT_TRUE(a.found && b.found);
  ASSERT_EQ(a.candidates.size(), b.candidates.size());
  int near = -1;
  for (int i = 0; i < static_cast<int>(a.candidates.size()); ++i) {
    if ((a.candidates[i].position - Vec2(1.5, 1.5)).norm() < 0.01) near = i;
  }
  ASSERT_GE(near, 0);
  ASSERT_GT(a.candidates[near].gain, 0.0);
  const double kept_near = b.candidates[near].gain / a.candidates[near].gain;
  const double kept_best = b.candidates[b.chosen].gain / a.candidates[b.chosen].gain;
  EXPECT_LT(kept_near, 0.8);
  EXPECT_LT(kept_near, kept_best - 0.1);
  EXPECT_LT(b.candidates[near].gain, 0.1 * b.candidates[b.chosen].gain);
  EXPECT_GT(b.goal.x, 7.0) << b.message;
  // No candidate gains more with the discount than without.
  for (std::size_t i = 0; i < a.candidates.size(); ++i)
    EXPECT_LE(b.candidates[i].gain, a.candidates[i].gain + 1e-9);
}

TEST(NextBestScan, SameResultTwiceAndWithOneOrTwoThreads) {
  const perception::OccupancyGrid map = MapOf(L().model);
  NbsResult res[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    res[threads - 1] = NextBestScan(L().model, map, Pose2{1.5, 1.5, 0.0}, 0.2);
  }
  ASSERT_EQ(res[0].candidates.size(), res[1].candidates.size());
  for (std::size_t i = 0; i < res[0].candidates.size(); ++i) {
    EXPECT_EQ(res[0].candidates[i].gain, res[1].candidates[i].gain);
    EXPECT_EQ(res[0].candidates[i].position, res[1].candidates[i].position);
  }
  EXPECT_EQ(res[0].chosen, res[1].chosen);
  EXPECT_EQ(res[0].message, res[1].message);
}

TEST(NextBestScan, CandidatesKeepClearOfObstaclesAndMustBeReachable) {
  perception::OccupancyGrid map = MapOf(L().model);
  // A box obstacle in leg A, and a barrier across leg A at x = 5 that cuts the junction off.
  map.FillBox(Vec2(2.8, 0.8), Vec2(3.2, 1.2), perception::CellState::kOccupied);
  NextBestScanParams p;
  const NbsResult open = NextBestScan(L().model, map, Pose2{1.5, 1.5, 0.0}, 0.2, p);
  ASSERT_TRUE(open.found);
  for (const auto& c : open.candidates) {
    const double dx = std::max({2.8 - c.position.x(), 0.0, c.position.x() - 3.2});
    const double dy = std::max({0.8 - c.position.y(), 0.0, c.position.y() - 1.2});
    EXPECT_GE(std::hypot(dx, dy), p.robot_radius + p.safety_margin - map.Resolution());
  }
  EXPECT_GT(open.rejected_unsafe, 0);
  map.FillBox(Vec2(5.0, -0.5), Vec2(5.1, 3.5), perception::CellState::kOccupied);
  const NbsResult cut = NextBestScan(L().model, map, Pose2{1.5, 1.5, 0.0}, 0.2, p);
  EXPECT_GT(cut.rejected_unreachable, 0);
  for (const auto& c : cut.candidates) EXPECT_LT(c.position.x(), 5.0);
  if (cut.found) {
    EXPECT_LT(cut.goal.x, 5.0);
  }
}

// The room of RoomWithDoorScene (6 x 4 m, door in the east wall), scanned once from (3, 2),
// optionally with a panel 4-7 cm in front of the west wall (a closed door's leaf: 1 x 2 m) and
// a cabinet against the south wall (1 x 0.6 x 1.8 m).
struct HiddenCase {
  HiddenArea hidden;
  modelling::CoverageFigures coverage;
};
HiddenCase HiddenOf(bool objects) {
  using modelling::testing::AddBox;
  using modelling::testing::V3;
  scenes::Scene s = modelling::testing::RoomWithDoorScene();
  if (objects) {
    AddBox(s, V3(0.04f, 1.5f, 0.0f), V3(0.07f, 2.5f, 2.0f), scenes::ElementClass::kDoorLeaf, "leaf",
           "R");
    AddBox(s, V3(1.0f, 0.001f, 0.0f), V3(2.0f, 0.6f, 1.8f), scenes::ElementClass::kFurniture,
           "cabinet", "R");
  }
  const sim::EmbreeWorld world(s);
  const SimScan scan = TakeScan(world, TestTls(0.2), 3.0, 2.0, 0);
  RoomModel model;
  model.AddScan(scan.scan, scan.X_MS);
  HiddenCase out;
  out.hidden = EstimateHiddenArea(model, MapOf(model), Pose2{3.0, 2.0, 0.0});
  out.coverage = model.Coverage();
  out.coverage.SetHiddenArea(out.hidden.area);
  return out;
}

TEST(EstimateHiddenArea, WallBehindALeafOrACabinetIsHiddenTheOpenFloorIsNot) {
  const HiddenCase bare = HiddenOf(false), with = HiddenOf(true);
  std::printf(
      "[figures] hidden: bare %.2f m2 (covered %.2f, %d positions), with leaf and "
      "cabinet %.2f m2 (covered %.2f); unsensed %.2f m2, observable ratio %.3f\n",
      bare.hidden.area, bare.hidden.covered_area, bare.hidden.positions, with.hidden.area,
      with.hidden.covered_area, with.coverage.total_area - with.coverage.sensed_area,
      with.coverage.observable_ratio);
  ASSERT_GT(with.hidden.positions, 50);
  // Known answer: the leaf covers 1 x 2 m of the west wall (seen as clutter 4-7 cm in front of
  // it). The cabinet hides 1 x 1.8 m of the south wall and 1 x 0.6 m of floor, but its west
  // side was never scanned and unseen voxels do not block, so part of that counts as visible
  // through it: between 2.0 (the leaf) + half the cabinet's and 2.0 + 2.4 m^2 more.
  EXPECT_NEAR(with.hidden.covered_area - bare.hidden.covered_area, 2.0, 0.3);
  EXPECT_GT(with.hidden.area - bare.hidden.area, 3.2);
  EXPECT_LT(with.hidden.area - bare.hidden.area, 4.6);
  // From one position the floor around the scanner (below the lowest beam) is unsensed, but the
  // robot can drive to where it sees it: not hidden.
  const double unsensed = with.coverage.total_area - with.coverage.sensed_area;
  EXPECT_GT(unsensed - with.hidden.area, 4.0);
  EXPECT_GT(with.coverage.observable_ratio, with.coverage.ratio);
  EXPECT_LT(with.coverage.observable_ratio, 1.0);
  // Deterministic with one or two threads.
  HiddenArea h[2];
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    h[threads - 1] = EstimateHiddenArea(L().model, MapOf(L().model), Pose2{1.5, 1.5, 0.0});
  }
  EXPECT_EQ(h[0].area, h[1].area);
  EXPECT_EQ(h[0].patches, h[1].patches);
  EXPECT_EQ(EstimateHiddenArea(RoomModel{}, MapOf(L().model), Pose2{}).area, 0.0);
}

TEST(EstimateHiddenArea, AWindowToTheOutsideIsSeenThroughNotUnsensedWall) {
  // A 6 x 4 m room whose east wall has a 1.0 x 1.2 m window (y 1.5-2.5, z 0.9-2.1) with
  // nothing behind it: its beams return nothing and leave no outlier to mark the opening, so
  // the model counts the window as unsensed wall until the rays without a return say otherwise.
  scenes::Scene s;
  sim::testing::AddRoomWithOpening(s, 6.0f, 4.0f, 2.7f, 1.5f, 2.5f, 0.9f, 2.1f);
  for (auto& p : s.parts) p.room = "R";
  const sim::EmbreeWorld world(s);
  const SimScan scan = TakeScan(world, TestTls(0.2), 3.0, 2.0, 0);
  RoomModel model;
  model.AddScan(scan.scan, scan.X_MS);
  modelling::OrthoPoints rays;
  modelling::AddNoReturnRays(scan.scan, scan.X_MS, 0, rays);
  ASSERT_GT(rays.no_return_dirs.size(), 1000u);
  const perception::OccupancyGrid map = MapOf(model);
  const HiddenArea without = EstimateHiddenArea(model, map, Pose2{3.0, 2.0, 0.0});
  const HiddenArea with = EstimateHiddenArea(model, map, Pose2{3.0, 2.0, 0.0}, {}, &rays);
  std::printf("[figures] window: seen through %.3f m2 (hidden %.3f without the rays, %.3f with)\n",
              with.seen_through_area, without.area, with.area);
  EXPECT_EQ(without.seen_through_area, 0.0);
  // Known answer: the window's 1.2 m^2, less the border cells its frame's points fall in.
  EXPECT_NEAR(with.seen_through_area, 1.2, 0.15);
  EXPECT_NEAR(with.area - without.area, with.seen_through_area, 0.05);
}

// A 24 m x 2.2 m x 2.6 m corridor scanned once from (2, 1.1): the scanner's 1.5 m minimum
// range hides the walls, floor and ceiling next to it, and far along the walls are grazed.
struct Corridor {
  sim::EmbreeWorld world{[] {
    scenes::Scene s;
    sim::testing::AddRoomBox(s, Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(24, 2.2f, 2.6f));
    for (auto& p : s.parts) p.room = "C";
    return s;
  }()};
  SimScan first = TakeScan(world, TestTls(0.2), 2.0, 1.1, 0);
  RoomModel model;
  Corridor() { model.AddScan(first.scan, first.X_MS); }
};

const Corridor& C() {
  static const Corridor c;
  return c;
}

TEST(NextBestScan, GainIsScaledByTheExpectedOverlapBelowMinOverlap) {
  const RoomModel& model = C().model;
  const perception::OccupancyGrid map = MapOf(model);
  NextBestScanParams off;
  off.min_overlap = 0.0;
  const NbsResult raw = NextBestScan(model, map, Pose2{2.0, 1.1, 0.0}, 0.2, off);
  const NbsResult r = NextBestScan(model, map, Pose2{2.0, 1.1, 0.0}, 0.2);
  std::printf("[figures] corridor NBS: %s\n", r.message.c_str());
  ASSERT_TRUE(r.found) << r.message;
  ASSERT_EQ(r.candidates.size(), raw.candidates.size());
  const double m = NextBestScanParams{}.min_overlap;
  int scaled = 0;
  const NbsCandidate *nearest = nullptr, *farthest = nullptr;
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const NbsCandidate& c = r.candidates[i];
    EXPECT_GE(c.expected_overlap, 0.0);
    EXPECT_LE(c.expected_overlap, 1.0);
    const double factor = std::min(1.0, c.expected_overlap / m);
    EXPECT_NEAR(c.gain, raw.candidates[i].gain * factor, 1e-9 * (1.0 + raw.candidates[i].gain));
    scaled += factor < 1.0 && raw.candidates[i].gain > 0.0;
    if (!nearest || c.position.x() < nearest->position.x()) nearest = &c;
    if (!farthest || c.position.x() > farthest->position.x()) farthest = &c;
  }
  // The far end of the corridor holds little of what the first scan sensed: the positions
  // there look mostly into unsensed structure, those near the scan see the sensed stretch.
  EXPECT_GT(scaled, 0);
  EXPECT_GT(nearest->expected_overlap, farthest->expected_overlap);
  EXPECT_LT(farthest->expected_overlap, m);
  // Without the overlap term the largest gain lies further down the corridor; with it the
  // chosen step is shorter and keeps more of the model in view.
  std::printf("[figures] corridor NBS without the overlap term: %s\n", raw.message.c_str());
  EXPECT_LT(r.goal.x, raw.goal.x) << r.message << " | " << raw.message;
  EXPECT_GT(r.candidates[r.chosen].expected_overlap, r.candidates[raw.chosen].expected_overlap);
  EXPECT_GT(r.candidates[r.chosen].expected_overlap, 0.8 * m) << r.message;
}

TEST(NextBestScan, SurfacesInsideTheMinimumRangeAreNeitherGainNorOverlap) {
  // From a candidate in the 2.2 m corridor every wall, the floor and the ceiling within 1.5 m
  // are inside the scanner's minimum range: with range_min 1.5 the candidate expects less
  // than with a scanner that could see them (range_min 0.1), and the sensed ones behind it
  // count only beyond the range.
  const RoomModel& model = C().model;
  const perception::OccupancyGrid map = MapOf(model);
  NextBestScanParams near_blind, sees_near;
  near_blind.min_overlap = sees_near.min_overlap = 0.0;
  near_blind.revisit_factor = sees_near.revisit_factor = 1.0;
  sees_near.range_min = 0.1;
  const NbsResult a = NextBestScan(model, map, Pose2{2.0, 1.1, 0.0}, 0.2, near_blind);
  const NbsResult b = NextBestScan(model, map, Pose2{2.0, 1.1, 0.0}, 0.2, sees_near);
  ASSERT_EQ(a.candidates.size(), b.candidates.size());
  ASSERT_FALSE(a.candidates.empty());
  // The surfaces around the first scan position are unsensed (inside its minimum range): a
  // scanner that sees them from there would gain them; the real one does not.
  std::size_t at_scan = 0;
  for (std::size_t i = 0; i < a.candidates.size(); ++i) {
    EXPECT_LE(a.candidates[i].gain, b.candidates[i].gain + 1e-9);
    if ((a.candidates[i].position - Vec2(2.0, 1.1)).norm() <
        (a.candidates[at_scan].position - Vec2(2.0, 1.1)).norm())
      at_scan = i;
  }
  EXPECT_LT((a.candidates[at_scan].position - Vec2(2.0, 1.1)).norm(), 0.5);
  EXPECT_LT(a.candidates[at_scan].gain, 0.5 * b.candidates[at_scan].gain)
      << a.candidates[at_scan].gain << " vs " << b.candidates[at_scan].gain;
}

TEST(NextBestScan, EmptyModelAndBadParams) {
  const RoomModel empty;
  const perception::OccupancyGrid map({}, Vec2(0, 0), 10, 10);
  const NbsResult r = NextBestScan(empty, map, Pose2{}, 0.2);
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.message.empty());
  NextBestScanParams p;
  p.elevation_min_deg = 70.0;
  EXPECT_THROW(NextBestScan(L().model, map, Pose2{}, 0.2, p), InputError);
  p = {};
  p.candidate_spacing = 0.0;
  EXPECT_THROW(NextBestScan(L().model, map, Pose2{}, 0.2, p), InputError);
  const auto q =
      LoadParams<NextBestScanParams>(LoadYamlString("frontier_factor: 2\n", "n.yaml"), "n.yaml");
  EXPECT_EQ(q.frontier_factor, 2.0);
}

TEST(RoomScanningDocs, YamlExampleLoadsIntoTheParamsStructs) {
  const std::string path = std::string(MOPAD_SOURCE_DIR) + "/docs/room-scanning.md";
  std::ifstream in(path);
  ASSERT_TRUE(in.good()) << path;
  std::string line, block;
  bool inside = false;
  int blocks = 0;
  while (std::getline(in, line)) {
    if (!inside && line.rfind("```yaml", 0) == 0) {
      inside = true;
      block.clear();
    } else if (inside && line.rfind("```", 0) == 0) {
      inside = false;
      const YAML::Node node = LoadYamlString(block, path);
      // The detail pass's blocks: its parameters load (typos rejected); `enabled` aside, the
      // documented values are the defaults (the other keys of a config, e.g. `drive`, belong
      // to the mission's params).
      if (node["detail"]) {
        auto d = LoadParams<DetailPassParams>(node["detail"], path);
        d.enabled = DetailPassParams{}.enabled;
        if (node["detail"].size() > 1) {
          EXPECT_EQ(YAML::Dump(SaveParams(d)), YAML::Dump(SaveParams(DetailPassParams{})));
        }
        continue;
      }
      ++blocks;
      const auto m = LoadParams<modelling::RoomModelParams>(node["room_model"], path);
      const auto s = LoadParams<modelling::StoppingParams>(node["stopping"], path);
      const auto n = LoadParams<NextBestScanParams>(node["next_best_scan"], path);
      // The documented values are the defaults.
      EXPECT_EQ(YAML::Dump(SaveParams(m)), YAML::Dump(SaveParams(modelling::RoomModelParams{})));
      EXPECT_EQ(YAML::Dump(SaveParams(s)), YAML::Dump(SaveParams(modelling::StoppingParams{})));
      EXPECT_EQ(YAML::Dump(SaveParams(n)), YAML::Dump(SaveParams(NextBestScanParams{})));
    } else if (inside) {
      block += line + "\n";
    }
  }
  EXPECT_EQ(blocks, 1);
}

}  // namespace
}  // namespace mopad::autonomy
