#pragma once
// A robot in a simulated world, driven step by step by a mission (issue 4 drive, issue 5
// scanning): the body, its sensors and the whole robot-side stack (obstacle map, AMCL, global
// planner, local controller) with simulation time that accumulates across calls. RunDrive
// (runner/drive_mission.h) is: session, first scan, NavigateTo(goal), Result().
//
// Two sides, kept apart by name: robot-side calls (TakeScan, NavigateTo, EstimatedPose, Map,
// ...) use only what the robot measures; world-side calls (TruePose*, X_MW, ScanTruths,
// ScheduleTeleport, Result's truth figures) are for missions' evaluators and tests only.
//
// Frames: map (M) := the robot's start pose (base_link at t = 0); the world (W) is the scene.
// X_MW = X_WB(0)^-1 maps truth into the map frame. Poses are Pose2 (x, y, yaw) unless 3D.
// Determinism: same world + params + seed + call sequence -> same trajectories (bytes).
// Not thread-safe; keeps a reference to `world`, which must outlive the session.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "interfaces/tls_scan.h"
#include "runner/drive_mission.h"
#include "sim/tls_truth.h"

namespace mopad::runner {

class RobotSession {
 public:
  /// Places the body at `X_WB_start` (world). Throws InputError for invalid params or a start
  /// pose in collision with the scene (door leaves as the world has them).
  RobotSession(const sim::EmbreeWorld& world, const DriveParams& params, const Pose2& X_WB_start,
               std::uint64_t seed);
  ~RobotSession();
  RobotSession(const RobotSession&) = delete;
  RobotSession& operator=(const RobotSession&) = delete;

  // ---- Robot side.

  /// Stops and takes one TLS scan at the current pose (params.tls_step_deg, or
  /// `step_deg_override` when > 0). The scan is stamped with the robot's estimate
  /// (X_MS_estimate), its band points go into the obstacle map (rebuilt from all scans), AMCL
  /// restarts about the estimate. Simulation time advances by the scan's duration (pulses /
  /// pulse rate of the profile). The reference stays valid until the next TakeScan.
  const interfaces::TlsScan& TakeScan(double step_deg_override = 0.0);
  /// The last scan taken (empty before the first).
  const interfaces::TlsScan& LastScan() const;
  /// After the caller refined the last scan's pose (e.g. ICP against earlier scans): re-stamps
  /// its map points with `X_MS` (scanner in map), rebuilds the map and re-seeds AMCL around the
  /// corresponding base pose (current odometry offset kept). Throws InputError before any scan.
  void CorrectLastScanPose(const Pose3& X_MS);
  /// Makes every later map cover `p_M` (e.g. a far goal), so the planner can reason about it.
  void ExtendMap(const Vec2& p_M);
  /// Drives to `goal_M` (map frame) with the full stack: planner, controller, AMCL, and
  /// scan-and-go within params limits (`max_scans` counts the scans of this call plus one).
  /// Returns the explained outcome; `message` receives the one-line reason.
  DriveStatus NavigateTo(const Pose2& goal_M, std::string* message = nullptr);

  Pose2 EstimatedPose() const;                             ///< base_link in map
  const perception::LocalisationEstimate& Localisation() const;  ///< AMCL health
  const perception::OccupancyGrid& Map() const;            ///< current obstacle map
  double SimTime() const;                                  ///< s, simulation time
  int ScanCount() const;                                   ///< TLS scans taken
  const DriveParams& Params() const;
  std::uint64_t Seed() const;

  // ---- World side (missions' evaluation, tests; never fed back to the robot).

  Pose2 X_MW() const;             ///< world -> map (inverse of the true start pose)
  Pose2 TruePoseInMap() const;    ///< true base_link pose in the map frame
  Pose2 TruePoseInWorld() const;  ///< true base_link pose in the world
  /// Truth sidecars of the TLS scans, in scan order (kept unless SetKeepScanTruths(false)).
  const std::vector<sim::TlsTruth>& ScanTruths() const;
  void SetKeepScanTruths(bool keep);  ///< ~16 B per pulse per scan when kept (default: kept)
  /// Kidnapping: at simulation time `t` the true body jumps to `X_WB` (world); odometry does
  /// not see it. One pending teleport at a time.
  void ScheduleTeleport(double t, const Pose2& X_WB);
  /// Everything so far: trajectories (estimate and truth, map frame, one sample per control
  /// step), plans, scan poses, map, counters, contacts, localisation and goal figures (goal =
  /// the last NavigateTo's), wall time since construction, TLS costs.
  DriveResult Result() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::runner
