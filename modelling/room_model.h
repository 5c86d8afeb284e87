#pragma once
// The robot's model of one room while it scans it (paper §3.1 steps (3)-(5), Figures 5-6):
// registered TLS scans accumulated in the map frame, and after every scan
//  - floor and ceiling heights (the two maxima of the Z-histogram, §3.2);
//  - the ceiling perimeter in plan view (per azimuth, the ceiling seen contiguously from the
//    scanner up to the wall that stops it; the union over scans, simplified, each edge refit to
//    its wall points). The scanner's blind cone above itself and the floor it cannot see
//    within ~1.7 m are inside the per-scan outline by construction, so they never read as holes;
//  - columns (vertical floor-to-ceiling structures inside the perimeter);
//  - per-point labels: inlier (on the floor, ceiling, a perimeter wall or a column), outlier
//    (outside the perimeter: through doors and windows, reflections), clutter (the rest);
//  - the RoI B-rep (modelling/roi.h) with faces classified as holding structural data or not,
//    each rasterised into sensed / unsensed / opening cells;
//  - the voxel space of the RoI (modelling/voxel_space.h);
//  - coverage figures for the stopping rule (modelling/stopping.h).
// SM1 (§3.1) is the labelled coloured full-resolution cloud (WriteSm1).
//
// Inputs are the robot's own: organised scans in the scanner frame and the registered pose
// X_MS of each. Deterministic (TBB loops write disjoint outputs; reductions in fixed order).
// Not thread-safe for concurrent AddScan; const accessors may run concurrently.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/tls_scan.h"
#include "io/scan_io.h"
#include "modelling/roi.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

/// Per-point SM1 labels (values written to the PLY `scalar_label`; the evaluator uses the same).
enum class PointLabel : std::uint8_t { kNone = 0, kInlier = 1, kOutlier = 2, kClutter = 3 };
const char* ToString(PointLabel label);

struct RoomModelParams {
  double working_voxel = 0.02;  ///< m, working-cloud downsampling, [0.005, 0.2]
  double histogram_bin = 0.01;  ///< m, Z-histogram bin, [0.002, 0.1]
  double plane_tolerance =
      0.03;  ///< m, |z - floor| or |z - ceiling| of structural points, [0.005, 0.2]
  double wall_tolerance =
      0.015;  ///< m, plan distance to a wall/column face of its points, [0.005, 0.2]
  double ceiling_tolerance = 0.05;  ///< m, |z - ceiling| for the perimeter trace, [0.01, 0.3]
  /// Points just beyond a wall face (in the reveal of a door or window: frames, glass, a closed
  /// leaf) up to this depth and between floor and ceiling are clutter, not outliers. 0 = the
  /// paper's rule (everything outside the perimeter is an outlier). [0, 1]
  double reveal_depth = 0.0;
  double perimeter_raster = 0.025;  ///< m, plan raster of the ceiling outline, [0.005, 0.2]
  double perimeter_epsilon = 0.04;  ///< m, polygon simplification tolerance, [0.005, 0.5]
  /// m: after the refit, a vertex this close to the segment joining its neighbours is dropped
  /// (a short edge fitted across a doorway can leave such a jog, splitting the wall). 0 = off.
  /// [0, 0.5]
  double jog_tolerance = 0.04;
  double min_edge_length = 0.1;  ///< m, shorter simplified edges are merged, [0, 2]
  /// m, a perimeter detour that leaves a wall line, passes up to this far behind it and comes
  /// back onto the same line is a view through an opening in that wall (the trace walked into
  /// a door's or window's reveal under a head close to the ceiling) and is cut off by the
  /// straight wall; 0 = off. Wall reveals are 0.1-0.5 m deep. [0, 2]
  double seal_depth = 0.6;
  /// m, widest such detour along the wall line (a double door's clear width), [0, 10]
  double seal_width = 3.0;
  /// m, how far such a detour may also reach into the room (the leaf of a door opened inwards,
  /// which hides the wall beside the doorway), [0, 5]
  double seal_inward = 1.2;
  double refit_band = 0.1;    ///< m, wall points gathered around an edge for its refit, [0.01, 1]
  int refit_min_points = 30;  ///< points an edge needs to be refit, [3, 100000]
  double column_max_size = 1.5;          ///< m, largest column footprint side, [0.1, 10]
  double column_min_height_share = 0.7;  ///< share of the floor-ceiling height seen, [0.1, 1]
  /// m, RoI face raster cell, [0.02, 1]. 5 cm: a cell counts as sensed from one point, so
  /// larger cells overstate sparse far coverage (the evaluator scores 5 cm cells).
  double face_cell = 0.05;
  double structural_share = 0.05;  ///< sensed share that makes a face structural, [0, 1]
  double voxel_size = 0.1;         ///< m, voxel space edge, [0.02, 1]
  double voxel_margin = 0.5;       ///< m, grid margin around the RoI, [0, 5]
  /// m, a RoI face is taken this far into the room when picking its voxel layer, so a face the
  /// robot places a few mm behind a voxel boundary still lands on the room side as the truth's
  /// does (DSM3: one structural layer per face), [0, 0.45 * voxel_size]
  double structure_tolerance = 0.01;
  int ray_stride = 2;  ///< every n-th row and column is ray-cast into voxels, [1, 64]

  template <class V>
  void Visit(V& v) {
    v("working_voxel", working_voxel, Bounds{0.005, 0.2});
    v("histogram_bin", histogram_bin, Bounds{0.002, 0.1});
    v("plane_tolerance", plane_tolerance, Bounds{0.005, 0.2});
    v("wall_tolerance", wall_tolerance, Bounds{0.005, 0.2});
    v("ceiling_tolerance", ceiling_tolerance, Bounds{0.01, 0.3});
    v("reveal_depth", reveal_depth, Bounds{0.0, 1.0});
    v("perimeter_raster", perimeter_raster, Bounds{0.005, 0.2});
    v("perimeter_epsilon", perimeter_epsilon, Bounds{0.005, 0.5});
    v("jog_tolerance", jog_tolerance, Bounds{0.0, 0.5});
    v("min_edge_length", min_edge_length, Bounds{0.0, 2.0});
    v("seal_depth", seal_depth, Bounds{0.0, 2.0});
    v("seal_width", seal_width, Bounds{0.0, 10.0});
    v("seal_inward", seal_inward, Bounds{0.0, 5.0});
    v("refit_band", refit_band, Bounds{0.01, 1.0});
    v("refit_min_points", refit_min_points, Bounds{3, 100000});
    v("column_max_size", column_max_size, Bounds{0.1, 10.0});
    v("column_min_height_share", column_min_height_share, Bounds{0.1, 1.0});
    v("face_cell", face_cell, Bounds{0.02, 1.0});
    v("structural_share", structural_share, Bounds{0.0, 1.0});
    v("voxel_size", voxel_size, Bounds{0.02, 1.0});
    v("voxel_margin", voxel_margin, Bounds{0.0, 5.0});
    v("structure_tolerance", structure_tolerance, Bounds{0.0, 0.45});
    v("ray_stride", ray_stride, Bounds{1, 64});
  }
  void Validate() const { ValidateParams(*this, "room_model."); }
};

/// The perimeter's last pass after its edges were refit onto their walls (plan polygon, CCW,
/// map frame, m): vertices closer than `jog_tolerance` to the segment joining their neighbours
/// dropped, detours behind a wall line deeper than that and at most `seal_depth` (views through
/// an opening) cut across, short and collinear edges merged.
void TidyPerimeter(std::vector<Vec2>& poly, const RoomModelParams& params);

/// One perimeter edge's wall line after the refit (plan, map frame): a point `p` of it, its unit
/// direction `t`, `fitted` false where no wall's points carried the edge (it keeps the traced
/// line), and `support` the principal direction of the points that carried it (`t` keeps the
/// traced direction, only shifted, where they run more than 10 deg off the edge).
struct PerimeterLine {
  Vec2 p = Vec2::Zero();
  Vec2 t = Vec2::UnitX();
  bool fitted = false;
  Vec2 support = Vec2::UnitX();
};

/// The refit perimeter's corners from its edges' lines (`lines[i]` for the edge poly[i] ->
/// poly[i+1]): a short end face of a wall standing into the room squared to it, short edges
/// that cut a corner (unfitted, or fitted onto a neighbour's wall) collapsed into the corner of
/// their neighbours, the other neighbours re-intersected.
std::vector<Vec2> JoinPerimeterLines(const std::vector<Vec2>& poly,
                                     const std::vector<PerimeterLine>& lines,
                                     const RoomModelParams& params);

/// Coverage of the structural elements after a scan (areas in m^2).
struct CoverageFigures {
  int scans = 0;
  double sensed_area = 0.0;   ///< sensed cells of all RoI faces
  double total_area = 0.0;    ///< estimated structural area: RoI face area minus openings
  double opening_area = 0.0;  ///< face cells seen through (doors, windows)
  double ratio = 0.0;         ///< sensed_area / total_area
  /// (sensed_area - previous sensed_area) / total_area; equals ratio for the first scan.
  double increment = 0.0;
  /// m^2, unsensed area of structural faces that no position the robot can reach sees (hidden
  /// behind clutter it has scanned, out of the scanner's elevation range); set by the room loop
  /// (autonomy::EstimateHiddenArea), 0 until then. [0, total_area]
  double hidden_area = 0.0;
  /// sensed_area / (total_area - hidden_area): the sensed share of the structure the robot can
  /// observe, what the stopping rule compares with epsilon1; equals ratio while hidden_area = 0.
  double observable_ratio = 0.0;
  /// Sets hidden_area (clamped to [0, total_area - sensed_area]) and observable_ratio.
  void SetHiddenArea(double area);
};

/// Per-point label counts.
struct LabelCounts {
  std::int64_t none = 0, inlier = 0, outlier = 0, clutter = 0;
};

class RoomModel {
 public:
  /// Validates `params` (InputError).
  explicit RoomModel(RoomModelParams params = {});
  RoomModel(const RoomModel&) = default;
  RoomModel& operator=(const RoomModel&) = default;
  RoomModel(RoomModel&&) noexcept = default;
  RoomModel& operator=(RoomModel&&) noexcept = default;

  /// Adds one scan with its registered scanner pose (map frame) and recomputes everything.
  /// Throws InputError if the scan's grid is inconsistent (points != rows * columns) or it
  /// has no valid return, or X_MS is not finite.
  void AddScan(const interfaces::TlsScan& scan, const Pose3& X_MS);
  /// From now on AddScan adds points, labels, face sensing, voxels and coverage but keeps the
  /// structure as it is: heights, perimeter, columns, RoI (for scans taken for data quality
  /// after the structural stopping rule, autonomy/detail_pass.h). Not undone.
  void FreezeStructure() { structure_frozen_ = true; }
  bool StructureFrozen() const { return structure_frozen_; }

  const RoomModelParams& Params() const { return params_; }
  int ScanCount() const { return static_cast<int>(scans_.size()); }
  const std::vector<Pose3>& ScanPoses() const { return scan_poses_; }
  double FloorZ() const { return roi_.floor_z; }
  double CeilingZ() const { return roi_.ceiling_z; }
  /// Simplified ceiling perimeter, CCW, map frame plan (m).
  const std::vector<Vec2>& Perimeter() const { return roi_.perimeter; }
  const std::vector<std::vector<Vec2>>& Columns() const { return roi_.columns; }
  const Roi& GetRoi() const { return roi_; }
  const VoxelSpace& Voxels() const { return voxels_; }
  const CoverageFigures& Coverage() const { return coverage_.back(); }
  /// One entry per AddScan.
  const std::vector<CoverageFigures>& CoverageHistory() const { return coverage_; }

  /// Label of a map-frame point against the current model (the rule used for every point).
  PointLabel Classify(const Vec3& p_M) const;

  // Full-resolution cloud (every valid return of every scan, map frame, scan order).
  std::size_t PointCount() const { return points_.size(); }
  const std::vector<Eigen::Vector3f>& Points() const { return points_; }
  const std::vector<std::array<std::uint8_t, 3>>& Colours() const { return colours_; }
  const std::vector<float>& Intensities() const { return intensity_; }
  const std::vector<std::uint16_t>& ScanIndices() const { return scan_index_; }
  const std::vector<PointLabel>& Labels() const { return labels_; }
  LabelCounts CountLabels() const;
  /// Working cloud: centroids of the occupied working voxels (map frame).
  const std::vector<Eigen::Vector3f>& WorkingPoints() const { return work_points_; }

  /// SM1 as a cloud: x y z red green blue scalar_intensity scalar_label scalar_scan, with the
  /// scan poses and heights in header comments.
  io::PointCloud Sm1Cloud() const;
  /// Writes Sm1Cloud() as binary PLY (InputError on I/O failure).
  void WriteSm1(const std::string& path) const;
  /// The figures (heights, perimeter, columns, faces, voxel label counts, coverage history,
  /// label counts) as a JSON object, for the mission log.
  std::string FiguresJson() const;

  /// Implementation detail (room_model.cpp): plan boundary for the signed-distance lookups.
  struct Boundary;

 private:
  struct ScanRecord {
    std::size_t begin = 0, end = 0;  // range in the full-resolution arrays
    Vec3 origin = Vec3::Zero();      // scanner centre, map
    std::vector<Vec2> outline;       // plan outline of its ceiling view (map)
    double min_range = 0.0;          // m, the shortest return of the scan (its minimum range)
    std::uint32_t columns = 0;       // azimuth columns of the scan
    double azimuth_min = 0.0, azimuth_step = 0.0;        // rad, scanner frame
    Eigen::Matrix3d R_MS = Eigen::Matrix3d::Identity();  // scanner orientation in map
  };

  void UpdateWorkingCloud(std::size_t begin, std::size_t end);
  void EstimateHeights();
  void TraceOutline(ScanRecord& rec) const;
  void BuildPerimeter();
  void RefitPerimeter(std::vector<Vec2>& poly) const;
  void DetectColumns();
  void BuildRoi();
  void LabelAll();
  void UpdateFaces();
  void UpdateVoxels(bool new_scan_only);
  void UpdateCoverage();

  RoomModelParams params_;
  std::vector<ScanRecord> scans_;
  std::vector<Pose3> scan_poses_;
  // Full resolution (structure of arrays).
  std::vector<Eigen::Vector3f> points_;
  std::vector<std::array<std::uint8_t, 3>> colours_;
  std::vector<float> intensity_;
  std::vector<std::uint16_t> scan_index_;
  std::vector<std::uint32_t> column_index_;  // azimuth column of each point in its scan
  std::vector<PointLabel> labels_;
  // Working cloud.
  std::unordered_map<std::int64_t, std::uint32_t>
      work_slot_;  // voxel key -> slot (insertion order)
  std::vector<Eigen::Vector3d> work_sum_;
  std::vector<std::uint32_t> work_count_;
  std::vector<Eigen::Vector3f> work_points_;
  std::vector<PointLabel> work_labels_;
  std::vector<std::int32_t> work_face_;
  // Model.
  Roi roi_;
  bool structure_frozen_ = false;             // FreezeStructure()
  std::shared_ptr<const Boundary> boundary_;  // of roi_, rebuilt with it
  VoxelSpace voxels_;
  std::vector<CoverageFigures> coverage_;
};

}  // namespace mopad::modelling
