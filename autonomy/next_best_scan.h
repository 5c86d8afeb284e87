#pragma once
// Next best scan (paper §3.1 step (1) a-e; Adán et al.'s NBS, ref. [61]): the base position
// inside the current room from which the scanner would see the most not-yet-sensed structural
// area of the RoI.
//  a. candidates: a grid inside the RoI perimeter, safe (clearance >= robot radius + margin,
//     clearance = the smaller of the obstacle map's and the distance to the RoI's walls and
//     columns, so walls the map missed still count) and reachable (connected to the current
//     pose through cells with clearance >= robot radius, inside the perimeter);
//  b. SE membership probability of every unsensed RoI face cell (grouped into patches): a
//     sensed cell is known (no gain), an opening cell is not structural (no gain), an unsensed
//     cell on a face classified structural has probability `probability_structural`, on a face
//     without structural data `probability_unclassified`. Faces without structural data are
//     the RoI's frontier (its boundary where the view ended, e.g. the mouth of a hidden leg of
//     an L-shaped room): what lies behind them is unseen, so their cells also stand for the
//     structure behind, weighted by `frontier_factor` (frontier exploration, Yamauchi 1997)
//     and by the cosine of the viewing angle (a frontier seen edge-on reveals nothing);
//  c/d. for each candidate, ray casting from the scanner centre (floor + mast height) through
//     the voxel space to every patch: visible when within the scanner's elevation limits and
//     range, at most `max_incidence_deg` from the face normal, and no occupied voxel on the
//     way; a visible patch counts with its sensing chance (point spacing r x angular step,
//     stretched by 1/cos(incidence), against the face cell: far and grazing patches stay
//     sparse). Certainty of a face = sum of probability x area x chance; certainty of
//     the RoI = the sum over faces (the candidate's gain, m^2);
//     A patch an earlier scan position already passes this test for, yet still unsensed, is
//     discounted by `revisit_factor` per such scan (what was looked at and not sensed will
//     not be sensed by looking again from about the same place);
//     Registrability (expected overlap): the share of what the candidate would sense that the
//     model already holds, sensed area x sensing chance against that plus the unsensed
//     area x chance (a frontier patch x frontier_factor, what lies behind it); the scan is
//     registered against the model, so below `min_overlap` the gain is scaled by overlap /
//     min_overlap: a position that would look mostly into unknown space (a corridor's far
//     end) loses to one that still sees enough of the known structure, and the corridor is
//     scanned in steps that register. Candidates see nothing closer than range_min (the
//     scanner's minimum range), so neither the gain nor the overlap counts surfaces there;
//  e. the candidate with the largest gain, except in a near-tie (gains within `tie_tolerance`
//     of the largest): there the one that sees clearly more frontier (its frontier gain more
//     than tie_tolerance x the largest gain above the others'), then the larger gain, the one
//     nearest the current pose, the lower index (row-major grid order).
// Deterministic: candidates are evaluated in parallel (TBB), each writing its own result.

#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "modelling/orthoimage.h"
#include "modelling/room_model.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {

struct NextBestScanParams {
  double candidate_spacing = 0.5;         ///< m, candidate grid step, [0.05, 5]
  double robot_radius = 0.35;             ///< m, footprint radius, (0, 5]
  double safety_margin = 0.10;            ///< m, extra clearance of a candidate, [0, 5]
  bool unknown_is_obstacle = false;       ///< treat unknown map cells as obstacles
  double mast_height = 1.4;               ///< m, scanner centre above the floor, [0, 10]
  double elevation_max_deg = 60.0;        ///< deg, scanner's upper limit, [-90, 90]
  double elevation_min_deg = -40.0;       ///< deg, scanner's lower limit, [-90, 90]
  double range_min = 1.5;                 ///< m, [0, 100]
  double range_max = 60.0;                ///< m, (0, 1000]
  double max_incidence_deg = 80.0;        ///< deg, from the face normal, [0, 90]
  double patch_size = 0.3;                ///< m, face cells grouped into target patches, [0.02, 5]
  double probability_structural = 0.9;    ///< [0, 1]
  double probability_unclassified = 0.5;  ///< [0, 1]
  /// Expected structural area behind one m^2 of frontier face: a room leg w = 3 m wide,
  /// H = 2.7 m high, seen D = 4 m deep shows (2 w D + 2 D H + w H) / (w H) ~ 6 times the
  /// frontier's area (floor, ceiling, two side walls, end wall). [0, 100]
  double frontier_factor = 6.0;
  double stop_short = 0.15;  ///< m, voxels this close to a target do not block, [0, 2]
  /// An unsensed patch that an earlier scan position passes the same visibility test for was
  /// evidently not sensable from there (hidden by something the voxels miss, an opening not
  /// recognised): per such scan its weight is multiplied by 1 - (1 - revisit_factor) x the
  /// sensing chance from there, so a candidate at or near an earlier scan position expects
  /// little. 1 = no discount. [0, 1]
  double revisit_factor = 0.2;
  /// Relative width of a near-tie, [0, 1]: the gain is an estimate from prior probabilities
  /// and a frontier prior, good to several per cent, so candidates within tie_tolerance x the
  /// best gain G are tied, and among them the one seeing clearly more frontier (by more than
  /// tie_tolerance x G) wins. The frontier part is the estimate's lower bound (what lies behind
  /// an open boundary may be a whole leg of the room) and the only part that can grow the RoI,
  /// so seeing it first lets every later choice plan with the room's extent. 0 = largest gain.
  double tie_tolerance = 0.05;
  /// m, lattice of the positions EstimateHiddenArea looks from (the reachable cells of the
  /// map), [0.05, 5]
  double observability_spacing = 0.25;
  /// m, unsensed cells grouped into patches of this size for EstimateHiddenArea, [0.02, 5]
  double observability_patch = 0.1;
  /// Least expected overlap (share of a candidate's expected sensed area already in the model)
  /// at which the gain counts in full; below it the gain is scaled by overlap / min_overlap.
  /// The room scan's registration matches a scan against the model; a scan that is mostly new
  /// space keeps few points on known surfaces to match: the same share as the room's ICP
  /// fitness bound (RoomScanParams::icp.min_fitness). 0 = off. [0, 1]
  double min_overlap = 0.3;

  template <class V>
  void Visit(V& v) {
    v("candidate_spacing", candidate_spacing, Bounds{0.05, 5.0});
    v("robot_radius", robot_radius, Bounds{1e-6, 5.0});
    v("safety_margin", safety_margin, Bounds{0.0, 5.0});
    v("unknown_is_obstacle", unknown_is_obstacle);
    v("mast_height", mast_height, Bounds{0.0, 10.0});
    v("elevation_max_deg", elevation_max_deg, Bounds{-90.0, 90.0});
    v("elevation_min_deg", elevation_min_deg, Bounds{-90.0, 90.0});
    v("range_min", range_min, Bounds{0.0, 100.0});
    v("range_max", range_max, Bounds{1e-6, 1000.0});
    v("max_incidence_deg", max_incidence_deg, Bounds{0.0, 90.0});
    v("patch_size", patch_size, Bounds{0.02, 5.0});
    v("probability_structural", probability_structural, Bounds{0.0, 1.0});
    v("probability_unclassified", probability_unclassified, Bounds{0.0, 1.0});
    v("frontier_factor", frontier_factor, Bounds{0.0, 100.0});
    v("stop_short", stop_short, Bounds{0.0, 2.0});
    v("revisit_factor", revisit_factor, Bounds{0.0, 1.0});
    v("tie_tolerance", tie_tolerance, Bounds{0.0, 1.0});
    v("observability_spacing", observability_spacing, Bounds{0.05, 5.0});
    v("observability_patch", observability_patch, Bounds{0.02, 5.0});
    v("min_overlap", min_overlap, Bounds{0.0, 1.0});
  }
  /// Bounds plus elevation_min < elevation_max and range_min < range_max; InputError.
  void Validate() const;
};

struct NbsCandidate {
  Vec2 position = Vec2::Zero();  ///< m, map frame
  double gain = 0.0;  ///< expected newly sensed structural area, m^2 (certainty of the RoI)
  /// m^2, the part of gain from frontier patches (faces without structural data)
  double frontier_gain = 0.0;
  int visible_patches = 0;
  /// Share of the candidate's expected sensed area the model already holds (see
  /// min_overlap; 0 when min_overlap is 0: not computed)
  double expected_overlap = 0.0;
  std::vector<double> face_certainty;  ///< per RoI face (m^2); sums to gain
};

struct NbsResult {
  bool found = false;  ///< false: no safe reachable candidate, or none with gain > 0
  std::vector<NbsCandidate> candidates;  ///< every safe reachable candidate, grid order
  int chosen = -1;                       ///< index into candidates
  Pose2 goal;                            ///< chosen base pose (yaw kept from the current pose)
  double expected_gain = 0.0;            ///< m^2
  int rejected_unsafe = 0;               ///< grid points inside the RoI without enough clearance
  int rejected_unreachable = 0;          ///< safe but not connected to the current pose
  std::string message;                   ///< one line with the figures
};

/// Step e on evaluated candidates: the index of the chosen one, -1 when none has a gain > 0.
/// `tolerance` as NextBestScanParams::tie_tolerance.
int ChooseNextBestScan(const std::vector<NbsCandidate>& candidates, const Vec2& current_position,
                       double tolerance);

/// Computes the next best scan from the robot's own model and obstacle map. Throws InputError
/// for invalid params. An empty model or no candidate gives found = false with a message.
/// `scan_step_deg` is the TLS angular step the next scan will use, (0, 10]: with the model's
/// face cell c it gives the chance that a patch seen at range r and incidence a gets a point in
/// each cell, min(1, c / (r step)) * min(1, c cos(a) / (r step)).
NbsResult NextBestScan(const modelling::RoomModel& model, const perception::OccupancyGrid& map,
                       const Pose2& current_M, double scan_step_deg,
                       const NextBestScanParams& params = {});

/// The structure the robot can judge unobservable (the stopping rule's denominator): unsensed
/// patches (observability_patch) of structural RoI faces that no scanner centre sees, where the
/// centres are the observability_spacing lattice over the map cells a robot_radius disc can
/// reach from the current pose inside the RoI, plus the scans taken. "Sees" is the next best
/// scan's geometric test without the incidence limit and the density (range, elevation, facing,
/// a line of sight free of the voxels the scans found occupied): what hides a patch is clutter
/// the robot has scanned, or the scanner's elevation limits; voxels never seen do not block, so
/// the estimate leans to calling a patch observable. The line of sight ignores voxels within
/// stop_short of the target (the face's own voxels), so a cell with clutter points standing
/// within stop_short in front of it (a closed door's leaf in its frame, a radiator) is judged
/// from the points: covered, hence hidden. With `no_return` (the room's rays without a return,
/// modelling::AddNoReturnRays, scan indices into model.ScanPoses()), an unsensed wall cell that
/// such a ray crossed beyond range_min (the first wall it crossed) is no structure but an
/// opening the ray passed (a window to the outside, where nothing returns): seen through, and
/// left out of the observable structure like a hidden cell. Frontier faces are never hidden.
/// Parallel (TBB), deterministic. Throws InputError for invalid params; an empty model gives 0.
struct HiddenArea {
  double area = 0.0;               ///< m^2, covered and seen-through cells plus hidden patches
  double covered_area = 0.0;       ///< m^2, unsensed cells with clutter just in front of them
  double seen_through_area = 0.0;  ///< m^2, unsensed wall cells a ray without a return passed
  int patches = 0;                 ///< hidden patches
  int positions = 0;               ///< scanner centres tried
};
HiddenArea EstimateHiddenArea(const modelling::RoomModel& model,
                              const perception::OccupancyGrid& map, const Pose2& current_M,
                              const NextBestScanParams& params = {},
                              const modelling::OrthoPoints* no_return = nullptr);

}  // namespace mopad::autonomy
