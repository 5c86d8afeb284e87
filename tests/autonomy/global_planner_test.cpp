// Global planner: OMPL RRT* over the obstacle map with clearance, exact unreachability,
// determinism for a seed.
#include "autonomy/global_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/error.h"
#include "tests/perception/synthetic_world.h"

namespace mopad::autonomy {
namespace {

using perception::DistanceField;
using perception::OccupancyGrid;

const OccupancyGrid& OpenMap() {
  static const OccupancyGrid g = testing::BuildGrid(testing::TwoRooms(false));
  return g;
}

/// Minimum clearance along the whole polyline, sampled every centimetre, by our own field.
double PathClearance(const GlobalPlan& plan, const OccupancyGrid& map) {
  const DistanceField f(map, true);
  double c = 1e9;
  for (std::size_t k = 0; k + 1 < plan.path.size(); ++k) {
    const Vec2 a(plan.path[k].pose.x, plan.path[k].pose.y);
    const Vec2 b(plan.path[k + 1].pose.x, plan.path[k + 1].pose.y);
    const int n = std::max(1, static_cast<int>((b - a).norm() / 0.01));
    for (int q = 0; q <= n; ++q) c = std::min(c, f.Clearance(Vec2(a + (b - a) * (double(q) / n))));
  }
  return c;
}

TEST(GlobalPlanner, FindsAPathThroughTheDoorGapWithRobotRadiusClearance) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  const Pose2 start{2.0, 3.8, 0.0}, goal{8.0, 2.0, kPi / 2};
  const GlobalPlan plan = planner.Plan(start, goal);
  ASSERT_TRUE(plan.ok()) << plan.message;
  std::printf("[ PLANNER  ] %s\n", plan.message.c_str());
  const double r = GlobalPlannerParams{}.robot_radius;
  EXPECT_GE(PathClearance(plan, OpenMap()), r - 1e-9);
  EXPECT_GE(plan.min_clearance, r);
  // Crosses the partition through the gap, near its middle (clearance-weighted objective).
  bool crossed = false;
  for (std::size_t k = 0; k + 1 < plan.path.size(); ++k) {
    const auto& a = plan.path[k].pose;
    const auto& b = plan.path[k + 1].pose;
    if ((a.x - 5.0) * (b.x - 5.0) <= 0.0) {
      crossed = true;
      EXPECT_NEAR(0.5 * (a.y + b.y), 3.0, 0.1);
    }
  }
  EXPECT_TRUE(crossed);
  EXPECT_NEAR(plan.path.front().pose.x, start.x, 1e-9);
  EXPECT_NEAR(plan.path.back().pose.x, goal.x, 1e-9);
  EXPECT_NEAR(plan.path.back().pose.yaw, goal.yaw, 1e-12);
  for (std::size_t k = 0; k + 1 < plan.path.size(); ++k) {
    const double d = std::hypot(plan.path[k + 1].pose.x - plan.path[k].pose.x,
                                plan.path[k + 1].pose.y - plan.path[k].pose.y);
    EXPECT_LE(d, GlobalPlannerParams{}.waypoint_spacing + 1e-9);
  }
  EXPECT_LT(plan.length, 1.3 * (std::hypot(3.0, 0.8) + std::hypot(3.0, 1.0)));
  EXPECT_NEAR(plan.path.back().s, plan.length, 1e-9);
}

// The grid Dijkstra seed (default) and OMPL RRT* (grid_seed: false) both cross the door gap
// near its middle with the robot radius; the grid seed needs no RRT* iterations.
TEST(GlobalPlanner, GridSeedAndRrtStarBothCrossTheDoorCentred) {
  for (const bool grid : {true, false}) {
    GlobalPlannerParams p;
    p.grid_seed = grid;
    GlobalPlanner planner(OpenMap(), p, 1);
    const GlobalPlan plan = planner.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, kPi / 2});
    ASSERT_TRUE(plan.ok()) << grid << ": " << plan.message;
    EXPECT_EQ(plan.iterations == 0, grid);
    EXPECT_GE(PathClearance(plan, OpenMap()), p.robot_radius - 1e-9);
    int crossings = 0;
    for (std::size_t k = 0; k + 1 < plan.path.size(); ++k) {
      const auto& a = plan.path[k].pose;
      const auto& b = plan.path[k + 1].pose;
      if ((a.x - 5.0) * (b.x - 5.0) <= 0.0) {
        ++crossings;
        EXPECT_NEAR(0.5 * (a.y + b.y), 3.0, 0.1) << grid;
      }
    }
    EXPECT_GE(crossings, 1);
    EXPECT_LT(plan.length, 1.3 * (std::hypot(3.0, 0.8) + std::hypot(3.0, 1.0))) << grid;
  }
}

// A plan that starts 0.35 m in front of the door (a replan there) still reports the doorway,
// so the controller crosses it aligned; one that starts inside the doorway does not.
TEST(GlobalPlanner, ReportsADoorwayJustAheadOfTheStart) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  const GlobalPlan ahead = planner.Plan({4.6, 3.0, 0.0}, {7.0, 3.0, 0.0});
  ASSERT_TRUE(ahead.ok()) << ahead.message;
  ASSERT_EQ(ahead.passages.size(), 1u);
  EXPECT_NEAR(ahead.passages[0].centre.x(), 5.0, 0.1);
  EXPECT_NEAR(ahead.passages[0].centre.y(), 3.0, 0.05);
  EXPECT_NEAR(ahead.passages[0].axis_yaw, 0.0, 0.1);
  const GlobalPlan inside = planner.Plan({5.05, 3.0, 0.0}, {7.0, 3.0, 0.0});
  ASSERT_TRUE(inside.ok()) << inside.message;
  EXPECT_TRUE(inside.passages.empty());
}

// A goal just behind the door (clearance still below passage_clearance at the goal): the
// doorway at the very end of the path is reported, so the controller runs its passage manoeuvre.
TEST(GlobalPlanner, ReportsADoorwayAtTheVeryEndOfThePath) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  const GlobalPlan plan = planner.Plan(Pose2{2.0, 3.8, 0.0}, Pose2{5.3, 3.0, 0.0});
  ASSERT_TRUE(plan.ok()) << plan.message;
  ASSERT_EQ(plan.passages.size(), 1u) << plan.message;
  const Passage& p = plan.passages.front();
  EXPECT_NEAR(p.centre.x(), 5.0, 0.06);
  EXPECT_NEAR(p.centre.y(), 3.0, 0.06);
  EXPECT_NEAR(std::abs(WrapAngle(p.axis_yaw)), 0.0, 0.1);  // crossing along +x
  EXPECT_NEAR(p.width, 0.9, 0.1);
}

TEST(GlobalPlanner, ReportsUnreachableWhenTheDoorIsClosed) {
  const OccupancyGrid closed = testing::BuildGrid(testing::TwoRooms(true));
  GlobalPlanner planner(closed, GlobalPlannerParams{}, 1);
  const GlobalPlan plan = planner.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  EXPECT_EQ(plan.status, PlanStatus::kUnreachable) << plan.message;
  EXPECT_NE(plan.message.find("not connected"), std::string::npos) << plan.message;
  EXPECT_NE(plan.message.find("no route through known free space"), std::string::npos)
      << plan.message;
  EXPECT_EQ(plan.widest_clearance, 0.0);
  EXPECT_TRUE(plan.path.empty());
  EXPECT_EQ(plan.iterations, 0);  // decided before sampling
  // The same map still plans within the room.
  EXPECT_TRUE(planner.Plan({2.0, 3.8, 0.0}, {3.5, 1.9, 0.0}).ok());
}

TEST(GlobalPlanner, ObstaclesAddedFromTheLrfCloseTheDoor) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  std::vector<Vec2> leaf;
  for (double y = 2.55; y <= 3.45; y += 0.02) leaf.emplace_back(5.0, y);
  planner.AddObstacles(leaf);
  EXPECT_EQ(planner.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0}).status, PlanStatus::kUnreachable);
}

// A leaf that leaves 0.5 m of the 0.9 m door (narrower than the 0.58 m the narrow radius
// needs): unreachable, and the message says how wide the widest route's passage is, so that a
// squeeze the base does not fit reads differently from a closed door.
TEST(GlobalPlanner, ExplainsAnUnreachableGoalByItsWidestRoute) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  std::vector<Vec2> leaf;
  for (double y = 2.55; y <= 2.951; y += 0.02) leaf.emplace_back(5.0, y);
  planner.AddObstacles(leaf);
  const GlobalPlan plan = planner.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  ASSERT_EQ(plan.status, PlanStatus::kUnreachable) << plan.message;
  // The gap between the leaf's end (2.95) and the jamb (3.45): a clearance of about 0.25 m,
  // less half a cell of the field's rounding at most on each side.
  EXPECT_GT(plan.widest_clearance, 0.15) << plan.message;
  EXPECT_LE(plan.widest_clearance, 0.26) << plan.message;
  EXPECT_NE(plan.message.find("the widest route keeps"), std::string::npos) << plan.message;
  // Through the open door the goal is reachable: no widest-route figure.
  GlobalPlanner open(OpenMap(), GlobalPlannerParams{}, 1);
  const GlobalPlan through = open.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  EXPECT_TRUE(through.ok()) << through.message;
  EXPECT_EQ(through.widest_clearance, 0.0);
}

// A 0.64 m squeeze whose faces lie just past 5 cm cell boundaries reads 0.55 m on the 5 cm
// map, too narrow for the narrow radius (0.29 m); on the map refined around its returns it
// is planned, and the path keeps the narrow radius from the true faces up to the fine cells'
// rounding.
TEST(GlobalPlanner, ASqueezeTheCellsNarrowIsPlannedOnTheReturns) {
  std::vector<testing::Box2> world = testing::TwoRooms();
  world[4].hi.y() = 2.655;
  world[5].lo.y() = 3.295;
  const OccupancyGrid map = testing::BuildGrid(world);
  GlobalPlannerParams p;
  p.robot_radius = 0.33;
  p.narrow_radius = 0.29;
  p.narrow_refinement = 1;
  GlobalPlanner coarse(map, p, 1);
  const GlobalPlan blocked = coarse.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  ASSERT_EQ(blocked.status, PlanStatus::kUnreachable) << blocked.message;
  p.narrow_refinement = 3;
  GlobalPlanner refined(map, p, 1);
  const GlobalPlan plan = refined.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  ASSERT_TRUE(plan.ok()) << plan.message;
  std::printf("[ PLANNER  ] %s\n", plan.message.c_str());
  EXPECT_NE(plan.message.find("on its returns"), std::string::npos);
  double true_clearance = 1e9;
  for (const PathPoint& q : plan.path) {
    const Vec2 x(q.pose.x, q.pose.y);
    for (const auto& b : world) {
      const Vec2 d = (b.lo - x).cwiseMax(x - b.hi).cwiseMax(Vec2::Zero());
      true_clearance = std::min(true_clearance, d.norm());
    }
  }
  EXPECT_GE(true_clearance, 0.29 - 0.5 * std::sqrt(2.0) * 0.05 / 3);
  ASSERT_FALSE(plan.passages.empty());
  EXPECT_NEAR(plan.passages.front().centre.y(), 2.975, 0.03);
  // A goal behind a closed door stays unreachable on the refined map too.
  GlobalPlanner closed(testing::BuildGrid(testing::TwoRooms(true)), p, 1);
  EXPECT_EQ(closed.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0}).status, PlanStatus::kUnreachable);
}

// LRF returns of the mapped jambs, a centimetre into the gap through the pose estimate, are
// the jambs seen again: they must not narrow the doorway by a cell (seen in office_5rooms: a
// 0.85 m door closed to the 0.33 m robot radius after a recovery's replan).
TEST(GlobalPlanner, LrfReturnsOfMappedJambsDoNotNarrowTheDoor) {
  const OccupancyGrid& map = OpenMap();
  GlobalPlanner before(map, GlobalPlannerParams{}, 1);
  const GlobalPlan a = before.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  ASSERT_TRUE(a.ok()) << a.message;
  // The jamb faces: the last occupied cells beside the gap on the door line x = 5.
  double lo = 0.0, hi = 10.0;
  for (double y = 2.0; y < 3.0; y += 0.005)
    if (map.StateAt({5.0, y}) == perception::CellState::kOccupied) lo = y;
  for (double y = 4.0; y > 3.0; y -= 0.005)
    if (map.StateAt({5.0, y}) == perception::CellState::kOccupied) hi = y;
  std::vector<Vec2> jambs;
  for (double x = 4.92; x <= 5.08; x += 0.02) {
    jambs.emplace_back(x, lo + 0.01 + 0.5 * map.Resolution());
    jambs.emplace_back(x, hi - 0.01 - 0.5 * map.Resolution());
  }
  GlobalPlanner after(map, GlobalPlannerParams{}, 1);
  after.AddObstacles(jambs);
  const GlobalPlan b = after.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
  ASSERT_TRUE(b.ok()) << b.message;
  EXPECT_NEAR(PathClearance(b, map), PathClearance(a, map), 1e-9);
  EXPECT_NEAR(after.Clearance({5.0, 3.0}), before.Clearance({5.0, 3.0}), 1e-9);
}

TEST(GlobalPlanner, SameSeedSamePathBytes) {
  auto run = [](std::uint64_t seed) {
    GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, seed);
    planner.Plan({1.0, 2.0, 0.0}, {3.5, 5.0, 0.0});  // a first query, as in a mission
    const GlobalPlan plan = planner.Plan({2.0, 3.8, 0.0}, {8.0, 2.0, 0.0});
    std::vector<double> v;
    for (const auto& p : plan.path) v.insert(v.end(), {p.pose.x, p.pose.y, p.pose.yaw, p.s});
    return v;
  };
  const auto a = run(5), b = run(5);
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

TEST(GlobalPlanner, ExplainsInvalidStartsAndGoals) {
  GlobalPlanner planner(OpenMap(), GlobalPlannerParams{}, 1);
  auto goal_in_wall = planner.Plan({2.0, 3.8, 0.0}, {4.96, 1.0, 0.0});
  EXPECT_EQ(goal_in_wall.status, PlanStatus::kGoalInvalid);
  EXPECT_NE(goal_in_wall.message.find("goal"), std::string::npos);
  auto goal_near_wall = planner.Plan({2.0, 3.8, 0.0}, {0.2, 3.0, 0.0});
  EXPECT_EQ(goal_near_wall.status, PlanStatus::kGoalInvalid);
  EXPECT_EQ(planner.Plan({-3.0, 3.0, 0.0}, {2.0, 3.0, 0.0}).status, PlanStatus::kStartInvalid);
  EXPECT_EQ(planner.Plan({0.05, 3.0, 0.0}, {2.0, 3.0, 0.0}).status, PlanStatus::kStartInvalid);
  // A start ~0.2 m from the wall (inside the 0.3 m margin) is led out and planned.
  const GlobalPlan lead_out = planner.Plan({0.25, 3.0, 0.0}, {3.0, 3.0, 0.0});
  EXPECT_TRUE(lead_out.ok()) << lead_out.message;
}

TEST(GlobalPlanner, ParamsRoundTripAndValidation) {
  GlobalPlannerParams p;
  p.robot_radius = 0.35;
  EXPECT_EQ(LoadParams<GlobalPlannerParams>(SaveParams(p), "p.yaml").robot_radius, 0.35);
  GlobalPlannerParams bad;
  bad.min_start_clearance = 0.5;
  EXPECT_THROW(bad.Validate(), InputError);
  EXPECT_THROW(GlobalPlanner(OpenMap(), bad, 0), InputError);
}

}  // namespace
}  // namespace mopad::autonomy
