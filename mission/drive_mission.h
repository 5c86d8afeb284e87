#pragma once
// The closed loop of `mopad drive`: one simulated robot (mission::RobotSession: the world's
// SimRobot and the robot's Navigator) driven to a goal. Only plain interface values cross the
// robot boundary: TlsScan, LrfScan, Odometry, VelocityCommand.
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
#include <limits>
#include <string>
#include <vector>

#include "autonomy/navigator.h"
#include "common/frames.h"
#include "common/params.h"
#include "perception/amcl.h"
#include "perception/occupancy_grid.h"
#include "perception/registration.h"
#include "sim/embree_world.h"
#include "sim/robot_body.h"

namespace mopad::mission {

/// One drive: the simulated robot (sensors, body, control period) and its navigator. YAML keys
/// are flat: the world's fields, then the navigator's (autonomy/navigator.h).
struct DriveParams {
  std::uint64_t seed = 1;    ///< run seed: sensor noise, odometry drift, AMCL, planner
  double control_dt = 0.02;  ///< s, physics/control step, [0.001, 0.2]
  std::string lrf_profile = "hokuyo_utm30lx";  ///< profile of both LRFs (sim/lrf.h)
  std::string tls_profile = "riegl_vz400";     ///< TLS profile (sim/tls_params.h)
  /// The base stands still for a TLS scan's duration (pulses / pulse rate of the profile);
  /// false: scans take no simulation time (tests of pure navigation).
  bool tls_scan_takes_time = true;
  /// A few per mille of calibration error and slip: odometry alone drifts decimetres over 50 m.
  sim::RobotBodyParams body{.odometry = {.left_radius_error = 0.004,
                                         .right_radius_error = -0.003,
                                         .track_width_error = 0.01,
                                         .slip_sigma = 0.003}};
  autonomy::NavigatorParams navigator;

  template <class V>
  void Visit(V& v) {
    v("seed", seed);
    v("control_dt", control_dt, Bounds{0.001, 0.2});
    v("lrf_profile", lrf_profile);
    v("tls_profile", tls_profile);
    v("tls_scan_takes_time", tls_scan_takes_time);
    v("body", body);
    navigator.Visit(v);
  }
  /// InputError naming `tls_profile` or `lrf_profile` when no profile of that name exists.
  void Validate() const;
};

using autonomy::DriveStatus;
using autonomy::ToString;
using autonomy::TrajectorySample;

struct DriveRequest {
  Pose2 X_WB_start;        ///< true start pose (world) — where the simulator puts the body
  Pose2 X_WB_goal;         ///< goal (world); handed to the robot in its map frame
  std::vector<Pose2> via;  ///< waypoints (world) reached in order before the goal
  /// Kidnapping test hook (world side): at `kidnap_time` s (> 0) the true body jumps to
  /// `kidnap_to` (world) without the odometry seeing it. <= 0: no kidnapping.
  double kidnap_time = 0.0;
  Pose2 kidnap_to;
};

/// A drive's figures: what the navigator did (autonomy::NavigatorLog) and, world side, what
/// really happened (truth, contacts, distance, sensor counts).
struct DriveResult : autonomy::NavigatorLog {
  std::vector<TrajectorySample> truth;  ///< true pose expressed in the map frame, per step
  perception::OccupancyGrid map{perception::OccupancyGridParams{}, Vec2::Zero(), 1, 1};
  Pose2 final_true_M;          ///< final true pose, map frame
  double goal_error_xy = 0.0;  ///< m, |true final - goal|
  double goal_error_yaw_deg = 0.0;
  double loc_rms = 0.0, loc_max = 0.0;  ///< m, |estimate - truth| over all steps
  double loc_yaw_rms_deg = 0.0, loc_yaw_max_deg = 0.0;
  int contacts = 0;                               ///< body contact episodes
  std::vector<sim::ContactEvent> contact_events;  ///< where and when (truth, world frame)
  int blocked_steps = 0;
  double path_length = 0.0;  ///< m, true distance travelled
  double sim_time = 0.0;     ///< s
  double wall_time = 0.0;    ///< s (reporting only)
  int lrf_sweeps = 0;
  int teleports = 0;           ///< kidnappings applied (world side)
  /// The world's injected faults that acted (mission/faults.h), one line each, in time order.
  std::vector<std::string> fault_events;
  /// People walking (sim/people.h): how many, how often the base touched one (episodes: the
  /// body's footprint within a person's 0.25 m), and the closest the footprint came (m).
  int people = 0;
  int person_contacts = 0;
  std::vector<std::string> person_contact_events;  ///< "12.34 s: the base touched person_2 at .."
  double person_closest = std::numeric_limits<double>::infinity();
  double tls_time = 0.0;       ///< s of simulation time spent standing for TLS scans
  double tls_wall_time = 0.0;  ///< s of wall time spent simulating TLS scans (reporting only)
  double RealTimeFactor() const { return wall_time > 0 ? sim_time / wall_time : 0.0; }
};

/// Runs one mission in `world` (door leaves as the world has them): a RobotSession
/// (mission/robot_session.h), its first TLS scan, NavigateTo(goal), Result(). The body's
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

}  // namespace mopad::mission
