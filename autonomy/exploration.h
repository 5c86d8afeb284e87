#pragma once
// Where to scan next when a goal lies outside the known free space (frontier exploration along
// the route to the goal; Yamauchi 1997), and how well the map knows a neighbourhood.

#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {

struct ExplorationParams {
  /// m, cells with less clearance block the route (robot radius), (0, 5]
  double pass_clearance = 0.33;
  double target_clearance = 0.55;  ///< m, preferred clearance of a scan target, (0, 5]
  /// m, targets this close to an earlier scan position are spent, [0, 10]
  double exclusion = 0.5;
  double blind_radius = 0.5;  ///< m, around scan positions the map counts as known, [0, 10]
  /// Cost per metre of unknown or too narrow cells, relative to known free space, [1, 100]
  double unknown_cost = 3.0;

  template <class V>
  void Visit(V& v) {
    v("pass_clearance", pass_clearance, Bounds{1e-3, 5.0});
    v("target_clearance", target_clearance, Bounds{1e-3, 5.0});
    v("exclusion", exclusion, Bounds{0.0, 10.0});
    v("blind_radius", blind_radius, Bounds{0.0, 10.0});
    v("unknown_cost", unknown_cost, Bounds{1.0, 100.0});
  }
};

/// An optimistic route from `from` to `goal` (unknown cells count as free; occupied cells and
/// `pass_clearance` around them block; Dijkstra over 8-neighbours, unknown cells costing
/// `unknown_cost` per metre, settled in (distance, index) order: deterministic) is followed
/// while it stays in the known, valid space (known free, clearance >= pass_clearance with
/// unknown counted as obstacle; within `blind_radius` of a scan position everything counts as
/// known). Returns the candidate scan targets along that stretch, in order of preference: the
/// farthest with clearance >= `target_clearance` first (in front of a doorway rather than in
/// it), then nearer ones, then the narrow ones. Targets within `exclusion` of a scan position
/// are spent. Empty + `why`: no passable cell near the robot, the goal inside obstacles, no
/// route even through unknown space, or no progress (the route leaves the known space where
/// the robot has already scanned; `why` then starts with "no progress").
std::vector<Vec2> ExplorationTargets(const perception::OccupancyGrid& grid, const Vec2& from,
                                     const Vec2& goal, const ExplorationParams& params,
                                     const std::vector<Pose2>& scan_poses, std::string* why);

/// Lengths (m) of the shortest 8-connected routes from `from` to each of `goals` through known
/// free cells with clearance >= `clearance` (unknown counts as obstacle), or with
/// `through_unknown` through any cell not occupied, with clearance from occupied cells only;
/// route ends snap to the nearest such cell within 0.5 m. +infinity where there is no route.
/// Deterministic.
std::vector<double> RouteLengths(const perception::OccupancyGrid& grid, const Vec2& from,
                                 const std::vector<Vec2>& goals, double clearance,
                                 bool through_unknown = false);

/// The known free point nearest to `p` within `radius` whose clearance in `known` (the grid's
/// DistanceField with unknown counted as obstacle) is at least `clearance`; nullopt when there
/// is none. Ties: the lower cell index.
std::optional<Vec2> NearestClearPoint(const perception::OccupancyGrid& grid,
                                      const perception::DistanceField& known, const Vec2& p,
                                      double radius, double clearance);

/// Fraction of the grid cells within `radius` of `p` that are known (free or occupied).
double KnownFraction(const perception::OccupancyGrid& grid, const Vec2& p, double radius);

}  // namespace mopad::autonomy
