#pragma once
// Global path planning over the robot's obstacle map (paper §3.1 step (2): MoPAD used ROS
// Navfn; here OMPL).
//
// The base is planned as a disc of radius `robot_radius` in R^2 (map frame, REP-105 `map`):
// a state is valid when its cell is known free and its clearance (DistanceField) is at least
// `robot_radius`. The default radius is the footprint's half-width plus a margin, not its
// circumscribed radius: doors narrower than the circumscribed circle are passable when the
// base is aligned with them, which the local controller's door-passage mode does.
//
// Pipeline of Plan():
//  1. start/goal checks (a start slightly inside the clearance margin is led out to the
//     nearest valid cell), then a flood fill of valid cells: a goal outside the start's
//     component is planned again at `narrow_radius`, then on the map refined around its
//     returns (`narrow_refinement`); one still outside is *unreachable* (a closed door, a
//     blocked corridor) — decided exactly and
//     quickly, before any sampling; the message then gives the widest route's clearance
//     (GlobalPlan::widest_clearance, a maximin path over the cells' clearance): a passage
//     narrower than the base needs, or none through known free space at all;
//  2. a grid Dijkstra seed path (`grid_seed`, default) or OMPL RRT* (Karaman & Frazzoli 2011)
//  minimising a clearance-weighted path length
//     (StateCostIntegralObjective, cost per metre 1 + w * max(0, 1 - clearance/preferred)),
//     with a state sampler drawing valid cells of the start's component, biased to the medial
//     axis of free space (MAPRM, Wilmarth et al. 1999) so that door gaps get samples;
//     stopped by iteration count (ompl::base::IterationTerminationCondition), never wall time;
//  3. deterministic shortcutting that never lowers the local clearance below
//     min(robot_radius + shortcut_margin, clearance of the replaced sub-path), then
//     ompl::geometric::PathSimplifier::smoothBSpline;
//  4. doorways: every short stretch with clearance below `passage_clearance` is measured on
//     the map (nearest obstacle cells left and right of the narrowest point = the jambs) and
//     the path is rerouted straight through the jambs' midpoint along their normal for
//     `passage_straight` m each side (when that is valid), so that the base crosses
//     perpendicular and centred; the passages are returned for the local controller;
//  5. resampling every `waypoint_spacing` with yaw along the path, goal yaw at the end.
//
// Determinism: ompl::RNG::setSeed is called once per process, before any planner exists (the
// first GlobalPlanner's seed; PITFALLS.md). The samples that shape the path come from our
// CounterRng keyed by (seed, query index, draw), and RRT*'s own goal bias is off (the sampler
// does it), so the same seed and the same sequence of queries give the same paths in any
// process. OMPL's log level is set to warnings once. Not thread-safe.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {

struct GlobalPlannerParams {
  double robot_radius = 0.30;  ///< m, clearance every path point needs, (0, 5]
  /// m: a goal the start's component at robot_radius does not reach is planned again at this
  /// radius (a door whose mapped jambs leave less than 2 robot_radius: the base, narrower than
  /// the disc, still passes aligned with it). >= robot_radius = off. [min_start_clearance, 5]
  double narrow_radius = 0.30;
  /// A goal still unreachable (at min(narrow_radius, robot_radius)) is planned once more on
  /// the map at this many times finer cells with its obstacles where the returns are
  /// (perception::OccupancyGrid::Refined): a 5 cm cell puts a surface up to 5 cm in front of
  /// where it is, so a 0.65 m squeeze between a chair and a door leaf read as 0.53 m. Only
  /// goals unreachable on the 5 cm map are affected. 1 = off, [1, 8]
  int narrow_refinement = 3;
  double min_start_clearance = 0.15;  ///< m, a start with less is invalid, [0, robot_radius]
  double preferred_clearance = 0.7;   ///< m, clearance beyond which there is no penalty, (0, 10]
  double clearance_weight = 3.0;      ///< cost weight of missing clearance, [0, 100]
  bool unknown_is_obstacle = true;    ///< plan only through known free cells
  /// Seed path from a grid Dijkstra over the start's component with the same clearance cost
  /// (8-connected, deterministic), then the shortcuts and OMPL's B-spline smoothing; RRT* runs
  /// only when false. The grid search is exact and about 10x cheaper than 8000 RRT* iterations.
  bool grid_seed = true;
  int max_iterations = 8000;      ///< RRT* iterations per attempt, [100, 10000000]
  int max_attempts = 2;           ///< attempts (fresh tree, new samples) before giving up, [1, 20]
  double range = 1.5;             ///< m, RRT* maximum extension, (0, 100]
  double goal_bias = 0.05;        ///< fraction of samples at the goal, [0, 1]
  double medial_axis_bias = 0.5;  ///< fraction of samples on the medial axis, [0, 1]
  double goal_tolerance = 0.01;   ///< m, OMPL goal region radius, (0, 1]
  double shortcut_margin = 0.15;  ///< m, see header comment, [0, 5]
  double passage_clearance = 0.55;  ///< m, path clearance below which a passage starts, [0, 5]
  double max_passage_length = 1.5;  ///< m, longer narrow stretches are corridors, (0, 50]
  double passage_straight = 0.6;    ///< m, straight run through a passage centre each side
  int smoothing_steps = 5;          ///< B-spline smoothing passes, [0, 100]
  double waypoint_spacing = 0.05;   ///< m, spacing of the returned path, (0, 1]

  template <class V>
  void Visit(V& v) {
    v("robot_radius", robot_radius, Bounds{1e-3, 5.0});
    v("narrow_radius", narrow_radius, Bounds{1e-3, 5.0});
    v("narrow_refinement", narrow_refinement, Bounds{1, 8});
    v("min_start_clearance", min_start_clearance, Bounds{0.0, 5.0});
    v("preferred_clearance", preferred_clearance, Bounds{1e-3, 10.0});
    v("clearance_weight", clearance_weight, Bounds{0.0, 100.0});
    v("unknown_is_obstacle", unknown_is_obstacle);
    v("grid_seed", grid_seed);
    v("max_iterations", max_iterations, Bounds{100, 10000000});
    v("max_attempts", max_attempts, Bounds{1, 20});
    v("range", range, Bounds{1e-3, 100.0});
    v("goal_bias", goal_bias, Bounds{0.0, 1.0});
    v("medial_axis_bias", medial_axis_bias, Bounds{0.0, 1.0});
    v("goal_tolerance", goal_tolerance, Bounds{1e-4, 1.0});
    v("shortcut_margin", shortcut_margin, Bounds{0.0, 5.0});
    v("passage_clearance", passage_clearance, Bounds{0.0, 5.0});
    v("max_passage_length", max_passage_length, Bounds{1e-3, 50.0});
    v("passage_straight", passage_straight, Bounds{0.0, 5.0});
    v("smoothing_steps", smoothing_steps, Bounds{0, 100});
    v("waypoint_spacing", waypoint_spacing, Bounds{1e-3, 1.0});
  }
  /// ValidateParams plus cross-field checks; throws InputError.
  void Validate() const;
};

enum class PlanStatus {
  kFound,           ///< a valid path
  kStartInvalid,    ///< start off the map, in an obstacle, or too close to one
  kGoalInvalid,     ///< goal off the map, in an obstacle, or closer than robot_radius to one
  kUnreachable,     ///< goal not connected to the start in free space (e.g. a closed door)
  kNoPathInBudget,  ///< connected, but no path within the iteration budget
};
const char* ToString(PlanStatus s);

/// A narrow passage (doorway) on the path, found from the map: the two nearest obstacles
/// (jambs) on either side of the path's narrowest point.
struct Passage {
  Vec2 centre;            ///< map, midpoint between the jambs
  double axis_yaw = 0.0;  ///< rad, direction of travel through it (perpendicular to the jambs)
  double width = 0.0;     ///< m, jamb-to-jamb distance (cell boundaries)
  double s = 0.0;         ///< m, arc length of the centre along the path
};

/// One waypoint of a planned path.
struct PathPoint {
  Pose2 pose;              ///< map frame; yaw along the path (goal yaw at the end)
  double clearance = 0.0;  ///< m, map clearance at the point
  double s = 0.0;          ///< m, arc length from the start
};

struct GlobalPlan {
  PlanStatus status = PlanStatus::kNoPathInBudget;
  std::string message;            ///< one line explaining the status
  std::vector<PathPoint> path;    ///< empty unless kFound
  std::vector<Passage> passages;  ///< doorways crossed, in path order
  double length = 0.0;            ///< m
  double min_clearance = 0.0;     ///< m, over the path
  /// kUnreachable: the largest clearance a route of known free cells from the start to the
  /// goal can keep everywhere (its narrowest passage is about twice as wide); 0 when no such
  /// route exists. m
  double widest_clearance = 0.0;
  int iterations = 0;  ///< RRT* iterations spent
  bool ok() const { return status == PlanStatus::kFound; }
};

class GlobalPlanner {
 public:
  /// Copies the map and builds its clearance field; throws InputError for invalid params.
  GlobalPlanner(const perception::OccupancyGrid& map, const GlobalPlannerParams& params,
                std::uint64_t seed);
  ~GlobalPlanner();
  GlobalPlanner(const GlobalPlanner&) = delete;
  GlobalPlanner& operator=(const GlobalPlanner&) = delete;
  GlobalPlanner(GlobalPlanner&&) noexcept;
  GlobalPlanner& operator=(GlobalPlanner&&) noexcept;

  /// Plans from `start` to `goal` (map frame). Expected failures are statuses, not exceptions.
  GlobalPlan Plan(const Pose2& start, const Pose2& goal);

  /// Marks obstacle points (map frame, e.g. LRF returns the map lacks) as occupied cells and
  /// rebuilds the clearance field; later plans avoid them. A point within one cell of a cell
  /// the map already has occupied is taken as that obstacle and not added.
  void AddObstacles(const std::vector<Vec2>& points_M);
  /// Replaces the map (e.g. after new scans).
  void SetMap(const perception::OccupancyGrid& map);

  /// Clearance (m) of a point in the planner's current map.
  double Clearance(const Vec2& p_M) const;
  const GlobalPlannerParams& Params() const { return params_; }

 private:
  struct Impl;
  std::vector<Passage> FindPassages(const std::vector<Vec2>& vertices) const;
  void RouteThroughPassages(const std::vector<Passage>& passages,
                            std::vector<Vec2>& vertices) const;
  void ShortcutPath(std::vector<Vec2>& vertices) const;
  std::vector<float> CellCosts() const;
  bool SearchPath(const Vec2& s, const Vec2& g0, perception::Cell sc, perception::Cell gc,
                  const std::vector<std::uint8_t>& comp, std::uint64_t query,
                  std::vector<Vec2>& vertices, GlobalPlan& plan) const;
  std::optional<perception::Cell> LeadOutCell(const Vec2& s0, perception::Cell sc,
                                              const std::vector<std::uint8_t>& valid) const;
  std::vector<std::uint8_t> Component(perception::Cell sc,
                                      const std::vector<std::uint8_t>& valid) const;
  double WidestRouteClearance(perception::Cell sc, perception::Cell gc) const;
  /// Per map cell (row-major): its centre keeps the robot radius from obstacles and is known free.
  std::vector<std::uint8_t> ValidCells() const;
  /// Plan's outcome when the goal is not connected to the start: the status, the widest route's
  /// clearance (at least `refined_widest`, that of the refined map, where there is a route) and
  /// the message.
  void ReportUnreachable(perception::Cell sc, perception::Cell gc, const Vec2& g0,
                         double refined_widest, GlobalPlan& plan) const;
  void FinishPlan(const std::vector<Vec2>& vertices, std::vector<Passage> passages,
                  const Pose2& goal, double goal_clear, const Vec2& s0, const Vec2& s,
                  GlobalPlan& plan) const;
  std::unique_ptr<Impl> impl_;
  GlobalPlannerParams params_;
  std::uint64_t seed_;
  std::uint64_t query_ = 0;
};

}  // namespace mopad::autonomy
