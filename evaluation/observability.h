#pragma once
// The observable structural area of a room: the part of the room's
// walls, floor, ceiling and columns that a scanner at mast height can see from some position
// the robot's footprint can reach in that room, by dense ray casting in the truth scene.
//
// Reachable positions. Every scene triangle is clipped to the body's height band
// [floor_z + body_z_min, floor_z + body_z_max] and rasterised (conservatively) into a plan grid
// of `raster_resolution` over the room; an exact Euclidean distance transform gives each free
// raster cell's clearance. A raster cell is free for the robot when its clearance exceeds
// `robot_radius` (a disc footprint) and it lies inside the room polygon; the largest
// 8-connected free region is the room's interior. Candidate positions are the points of a
// `grid_step` lattice (multiples of grid_step in world x, y) in that region.
//
// Visibility. Scanner centre c = position + (0, 0, floor_z + mast_height). Cell k (centre p,
// normal n) is visible from c when n . (c - p) > 0, |p - c| is in [range_min, range_max], the
// elevation of p seen from c is in [elevation_min_deg, elevation_max_deg], and the first
// surface along the ray from c towards p is the cell's own element within hit_tolerance of
// |p - c|. Positions are tried in a fixed spread-out order and a cell stops being tested once
// seen; the result (a set) does not depend on order or thread count.
//
// Build the EmbreeWorld with WorldOptions::robust for exact figures: the fast intersector can,
// rarely, let a ray aimed exactly at an edge shared by two triangles slip through to the surface
// behind (in office_5rooms this changes the observable area by < 0.1 %). The world's door
// angles are used as they are.
//
// Furniture against a wall hides the wall and floor behind it: the observable area is honestly
// lower than the total. World frame, metres; angles in degrees only in the params.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/params.h"
#include "evaluation/truth_surfaces.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"

namespace mopad::evaluation {

struct ObservabilityParams {
  double grid_step = 0.2;            ///< m, lattice of candidate scan positions, [0.02, 5]
  double robot_radius = 0.35;        ///< m, disc footprint of the base, [0, 3]
  double body_z_min = 0.02;          ///< m above the floor, bottom of the collision band, [0, 3]
  double body_z_max = 1.9;           ///< m above the floor, top of the collision band, [0, 5]
  double raster_resolution = 0.02;   ///< m, plan raster of the collision test, [0.005, 0.5]
  double mast_height = 1.4;          ///< m, scanner centre above the floor, [0, 5]
  double elevation_max_deg = 60.0;   ///< deg, highest beam, [-90, 90]
  double elevation_min_deg = -40.0;  ///< deg, lowest beam, [-90, 90]
  double range_min = 1.5;            ///< m, closer surfaces are not reported, [0, 100]
  double range_max = 100.0;          ///< m, [0.1, 1e4]
  double hit_tolerance = 0.02;       ///< m, first hit may be this much short of the cell, [0, 1]

  template <class V>
  void Visit(V& v) {
    v("grid_step", grid_step, Bounds{0.02, 5.0});
    v("robot_radius", robot_radius, Bounds{0.0, 3.0});
    v("body_z_min", body_z_min, Bounds{0.0, 3.0});
    v("body_z_max", body_z_max, Bounds{0.0, 5.0});
    v("raster_resolution", raster_resolution, Bounds{0.005, 0.5});
    v("mast_height", mast_height, Bounds{0.0, 5.0});
    v("elevation_max_deg", elevation_max_deg, Bounds{-90.0, 90.0});
    v("elevation_min_deg", elevation_min_deg, Bounds{-90.0, 90.0});
    v("range_min", range_min, Bounds{0.0, 100.0});
    v("range_max", range_max, Bounds{0.1, 1e4});
    v("hit_tolerance", hit_tolerance, Bounds{0.0, 1.0});
  }
};

/// Plan-view positions the robot can stand on in one room.
struct ReachableArea {
  std::vector<Eigen::Vector2d> positions;  ///< m, world x-y, lattice points, sorted by (y, x)
  double free_area = 0.0;  ///< m^2, area of the connected free raster region (centre locus)
};

/// Reachable positions of the robot centre in `room` (see the file comment). InputError for an
/// unknown room or bad params.
ReachableArea ComputeReachable(const scenes::Scene& scene, const scenes::GroundTruth& truth,
                               const std::string& room, const ObservabilityParams& params = {});

struct Observability {
  std::vector<std::uint8_t> observable;  ///< one per SurfaceCell: 1 = visible from some position
  std::size_t positions = 0;             ///< reachable positions tried
  std::uint64_t rays = 0;                ///< rays cast (depends on nothing but the inputs)
  double total_area = 0.0;               ///< m^2
  double observable_area = 0.0;          ///< m^2
};

/// Which cells of `surfaces` are visible from some position of `reachable`. Parallel (TBB);
/// deterministic (the same bytes with any number of threads).
Observability ComputeObservability(const sim::EmbreeWorld& world,
                                   const StructuralSurfaces& surfaces,
                                   const ReachableArea& reachable,
                                   const ObservabilityParams& params = {});

}  // namespace mopad::evaluation
