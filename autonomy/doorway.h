#pragma once
// How much of a doorway the robot's obstacle map shows free: the width a base could pass
// through it now. The floor mission measures each door's doorway when it finds the door and
// again when it comes to pass it (autonomy/floor_scan.h): a doorway the map showed passable that
// has become blocked is a door closed since it was mapped (someone shut it) — the robot records
// it and replans instead of driving into the leaf.
//
// The doorway is the hole's bottom edge from `a` to `b` on the wall plane (map frame, plan) and
// a slab `depth_front` (m) towards the room it is seen from (`inward`) and `depth_beyond` (m)
// past the plane: where a leaf stands when it is shut (in the frame, within the wall's
// thickness). Across the width, every half cell, a station is blocked when a cell of the slab
// on it is occupied; the clear width is the longest run of stations not blocked. Unknown cells
// do not block: a door counts as closed on evidence, not on a lack of it.
//
// Robot side: reads only the robot's occupancy grid and its own door records. Deterministic.

#include "common/frames.h"
#include "common/params.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {

struct DoorwayParams {
  /// m, the slab reaches this far from the wall plane into the room the door is seen from
  /// (the plane's own error, a leaf's thickness), [0, 1]
  double depth_front = 0.10;
  /// m, and this far past the plane: the thickest wall (a shut leaf stands in its frame
  /// anywhere within it), [0, 2]
  double depth_beyond = 0.30;
  /// A doorway counts as shut since it was mapped when its clear width fell below the robot's
  /// minimum and below this share of its clear width then: a leaf swung across it, not a leaf
  /// seen better from in front (its thickness, a few cells), [0, 1]
  double shut_ratio = 0.5;

  template <class V>
  void Visit(V& v) {
    v("depth_front", depth_front, Bounds{0.0, 1.0});
    v("depth_beyond", depth_beyond, Bounds{0.0, 2.0});
    v("shut_ratio", shut_ratio, Bounds{0.0, 1.0});
  }
};

/// m, the clear width of the doorway from `a` to `b` (map frame) whose room side `inward`
/// (unit, plan) points to, in `map` (see the file comment); 0 for a doorway of no width.
double DoorwayClearWidth(const perception::OccupancyGrid& map, const Vec2& a, const Vec2& b,
                         const Vec2& inward, const DoorwayParams& params);

}  // namespace mopad::autonomy
