#pragma once
// The closed loop of `mopad room` (issue 5; paper §3.1 Figure 5, yellow part): the robot scans
// one room from positions it chooses itself until the stopping rule holds, and produces SM1.
//
//   scan 1 at the start (map frame := start pose) -> RoomModel
//   loop: stopping rule (epsilon1 / epsilon2)? -> next best scan (autonomy) -> NavigateTo
//         -> scan -> registration (odometry/AMCL prior, point-to-plane ICP against S(t-1))
//         -> RoomModel.AddScan (labels, RoI, voxels, coverage)
//
// Robot and world meet here only through runner::RobotSession (plain interface values); the
// truth sidecars stay in the session for the evaluator (tools/ and evaluation/).
// Deterministic: same world + params + seed -> same outputs (timings aside).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "autonomy/next_best_scan.h"
#include "common/frames.h"
#include "common/params.h"
#include "modelling/room_model.h"
#include "modelling/structural_model.h"
#include "modelling/stopping.h"
#include "perception/registration.h"
#include "runner/drive_mission.h"
#include "runner/robot_session.h"

namespace mopad::runner {

struct RoomMissionParams {
  double scan_step_deg = 0.2;  ///< deg, TLS angular step of the room scans, [0.02, 5]
  int max_scans = 10;          ///< hard cap of scans in the room (beyond the paper's rule), [1, 100]
  int nav_attempts = 5;        ///< NBS candidates tried when driving to one fails, [1, 20]
  /// m, NBS candidates this close to a position whose scan could not be registered are not
  /// chosen again (the model did not change, so the same spot would win again), [0, 10]
  double failed_scan_exclusion = 1.0;
  DriveParams drive = DefaultDrive();
  perception::IcpParams icp = DefaultIcp();
  modelling::RoomModelParams model;
  modelling::StoppingParams stopping;
  autonomy::NextBestScanParams nbs = DefaultNbs();
  modelling::Sm3Params sm3;

  static DriveParams DefaultDrive();
  static autonomy::NextBestScanParams DefaultNbs();
  static perception::IcpParams DefaultIcp();

  template <class V>
  void Visit(V& v) {
    v("scan_step_deg", scan_step_deg, Bounds{0.02, 5.0});
    v("max_scans", max_scans, Bounds{1, 100});
    v("nav_attempts", nav_attempts, Bounds{1, 20});
    v("failed_scan_exclusion", failed_scan_exclusion, Bounds{0.0, 10.0});
    v("drive", drive);
    v("icp", icp);
    v("room_model", model);
    v("stopping", stopping);
    v("nbs", nbs);
    v("sm3", sm3);
  }
};

/// One scan of the room mission, as logged (robot side, plus the timing of each step).
struct RoomScanLog {
  int index = 0;
  int session_scan = 0;                  ///< the session's scan index (ScanTruths() order)
  double sim_time = 0.0;                 ///< s, when the scan was taken
  Pose3 X_MS_prior = Pose3::Identity();  ///< odometry/AMCL estimate
  Pose3 X_MS = Pose3::Identity();        ///< registered pose used for the model
  bool registered = true;                ///< false: ICP refused; the scan was left out of the model
  perception::RegistrationResult registration;  ///< empty for the first scan
  modelling::CoverageFigures coverage;
  std::string stop_message;              ///< the stopping rule's verdict after this scan
  // Next best scan chosen after this scan (none after the last one).
  bool has_next = false;
  Pose2 next_goal;                       ///< base pose, map frame
  double expected_gain = 0.0;            ///< NBS certainty of the chosen candidate
  int candidates = 0;
  std::string nav_status;                ///< outcome of driving there
  std::string nav_message;
  // Wall-clock seconds of the processing steps (reporting only).
  double t_registration = 0.0, t_model = 0.0, t_nbs = 0.0, t_scan = 0.0, t_drive = 0.0;
};

struct RoomMissionResult {
  std::vector<RoomScanLog> scans;
  std::string stop_reason;          ///< why the mission ended (stopping rule, cap, no candidate)
  bool registration_failed = false; ///< some scan could not be registered
  double sim_time = 0.0, wall_time = 0.0;
};

/// Runs the mission with the robot starting at `X_WB_start` (world; inside the room).
/// The session is created by the caller so that the world side (truths, trajectories) stays
/// available afterwards. `model` receives the final RoomModel.
/// `on_scan` (optional, world side) sees every scan the model accepted, with the session's
/// scan index (ScanTruths() order), e.g. for an evaluator to pair it with its truth sidecar.
using ScanHook = std::function<void(int index, const interfaces::TlsScan& scan)>;
RoomMissionResult RunRoomMission(RobotSession& session, const RoomMissionParams& params,
                                 modelling::RoomModel& model, const ScanHook& on_scan = {});

/// SM3 of the room from the model's inlier points (at most ~1 M, evenly subsampled), its
/// perimeter and columns (paper §3.2). `room` labels the model.
modelling::StructuralModel BuildRoomSm3(const modelling::RoomModel& model,
                                        const modelling::Sm3Params& params,
                                        const std::string& room);

/// Writes into `dir`: sm1.ply, sm2.json, sm3.json, dsm3.ply (docs/models.md), scans.json
/// (per-scan log), scan_poses.tum, trajectory_estimated.tum, trajectory_true.tum, map.png +
/// map.yaml, model.json, summary.json (driving figures) and room.effective.yaml.
void WriteRoomOutputs(const RoomMissionResult& result, const RoomMissionParams& params,
                      const RobotSession& session, const modelling::RoomModel& model,
                      const modelling::StructuralModel& sm3, const std::string& dir);

}  // namespace mopad::runner
