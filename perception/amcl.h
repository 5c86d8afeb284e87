#pragma once
// AMCL-style localisation of the base in the obstacle map from wheel odometry and a 2D LRF
// (paper §3.1 step (2): "matches it with the readings of a 2D laser range finder, by means of
// an Adaptive Monte-Carlo Localization algorithm").
//
// Algorithms, after Thrun, Burgard & Fox, *Probabilistic Robotics* (2005):
// - motion: sample_motion_model_odometry (Table 5.6), noise std sqrt(a1 rot^2 + a2 trans^2)
//   etc. as in ROS amcl, with the reverse-driving correction of ROS amcl;
// - measurement: likelihood_field_range_finder_model (Table 6.3) over a precomputed distance
//   field of the map (d = distance to the mean return position inside the nearest obstacle
//   cell, so a 5 cm grid adds no half-cell bias), mixture
//   z_hit * N(d; 0, sigma_hit) + z_rand / range_max;
//   max-range readings are skipped; log-domain weights;
// - resampling: low-variance sampler (Table 4.4) whenever N_eff falls below a fraction of N,
//   with the particle count chosen by KLD sampling (Fox 2003; Table 8.4) over (x, y, yaw) bins;
// - recovery: Augmented MCL (Table 8.3): short- and long-term averages w_fast / w_slow of the
//   per-beam measurement likelihood inject uniform free-space particles with probability
//   max(0, 1 - w_fast / w_slow);
// - health: weighted pose, covariance, effective particle count N_eff = 1 / sum(w^2), and the
//   ratio of beams whose endpoint lies within `inlier_distance` of a mapped obstacle at the
//   estimate, among the beams ending in mapped space (unknown space is no evidence; with too
//   few such beams the update is inconclusive). `lost_updates` consecutive updates below
//   `lost_inlier_ratio` declare the filter lost (status kLost in that update) and, if enabled,
//   start global re-localisation;
// - global (re-)localisation: uniform particles over free space do not reliably find the right
//   mode in symmetric buildings, so the next scan is first matched exhaustively (correlative
//   search: every free position on a `global_search_step` lattice x every
//   `global_search_yaw_deg`, likelihood-field score with `global_sigma_hit`), and the particles
//   are seeded around the `global_hypotheses` best poses after non-maximum suppression; the
//   filter then tells the hypotheses apart as the base moves, with the wider sigma, until the
//   estimate has converged for `relocalisation_min_updates` updates.
// - refinement (`refine`, off by default): the particle filter is robust but, with a wide hit
//   sigma over a few beams, imprecise where only a few beams carry the information (the end
//   wall of a corridor, the jambs of a doorway). After each tracking update the estimate is
//   refined by a point-to-line Gauss-Newton match of all the sweep's beams that end near a
//   mapped return (the same segments as the likelihood field, Huber-weighted; a beam that ends
//   in unknown space away from a return at the filter's estimate stays out, however near a
//   return the moving pose brings it), corrected only along the directions the matched beams
//   constrain (eigenvalues of J^T J, in beams' worth; a corridor without a visible end wall
//   stays as the filter has it), a beam paired only with a mapped surface facing its way (the
//   normals within `refine_max_normal_angle_deg`: an unmapped reveal is not matched to the
//   wall face beside it), and accepted only when it is small, lowers the robust cost of
//   the beams matched before and after, and has enough of them; the whole particle set is then
//   moved rigidly so the filter carries the correction on.
//
// Frames (REP-105): particles are poses of base_link in `map`; odometry gives base_link in
// `odom`; the scan's X_BL (its mount on base_link) is projected to the plane.
// Determinism: every random draw comes from CounterRng keyed by (seed, stream, update index,
// particle index), and per-particle work is independent, so the particle set is the same bytes
// whatever the number of TBB threads. Not thread-safe: one filter per thread of control.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/lrf_scan.h"
#include "interfaces/odometry.h"
#include "perception/occupancy_grid.h"

namespace mopad::perception {

/// a ∘ b: the pose b expressed in a's parent frame (e.g. X_MB = Compose(X_MO, X_OB)).
Pose2 Compose(const Pose2& a, const Pose2& b);
/// Inverse of a planar pose.
Pose2 Inverse(const Pose2& a);

struct AmclParams {
  int min_particles = 500;         ///< count, [10, max_particles]
  int max_particles = 5000;        ///< count, [min_particles, 200000]
  double kld_err = 0.05;           ///< KLD bound epsilon, (0, 1)
  double kld_z = 2.33;             ///< upper standard normal quantile z_(1-delta), (0, 5]
  double bin_size_xy = 0.2;        ///< m, KLD histogram bin, (0, 5]
  double bin_size_yaw_deg = 10.0;  ///< deg, KLD histogram bin, (0, 180]
  double odom_alpha1 = 0.05;       ///< rotation noise from rotation, [0, 10]
  double odom_alpha2 = 0.01;       ///< rotation noise from translation, [0, 10]
  double odom_alpha3 = 0.05;       ///< translation noise from translation, [0, 10]
  double odom_alpha4 = 0.01;       ///< translation noise from rotation, [0, 10]
  int max_beams = 60;              ///< beams used per scan, evenly spaced, [2, 10000]
  double z_hit = 0.9;              ///< mixture weight of the Gaussian hit term, (0, 1]
  double z_rand = 0.1;             ///< mixture weight of the uniform term, [0, 1]
  /// A beam ending in an unknown cell (a wall face the map has not seen yet, e.g. the far side
  /// of a wall entered through its door) is scored as if this far (m) from an obstacle, not by
  /// its distance to the nearest mapped one, which would pull the estimate towards poses that
  /// put it on a mapped face (the wall's other face, a thickness away); unless it ends within a
  /// cell of a return. 0 = off (plain likelihood field). [0, 5]
  double unknown_endpoint_distance = 0.0;
  double sigma_hit = 0.05;             ///< m, std of the hit term while tracking, (0, 5]
  double global_sigma_hit = 0.2;       ///< m, std of the hit term while re-localising, (0, 5]
  double likelihood_max_dist = 2.0;    ///< m, distance field cap, (0, 100]
  double update_min_d = 0.05;          ///< m, odometry travel that triggers an update, [0, 10]
  double update_min_a_deg = 3.0;       ///< deg, odometry rotation that triggers an update, [0, 180]
  double resample_neff_ratio = 0.5;    ///< resample when N_eff < ratio * N, [0, 1]
  double recovery_alpha_slow = 0.001;  ///< Augmented MCL long-term rate, [0, 1]
  double recovery_alpha_fast = 0.1;    ///< Augmented MCL short-term rate, [0, 1]
  double inlier_distance = 0.1;        ///< m, endpoint-to-map distance of a matching beam, (0, 5]
  double lost_inlier_ratio = 0.5;      ///< below this the update counts as bad, [0, 1]
  /// The inlier ratio counts only beams ending in mapped (known) cells; with fewer than this
  /// share of all beams there the update is inconclusive (neither bad nor good), [0, 1]
  double min_mapped_beam_fraction = 0.25;
  int lost_updates = 3;                ///< consecutive bad updates that declare loss, [1, 1000]
  bool relocalise_when_lost = true;    ///< start global re-localisation on loss
  double global_min_clearance = 0.2;   ///< m, clearance of uniformly drawn poses, [0, 5]
  double global_search_step = 0.1;     ///< m, position lattice of the global search, (0, 5]
  double global_search_yaw_deg = 5.0;  ///< deg, yaw step of the global search, (0, 90]
  int global_search_beams = 30;        ///< beams scored per candidate pose, [2, 1000]
  int global_hypotheses = 20;          ///< best distinct poses seeded with particles, [1, 1000]
  int relocalisation_min_updates = 3;  ///< updates before a re-localisation may converge, [1, 1000]
  double converged_sigma_xy = 0.1;     ///< m, position std for "localised", (0, 10]
  double converged_sigma_yaw_deg = 5.0;  ///< deg, yaw std for "localised", (0, 180]
  double cluster_radius = 0.5;           ///< m, particles within this of the mode form the estimate
  double cluster_angle_deg = 30.0;       ///< deg, idem for yaw
  bool refine = false;                   ///< scan-matching refinement while tracking (above)
  int refine_max_beams = 1080;           ///< beams matched per sweep, evenly spaced, [10, 100000]
  double refine_gate =
      0.25;  ///< m, beams ending farther from a mapped return are unmatched, (0, 2]
  double refine_huber = 0.05;  ///< m, Huber threshold of the match's residuals, (0, 1]
  /// m, smallest and largest neighbourhood radius of a sweep's surface normal at a beam's
  /// endpoint (the match measures each beam along it), (0, 2]
  double refine_normal_radius = 0.1;
  double refine_normal_max_radius = 0.4;
  int refine_iterations = 10;  ///< Gauss-Newton steps, [1, 100]
  /// Information (in beams' worth: sum over matched beams of (normal . direction)^2, rotation
  /// measured as the displacement 1 m from the base) a direction needs to be corrected along.
  double refine_min_constraint = 15.0;  ///< [1, 1e6]
  int refine_min_beams = 40;            ///< matched beams needed to apply a refinement, [3, 100000]
  double refine_max_shift = 0.2;        ///< m, larger corrections are refused, (0, 5]
  double refine_max_turn_deg = 5.0;     ///< deg, idem for yaw, (0, 90]
  /// deg, largest angle between a beam's surface normal in the sweep and the mapped surface's
  /// normal at its nearest return for the two to be matched: a correspondence pairs the same
  /// surface, whose two normal estimates (the sweep's line fit, the map cell's returns) agree
  /// to a few tens of degrees, while a face the map has not seen (a door reveal across a
  /// wall) meets the wall's returns at about 90 deg. Where the map's returns in the cell are
  /// no line (a point), no orientation is known and the beam is matched on distance alone. (0, 90]
  double refine_max_normal_angle_deg = 45.0;

  template <class V>
  void Visit(V& v) {
    v("min_particles", min_particles, Bounds{10, 200000});
    v("max_particles", max_particles, Bounds{10, 200000});
    v("kld_err", kld_err, Bounds{1e-6, 1.0 - 1e-6});
    v("kld_z", kld_z, Bounds{1e-6, 5.0});
    v("bin_size_xy", bin_size_xy, Bounds{1e-3, 5.0});
    v("bin_size_yaw_deg", bin_size_yaw_deg, Bounds{1e-3, 180.0});
    v("odom_alpha1", odom_alpha1, Bounds{0.0, 10.0});
    v("odom_alpha2", odom_alpha2, Bounds{0.0, 10.0});
    v("odom_alpha3", odom_alpha3, Bounds{0.0, 10.0});
    v("odom_alpha4", odom_alpha4, Bounds{0.0, 10.0});
    v("max_beams", max_beams, Bounds{2, 10000});
    v("z_hit", z_hit, Bounds{1e-6, 1.0});
    v("z_rand", z_rand, Bounds{0.0, 1.0});
    v("sigma_hit", sigma_hit, Bounds{1e-4, 5.0});
    v("global_sigma_hit", global_sigma_hit, Bounds{1e-4, 5.0});
    v("likelihood_max_dist", likelihood_max_dist, Bounds{1e-3, 100.0});
    v("update_min_d", update_min_d, Bounds{0.0, 10.0});
    v("update_min_a_deg", update_min_a_deg, Bounds{0.0, 180.0});
    v("resample_neff_ratio", resample_neff_ratio, Bounds{0.0, 1.0});
    v("recovery_alpha_slow", recovery_alpha_slow, Bounds{0.0, 1.0});
    v("recovery_alpha_fast", recovery_alpha_fast, Bounds{0.0, 1.0});
    v("inlier_distance", inlier_distance, Bounds{1e-4, 5.0});
    v("unknown_endpoint_distance", unknown_endpoint_distance, Bounds{0.0, 5.0});
    v("lost_inlier_ratio", lost_inlier_ratio, Bounds{0.0, 1.0});
    v("min_mapped_beam_fraction", min_mapped_beam_fraction, Bounds{0.0, 1.0});
    v("lost_updates", lost_updates, Bounds{1, 1000});
    v("relocalise_when_lost", relocalise_when_lost);
    v("global_min_clearance", global_min_clearance, Bounds{0.0, 5.0});
    v("global_search_step", global_search_step, Bounds{1e-3, 5.0});
    v("global_search_yaw_deg", global_search_yaw_deg, Bounds{1e-2, 90.0});
    v("global_search_beams", global_search_beams, Bounds{2, 1000});
    v("global_hypotheses", global_hypotheses, Bounds{1, 1000});
    v("relocalisation_min_updates", relocalisation_min_updates, Bounds{1, 1000});
    v("converged_sigma_xy", converged_sigma_xy, Bounds{1e-4, 10.0});
    v("converged_sigma_yaw_deg", converged_sigma_yaw_deg, Bounds{1e-3, 180.0});
    v("cluster_radius", cluster_radius, Bounds{1e-3, 100.0});
    v("cluster_angle_deg", cluster_angle_deg, Bounds{1e-3, 180.0});
    v("refine", refine);
    v("refine_max_beams", refine_max_beams, Bounds{10, 100000});
    v("refine_gate", refine_gate, Bounds{1e-3, 2.0});
    v("refine_huber", refine_huber, Bounds{1e-4, 1.0});
    v("refine_normal_radius", refine_normal_radius, Bounds{1e-3, 2.0});
    v("refine_normal_max_radius", refine_normal_max_radius, Bounds{1e-3, 2.0});
    v("refine_iterations", refine_iterations, Bounds{1, 100});
    v("refine_min_constraint", refine_min_constraint, Bounds{1.0, 1e6});
    v("refine_min_beams", refine_min_beams, Bounds{3, 100000});
    v("refine_max_shift", refine_max_shift, Bounds{1e-3, 5.0});
    v("refine_max_turn_deg", refine_max_turn_deg, Bounds{1e-3, 90.0});
    v("refine_max_normal_angle_deg", refine_max_normal_angle_deg, Bounds{1e-3, 90.0});
  }
  /// ValidateParams plus cross-field checks (min <= max particles); throws InputError.
  void Validate() const;
};

enum class LocalisationStatus {
  kNotInitialised,  ///< no initial pose yet
  kLocalised,       ///< converged and the scan matches the map
  kUncertain,       ///< tracking, but spread or scan match is not yet good enough
  kLost,            ///< loss detected in this update (re-localisation started if enabled)
  kRelocalising,    ///< global re-localisation under way
};
const char* ToString(LocalisationStatus s);

struct LocalisationEstimate {
  LocalisationStatus status = LocalisationStatus::kNotInitialised;
  std::string message;  ///< why the status is what it is, for logs and summaries
  Pose2 X_MB;           ///< base_link in map at the last filter update
  Pose2 X_MO;           ///< odom in map: X_MB = Compose(X_MO, X_OB)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< (x, y, yaw) about X_MB; m^2, rad^2
  double n_eff = 0.0;                                    ///< effective particle count, 1 / sum(w^2)
  int particles = 0;                                     ///< current particle count
  double inlier_ratio = 0.0;          ///< fraction of beams matching the map at X_MB, [0, 1]
  double w_slow = 0.0, w_fast = 0.0;  ///< Augmented MCL likelihood averages (per beam)
  /// The last update's refinement (params.refine): applied, and the correction it made
  /// (x, y in m, yaw in rad, map frame) — zero when not applied.
  bool refined = false;
  Pose2 refinement{};
  std::uint64_t updates = 0;  ///< filter updates so far
  double timestamp = 0.0;     ///< s, odometry time of the last update
  /// Current pose estimate for a newer odometry reading (odometry between filter updates).
  Pose2 PoseAt(const Pose2& X_OB) const { return Compose(X_MO, X_OB); }
};

struct Particle {
  double x = 0.0, y = 0.0, yaw = 0.0;  ///< base_link in map: m, m, rad
  double weight = 0.0;                 ///< normalised
};

/// Result of one call to Update.
struct AmclUpdateResult {
  bool updated = false;  ///< a filter update ran (enough motion, or forced)
  bool resampled = false;
  bool lost_detected = false;  ///< loss declared in this update
};

class Amcl {
 public:
  /// The map is copied into a likelihood field (occupied cells are obstacles); throws
  /// InputError for invalid params.
  Amcl(const OccupancyGrid& map, const AmclParams& params, std::uint64_t seed);
  ~Amcl();
  Amcl(const Amcl&) = delete;
  Amcl& operator=(const Amcl&) = delete;
  Amcl(Amcl&&) noexcept;
  Amcl& operator=(Amcl&&) noexcept;

  /// Gaussian particles about `X_MB` (map) with covariance `cov` over (x, y, yaw).
  void SetInitialPose(const Pose2& X_MB, const Eigen::Matrix3d& cov);
  /// Global localisation: uniform particles over free space (clearance >=
  /// global_min_clearance) at once, replaced at the next Update by particles seeded from the
  /// correlative search of that scan (see the class comment); status kRelocalising until
  /// converged.
  void StartGlobalLocalisation();

  /// Feeds one odometry reading and the scan taken at the same time. The filter updates when
  /// the odometry moved by update_min_d / update_min_a since the last update, on the first scan
  /// after (re)initialisation, or when `force`.
  AmclUpdateResult Update(const interfaces::Odometry& odom, const interfaces::LrfScan& scan,
                          bool force = false);

  const LocalisationEstimate& Estimate() const { return estimate_; }
  const std::vector<Particle>& Particles() const { return particles_; }
  const AmclParams& Params() const { return params_; }

 private:
  struct Impl;
  void SeedFromGlobalSearch(const std::vector<Vec2>& beams_B, double range_max,
                            std::uint64_t update);
  // The steps of Update (Probabilistic Robotics: Table 5.6 motion, Table 6.3 likelihood field,
  // Table 8.4 KLD resampling; Augmented MCL for injection).
  void MotionUpdate(const Pose2& last, const Pose2& cur, std::uint64_t update);
  /// Up to `max_beams` (default params.max_beams) evenly spaced valid returns in base_link.
  std::vector<Vec2> SelectBeams(const interfaces::LrfScan& scan, int max_beams = 0) const;
  /// Weights from the likelihood field; returns N_eff. Updates w_slow / w_fast.
  double MeasurementUpdate(const std::vector<Vec2>& beams_B, const interfaces::LrfScan& scan);
  std::int64_t BinKey(const Particle& q) const;
  /// Weighted mean of the cluster around the heaviest KLD bin; `cov` of the whole set about it.
  Pose2 ClusterEstimate(Eigen::Matrix3d* cov) const;
  /// Beams (base_link) at X_MB ending near an obstacle, among those ending in mapped space.
  void CountInliers(const std::vector<Vec2>& beams_B, const Pose2& X_MB, int* inliers,
                    int* mapped_beams) const;
  void Resample(std::uint64_t update, double p_inject);
  /// Scan-matching refinement of `X_MB` (see the class comment); returns false, leaving it,
  /// when the match is refused.
  bool Refine(const interfaces::LrfScan& scan, Pose2* X_MB) const;
  /// Update's step 4b: while tracking (refine on, not re-localising, beams in the scan), moves
  /// `X_MB` and the whole set rigidly by Refine's correction and rotates `cov` with it; records
  /// the correction in the estimate.
  void RefineEstimate(const interfaces::LrfScan& scan, bool have_beams, Pose2* X_MB,
                      Eigen::Matrix3d* cov);
  std::unique_ptr<Impl> impl_;
  AmclParams params_;
  std::uint64_t seed_;
  std::vector<Particle> particles_;
  LocalisationEstimate estimate_;
};

}  // namespace mopad::perception
