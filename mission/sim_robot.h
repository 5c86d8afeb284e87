#pragma once
// The simulated robot: an interfaces::RobotPlatform over a sim::EmbreeWorld — the Bullet body
// with drifting wheel odometry, the two LRFs at their profile rates and the terrestrial laser
// scanner, on a simulation clock. It is the world side of a mission: it also keeps what only
// an evaluator may read (the true trajectory, contacts, the scans' truth sidecars) and the
// kidnapping hook of tests.
//
// Faults (mission/faults.h) are applied here, on the world side: a scan's lost returns, silent
// LRFs, slipping wheels, a push of the base. The robot sees only their effect on its sensors;
// FaultEvents() says what happened, when.
//
// Frames: the world W is the scene; map M := the body's start pose, X_MW = X_WB(0)^-1 (truth
// expressed in the robot's map frame for evaluation only).
// Determinism: same world + params + seed + call sequence -> same bytes.
// Not thread-safe; keeps a reference to `world`, which must outlive it.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "interfaces/robot_platform.h"
#include "mission/drive_mission.h"
#include "mission/faults.h"
#include "sim/realism.h"
#include "sim/tls_truth.h"

namespace mopad::sim {
struct SceneWorld;
}

namespace mopad::mission {

/// The world side of people walking (sim/people.h): the world they walk in (the robot's, which
/// gains them as movers) and the truth whose rooms they walk in.
struct PeopleWorld {
  sim::EmbreeWorld* world = nullptr;
  const scenes::GroundTruth* truth = nullptr;
};

/// The people's world in `mw` for `realism`, or none when the realism has no people. InputError
/// when it has people and the scene no truth (people walk in the truth's rooms).
std::optional<PeopleWorld> PeopleOf(const sim::SceneWorld& mw, const sim::RealismParams& realism);

class SimRobot final : public interfaces::RobotPlatform {
 public:
  /// Places the body at `X_WB_start` (world). Throws InputError for invalid params or a start
  /// pose in collision with the scene (door leaves as the world has them). `faults`: the
  /// world's faults (default: none); `door`: the world and door of the door fault
  /// (DoorFaultOf; its world must be `world`), which the robot then opens to the scene's angle
  /// for its start and closes at the fault's time. `realism`: the world's departure from ideal
  /// (sim/realism.h): the scanner is RealisticTls of the profile for `seed`, and its people
  /// (`realism.people`) walk in `people` (PeopleOf; its world must be `world`), from the people's
  /// seed or else `seed`.
  SimRobot(const sim::EmbreeWorld& world, const DriveParams& params, const Pose2& X_WB_start,
           std::uint64_t seed, const FaultParams& faults = {},
           const std::optional<DoorFaultWorld>& door = std::nullopt,
           const sim::RealismParams& realism = {},
           const std::optional<PeopleWorld>& people = std::nullopt);
  ~SimRobot() override;
  SimRobot(const SimRobot&) = delete;
  SimRobot& operator=(const SimRobot&) = delete;

  // ---- The robot boundary (interfaces::RobotPlatform).
  double Time() const override;
  double ControlPeriod() const override;
  bool Step(const interfaces::VelocityCommand& cmd) override;
  const interfaces::Odometry& WheelOdometry() const override;
  const interfaces::LrfScan& BaseSweep() const override;
  const interfaces::LrfScan& TopSweep() const override;
  interfaces::TlsScan Scan(double step_deg, double* still_for) override;

  // ---- World side (evaluators and tests; never fed back to the robot).
  Pose2 X_MW() const;             ///< world -> map (inverse of the true start pose)
  Pose2 TruePoseInWorld() const;  ///< true base_link pose in the world
  Pose2 TruePoseInMap() const;    ///< true base_link pose in the map frame
  /// The true pose (map frame) at the first scan and after every step: the samples of the
  /// navigator's estimated trajectory, one for one.
  const std::vector<autonomy::TrajectorySample>& TrueTrajectory() const;
  /// Truth sidecars of the TLS scans, in scan order (kept unless SetKeepScanTruths(false)).
  const std::vector<sim::TlsTruth>& ScanTruths() const;
  void SetKeepScanTruths(bool keep);  ///< ~16 B per pulse per scan when kept (default: kept)
  /// Frees the per-pulse truth of every scan taken so far (poses, ids and sizes kept; `points`
  /// empty): a finished room's scans are scored, and a floor keeps no pulse truth of its past.
  void ReleaseScanTruthPoints();
  /// Kidnapping: at simulation time `t` the true body jumps to `X_WB` (world); odometry does
  /// not see it. One pending teleport at a time.
  void ScheduleTeleport(double t, const Pose2& X_WB);
  /// The faults that acted so far, one line each ("12.34 s: ..."), in time order.
  const std::vector<std::string>& FaultEvents() const;
  /// The world-side figures of a DriveResult: truth, contacts, distance, sensor counts, times.
  void FillResult(DriveResult& result) const;
  const DriveParams& Params() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::mission
