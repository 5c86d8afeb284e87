#pragma once
// SM3 (paper §3.2, Figure 8a): the structural model of one room from its labelled points —
// floor and ceiling from the two maxima of the Z-histogram, walls from the edges of the polygon
// enclosing the plan-view image of the points, planes fitted with MLESAC (Torr & Zisserman 2000)
// and refined by least squares, then intersected coherently into a closed model: each wall a
// quadrilateral between its neighbours' planes and the floor and ceiling planes. Columns become
// vertical patches from their footprints: a roughly circular footprint (many short edges, no
// sharp corner) whose wall points fit a circle (least squares in plan) becomes a regular
// `round_segments`-gon prism of the fitted circle's area (centre and radius from the points);
// any other footprint keeps one plane fit per edge. Patches are labelled (`wall_1`, ..., `floor`,
// `ceiling`, `column_1_face_1`) and carry their topology (which patches share an edge).
//
// Robot side: input is the robot's own registered points (map frame) and the perimeter its
// RoomModel found; nothing here reads the truth. Deterministic for a given seed.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/ceiling_planes.h"
#include "common/params.h"

namespace mopad::modelling {

struct Sm3Params {
  double histogram_bin = 0.02;  ///< m, Z-histogram bin, [0.001, 0.5]
  /// m, a Z-histogram maximum this far from the room model's floor or ceiling (Sm3Input) is
  /// another surface's (a bathtub's top, a next room's ceiling): the room model's height is
  /// taken instead. [0.01, 10]
  double heights_tolerance = 0.1;
  double plane_band =
      0.10;  ///< m, points this close to a hypothesised surface feed its fit, (0, 1]
  double corner_margin =
      0.15;  ///< m, wall points this close to a corner are left out of the fit, [0, 2]
  double mlesac_sigma = 0.005;  ///< m, inlier noise of MLESAC's Gaussian, (0, 0.5]
  int mlesac_iterations = 300;  ///< hypotheses per plane, [1, 100000]
  int min_points = 50;  ///< points needed to fit a plane (else the edge line is used), [3, 1e7]
  double merge_angle_deg = 2.0;  ///< consecutive walls closer than this in direction merge, [0, 45]
  /// deg, an unsupported face between two fitted faces that turn at least this much is a cut
  /// corner and collapses into their corner, [1, 90]
  double corner_min_angle_deg = 30.0;
  int max_fit_points =
      2000;                ///< points scoring each MLESAC hypothesis (even subsample), [100, 1e8]
  std::uint64_t seed = 1;  ///< MLESAC sampling
  // Round columns (see the file comment).
  int round_min_vertices =
      6;  ///< footprint vertices (after merging) a round column has at least, [3, 1000]
  double round_max_turn_deg =
      60.0;  ///< deg, no footprint corner of a round column turns more, (0, 180]
  double round_max_rms_ratio =
      0.05;                 ///< circle fit residual RMS / radius accepted as round, (0, 1]
  int round_segments = 16;  ///< faces of the prism that models a round column, [3, 360]
  /// m, column footprint edges shorter than this collapse into a corner, and so do column faces
  /// the plane fit leaves shorter or reversed: no sliver face, no clockwise polygon, [0, 1]
  double min_column_edge = 0.05;
  /// deg, a fitted floor or ceiling tilted less than this from horizontal is taken horizontal
  /// through the fit's height at its points' centroid: the map frame is levelled (the
  /// scanner's inclinometer, +-0.008 deg), and a smaller fitted tilt is range noise and clutter
  /// over the room's span (0.05 deg over a 15 m hall is 1.3 cm at its far walls' tops); a
  /// sloped ceiling tilts more and keeps its fit. 0: every fit kept, [0, 10]
  double level_tolerance_deg = 0.5;
  /// m, a face's fitted tilt (a wall's from plumb, a floor's or ceiling's from level) is read
  /// only from inliers spanning at least this along the slope; over a narrower strip (a wall
  /// seen only in the band under its ceiling, a floor seen only along a far wall) a few mm of
  /// systematic error is degrees of tilt, and the face is taken plumb or level through the
  /// strip's centroid. 0: every tilt kept, [0, 10]
  double min_tilt_extent = 0.5;

  template <class V>
  void Visit(V& v) {
    v("histogram_bin", histogram_bin, Bounds{0.001, 0.5});
    v("heights_tolerance", heights_tolerance, Bounds{0.01, 10.0});
    v("plane_band", plane_band, Bounds{1e-4, 1.0});
    v("corner_margin", corner_margin, Bounds{0.0, 2.0});
    v("mlesac_sigma", mlesac_sigma, Bounds{1e-5, 0.5});
    v("mlesac_iterations", mlesac_iterations, Bounds{1, 100000});
    v("min_points", min_points, Bounds{3, 10000000});
    v("merge_angle_deg", merge_angle_deg, Bounds{0.0, 45.0});
    v("corner_min_angle_deg", corner_min_angle_deg, Bounds{1.0, 90.0});
    v("max_fit_points", max_fit_points, Bounds{100, 100000000});
    v("seed", seed);
    v("round_min_vertices", round_min_vertices, Bounds{3, 1000});
    v("round_max_turn_deg", round_max_turn_deg, Bounds{1e-6, 180.0});
    v("round_max_rms_ratio", round_max_rms_ratio, Bounds{1e-6, 1.0});
    v("round_segments", round_segments, Bounds{3, 360});
    v("min_column_edge", min_column_edge, Bounds{0.0, 1.0});
    v("level_tolerance_deg", level_tolerance_deg, Bounds{0.0, 10.0});
    v("min_tilt_extent", min_tilt_extent, Bounds{0.0, 10.0});
  }
};

enum class PatchClass : std::uint8_t { kWall = 1, kFloor = 2, kCeiling = 3, kColumn = 4 };
const char* ToString(PatchClass c);

/// A plane n.x + d = 0 with unit n pointing into the room.
struct Plane {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  double Distance(const Eigen::Vector3d& p) const { return n.dot(p) + d; }
};

/// Result of one MLESAC + least-squares fit.
struct PlaneFit {
  Plane plane;
  int support = 0;      ///< points within 3 sigma of the final plane
  double rms = 0.0;     ///< m, of the supporting points
  bool fitted = false;  ///< false: too few points (the caller's fallback was used)
};

/// MLESAC over `points` (3-point hypotheses, mixture of Gaussian inliers and uniform outliers,
/// mixing weight by EM), then least squares (PCA) on the inliers. `stream` names the random
/// stream so that different fits draw independent samples.
PlaneFit FitPlaneMlesac(const std::vector<Eigen::Vector3d>& points, const Sm3Params& params,
                        const std::string& stream);

struct StructuralPatch {
  std::string id;  ///< "wall_1", "floor", "ceiling", "column_1_face_2"
  PatchClass patch_class = PatchClass::kWall;
  Plane plane;
  std::vector<Eigen::Vector3d> polygon;  ///< closed, CCW seen from inside the room (along -n)
  int support = 0;                       ///< points supporting the plane
  double rms = 0.0;                      ///< m
  bool fitted = false;                   ///< plane from data (false: from the perimeter only)
};

struct StructuralModel {
  std::string room;                       ///< label given by the caller (e.g. "A" or "room_1")
  double floor_z = 0.0, ceiling_z = 0.0;  ///< m, from the Z-histogram
  std::vector<StructuralPatch> patches;
  std::vector<std::pair<int, int>> adjacency;  ///< indices of patches sharing an edge
};

/// Input of one room: points in the map frame (inliers of SM1 only, or all — non-structural
/// points far from every surface are ignored), the plan-view perimeter (CCW, from the ceiling
/// points) and column footprints (CCW each).
struct Sm3Input {
  std::string room;
  const std::vector<Eigen::Vector3d>* points = nullptr;
  std::vector<Eigen::Vector2d> perimeter;
  std::vector<std::vector<Eigen::Vector2d>> columns;
  /// m, the room model's floor and ceiling (RoomModel::FloorZ/CeilingZ: the floor the robot
  /// stands on, the ceiling over the scanners), NaN when not known. A Z-histogram maximum more
  /// than Sm3Params::heights_tolerance from one yields to it: the strongest maxima of a
  /// washroom's points are its ceiling and a bathtub's top, not its floor.
  double floor_z = std::numeric_limits<double>::quiet_NaN();
  double ceiling_z = std::numeric_limits<double>::quiet_NaN();
  /// Sloped ceilings (an attic's roof, RoomModel's Roi::slopes) and whether the level ceiling at
  /// ceiling_z is one: each slope becomes a ceiling patch `ceiling_<k>` where it is the lowest,
  /// and the walls end under them.
  std::vector<CeilingPlane> slopes;
  bool level_ceiling = true;
};

/// Floor and ceiling heights: the lowest and the highest strong maxima of the Z-histogram.
/// Throws InputError when fewer than two maxima exist.
std::pair<double, double> FloorCeilingFromHistogram(const std::vector<Eigen::Vector3d>& points,
                                                    double bin);

/// A circle fitted in plan to a column's wall points.
struct CircleFit {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;  ///< m
  double rms = 0.0;     ///< m, radial residual of the supporting points
  int support = 0;      ///< points used in the final fit
  bool round = false;   ///< the footprint looks circular and the points fit the circle
};

/// Tests whether `footprint` (CCW) is a round column and fits its circle: the footprint needs
/// >= round_min_vertices vertices after merging collinear edges and no turn above
/// round_max_turn_deg; the circle through its vertices (Kasa) seeds a least-squares circle fit
/// (Kasa, then Gauss-Newton on the geometric distance) to the points with floor_z + 0.15 < z <
/// ceiling_z - 0.15 within plane_band of the seed circle, refitted once within half that band;
/// round when rms <= round_max_rms_ratio * radius and support >= min_points.
CircleFit FitColumnCircle(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<Eigen::Vector2d>& footprint, double floor_z,
                          double ceiling_z, const Sm3Params& params);

/// Builds SM3. Throws InputError for a perimeter with fewer than 3 vertices or no points.
StructuralModel BuildStructuralModel(const Sm3Input& input, const Sm3Params& params);

class RoomModel;

/// SM3 of a room from its RoomModel: the inlier points (at most ~1 M, evenly subsampled), the
/// RoI perimeter and the columns (paper §3.2). `room` labels the model. `exclude`, when not
/// null, has one entry per RoomModel point (InputError otherwise); points with a non-zero entry
/// are left out of the fit: the refit with SM4, where a closed door's leaf and casing
/// (ClosedDoorPointMask in modelling/openings.h) must not move its wall.
StructuralModel BuildRoomSm3(const RoomModel& model, const Sm3Params& params,
                             const std::string& room,
                             const std::vector<std::uint8_t>* exclude = nullptr);

}  // namespace mopad::modelling
