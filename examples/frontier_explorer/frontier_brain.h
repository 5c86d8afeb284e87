#pragma once
// A small robot brain of its own: a frontier explorer of the room the robot starts in, driving
// any interfaces::RobotPlatform (the robot boundary) and seeing nothing else. It is the robot
// side of this example; it links only the robot's libraries (OpenMoPAD::modelling and
// OpenMoPAD::runfolder), so an include of sim/, scenes/, mission/ or evaluation/ would not compile.
//
// The loop:
//  1. a TLS scan where the robot stands, registered to the earlier scans by ICP
//     (perception::RegisterScan, the prior from wheel odometry) and added to a room model
//     (modelling::RoomModel: floor, ceiling and the ceiling perimeter that bounds the room);
//  2. an occupancy grid (perception::OccupancyGrid) from the TLS scans and the base LRF's sweeps;
//  3. frontiers: unknown cells next to free ones, inside the room's perimeter; the cluster worth
//     most (cells per metre of path) that has a reachable free cell near it is the next goal;
//  4. a drive there along a grid shortest path (perception::GridShortestPath), then 1 again;
//  until no frontier is left, max_scans scans are taken or the time budget is spent.
//
// Frames: map M := odom at the start (base_link at t = 0, on the floor); the scanner S. SI units,
// degrees only in `_deg` names. Deterministic: the same platform gives the same decisions (no
// wall clock, no random numbers). Not thread-safe.

#include <functional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "interfaces/robot_platform.h"
#include "modelling/room_model.h"
#include "perception/occupancy_grid.h"

namespace frontier {

struct ExplorerParams {
  double scan_step_deg = 0.5;     ///< deg, TLS angular step, [0.02, 5]
  int max_scans = 4;              ///< TLS scans at most, [1, 100]
  double time_budget = 900.0;     ///< s of platform time, > 0
  double grid_resolution = 0.1;   ///< m per occupancy cell, [0.02, 0.5]
  double grid_size = 40.0;        ///< m, side of the square grid centred on the start, > 0
  double clearance = 0.45;        ///< m, path and goal cells keep this from obstacles (> the
                                  ///< body's turning radius, 0.39 m for the default body)
  double wall_margin = 0.5;       ///< m, frontier cells this close to the perimeter are ignored
  int min_frontier_cells = 6;     ///< clusters with fewer cells are noise, >= 1
  double goal_reach = 2.5;        ///< m, a goal lies at most this far from its frontier
  double min_scan_spacing = 0.8;  ///< m, no goal this close to an earlier scan position
  double speed = 0.35;            ///< m/s, cruise speed, (0, 1]
  double turn_rate = 0.8;         ///< rad/s, largest yaw rate, (0, 2]
  double lookahead = 0.5;         ///< m, pure-pursuit lookahead along the path
  double goal_tolerance = 0.15;   ///< m, a goal is reached this close
  double leg_timeout = 90.0;      ///< s, a goal not reached by then is given up
  double replan_period = 2.0;     ///< s, the path is planned again this often (new sweeps)

  /// Throws std::invalid_argument naming the field, the value and the allowed range.
  void Validate() const;
};

/// One TLS scan as the explorer used it.
struct ExplorerScan {
  double time = 0.0;         ///< s, platform time of the scan
  mopad::Pose3 X_MS;         ///< scanner pose used (registered, or the odometry prior)
  bool registered = false;   ///< in the room model (the first scan, or ICP accepted)
  std::string registration;  ///< one line: the ICP outcome ("" for the first scan)
};

struct ExplorerResult {
  std::vector<ExplorerScan> scans;
  mopad::modelling::RoomModel model;  ///< the registered scans
  mopad::perception::OccupancyGrid grid{mopad::perception::OccupancyGridParams{},
                                        mopad::Vec2::Zero(), 1, 1};
  mopad::Pose2 final_pose_M;       ///< the explorer's estimate of where it ended (map)
  double odometry_distance = 0.0;  ///< m, driven by the wheel odometry
  int frontiers_left = 0;          ///< frontier clusters still open when it stopped
  std::string stop_reason;         ///< one line
};

/// Explores the room the platform stands in. `log` hears one line per event (may be empty).
/// Throws std::invalid_argument for invalid params; the platform's exceptions pass through.
ExplorerResult Explore(mopad::interfaces::RobotPlatform& robot, const ExplorerParams& params,
                       const std::function<void(const std::string&)>& log);

/// Writes the robot's files of the room into `dir` (created), with the run folder's names
/// (runfolder/layout.h): sm1.ply, sm2.json, sm3.json (SM3 built from the model here),
/// dsm3.ply and scan_poses.tum. `room` is the robot's name for the room. Returns the count of
/// SM3 patches. The harness adds run.json (where the map lies in the world is the world's
/// record, not the robot's).
std::size_t WriteRoomFiles(const ExplorerResult& result, const std::string& room,
                           const std::string& dir);

}  // namespace frontier
