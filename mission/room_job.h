#pragma once
// One room of a mission on the world side: the truth labels of its scans, its files in the run
// folder (through runfolder/), its evaluation (evaluation/room_scores.h), and the room job of
// `mopad room` and `mopad run --room` (a fresh robot placed in one room).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/room_scores.h"
#include "mission/robot_session.h"
#include "mission/room_mission.h"
#include "modelling/room_model.h"
#include "modelling/room_models.h"
#include "runfolder/room_files.h"
#include "scenes/ground_truth.h"
#include "sim/scene_world.h"

namespace mopad::mission {

/// Collects the truth label of every valid return of every scan, in the order the RoomModel
/// stores its points (column by column, as in the scan PLY) (pass Hook() to RunRoomMission).
class Sm1TruthCollector {
 public:
  Sm1TruthCollector(const RobotSession& session, const scenes::GroundTruth& truth, std::string room)
      : session_(session), truth_(truth), room_(std::move(room)) {}
  autonomy::ScanHook Hook();
  const std::vector<evaluation::Sm1Label>& Labels() const { return labels_; }

 private:
  const RobotSession& session_;
  const scenes::GroundTruth& truth_;
  std::string room_;
  std::vector<evaluation::Sm1Label> labels_;
};

/// The room's scans as the evaluator scores them.
std::vector<evaluation::LoggedScan> LoggedScans(const RoomMissionResult& log);

/// The report's plan view of a room: a subsample of its SM1 points near scanner height, in the
/// world (every kPlanPointStride-th point between kPlanBand metres above the model's floor).
inline constexpr double kPlanBandLow = 1.2, kPlanBandHigh = 1.6;  ///< m above the floor
inline constexpr std::size_t kPlanPointStride = 13;
std::vector<Eigen::Vector2f> PlanPoints(const modelling::RoomModel& model, const Pose3& X_WM);

/// What a room's scan files hold beyond the room loop's own: in a floor mission, the door scan
/// listed with the room (first in scan_poses.tum) and the time window of its trajectory files.
struct RoomWindow {
  std::vector<std::pair<double, Pose3>> door_scans;  ///< (sim time s, X_MS)
  double t_begin = -1e300, t_end = 1e300;            ///< s
};

/// The run folder's files of one room as the simulated session leaves them (runfolder/).
/// `scene_room`: the scene's id of the room (run.json); `evaluation`: evaluation.json's
/// document, or null for none.
runfolder::RoomScanFiles ScanFilesOf(
    const sim::SceneWorld& mw, const RobotSession& session, const RoomMissionParams& params,
    const RoomMissionResult& log, const modelling::RoomModel& model,
    const modelling::RoomModels& models,
    const std::vector<std::pair<std::string, modelling::Orthoimage>>& images,
    const std::string& scene_room, const RoomWindow& window,
    const nlohmann::ordered_json& evaluation);

/// One room job as `mopad room` and `mopad run` do it: a fresh robot at `start` (default: the
/// harness's free spot), the room mission, its files in `dir`, and (with `evaluate`) the
/// evaluation written to dir/evaluation.json.
struct RoomJob {
  std::string room;
  Pose2 start_W;  ///< where the harness put the robot (world)
  RoomMissionResult mission;
  std::optional<evaluation::RoomEvaluation> evaluation;
  std::vector<Eigen::Vector3d> scan_positions_W;  ///< true scanner centres (world), for plots
  std::vector<Eigen::Vector2f> plan_points_W;     ///< PlanPoints (world)
  modelling::LabelCounts labels;
  std::size_t points = 0;
  double path_length = 0.0;    ///< m, true distance driven in the room
  std::size_t openings = 0;    ///< SM4: doors and windows found
  double sm4_seconds = 0.0;    ///< s of wall time of SM4 (reporting only)
  std::size_t components = 0;  ///< SM5: service components found
  double sm5_seconds = 0.0;    ///< s of wall time of SM5 (reporting only)
  std::vector<std::string> fault_events;  ///< the world's injected faults that acted
};
/// The harness's check of a job's scene and rooms, before any work: the scene has truth rooms
/// and each of `rooms` is one of their ids. InputError naming the first unknown id and the
/// scene's room ids otherwise (a floor mission passes no ids: the rooms must exist).
void CheckJobRooms(const sim::SceneWorld& mw, const std::vector<std::string>& rooms);

RoomJob RunRoomJob(const sim::SceneWorld& mw, const std::string& room,
                   const RoomMissionParams& params, const std::optional<Pose2>& start_W,
                   const std::string& dir, bool evaluate);

}  // namespace mopad::mission
