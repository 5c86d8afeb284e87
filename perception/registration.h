#pragma once
// Registration of a new TLS scan s(t) to the accumulated cloud S(t-1) (paper §3.1 step (3):
// "The set s(t) is firstly horizontally aligned according to the inclinometer ... the 2D
// registration ... is estimated using the odometry ... Finally, this transformation is refined
// by applying the well-known Iterative Closest Point (ICP) technique").
//
// The caller gives the scan's points in the (levelled) scanner frame S and the prior X_MS
// (odometry / localisation, e.g. TlsScan::X_MS_estimate). The refinement is point-to-plane ICP
// (Chen & Medioni 1992; linearised as in Low 2004) with a coarse-to-fine schedule of maximum
// correspondence distances, a robust kernel on the point-to-plane residual (Huber, Tukey or
// Cauchy; scale = kernel_scale_ratio x the stage's correspondence distance), Gauss-Newton
// steps on SE(3) (6 DoF) or on x, y, z, yaw (4 DoF: the inclinometer's levelling is trusted).
//
// Health: fitness = share of the downsampled source points the map could have seen that have a
// correspondence within the last stage's distance (expected overlap: a point counts when some
// map scan's ray in its direction reached at least as far, so points in space no map scan
// looked into, beyond its returns or inside its minimum range, neither help nor hurt: a scan
// that looks into new space is not a bad scan; without map scan origins every point counts);
// rmse = RMS point-to-plane residual of those; free-space violation = share
// of source points lying where a map scan saw through (catches a wrong pose that fits the
// room's symmetric shell, e.g. a prior 180 deg off, when the scan's asymmetric content floats
// in observed empty space); `degenerate` when the normalised information along some direction
// is below `degeneracy_threshold` (after Zhang, Kaess & Singh 2016: eigenvalues of the
// Gauss-Newton Hessian; e.g. the axis of a long corridor). Such directions are also frozen in
// every step (solution remapping), so the pose keeps the prior along them instead of drifting
// on noise. The result carries its information matrix (the Gauss-Newton Hessian over the
// residual variance, Censi 2007's first-order term) and, with RegistrationCovariance, a
// covariance that takes the constrained directions from the scan and the weak ones from the
// prior's covariance (docs/registration.md). `ok` = converged, fitness >= min_fitness, rmse <= max_rmse, violation <=
// max_free_space_violation and not degenerate. A
// failed registration is a result with ok = false and a message, never an exception.
//
// Frames: map M (REP-105 `map`, Z up), scanner S. Determinism: source and map are ordered by
// voxel key; correspondences and sums are computed per fixed block of points and reduced in
// block order, so results are the same bytes with 1 or N TBB threads. PointMap is not
// thread-safe for Add; const queries (RegisterScan) may run concurrently.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/params.h"
#include "perception/point_cloud_ops.h"

namespace mopad::perception {

struct IcpParams {
  double voxel_size = 0.05;        ///< m, voxel grid of the accumulated map, [0.005, 1]
  double source_voxel_size = 0.1;  ///< m, voxel grid of the new scan, [0.005, 2]
  /// m, coarse-to-fine maximum correspondence distances, one ICP stage each, (0, 10]. The 1 m
  /// first stage widens the basin: office rooms register from priors 1.2 m / 20 deg off.
  std::vector<double> max_correspondence = {1.0, 0.5, 0.2, 0.08};
  int max_iterations = 30;               ///< Gauss-Newton iterations per stage, [1, 1000]
  double min_delta_translation = 1e-5;   ///< m, stage converged when a step is below both, (0, 1]
  double min_delta_rotation_deg = 1e-4;  ///< deg, idem, (0, 10]
  /// 4: x, y, z, yaw, roll and pitch kept from the prior (the inclinometer's levelling, paper
  /// §3.1 step (3)); 6: full pose. 4 is the default: in a 2 m corridor 6-DoF roll came out up
  /// to 0.12 deg wrong (walls constrain it with a ~1 m lever), while the VZ-400 inclinometer
  /// levels to ~0.01 deg. Use 6 for an unlevelled or badly levelled scanner.
  int dof = 4;
  std::string robust_kernel = "tukey";  ///< none | huber | tukey | cauchy
  double kernel_scale_ratio = 0.5;      ///< kernel scale / stage correspondence distance, (0, 10]
  int normal_neighbours = 12;           ///< k of the map's PCA normals, [3, 100]
  double normal_radius = 0.25;          ///< m, neighbours farther than this are ignored, (0, 5]
  double max_normal_curvature = 0.1;    ///< map points less planar than this are unused, (0, 1/3]
  double min_fitness = 0.5;  ///< ok needs at least this share of matched source points, [0, 1]
  double max_rmse = 0.03;    ///< m, ok needs the final RMS residual below this, (0, 1]
  double degeneracy_threshold = 0.02;  ///< min normalised eigenvalue of the information, [0, 1]
  /// Free-space check: a source point with no map point within the last stage's distance and
  /// closer to a map scan's origin than that scan's nearest return in the same direction bin
  /// (by more than the margin) lies where that scan saw empty space; only bins whose returns
  /// span at most the margin in range count (grazing surfaces and depth edges do not). ok
  /// needs the share of such points at most max_free_space_violation. Right registrations
  /// stay well below the default; poses 90 or 180 deg off exceed it (docs/room-scanning.md).
  double free_space_bin_deg = 0.5;          ///< deg, direction bins of each map scan, [0.05, 10]
  double free_space_margin = 0.1;           ///< m, plus 2 % of the range, [0, 10]
  double max_free_space_violation = 0.006;  ///< share of source points, [0, 1]
  double min_range = 0.0;     ///< m, source points closer to the scanner are dropped, [0, 1000]
  double max_range = 1000.0;  ///< m, source points farther are dropped, (0, 1e6]
  /// A source point's nearest map point counts only when both were seen from the same side of
  /// the map point's plane (map points from scans added with their origin): the two faces of a
  /// thin wall, seen from the rooms on either side, are two surfaces, not one.
  bool same_side = false;
  /// m, 0 = off: a degenerate result whose weak direction is a horizontal translation is placed
  /// along it by the free-space evidence: the offsets within +-weak_search are scored by their
  /// free-space violation, and when the least violating ones are bounded on both sides within
  /// the range (points that would float in empty space either way: a door's jambs, furniture
  /// seen by both scans) and exclude the prior, the result keeps its place if it lies among
  /// them and otherwise moves to their middle, the last two stages then run again from there;
  /// otherwise it stays, and the acceptance policy's slide rule applies. [0, 2]
  double weak_search = 0.0;
  double weak_search_step = 0.01;  ///< m, spacing of the offsets searched, [0.001, 0.5]
  /// Offsets whose violation is within this share of the source points of the least one
  /// count as least violating (noise of a few points). [0, 1]
  double weak_search_tolerance = 0.0005;

  template <class V>
  void Visit(V& v) {
    v("voxel_size", voxel_size, Bounds{0.005, 1.0});
    v("source_voxel_size", source_voxel_size, Bounds{0.005, 2.0});
    v("max_correspondence", max_correspondence, Bounds{1e-4, 10.0});
    v("max_iterations", max_iterations, Bounds{1, 1000});
    v("min_delta_translation", min_delta_translation, Bounds{1e-12, 1.0});
    v("min_delta_rotation_deg", min_delta_rotation_deg, Bounds{1e-12, 10.0});
    v("dof", dof, Bounds{4, 6});
    v("robust_kernel", robust_kernel);
    v("kernel_scale_ratio", kernel_scale_ratio, Bounds{1e-3, 10.0});
    v("normal_neighbours", normal_neighbours, Bounds{3, 100});
    v("normal_radius", normal_radius, Bounds{1e-3, 5.0});
    v("max_normal_curvature", max_normal_curvature, Bounds{1e-6, 1.0 / 3.0});
    v("min_fitness", min_fitness, Bounds{0.0, 1.0});
    v("max_rmse", max_rmse, Bounds{1e-6, 1.0});
    v("degeneracy_threshold", degeneracy_threshold, Bounds{0.0, 1.0});
    v("free_space_bin_deg", free_space_bin_deg, Bounds{0.05, 10.0});
    v("free_space_margin", free_space_margin, Bounds{0.0, 10.0});
    v("max_free_space_violation", max_free_space_violation, Bounds{0.0, 1.0});
    v("min_range", min_range, Bounds{0.0, 1000.0});
    v("max_range", max_range, Bounds{1e-3, 1e6});
    v("same_side", same_side);
    v("weak_search", weak_search, Bounds{0.0, 2.0});
    v("weak_search_step", weak_search_step, Bounds{0.001, 0.5});
    v("weak_search_tolerance", weak_search_tolerance, Bounds{0.0, 1.0});
  }
  /// Bounds plus cross-field rules (dof 4 or 6, known kernel, non-empty schedule,
  /// min_range < max_range); throws InputError naming the field.
  void Validate() const;
};

struct RegistrationResult {
  Eigen::Isometry3d X_MS = Eigen::Isometry3d::Identity();  ///< refined scanner pose in the map
  bool ok =
      false;  ///< converged, fits, free space consistent, well conditioned: safe to accumulate
  bool converged = false;  ///< the last stage's step fell below the deltas within max_iterations
  /// Share of the source points the map could have seen (expected overlap) that are matched
  /// in the last stage, [0, 1]
  double fitness = 0.0;
  double raw_fitness = 0.0;  ///< share of all source points matched in the last stage, [0, 1]
  /// Share of the source points lying where a map scan could have seen them, [0, 1] (1 when
  /// the map has no scan origins)
  double expected_overlap = 1.0;
  double rmse = 0.0;       ///< m, RMS point-to-plane residual of the matches
  /// Share of source points lying in space a map scan saw empty (0 if the map has no origins).
  double free_space_violation = 0.0;
  int iterations = 0;          ///< Gauss-Newton iterations over all stages
  double last_step = 0.0;      ///< m, translation of the last Gauss-Newton step
  double last_step_deg = 0.0;  ///< deg, rotation of the last Gauss-Newton step
  bool degenerate = false;     ///< some direction is ill-constrained (e.g. a long corridor)
  /// Eigenvalues (ascending) of the normalised Gauss-Newton information at the result, in
  /// homogeneous units (rotations scaled by the RMS lever arm): 6 values, or 4 in 4 DoF.
  /// Degenerate if the smallest is below degeneracy_threshold.
  std::vector<double> information;
  /// Eigenvector of the smallest one, (rx, ry, rz, tx, ty, tz); in 4 DoF rx = ry = 0.
  Eigen::Matrix<double, 6, 1> weakest_direction = Eigen::Matrix<double, 6, 1>::Zero();
  /// Information of the pose at the result: sum J J^T / rmse^2 over the planar matches, J =
  /// [(p - c) x n; n] with c the placed source centroid, in (rx, ry, rz, tx, ty, tz) (1/rad^2,
  /// 1/m^2, map frame axes); the rows of DoF the ICP does not estimate (roll and pitch in 4
  /// DoF) are zero. Zero when there were too few matches.
  Eigen::Matrix<double, 6, 6> information_matrix = Eigen::Matrix<double, 6, 6>::Zero();
  /// Unit basis (columns, same coordinates) of the directions the scan constrains: the
  /// eigenvectors of the normalised information at or above degeneracy_threshold, in DoF the
  /// ICP estimates. The others kept the prior (solution remapping).
  Eigen::Matrix<double, 6, Eigen::Dynamic> constrained_directions;
  /// The free-space search (IcpParams::weak_search) found the least violating offsets along
  /// the weak direction bounded on both sides, the prior outside them and X_MS among them: its
  /// place along that direction is evidence, not a slide (AcceptRegistration).
  bool weak_bounded = false;
  /// m, the move along the weak direction the search made (0 when the result already lay in
  /// the evidence or there was none); part of X_MS.
  double weak_offset = 0.0;
  Eigen::Vector3d weak_offset_direction = Eigen::Vector3d::Zero();  ///< unit, map frame
  std::size_t source_points = 0;  ///< after downsampling
  std::size_t target_points = 0;
  std::string message;  ///< one line: the outcome with its figures
};

/// The one policy that decides whether a registration's pose replaces the prior (the room scan
/// and the navigator's map scans use it with their own params). A result is used when it is
/// `ok`, or when it fits (residual, fitness, free space) and its only flaw is one the policy
/// accepts: a weak direction (a corridor; ICP kept the prior along it) or a last stage that ran
/// out of iterations while still creeping below the step thresholds. Either way the correction
/// must stay within the bounds: a larger jump is ICP sliding into a neighbouring minimum.
struct RegistrationAcceptanceParams {
  bool accept_degenerate = true;  ///< use results whose only flaw is a weak direction
  /// A result that fits but whose last stage ran out of iterations creeping by less than this
  /// many times the ICP step thresholds counts as converged (a degenerate one: its correction
  /// across the weak direction, under max_weak_slide). 0 = off. [0, 1000]
  double creeping_step_factor = 10.0;
  double max_correction = 0.1;      ///< m, largest accepted x-y correction of the prior, [0, 1000]
  double max_correction_deg = 2.0;  ///< deg, largest accepted yaw correction, [0, 180]
  /// The x-y correction must also be within this many standard deviations of the prior (its
  /// largest x-y std, `prior_sigma`), but at least `min_gate` and at most `max_correction`.
  /// Applies to degenerate results, or to all when `trust_constrained` is false. 0 = off. [0, 100]
  double gate_sigmas = 3.0;
  double min_gate = 0.03;  ///< m, [0, 10]
  /// A result that constrains every direction is bounded by max_correction alone (a
  /// localiser drifts more in door passages than it reports; the scan sees it).
  bool trust_constrained = true;
  /// m: a degenerate result may have moved along its weak direction by up to this (the ICP
  /// keeps the prior there while that direction is weak all the way; a direction that turns
  /// weak only at the result lets it slide). A larger slide is no evidence: the used pose takes
  /// the result's correction across the weak direction and keeps the prior along it. [0, 10]
  double max_weak_slide = 0.02;

  template <class V>
  void Visit(V& v) {
    v("accept_degenerate", accept_degenerate);
    v("creeping_step_factor", creeping_step_factor, Bounds{0.0, 1000.0});
    v("max_correction", max_correction, Bounds{0.0, 1000.0});
    v("max_correction_deg", max_correction_deg, Bounds{0.0, 180.0});
    v("gate_sigmas", gate_sigmas, Bounds{0.0, 100.0});
    v("min_gate", min_gate, Bounds{0.0, 10.0});
    v("trust_constrained", trust_constrained);
    v("max_weak_slide", max_weak_slide, Bounds{0.0, 10.0});
  }
};

struct RegistrationDecision {
  bool use = false;  ///< the registered pose replaces the prior
  Eigen::Isometry3d X_MS = Eigen::Isometry3d::Identity();  ///< the pose to use (when `use`)
  double weak_slide = 0.0;      ///< m, a degenerate result's move along its weak direction
  bool creeping = false;        ///< counted as converged while creeping (see creeping_step_factor)
  bool within_bounds = false;   ///< the correction is within the gate and the yaw bound
  double correction = 0.0;      ///< m, x-y distance of the result from the prior
  double correction_deg = 0.0;  ///< deg, yaw difference
  double gate = 0.0;            ///< m, the x-y bound applied
  std::string message;          ///< one line: the registration's message and the decision
};

/// Applies `policy` to `r` registered from `prior_X_MS` with `icp`; `prior_sigma` (m) is the
/// largest x-y standard deviation of the prior (0 when unknown).
RegistrationDecision AcceptRegistration(const RegistrationResult& r,
                                        const Eigen::Isometry3d& prior_X_MS, const IcpParams& icp,
                                        const RegistrationAcceptanceParams& policy,
                                        double prior_sigma);

/// Covariance (6 x 6, coordinates as RegistrationResult::information_matrix) of a registered
/// pose: in the directions the scan constrains, the inverse of its information there; in the
/// others (weak directions, and DoF the ICP does not estimate) the prior's covariance
/// `prior_cov` projected onto them, so the uncertainty of what the scan could not see is
/// carried on (Zhang et al. 2016's solution remapping applied to the covariance). A result
/// without information gives `prior_cov`.
Eigen::Matrix<double, 6, 6> RegistrationCovariance(const RegistrationResult& r,
                                                   const Eigen::Matrix<double, 6, 6>& prior_cov);

/// The accumulated target S(t-1) in the map frame: voxel-grid centroids (sums kept, so scans
/// added later refine the same cells), PCA normals (updated where cells changed) and a kd-tree
/// (rebuilt on every Add), plus per-scan direction-binned ranges for the free-space check.
class PointMap {
 public:
  /// Uses voxel_size, normal_neighbours, normal_radius of `params` (validated: InputError).
  explicit PointMap(const IcpParams& params = {});
  ~PointMap();
  PointMap(PointMap&&) noexcept;
  PointMap& operator=(PointMap&&) noexcept;
  PointMap(const PointMap&) = delete;
  PointMap& operator=(const PointMap&) = delete;

  /// Adds registered points (map frame); non-finite points are skipped. Records no free-space
  /// evidence (prefer the overload with the scan origin).
  void Add(const Points& points_M);
  /// Adds one registered scan taken from `origin_M` (the scanner centre in the map): also
  /// records its direction-binned nearest ranges for RegisterScan's free-space check.
  void Add(const Points& points_M, const Eigen::Vector3d& origin_M);
  /// Share of `points_M` that lie in space some added scan saw empty (see IcpParams).
  double FreeSpaceViolation(const Points& points_M) const;
  /// How many of `points_M` lie where some added scan could have seen them: in a direction
  /// bin where it had a return no nearer than the point (less free_space_margin plus 2 % of
  /// the range). Points beyond every scan's returns (new space, or hidden behind what the scans
  /// saw) or in bins without a return (inside the minimum range, outside the field of view) do
  /// not count. Only scans added with their origin count.
  std::size_t CountInView(const Points& points_M) const;
  bool has_origins() const;  ///< some scan was added with its origin
  bool empty() const;
  std::size_t size() const;
  const Points& points() const;  ///< voxel centroids, in voxel-key order
  const std::vector<Normal>& normals() const;
  /// Per point: the sum of unit vectors towards the origins of the scans that saw its cell
  /// (zero for points added without an origin).
  const std::vector<Eigen::Vector3f>& views() const;
  const KdTree3& tree() const;  ///< precondition: !empty()
  const IcpParams& params() const;
  /// The map's cells within `distance` (m) of some of `points_M` (map frame; and a few more:
  /// those in the same tiles of that edge), with their normals and views, and every scan's
  /// free-space evidence: what a registration near one scan needs.
  PointMap Local(const Points& points_M, double distance) const;
  /// Normals recomputed by the last Add (cells within normal_radius of a changed cell; the
  /// others keep theirs, which is exact: a normal only depends on points within that radius).
  std::size_t last_normals_recomputed() const;

 private:
  void AddCells(const Points& points_M, const Eigen::Vector3d* origin_M);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// m: RegisterScan registers against the map within this (besides the correspondence
/// distance) of the scan's points at its prior: the pairs, and so the result, are those of
/// the whole map while the correction moves no source point farther (room scans are corrected
/// by millimetres to centimetres).
inline constexpr double kLocalMapSlack = 1.0;

/// Refines `prior_X_MS` so that `source_S` (scanner frame) lies on `target` (see the file
/// comment). Throws InputError for bad params or a non-finite prior; an empty target or source
/// gives ok = false with a message.
RegistrationResult RegisterScan(const Points& source_S, const PointMap& target,
                                const Eigen::Isometry3d& prior_X_MS, const IcpParams& params);

/// Convenience for a whole scan: its valid returns within [min_range, max_range] of params,
/// from the prior scan.X_MS_estimate (the robot's odometry / localisation estimate).
RegistrationResult RegisterScan(const interfaces::TlsScan& scan, const PointMap& target,
                                const IcpParams& params);

}  // namespace mopad::perception
