#pragma once
// The evaluator's view of one room mission (issue 5 acceptance): structural coverage against
// the truth's observable and total area, per-scan registration error, SM1 label agreement.
// Truth side only (tools): the robot's mission never sees any of this.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/coverage.h"
#include "evaluation/observability.h"
#include "evaluation/scan_eval.h"
#include "evaluation/truth_eval.h"
#include "evaluation/truth_surfaces.h"
#include "mission/robot_session.h"
#include "mission/room_mission.h"
#include "modelling/room_model.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"
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

struct RoomEvaluation {
  std::string room;
  evaluation::CoverageReport coverage;
  /// Share of the observable area sensed after each scan of the room's log, [0, 1]; empty
  /// when the log and the model's scans disagree.
  std::vector<double> coverage_per_scan;
  double observable_area = 0.0, total_area = 0.0;
  std::vector<evaluation::PoseError> registration;  ///< per scan (the first scan included)
  double max_translation_error = 0.0, max_rotation_error_deg = 0.0;
  evaluation::LabelAccuracy labels;
  double seconds = 0.0;  ///< evaluation wall time
};

RoomEvaluation EvaluateRoom(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                            const std::string& room, const RobotSession& session,
                            const RoomMissionResult& result, const modelling::RoomModel& model,
                            const std::vector<evaluation::Sm1Label>& truth_labels);

nlohmann::ordered_json ToJson(const RoomEvaluation& e);

/// One room job as `mopad room` and `mopad run` do it: a fresh robot at `start` (default: the
/// harness's free spot), the room mission, its outputs in `dir`, and (with `evaluate`) the
/// evaluation written to dir/evaluation.json.
struct RoomJob {
  std::string room;
  Pose2 start_W;  ///< where the harness put the robot (world)
  RoomMissionResult mission;
  std::optional<RoomEvaluation> evaluation;
  std::vector<Eigen::Vector3d> scan_positions_W;  ///< true scanner centres (world), for plots
  std::vector<Eigen::Vector2f> plan_points_W;     ///< subsample of SM1 near scanner height (world)
  modelling::LabelCounts labels;
  std::size_t points = 0;
  double path_length = 0.0;    ///< m, true distance driven in the room
  std::size_t openings = 0;    ///< SM4: doors and windows found
  double sm4_seconds = 0.0;    ///< s of wall time of SM4 (reporting only)
  std::size_t components = 0;  ///< SM5: service components found
  double sm5_seconds = 0.0;    ///< s of wall time of SM5 (reporting only)
};
RoomJob RunRoomJob(const sim::SceneWorld& mw, const std::string& room,
                   const RoomMissionParams& params, const std::optional<Pose2>& start_W,
                   const std::string& dir, bool evaluate);

}  // namespace mopad::mission
