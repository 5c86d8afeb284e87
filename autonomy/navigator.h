#pragma once
// The robot's brain for getting around (docs/navigation.md): it drives an
// interfaces::RobotPlatform and consumes only what crosses the robot boundary — wheel odometry,
// the two LRF sweeps, its own TLS scans — and returns its decisions through the platform
// (velocity commands, "scan here") and an explained status. It never sees the truth.
//
// What it owns: the obstacle map (rebuilt from the height band of all its scans, the LRF sweeps
// taken at scan positions, and those taken while driving), AMCL on the top LRF, the global
// planner and the local controller, scan registration (ICP against its earlier scans, through
// the one acceptance policy of perception/registration.h), and the scan-and-go leg policy:
//  - a goal plan is driven only as far as the map around it is well known and near the scans
//    (typically into the next doorway), then the robot scans again;
//  - MoPAD's two scans at a doorframe: one in front of a door passage, one just beyond it;
//  - a goal outside the known free space: drive to the frontier on the shortest estimated
//    route to it (autonomy/exploration.h) and scan there; look around once when that route
//    leaves the known space right behind the base;
//  - blocked or unreachable legs are planned again (re-legs) with what the LRFs added;
//  - every outcome is a DriveStatus with a one-line reason.
//
// Frames: map (M) := base_link at the first scan; poses are Pose2 (x, y, yaw) in M.
// Determinism: same platform behaviour + params + seed + call sequence -> same decisions.
// Not thread-safe; keeps a reference to the platform, which must outlive the navigator.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "autonomy/global_planner.h"
#include "autonomy/local_controller.h"
#include "common/frames.h"
#include "common/params.h"
#include "interfaces/robot_platform.h"
#include "interfaces/tls_scan.h"
#include "perception/amcl.h"
#include "perception/occupancy_grid.h"
#include "perception/range_bias.h"
#include "perception/registration.h"

namespace mopad::autonomy {

/// m, the ICP stages (IcpParams::max_correspondence) of a scan registered from AMCL's prior:
/// it is centimetres off, not odometry's decimetres, so no 1 m first stage, whose wide basin
/// let a hall scan slide 0.2 m along the corridor onto the next door frame.
inline const std::vector<double> kAmclPriorIcpStages = {0.3, 0.15, 0.08};

struct NavigatorParams {
  /// s of platform time one NavigateTo may take before `timeout` (from its call, not from the
  /// mission's start: a floor mission's drives add up past any one drive's bound), (0, 1e5]
  double max_time = 600.0;
  double tls_step_deg = 0.2;  ///< deg, angular step of the scans taken for maps, [0.05, 5]
  int max_scans = 20;         ///< TLS scans per NavigateTo, the mission's first included, [1, 100]
  double min_scan_progress = 0.1;  ///< m, a new scan target must be this much closer, (0, 10]
  double goal_known_radius =
      1.0;  ///< m, neighbourhood of the goal checked before the last leg, (0, 10]
  double goal_known_fraction = 0.85;  ///< mapped share of it needed to drive there directly, [0, 1]
  double scan_target_clearance = 0.55;  ///< m, clearance of scan-and-go targets, (0, 5]
  double doorway_margin = 0.1;  ///< m, scan stops keep this clearance beyond robot_radius, [0, 2]
  /// m along the path: entering space the map does not know well through a door passage, the
  /// robot scans this far beyond the passage (MoPAD's scan "after the doorframe", which still
  /// sees the room behind through the door and so registers against it). 0 = off. [0, 10]
  double door_exit_scan_distance = 0.8;
  /// m: a leg that reaches a door passage with no scan within this distance of the passage's
  /// near end stops in front of it (at least 0.6 m before, with a scan stop's clearance) and
  /// scans there: MoPAD's scan "before the doorframe". 0 = off. [0, 100]
  double door_entry_scan_distance = 3.0;
  /// m: a leg along a goal plan ends with a scan where the route gets farther than this from
  /// every scan position (AMCL tracks best where its map is complete, near the scans).
  /// Exploration legs are not cut by it. 0 = off. [0, 100]
  double max_distance_from_scans = 4.0;
  double frontier_exclusion =
      0.5;  ///< m, exploration targets this close to a scan position are spent, [0, 10]
  double scan_blind_radius = 0.5;  ///< m, around scan positions the map counts as known, [0, 10]
  double initial_sigma_xy = 0.01;  ///< m, AMCL's initial std after each scan, [1e-4, 10]
  double initial_sigma_yaw_deg = 0.5;  ///< deg, AMCL's initial yaw std after each scan, [1e-3, 180]
  double map_margin = 1.0;             ///< m, grid margin around the scanned points, [0, 20]
  std::uint64_t max_points_per_scan =
      400000;  ///< band points kept per scan (thinned beyond), [1, 1e9]
  /// s: while localised, both LRF sweeps go into the obstacle map this often (0: only those at
  /// scan positions), traced up to `map_lrf_range`, so obstacles the TLS saw edge-on (an open
  /// door leaf) appear before the base reaches them. [0, 100]
  double map_lrf_period = 0.5;
  double map_lrf_range = 4.0;  ///< m, (0, 100]
  /// Transient points: a scan's obstacle evidence in a map cell that a later scan saw through
  /// (its beams ran on more than `transient_margin` beyond the cell's lowest and highest band
  /// points), and the obstacles the driving sweeps mapped there, are dropped: someone walked
  /// on, or a door swung (perception/range_image.h). Off by default: with people walking it
  /// has not yet shown a gain beyond the seeds' spread (docs/navigation.md).
  bool transient_points = false;
  double transient_margin = 0.2;  ///< m, [0.01, 5]
  /// A leg that ends blocked or unreachable is planned again this many times per NavigateTo
  /// (first with a TLS scan there when the pose is new and the localisation matches). [0, 20]
  int max_relegs = 3;
  /// s: a NavigateTo whose estimated base visits no new 0.5 m cell for this long ends
  /// `blocked` ("no progress"). 0 = off. [0, 1e5]
  double stall_time = 60.0;
  /// Each TLS scan after the first is registered (`icp`) against the earlier scans, through
  /// `acceptance`, before it enters the map, and the pose estimate takes the registered pose.
  /// Missions that register scans themselves (the room scan) turn it off.
  bool register_scans = true;
  /// When the route to the goal leaves the known space right behind the base (the LRFs' rear
  /// gap; the TLS sees nothing within its minimum range), turn on the spot once, mapping the
  /// LRF sweeps, and plan again.
  bool look_around = true;
  double look_around_rate = 0.5;  ///< rad/s, turn rate of the look-around, (0, 3]
  /// m: scan stops in front of a door passage stand at least this far before it, [0, 5]
  double door_entry_standoff = 0.6;
  /// Cost per metre of a route through unknown or too narrow cells, relative to known free
  /// space, when choosing exploration targets (keeps routes in what the scans saw), [1, 100]
  double exploration_unknown_cost = 3.0;
  /// Each TLS scan's range offset, estimated from its floor and ceiling, is removed before the
  /// scan is used (perception/range_bias.h).
  perception::RangeBiasParams range_bias{};
  /// Registration of a scan just beyond a door (the door scans of register_scans).
  perception::IcpParams icp{
      .max_correspondence = kAmclPriorIcpStages,
      // Such a scan sees mostly new space: 0.15-0.3 of its points lie in the earlier scans, and
      // its registration is still right. The residual, free-space and conditioning checks and
      // the correction bound guard against a wrong pose.
      .min_fitness = 0.15,
      // Right registrations of a scan beyond a door reach violations of 0.007-0.008 (its new
      // room seen past the earlier scans' door-frame rays); poses 90 or 180 deg off give 0.012
      // and more.
      .max_free_space_violation = 0.01,
  };
  perception::RegistrationAcceptanceParams acceptance{};
  perception::OccupancyGridParams grid{};
  /// docs/navigation.md (localisation) has the measurements behind these values.
  perception::AmclParams amcl{
      .min_particles = 300,
      .max_particles = 3000,
      // The motion noise is sized to the odometry's error (about 1 % of the distance: radius
      // and track errors, slip) with margin.
      .odom_alpha1 = 0.02,
      .odom_alpha3 = 0.01,
      // Beams are not independent in the world: a wide hit sigma over few beams keeps the
      // weights from collapsing onto a handful of particles.
      .max_beams = 30,
      // Beams ending on wall faces the map lacks (the far side of a wall entered through its
      // door) must not pull the estimate back towards the mapped face.
      .unknown_endpoint_distance = 0.1,
      .sigma_hit = 0.2,
      // No random-particle injection while tracking: offices repeat (two equal rooms look
      // alike), and a random particle in the twin room can win one poor update. Real loss is
      // still caught by the inlier test, which starts a global re-localisation.
      .recovery_alpha_slow = 0.0,
      // The wide sigma keeps the filter robust; the precision comes from matching every beam
      // (perception/amcl.h, refinement).
      .refine = true,
  };
  GlobalPlannerParams planner{
      // The planner's disc is smaller than the 0.6 x 0.5 m box (half-diagonal 0.39 m); 3 cm
      // more than the library's keeps the corners off furniture the base LRF cannot see (desk
      // tops, kept in the map from the 3D scans) and still passes a 0.9 m door as mapped: its
      // jamb cells take up to a cell on each side, leaving a clearance of about 0.35-0.37 m.
      .robot_radius = 0.33,
      // A door whose mapped jambs (or an opened leaf beside them) leave 0.58-0.66 m is still
      // passable by the 0.5 m wide base aligned with it: its half-width plus the controller's
      // safety margin plus 1 cm.
      .narrow_radius = 0.29,
  };
  LocalControllerParams controller{
      // 3 cm around the box (not 6): a 0.5 m wide base keeps 0.17 m a side in a 0.9 m door,
      // enough for the docking error at a doorway scan position. Contacts are still counted by
      // the body.
      .safety_margin = 0.03,
  };
  bool trace = false;  ///< print plans and localisation to stderr every 50 steps (debugging)

  template <class V>
  void Visit(V& v) {
    v("trace", trace);
    v("max_time", max_time, Bounds{1e-3, 1e5});
    v("tls_step_deg", tls_step_deg, Bounds{0.05, 5.0});
    v("max_scans", max_scans, Bounds{1, 100});
    v("min_scan_progress", min_scan_progress, Bounds{1e-3, 10.0});
    v("goal_known_radius", goal_known_radius, Bounds{0.05, 10.0});
    v("goal_known_fraction", goal_known_fraction, Bounds{0.0, 1.0});
    v("scan_target_clearance", scan_target_clearance, Bounds{1e-3, 5.0});
    v("doorway_margin", doorway_margin, Bounds{0.0, 2.0});
    v("door_exit_scan_distance", door_exit_scan_distance, Bounds{0.0, 10.0});
    v("door_entry_scan_distance", door_entry_scan_distance, Bounds{0.0, 100.0});
    v("max_distance_from_scans", max_distance_from_scans, Bounds{0.0, 100.0});
    v("frontier_exclusion", frontier_exclusion, Bounds{0.0, 10.0});
    v("scan_blind_radius", scan_blind_radius, Bounds{0.0, 10.0});
    v("initial_sigma_xy", initial_sigma_xy, Bounds{1e-4, 10.0});
    v("initial_sigma_yaw_deg", initial_sigma_yaw_deg, Bounds{1e-3, 180.0});
    v("map_margin", map_margin, Bounds{0.0, 20.0});
    v("max_points_per_scan", max_points_per_scan, Bounds{1.0, 1e9});
    v("map_lrf_period", map_lrf_period, Bounds{0.0, 100.0});
    v("map_lrf_range", map_lrf_range, Bounds{1e-3, 100.0});
    v("transient_points", transient_points);
    v("transient_margin", transient_margin, Bounds{0.01, 5.0});
    v("max_relegs", max_relegs, Bounds{0, 20});
    v("stall_time", stall_time, Bounds{0.0, 1e5});
    v("register_scans", register_scans);
    v("look_around", look_around);
    v("look_around_rate", look_around_rate, Bounds{1e-3, 3.0});
    v("door_entry_standoff", door_entry_standoff, Bounds{0.0, 5.0});
    v("exploration_unknown_cost", exploration_unknown_cost, Bounds{1.0, 100.0});
    v("range_bias", range_bias);
    v("icp", icp);
    v("registration_acceptance", acceptance);
    v("occupancy_grid", grid);
    v("amcl", amcl);
    v("global_planner", planner);
    v("local_controller", controller);
  }
};

/// How a NavigateTo ended.
enum class DriveStatus { kArrived, kUnreachable, kBlocked, kLocalisationLost, kTimeout };
const char* ToString(DriveStatus s);

struct TrajectorySample {
  double t = 0.0;  ///< s, platform time
  Pose2 pose;      ///< base_link in map
};

/// What the navigator did and decided (robot side only: no truth).
struct NavigatorLog {
  DriveStatus status = DriveStatus::kTimeout;
  std::string message;
  std::vector<TrajectorySample> estimated;  ///< estimate after every step (and at the first scan)
  std::vector<std::vector<Pose2>> plans;    ///< every global plan followed (map frame)
  std::vector<Pose2> scan_poses;            ///< estimated base poses of the TLS scans (map)
  Pose2 goal_M;                             ///< the last NavigateTo's goal
  int tls_scans = 0, amcl_updates = 0, replans = 0, lost_events = 0;
  /// TLS scans registered by ICP (register_scans): accepted, used degenerate, refused.
  int scan_registrations_ok = 0, scan_registrations_degenerate = 0, scan_registrations_failed = 0;
  std::vector<std::string> scan_registration_messages;  ///< one line per registered scan
};

class Navigator {
 public:
  /// Throws InputError for invalid params. Nothing happens until the first TakeScan.
  Navigator(interfaces::RobotPlatform& platform, const NavigatorParams& params, std::uint64_t seed);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// Stops and takes one TLS scan here (params.tls_step_deg, or `step_deg_override` when > 0),
  /// stamped with the pose estimate (registered first when register_scans); its band points
  /// go into the obstacle map, AMCL restarts about the estimate, and the base stands still for
  /// the scan's duration. The reference stays valid until the next TakeScan.
  const interfaces::TlsScan& TakeScan(double step_deg_override = 0.0);
  const interfaces::TlsScan& LastScan() const;  ///< empty before the first
  /// The range offset estimated for LastScan (removed from it when ok).
  const perception::RangeBiasEstimate& LastRangeBias() const;
  /// After the caller refined the last scan's pose (e.g. its own ICP): re-stamps its map
  /// points with `X_MS` (scanner in map), rebuilds the map and re-seeds AMCL around the
  /// corresponding base pose (odometry offset since the scan kept). InputError before any scan.
  /// `extra_cov` (x, y, yaw; m^2, rad^2) is added to AMCL's initial covariance at the re-seed:
  /// the uncertainty the correction could not remove (a registration's weak directions, whose
  /// prior it kept), carried on to the next prior.
  void CorrectLastScanPose(const Pose3& X_MS,
                           const Eigen::Matrix3d& extra_cov = Eigen::Matrix3d::Zero());
  /// Makes every later map cover `p_M` (e.g. a far goal), so the planner can reason about it.
  void ExtendMap(const Vec2& p_M);
  /// Drives to `goal_M` with the full stack and scan-and-go within params limits. Returns the
  /// explained outcome (Log().message has the one-line reason). InputError before any scan.
  DriveStatus NavigateTo(const Pose2& goal_M);

  Pose2 EstimatedPose() const;                                   ///< base_link in map
  const perception::LocalisationEstimate& Localisation() const;  ///< AMCL health
  const perception::OccupancyGrid& Map() const;                  ///< current obstacle map
  int ScanCount() const;                                         ///< TLS scans taken
  double Time() const;                                           ///< s, the platform clock
  const NavigatorParams& Params() const;
  const NavigatorLog& Log() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::autonomy
