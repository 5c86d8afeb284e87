#pragma once
// The truth side of the structural models: the truth SM3 patches of a room,
// the truth floorplan, and the truth DSM3 labels on the robot's own voxel grid.
//
// Truth patches come from the ground-truth sidecar (scenes/ground_truth.h), never from mesh
// names: a wall is the rectangle origin + [0, length] u_axis + [0, height] z (openings are not
// cut: SM3 walls are whole planar patches), the floor and ceiling are their element polygons,
// a column gives one patch per face polygon. Every patch is CCW seen from its normal, which
// points into the room (column faces: away from the column's vertex centroid), as metrics.h
// expects. World frame, metres.
//
// Truth DSM3 (TruthDsm3): for each voxel the robot listed, in the robot's map frame M (voxel
// boxes are axis-aligned in M; the truth is mapped into M with X_WM^-1). Rules, first match wins:
//  1. structure / occluded_structure - the voxel contains a sample of a structural surface of
//     the room (its truth patches with the openings cut out of the walls). Surfaces are sampled
//     at the centres of a square grid of spacing voxel_size / samples_per_voxel (SamplePatch);
//     a sample is nudged 1e-6 voxel into the room along the normal, so a surface lying exactly
//     on a voxel face belongs to the voxel on the room side. The voxel is structure when at
//     least one of its samples is visible from at least one true scanner centre (below),
//     otherwise occluded_structure.
//  2. opening - the voxel contains a sample of a wall plane inside an opening (door or window)
//     rectangle of that wall (same sampling), and no structural sample.
//  3. clutter - the voxel centre lies inside the room prism (plan polygon, floor_z..ceiling_z)
//     and the voxel contains a sample of any non-structural scene geometry (furniture, door
//     leaves and frames, BSCs, window frames and glass, clutter; triangles sampled along a
//     barycentric lattice of spacing <= voxel_size / samples_per_voxel, vertices included).
//  4. empty - the voxel centre lies inside the room prism and is visible from a scanner centre:
//     the segment from the scanner to the centre hits nothing, its elevation is inside the
//     scanner's band and its length <= range_max (range_min does not apply: beams pass through).
//  5. unseen - everything else (inside but hidden, or outside the room).
// Visibility of a surface sample p (normal n) from scanner centre c: n . (c - p) > 0, |p - c| in
// [range_min, range_max], the elevation of p seen from c in [elevation_min_deg,
// elevation_max_deg], and the first hit along the ray from c towards p at t >= |p - c| -
// hit_tolerance. Ray casting in sim::EmbreeWorld with the world's door angles as they are.
// Parallel (TBB) into fixed slots: the same labels with any thread count.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "evaluation/metrics.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/model_files.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"

namespace mopad::evaluation {

/// The truth as a robot meets it: rooms joined by open passages (truth format 2: connections
/// with door "", rooms split by a boundary without a wall, as a BIM model's spaces of one
/// open-plan area) are one room, because no wall divides them and a robot scans and models them
/// as one. Each group of joined rooms becomes its first room (sidecar order): plan polygon the
/// union of theirs (UnionOfTiledPolygons), floor_z the lowest, ceiling_z the highest; every
/// element, opening, component and furniture item of a member is the group's; floor and ceiling
/// elements of one height are merged into one element (the first one's id) with the union of
/// their polygons; the open passages inside the group are dropped. A group whose plans do not
/// form one simple outline (a hole, overlaps) is left as separate rooms, with a line in `notes`.
/// A truth without open passages comes back unchanged. With `join_faces` false only the rooms
/// are merged and every element keeps its id and geometry (what needs the scene's element ids
/// to stay valid: SM1 truth labels, surface sampling).
struct OpenPlanTruth {
  scenes::GroundTruth truth;
  std::map<std::string, std::string> room_of;  ///< every sidecar room id -> its room in `truth`
  std::map<std::string, std::vector<std::string>> members;  ///< merged room -> its rooms (>= 2)
  std::vector<std::string> notes;                           ///< groups left unmerged, and why
};
OpenPlanTruth MergeOpenPlanRooms(const scenes::GroundTruth& truth, bool join_faces = true);

/// Truth SM3 patches of `room` (world frame). InputError for an unknown room or a room without
/// structural elements.
std::vector<Patch> TruthPatches(const scenes::GroundTruth& truth, const std::string& room);

/// Truth columns of `room` as objects (metrics_patches.h): one per sidecar element of class
/// column, its faces as in TruthPatches (ids `<element>_<k>`, normals away from the column), its
/// footprint the plan convex hull of the faces, heights their z range. Empty when the room has
/// none; InputError for an unknown room.
std::vector<ColumnObject> TruthColumns(const scenes::GroundTruth& truth, const std::string& room);

/// Truth floorplan: every truth room as a plan polygon (world x-y), in the sidecar's order.
std::vector<Room> TruthFloorplan(const scenes::GroundTruth& truth);

/// Opening rectangles of one wall patch, as patches on the wall plane (same normal), world frame.
std::vector<Patch> TruthOpeningPatches(const scenes::GroundTruth& truth, const std::string& room);

struct TruthDsm3Params {
  int samples_per_voxel = 4;         ///< surface samples per voxel edge, [1, 16]
  double hit_tolerance = 0.02;       ///< m, first hit may be this much short of a sample, [0, 1]
  double elevation_max_deg = 60.0;   ///< deg, highest beam of the scanner, [-90, 90]
  double elevation_min_deg = -40.0;  ///< deg, lowest beam, [-90, 90]
  double range_min = 1.5;            ///< m, nearer surfaces return nothing, [0, 100]
  double range_max = 100.0;          ///< m, [0.1, 1e4]
  std::int64_t max_grid_voxels = 200'000'000;  ///< refuse bigger grids (dense index), [1, 1e9]
  template <class V>
  void Visit(V& v) {
    v("samples_per_voxel", samples_per_voxel, Bounds{1, 16});
    v("hit_tolerance", hit_tolerance, Bounds{0.0, 1.0});
    v("elevation_max_deg", elevation_max_deg, Bounds{-90.0, 90.0});
    v("elevation_min_deg", elevation_min_deg, Bounds{-90.0, 90.0});
    v("range_min", range_min, Bounds{0.0, 100.0});
    v("range_max", range_max, Bounds{0.1, 1e4});
    v("max_grid_voxels", max_grid_voxels, Bounds{1, 1e9});
  }
};

/// Truth DSM3 labels (VoxelLabel codes) of `voxels` (grid indices of `grid`, map frame) for
/// `room`, with the true scanner centres `scanners_W` (world frame). See the file comment for
/// the rules. InputError for an unknown room, a grid over max_grid_voxels or bad params.
std::vector<std::uint8_t> TruthDsm3(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                                    const std::string& room, const VoxelGrid& grid,
                                    const std::vector<std::array<int, 3>>& voxels,
                                    const Pose3& X_WM, const std::vector<Vec3>& scanners_W,
                                    const TruthDsm3Params& params = {});

/// Number of voxels per VoxelLabel code (6 entries) in `labels`.
std::array<std::int64_t, 6> CountVoxelLabels(const std::vector<std::uint8_t>& labels);

}  // namespace mopad::evaluation
