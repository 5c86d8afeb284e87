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
#include "mission/robot_session.h"

namespace mopad::mission {

/// The room loop's params (flat YAML keys) and the simulated robot's (`drive`).
struct RoomMissionParams : autonomy::RoomScanParams {
  DriveParams drive = DefaultDrive();

  static DriveParams DefaultDrive();

  template <class V>
  void Visit(V& v) {
    autonomy::RoomScanParams::Visit(v);
    v("drive", drive);
  }
};

using RoomScanLog = autonomy::RoomScanLog;
using RoomMissionResult = autonomy::RoomScanResult;

/// Runs the room loop with the session's robot (already placed in the room).
inline RoomMissionResult RunRoomMission(RobotSession& session, const RoomMissionParams& params,
                                        modelling::RoomModel& model,
                                        const autonomy::ScanHook& on_scan = {}) {
  return autonomy::RunRoomScan(session.Robot(), params, model, on_scan);
}

}  // namespace mopad::mission
