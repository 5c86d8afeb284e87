#pragma once
// Doorways in the robot's obstacle map: gaps in a room's walls that its scans saw through.
//
// SM4 finds doors in the wall orthoimages; where a door is seen only at grazing angles (the far
// end of a long corridor) or the orthoimage is too sparse, it can miss one that the obstacle map
// shows plainly: along the room's perimeter, a stretch where the wall band holds no obstacle,
// framed by obstacles (the jambs, a leaf) on both sides, with free cells beyond the wall. The
// floor mission (autonomy/floor_scan.h) treats such a gap as a door SM4 did not model.
//
// Robot side: reads only the robot's occupancy grid and its own room perimeter. Deterministic.

#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {

struct WallGapParams {
  /// m, depth of the wall band beyond the perimeter searched for obstacles: the thickest wall
  /// the robot expects (a gap needs no obstacle over it), [0.05, 2]
  double wall_band = 0.35;
  /// m, the band also reaches this far into the room (the perimeter's own error), [0, 0.5]
  double inside_tolerance = 0.05;
  /// m: free cells beyond the perimeter, up to this far past the wall band, show the scans
  /// saw through (a wall nothing saw stays unknown), [0.05, 3]
  double see_through_depth = 0.3;
  /// m, gaps narrower than this are not doorways (the floor mission's minimum clear width
  /// applies on top), [0, 10]
  double min_width = 0.5;
  /// m, gaps wider than this are not taken as doorways (a wall the scans did not see), [0.1, 50]
  double max_width = 3.0;
  /// Consecutive perimeter edges turning by less than this (deg) and staying within
  /// `collinear_offset` (m) of the first one's line are one wall line: a gap may span the
  /// small steps an outline makes in a doorway. [0, 45], [0, 0.5]
  double collinear_deg = 10.0;
  double collinear_offset = 0.08;

  template <class V>
  void Visit(V& v) {
    v("wall_band", wall_band, Bounds{0.05, 2.0});
    v("inside_tolerance", inside_tolerance, Bounds{0.0, 0.5});
    v("see_through_depth", see_through_depth, Bounds{0.05, 3.0});
    v("min_width", min_width, Bounds{0.0, 10.0});
    v("max_width", max_width, Bounds{0.1, 50.0});
    v("collinear_deg", collinear_deg, Bounds{0.0, 45.0});
    v("collinear_offset", collinear_offset, Bounds{0.0, 0.5});
  }
};

/// A gap in one wall line of the perimeter, in the map frame.
struct WallGap {
  int edge = -1;  ///< perimeter edge (from vertex `edge` to `edge + 1`) where the gap starts
  Vec2 a = Vec2::Zero();  ///< m, the gap's ends on the perimeter line
  Vec2 b = Vec2::Zero();
  Vec2 inward = Vec2::UnitX();  ///< unit, plan normal into the room
  double width() const { return (b - a).norm(); }
  Vec2 centre() const { return 0.5 * (a + b); }
};

/// The gaps of `perimeter` (a simple polygon, either orientation) in `grid`: per wall line
/// (consecutive near-collinear edges, see collinear_deg), samples every half cell along it; a
/// sample is blocked when an occupied cell lies in the band from `inside_tolerance` inside to
/// `wall_band` beyond the perimeter, seen-through when it is not blocked and a free cell lies
/// beyond the perimeter (from one cell out to `see_through_depth` past the band: rays crossed the
/// wall line there). A gap is a run of unblocked samples with a blocked sample at each end, at
/// least one seen-through sample, and a width in [min_width, max_width]. In line order from a
/// corner, then along each line.
std::vector<WallGap> WallGaps(const perception::OccupancyGrid& grid,
                              const std::vector<Vec2>& perimeter, const WallGapParams& params);

}  // namespace mopad::autonomy
