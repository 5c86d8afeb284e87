#pragma once
// A simulated robot and its brain, stepped by a mission: the world side (mission::SimRobot) and
// the robot side (autonomy::Navigator) wired together, with the world's truth kept for the
// evaluator. RunDrive (mission/drive_mission.h) is: session, first scan, NavigateTo(goal),
// Result().
//
// Robot-side calls (TakeScan, NavigateTo, EstimatedPose, Map, ...) forward to the navigator;
// world-side calls (TruePose*, X_MW, ScanTruths, ScheduleTeleport, Result's truth figures) to
// the simulated robot, and are for missions' evaluators and tests only.
//
// Frames: map (M) := the robot's start pose (base_link at t = 0); the world (W) is the scene.
// Determinism: same world + params + seed + call sequence -> same trajectories (bytes).
// Not thread-safe; keeps a reference to `world`, which must outlive the session.

#include <cstdint>
#include <string>
#include <vector>

#include "autonomy/navigator.h"
#include "mission/drive_mission.h"
#include "mission/sim_robot.h"

namespace mopad::mission {

class RobotSession {
 public:
  /// Places the body at `X_WB_start` (world); params.seed seeds both sides. `faults`: the
  /// world's (mission/faults.h; default none), `door` the door fault's world (SimRobot). Throws
  /// InputError for invalid params or a start pose in collision with the scene. `realism`: the
  /// world's departure from ideal (sim/realism.h; default ideal), its people walking in
  /// `people` (PeopleOf).
  RobotSession(const sim::EmbreeWorld& world, const DriveParams& params, const Pose2& X_WB_start,
               const FaultParams& faults = {},
               const std::optional<DoorFaultWorld>& door = std::nullopt,
               const sim::RealismParams& realism = {},
               const std::optional<PeopleWorld>& people = std::nullopt);
  RobotSession(const RobotSession&) = delete;
  RobotSession& operator=(const RobotSession&) = delete;

  /// The robot's brain: everything a robot-side loop may use.
  autonomy::Navigator& Robot() { return navigator_; }
  const autonomy::Navigator& Robot() const { return navigator_; }

  // ---- Robot side (forwarded to the navigator).
  const interfaces::TlsScan& TakeScan(double step_deg_override = 0.0) {
    return navigator_.TakeScan(step_deg_override);
  }
  void ExtendMap(const Vec2& p_M) { navigator_.ExtendMap(p_M); }
  DriveStatus NavigateTo(const Pose2& goal_M, std::string* message = nullptr);
  Pose2 EstimatedPose() const { return navigator_.EstimatedPose(); }
  const perception::OccupancyGrid& Map() const { return navigator_.Map(); }
  int ScanCount() const { return navigator_.ScanCount(); }
  double SimTime() const { return world_robot_.Time(); }
  const DriveParams& Params() const { return params_; }
  std::uint64_t Seed() const { return params_.seed; }

  // ---- World side (missions' evaluation, tests; never fed back to the robot).
  SimRobot& World() { return world_robot_; }
  const SimRobot& World() const { return world_robot_; }
  Pose2 X_MW() const { return world_robot_.X_MW(); }
  Pose2 TruePoseInMap() const { return world_robot_.TruePoseInMap(); }
  Pose2 TruePoseInWorld() const { return world_robot_.TruePoseInWorld(); }
  const std::vector<sim::TlsTruth>& ScanTruths() const { return world_robot_.ScanTruths(); }
  void SetKeepScanTruths(bool keep) { world_robot_.SetKeepScanTruths(keep); }
  void ReleaseScanTruthPoints() { world_robot_.ReleaseScanTruthPoints(); }
  void ScheduleTeleport(double t, const Pose2& X_WB) { world_robot_.ScheduleTeleport(t, X_WB); }
  /// Everything so far: the navigator's log and map, with the world's figures (truth,
  /// localisation error, contacts, goal error against the last NavigateTo's goal, times).
  DriveResult Result() const;

 private:
  DriveParams params_;
  SimRobot world_robot_;
  autonomy::Navigator navigator_;
};

}  // namespace mopad::mission
