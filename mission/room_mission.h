#pragma once
// The closed loop of `mopad room`: the simulated robot (mission::RobotSession) runs the robot's
// room loop (autonomy::RunRoomScan) in one room; the world side keeps the truth for the
// evaluator and writes the room's files.
// Deterministic: same world + params + seed -> same outputs (timings aside).

#include <string>
#include <utility>
#include <vector>

#include "autonomy/room_scan.h"
#include "mission/drive_mission.h"
#include "mission/faults.h"
#include "mission/robot_session.h"
#include "sim/realism.h"

namespace mopad::mission {

/// The room loop's params and the simulated robot's. YAML keys: the room loop's at the top
/// level (autonomy::RoomScanParams), the robot's under `drive`, the world's injected faults
/// under `faults` (mission/faults.h; all off by default), how far the world departs from an ideal
/// one under `realism` (sim/realism.h; ideal by default).
struct RoomMissionParams {
  autonomy::RoomScanParams scan{};
  /// Inside one room every NBS candidate lies in mapped free space: no scan-and-go stops (they
  /// would be scans the room model never sees), and no registration by the navigator (the room
  /// loop registers against its own S(t-1)).
  DriveParams drive{.navigator = {.max_scans = 1, .register_scans = false}};
  FaultParams faults{};          ///< world side: the robot never reads them
  sim::RealismParams realism{};  ///< world side: the robot never reads it

  template <class V>
  void Visit(V& v) {
    scan.Visit(v);
    v("drive", drive);
    v("faults", faults);
    v("realism", realism);
  }
};

using RoomScanLog = autonomy::RoomScanLog;
using RoomMissionResult = autonomy::RoomScanResult;

/// Runs the room loop with the session's robot (already placed in the room).
inline RoomMissionResult RunRoomMission(RobotSession& session, const RoomMissionParams& params,
                                        modelling::RoomModel& model,
                                        const autonomy::ScanHook& on_scan = {}) {
  return autonomy::RunRoomScan(session.Robot(), params.scan, model, on_scan);
}

}  // namespace mopad::mission
