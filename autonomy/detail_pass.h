#pragma once
// The detail pass (the paper's §6 future work: "the NBS algorithm should take
// into account the quality and density of the data in the SEs"): after the structural stopping
// rule, extra scans where the structural elements' (SE: walls, column faces, ceiling) data are
// too sparse or too grazing for SM5 to recognise small service components on them.
//
//  1. Cells: each SE face of the RoI is cut into `cell` x `cell` squares. A cell is *seen* by a
//     scan that put at least `min_points` of its points within `band` of the face there. Its
//     sample density is the sum over the scans that saw it of the analytic density of a
//     scanner with angular step s at range r, incidence a and elevation e:
//        cos(a) / (r^2 s^2 cos(e))      (points per m^2; each ray covers s^2 cos(e) sr)
//     and its incidence is the smallest over those scans. A seen cell is *deficient* when
//     its spacing 1/sqrt(density) exceeds `max_spacing` or its incidence exceeds
//     `max_incidence_deg`. Cells no scan saw are left to the next best scan (coverage): they
//     are occluded or outside the view, and the detail pass does not know which.
//  2. Planning: candidates are base positions (the next best scan's safe, reachable grid and
//     the current pose) at the room step and, when set, at `fine_step_deg`. A candidate
//     *fixes* a deficient cell it sees (range and elevation limits, in front of the face, free
//     line of sight in the voxel space) when the cell's density with the candidate's added is
//     within max_spacing and the candidate's incidence (or the cell's best) is within
//     max_incidence_deg. Its gain is the fixed area, its cost `scan_overhead` plus the
//     platform seconds of the scan (measured from the room's first scan, x (room step /
//     step)^2) plus the drive (straight distance x `route_factor` / `drive_speed`). The
//     candidate with the largest gain per second wins when its gain is at least
//     `min_gain_area`; ties: the nearer, then the lower index. A candidate within
//     `same_place` of a scan taken at a step no finer than that scan's is skipped (its rays
//     would land on that scan's samples).
//  3. After each detail scan the cells are measured again; at most `max_scans` per room. A
//     detail scan adds data, never structure: the room model's structure (heights, perimeter,
//     columns, RoI) is frozen when the pass begins (modelling::RoomModel::FreezeStructure).
//
// Robot side only: the robot's own points, scan poses, RoI and voxel space (no truth).
// Deterministic: fixed-order loops over cells and candidates.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "modelling/roi.h"

namespace mopad::autonomy {

struct DetailPassParams {
  /// On (the default): the structural scans leave walls too sparse or grazing for SM5's small
  /// components; the pass costs about two scans per room. Off: the room loop ends at the
  /// structural stopping rule (the paper's behaviour). Figures: docs/room-scanning.md.
  bool enabled = true;
  double cell = 0.25;  ///< m, SE cell whose data quality is judged, [0.05, 2]
  /// m, largest acceptable sample spacing on an SE: the smallest catalogue component (an 8 cm
  /// switch) should hold about 7 samples across, [0.001, 0.2]
  double max_spacing = 0.012;
  /// deg, largest acceptable incidence from the SE normal: beyond 60 deg a sample's footprint
  /// stretches more than 2x and protrusions shadow the wall behind them, [1, 89]
  double max_incidence_deg = 60.0;
  double band = 0.05;  ///< m, points within +-band of a face count for its cells, [0.005, 0.5]
  int min_points = 3;  ///< points of one scan in a cell for that scan to have seen it, [1, 1000]
  /// deg, a finer step a detail scan may also use (then from any candidate, the current pose
  /// included); 0 = the room step only. Off by default: on office_5rooms, with the 0.1 deg
  /// scans it chose, SM5 found fewer components and more false positives than with room-step
  /// scans from new positions (docs/room-scanning.md, "Detail pass"). [0, 5]
  double fine_step_deg = 0.0;
  int max_scans = 2;  ///< detail scans per room, [0, 20]
  /// m^2, least deficient area a detail scan must fix to be taken (16 cells of 25 cm), [0, 100]
  double min_gain_area = 1.0;
  double drive_speed = 0.3;   ///< m/s, mean speed of a drive, for the cost, (0, 5]
  double route_factor = 1.5;  ///< route length / straight distance, for the cost, [1, 10]
  /// s, fixed cost of any scan beyond its rays (stop, registration, model update), [0, 600]
  double scan_overhead = 10.0;
  /// m: a candidate this close (plan) to a scan already taken, at a step no finer than that
  /// scan's, is no candidate: the scanner's angular grid would put its samples where that
  /// scan's are (no new samples), [0, 5]
  double same_place = 0.25;

  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("cell", cell, Bounds{0.05, 2.0});
    v("max_spacing", max_spacing, Bounds{0.001, 0.2});
    v("max_incidence_deg", max_incidence_deg, Bounds{1.0, 89.0});
    v("band", band, Bounds{0.005, 0.5});
    v("min_points", min_points, Bounds{1, 1000});
    v("fine_step_deg", fine_step_deg, Bounds{0.0, 5.0});
    v("max_scans", max_scans, Bounds{0, 20});
    v("min_gain_area", min_gain_area, Bounds{0.0, 100.0});
    v("drive_speed", drive_speed, Bounds{1e-3, 5.0});
    v("route_factor", route_factor, Bounds{1.0, 10.0});
    v("scan_overhead", scan_overhead, Bounds{0.0, 600.0});
    v("same_place", same_place, Bounds{0.0, 5.0});
  }
};

/// A planar SE rectangle: origin + [0, width] u + [0, height] v, `n` its unit normal into the
/// room (the side the scanner must stand on). Map frame, m.
struct DetailSurface {
  std::string name;  ///< "wall_3", "ceiling", ... (for logs)
  Vec3 origin = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitZ(), n = -Vec3::UnitY();
  double width = 0.0, height = 0.0;
};

/// The SE faces of a RoI (walls, column faces, ceiling; not the floor) as DetailSurfaces.
std::vector<DetailSurface> DetailSurfacesOf(const modelling::Roi& roi);

/// One seen SE cell and its data quality.
struct DetailCell {
  int surface = -1;
  Vec3 centre = Vec3::Zero();  ///< map frame
  double area = 0.0;           ///< m^2
  double density = 0.0;        ///< points per m^2 (analytic, see the file comment)
  double incidence = 0.0;      ///< rad, the smallest of the scans that saw it
  bool deficient = false;
  double Spacing() const;  ///< m, 1/sqrt(density) (infinite at 0)
};

/// The scans a room's points came from: per scan its scanner centre (map frame) and angular
/// step (rad). Points: map frame, with their scan index.
struct DetailScans {
  std::vector<Vec3> origins;
  std::vector<double> step_rad;
};

/// Step 1: the seen cells of every surface, with their quality (surface order, then v, u).
/// InputError when the arrays disagree or a scan index is out of range.
std::vector<DetailCell> AnalyseDetailCells(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<std::uint16_t>& scan_index,
                                           const DetailScans& scans,
                                           const std::vector<DetailSurface>& surfaces,
                                           const DetailPassParams& params);

/// Where a detail scan could be taken.
struct DetailCandidate {
  Vec2 base = Vec2::Zero();     ///< base position, map frame
  double scanner_z = 0.0;       ///< m, scanner centre height (map frame)
  double step_rad = 0.0;        ///< angular step of the scan
  double drive_distance = 0.0;  ///< m, straight distance from the current pose
};

/// The scanner's view limits, for the visibility test.
struct DetailView {
  double range_min = 1.5, range_max = 60.0;              ///< m
  double elevation_min = -0.698, elevation_max = 1.047;  ///< rad
  /// Platform seconds of a scan at step s: seconds_at_ref x (ref_step / s)^2 (rays ~ 1/s^2)
  double ref_step_rad = 0.0, seconds_at_ref = 0.0;
};

/// True when the segment from a scanner centre to a cell centre is not blocked (e.g. the voxel
/// space); the default sees everything.
using LineOfSight = std::function<bool(const Vec3& scanner, const Vec3& target)>;

struct DetailPlan {
  bool found = false;
  int chosen = -1;              ///< index into the candidates
  double gain_area = 0.0;       ///< m^2 of deficient cells it fixes
  double cost_seconds = 0.0;    ///< s, its estimated cost
  double deficient_area = 0.0;  ///< m^2 of deficient cells before it
  std::string message;          ///< one line with the figures
};

/// Step 2: the best candidate for the deficient cells (see the file comment). `taken`: the
/// scans already in the model (candidates at their place and step add nothing; see
/// DetailPassParams::same_place).
DetailPlan PlanDetailScan(const std::vector<DetailCell>& cells,
                          const std::vector<DetailSurface>& surfaces,
                          const std::vector<DetailCandidate>& candidates, const DetailView& view,
                          const DetailPassParams& params, const DetailScans& taken,
                          const LineOfSight& visible = {});

}  // namespace mopad::autonomy
