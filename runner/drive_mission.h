#pragma once
// The closed loop of `mopad drive` (issue 4): the one place where the world (scenes, sim) and
// the robot (perception, autonomy) meet (STYLE.md §1). Only plain interface values cross:
// TlsScan, LrfScan, Odometry, VelocityCommand.
//
// Loop (simulation time, fixed `control_dt` steps; no algorithm reads the wall clock):
//  1. TLS scan at the start. map frame := the robot's start pose (base_link at t = 0), so the
//     first scan is registered with the identity; later scans with the AMCL estimate. The
//     obstacle map is rebuilt from the height band of all the robot's scans (never from the
//     truth geometry).
//  2. Each step: body step under the last command -> drifting wheel odometry; base and top LRF
//     sweeps at their profile rates; AMCL on the top LRF; LocalController on the base LRF;
//     GlobalPlanner (with LRF obstacles) for plans and replans.
//  3. Scan-and-go: a goal plan is driven only as far as the map around it is well known
//     (typically into the next doorway), then the robot scans again; a goal outside the known
//     free space: drive to the reachable point nearest to it and scan. No progress (or
//     `max_scans` spent) ends in `unreachable`.
//  4. Ends with an explained status: arrived, unreachable, blocked, localisation_lost, timeout.
//
// Truth is read only here: the body's true pose for the true trajectory and the evaluation
// figures (expressed in the map frame: X_MW = X_WB(0)^-1).
// Determinism: same world + params + request (seed) -> same trajectories (bytes).

#include <cstdint>
#include <string>
#include <vector>

#include "autonomy/global_planner.h"
#include "autonomy/local_controller.h"
#include "common/frames.h"
#include "common/params.h"
#include "perception/amcl.h"
#include "perception/occupancy_grid.h"
#include "perception/registration.h"
#include "sim/embree_world.h"
#include "sim/robot_body.h"

namespace mopad::runner {

struct DriveParams {
  double control_dt = 0.02;        ///< s, physics/control step, [0.001, 0.2]
  double max_time = 600.0;         ///< s of simulation time before `timeout`, (0, 1e5]
  std::string lrf_profile = "hokuyo_utm30lx";  ///< profile of both LRFs (sim/lrf.h)
  std::string tls_profile = "riegl_vz400";     ///< TLS profile (sim/tls_params.h)
  double tls_step_deg = 0.2;       ///< deg, TLS angular step used for obstacle maps, [0.05, 5]
  int max_scans = 20;              ///< TLS scans per mission (scan-and-go), [1, 100]
  double min_scan_progress = 0.1;  ///< m, a new scan target must be this much closer, (0, 10]
  double goal_known_radius = 1.0;    ///< m, neighbourhood of the goal checked before the last leg
  double goal_known_fraction = 0.85; ///< mapped share of it needed to drive there directly, [0, 1]
  double scan_target_clearance = 0.55; ///< m, clearance of scan-and-go targets, (0, 5]
  double doorway_margin = 0.1;       ///< m, scan stops keep this clearance beyond robot_radius, [0, 2]
  /// Entering space the map does not know well through a door passage, the robot scans this
  /// far (m, along the path) beyond the passage, as MoPAD scans "one before and one after the
  /// doorframe": that scan still sees the room behind through the door and registers against
  /// it, where a scan deep in the new room sees almost nothing the map has (office_5rooms R1:
  /// ICP fitness 0.18, refused at the then 0.3 limit, and its AMCL pose became the room's
  /// map). 0 = off. [0, 10]
  double door_exit_scan_distance = 0.8;
  /// The first of MoPAD's two scans at a doorframe: a leg that reaches a door passage with no
  /// scan within this distance (m) of the passage's near end stops in front of it (at least
  /// 0.6 m before it, with a scan stop's clearance) and scans there, so that the scan after
  /// the doorframe finds the door's surroundings mapped from close by (office_5rooms seed 2:
  /// the room's only scan 6.7 m away, and the scan beyond the door registered 0.3 deg and
  /// 2.7 cm off along the hall, which the hall's map then carried). 0 = off. [0, 100]
  double door_entry_scan_distance = 3.0;
  /// A leg along a goal plan ends with a scan where the route gets farther than this from
  /// every scan position (m; 0 = off): AMCL tracks best where the map is complete, near the
  /// scans. Exploration legs are not cut by it (cut there, their scan stops fell inside
  /// doorways, where the next plan found no way out; office_5rooms seeds 6 and 10). [0, 100]
  double max_distance_from_scans = 4.0;
  double frontier_exclusion = 0.5;   ///< m, exploration targets this close to a scan position are spent, [0, 10]
  double scan_blind_radius = 0.5;    ///< m, around scan positions the map counts as known, [0, 10]
  double initial_sigma_xy = 0.01;  ///< m, AMCL initial std (the map is built at the start)
  double initial_sigma_yaw_deg = 0.5;  ///< deg, AMCL initial std
  double map_margin = 1.0;         ///< m, grid margin around the scanned points, [0, 20]
  std::uint64_t max_points_per_scan = 400000;  ///< cap of band points kept per scan
  /// The base stands still for the TLS scan's duration (pulses / pulse rate of the profile);
  /// false: scans take no simulation time (the behaviour before; tests of pure navigation).
  bool tls_scan_takes_time = true;
  /// While driving (localised), both LRF sweeps go into the obstacle map every this many
  /// seconds (0: only those at scan positions), traced up to `map_lrf_range`: obstacles the
  /// TLS saw edge-on (an open door leaf) appear before the base reaches them. They never
  /// clear cells with 3D band evidence (occupancy_grid.lrf_clears_cloud_obstacles). [0, 100]
  double map_lrf_period = 0.5;
  double map_lrf_range = 4.0;  ///< m, (0, 100]
  /// A leg that ends blocked or unreachable is planned again this many times per NavigateTo
  /// (with the LRF evidence now in the map; first a TLS scan there when the pose is new and the
  /// localisation matches) before the mission gives up. [0, 20]
  int max_relegs = 3;
  /// s of simulation time; a NavigateTo whose base (estimate) visits no new 0.5 m cell for this
  /// long ends `blocked` ("no progress"): replans and re-legs that send it back and forth
  /// between the same places (seen: 8 round trips in a room until the 600 s limit). 0 = off.
  /// [0, 1e5]
  double stall_time = 60.0;
  /// Each TLS scan after the first is registered (point-to-plane ICP, `icp`) against the
  /// robot's earlier scans before it enters the obstacle map, and the pose estimate is reset to
  /// the registered one; without it a scan is placed with the AMCL estimate of the moment and
  /// its error is baked into the map that AMCL then tracks against. A registration that fails
  /// leaves the AMCL pose (counted in `scan_registrations_failed`). A result that is
  /// degenerate only (a corridor: the weak direction keeps the prior, ICP froze it) but
  /// otherwise fits is used. Missions that register scans themselves (the room mission) turn
  /// it off.
  bool register_scans = true;
  /// When the route to the goal leaves the known space right behind the base (the LRFs' rear
  /// gap; the TLS sees nothing within 1.5 m), turn on the spot once, mapping the LRF sweeps,
  /// and plan again, rather than end `unreachable` with "no progress".
  bool look_around = true;
  perception::IcpParams icp = DefaultIcp();
  /// A registration that moves the scan further than this from its AMCL prior (m, or
  /// `max_registration_correction_deg` in yaw) is refused: AMCL is good to a few centimetres
  /// while localised, so a larger jump is ICP sliding into a neighbouring minimum (periodic
  /// door frames along a corridor). [0, 10]
  double max_registration_correction = 0.1;
  double max_registration_correction_deg = 2.0;  ///< deg, [0, 180]
  /// The position correction of a degenerate registration (a corridor) must also be within
  /// this many AMCL standard deviations (largest of its x-y covariance at the scan), but at
  /// least `min_registration_gate`: a hall scan that ICP moved 8.3 cm along the corridor while
  /// AMCL, good to 1-3 cm (sigma 1.1 cm), was right (office_5rooms, seed 10). 0 = only the
  /// fixed bound. [0, 100]
  double registration_gate_sigmas = 3.0;
  double min_registration_gate = 0.03;  ///< m, [0, 10]
  /// A registration that constrains every direction and passes every other check, but whose
  /// last stage ran out of iterations still creeping by less than this many times the ICP
  /// step thresholds, counts as converged (office_5rooms seed 7: the scan beyond D1 crept
  /// 13 um per iteration after 30; refused, its AMCL yaw, 0.9 deg off, turned R1's map about
  /// the door). 0 = off; degenerate results never. [0, 1000]
  double creeping_step_factor = 10.0;
  /// A registration that constrains every direction is bounded by max_registration_correction
  /// alone (false: the sigma gate applies to every registration, as before 2026-11-24). AMCL
  /// drifts 10-20 cm in door passages while reporting a sigma of 1-2 cm; the scan beyond the
  /// door (door_exit_scan_distance) registers onto the truth, and the sigma gate refused it.
  bool trust_constrained_registration = true;

  sim::RobotBodyParams body = DefaultBody();
  perception::OccupancyGridParams grid;
  perception::AmclParams amcl = DefaultAmcl();
  autonomy::GlobalPlannerParams planner = DefaultPlanner();
  autonomy::LocalControllerParams controller = DefaultController();
  bool trace = false;  ///< print plans and localisation to stderr every 50 steps (debugging)

  static sim::RobotBodyParams DefaultBody();
  static perception::AmclParams DefaultAmcl();
  static autonomy::GlobalPlannerParams DefaultPlanner();
  static autonomy::LocalControllerParams DefaultController();
  static perception::IcpParams DefaultIcp();

  template <class V>
  void Visit(V& v) {
    v("control_dt", control_dt, Bounds{0.001, 0.2});
    v("trace", trace);
    v("max_time", max_time, Bounds{1e-3, 1e5});
    v("lrf_profile", lrf_profile);
    v("tls_profile", tls_profile);
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
    v("tls_scan_takes_time", tls_scan_takes_time);
    v("map_lrf_period", map_lrf_period, Bounds{0.0, 100.0});
    v("map_lrf_range", map_lrf_range, Bounds{1e-3, 100.0});
    v("max_relegs", max_relegs, Bounds{0, 20});
    v("stall_time", stall_time, Bounds{0.0, 1e5});
    v("register_scans", register_scans);
    v("look_around", look_around);
    v("icp", icp);
    v("max_registration_correction", max_registration_correction, Bounds{0.0, 10.0});
    v("max_registration_correction_deg", max_registration_correction_deg, Bounds{0.0, 180.0});
    v("registration_gate_sigmas", registration_gate_sigmas, Bounds{0.0, 100.0});
    v("min_registration_gate", min_registration_gate, Bounds{0.0, 10.0});
    v("creeping_step_factor", creeping_step_factor, Bounds{0.0, 1000.0});
    v("trust_constrained_registration", trust_constrained_registration);
    v("body", body);
    v("occupancy_grid", grid);
    v("amcl", amcl);
    v("global_planner", planner);
    v("local_controller", controller);
  }
};

enum class DriveStatus { kArrived, kUnreachable, kBlocked, kLocalisationLost, kTimeout };
const char* ToString(DriveStatus s);

struct DriveRequest {
  Pose2 X_WB_start;          ///< true start pose (world) — where the simulator puts the body
  Pose2 X_WB_goal;           ///< goal (world); handed to the robot in its map frame
  std::vector<Pose2> via;    ///< waypoints (world) reached in order before the goal
  std::uint64_t seed = 1;    ///< run seed: sensor noise, odometry drift, AMCL, planner
  /// Kidnapping test hook (world side): at `kidnap_time` s (> 0) the true body jumps to
  /// `kidnap_to` (world) without the odometry seeing it. <= 0: no kidnapping.
  double kidnap_time = 0.0;
  Pose2 kidnap_to;
};

struct TrajectorySample {
  double t = 0.0;  ///< s, simulation time
  Pose2 pose;      ///< base_link in map
};

struct DriveResult {
  DriveStatus status = DriveStatus::kTimeout;
  std::string message;
  std::vector<TrajectorySample> estimated;  ///< AMCL estimate (with odometry between updates)
  std::vector<TrajectorySample> truth;      ///< true pose expressed in the map frame
  std::vector<std::vector<Pose2>> plans;    ///< every global plan followed (map frame)
  std::vector<Pose2> scan_poses;            ///< estimated base poses of the TLS scans (map)
  perception::OccupancyGrid map{perception::OccupancyGridParams{}, Vec2::Zero(), 1, 1};
  Pose2 goal_M;                  ///< goal in the map frame
  Pose2 final_true_M;            ///< final true pose, map frame
  double goal_error_xy = 0.0;    ///< m, |true final - goal|
  double goal_error_yaw_deg = 0.0;
  double loc_rms = 0.0, loc_max = 0.0;  ///< m, |estimate - truth| over all steps
  double loc_yaw_rms_deg = 0.0, loc_yaw_max_deg = 0.0;
  int contacts = 0;              ///< body contact episodes
  std::vector<sim::ContactEvent> contact_events;  ///< where and when (truth, world frame)
  int blocked_steps = 0;
  double path_length = 0.0;      ///< m, true distance travelled
  double sim_time = 0.0;         ///< s
  double wall_time = 0.0;        ///< s (reporting only)
  int tls_scans = 0, lrf_sweeps = 0, amcl_updates = 0, replans = 0, lost_events = 0;
  int teleports = 0;             ///< kidnappings applied (world side)
  /// TLS scans registered by ICP (register_scans), used degenerate, refused (AMCL pose kept).
  int scan_registrations_ok = 0, scan_registrations_degenerate = 0, scan_registrations_failed = 0;
  std::vector<std::string> scan_registration_messages;  ///< one line per registered scan
  double tls_time = 0.0;         ///< s of simulation time spent standing for TLS scans
  double tls_wall_time = 0.0;    ///< s of wall time spent simulating TLS scans (reporting only)
  double RealTimeFactor() const { return wall_time > 0 ? sim_time / wall_time : 0.0; }
};

/// Runs one mission in `world` (door leaves as the world has them): a RobotSession
/// (runner/robot_session.h), its first TLS scan, NavigateTo(goal), Result(). The body's
/// collision mesh is the world's triangles, door leaves included at their current angle.
/// Throws InputError for invalid params or a start pose in collision.
DriveResult RunDrive(const sim::EmbreeWorld& world, const DriveParams& params,
                     const DriveRequest& request);

/// Writes trajectory_estimated.tum, trajectory_true.tum, map.png + map.yaml, map_path.png and
/// summary.json into `dir` (created).
void WriteDriveOutputs(const DriveResult& result, const DriveParams& params,
                       const DriveRequest& request, const std::string& dir);

/// TUM trajectory text ("t tx ty tz qx qy qz qw" per line).
std::string ToTum(const std::vector<TrajectorySample>& samples);

}  // namespace mopad::runner
