#pragma once
// The evaluator's view of one room of a mission, scored as the room ends (rooms/<ID>/
// evaluation.json, docs/evaluation.md): structural coverage against the truth's observable and
// total area (after the room and after each scan), per-scan registration error, SM1 label
// agreement. Truth side: the robot never sees any of this.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/frames.h"
#include "evaluation/coverage.h"
#include "evaluation/scan_eval.h"
#include "evaluation/truth_eval.h"
#include "modelling/room_model.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"
#include "sim/tls_truth.h"

namespace mopad::evaluation {

/// One scan of the room's log as the evaluator needs it.
struct LoggedScan {
  Pose3 X_MS = Pose3::Identity();  ///< the pose the robot used (the prior when refused)
  bool registered = true;          ///< in the room model (ICP accepted it)
  std::size_t truth = 0;           ///< index of its truth among the mission's scan truths
};

struct RoomEvaluation {
  std::string room;
  CoverageReport coverage;
  /// Share of the observable area sensed after each scan of the room's log, [0, 1]; empty
  /// when the log and the model's scans disagree.
  std::vector<double> coverage_per_scan;
  double observable_area = 0.0, total_area = 0.0;  ///< m^2
  std::vector<PoseError> registration;             ///< per scan (the first scan included)
  double max_translation_error = 0.0;              ///< m
  double max_rotation_error_deg = 0.0;             ///< deg
  LabelAccuracy labels;
  double seconds = 0.0;  ///< evaluation wall time (reporting only)
};

/// Scores the room `room` of `truth` as the robot's `model` holds it: `X_WM` places the map in
/// the world; `scans` is the room's log, `scan_truths` the mission's scan truths; `truth_labels`
/// the truth label of every SM1 point in the model's order. std::runtime_error when the labels
/// and the model disagree in size or a scan has no truth.
RoomEvaluation EvaluateRoom(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                            const std::string& room, const Pose3& X_WM,
                            const std::vector<LoggedScan>& scans,
                            const std::vector<sim::TlsTruth>& scan_truths,
                            const modelling::RoomModel& model,
                            const std::vector<Sm1Label>& truth_labels);

/// evaluation.json's document.
nlohmann::ordered_json ToJson(const RoomEvaluation& e);

}  // namespace mopad::evaluation
