#include "evaluation/room_scores.h"

#include <algorithm>
#include <chrono>
#include <span>
#include <stdexcept>

#include "evaluation/observability.h"
#include "evaluation/truth_surfaces.h"

namespace mopad::evaluation {
namespace {

// The share of the observable area sensed after each scan of the log: the cells of the model's
// scans so far (a scan ICP refused is not in the model and adds none). SM1 is in scan order, so
// each scan's points are one run of ScanIndices. Empty when the log and the model disagree.
std::vector<double> CoveragePerScan(const StructuralSurfaces& surfaces,
                                    const std::vector<std::uint8_t>& observable,
                                    const std::vector<LoggedScan>& log,
                                    const modelling::RoomModel& model, const Pose3& X_WM) {
  const auto& points = model.Points();
  const auto& scan = model.ScanIndices();
  std::size_t registered = 0;
  for (const LoggedScan& s : log) registered += s.registered ? 1 : 0;
  if (registered != static_cast<std::size_t>(model.ScanCount()) || scan.size() != points.size())
    return {};
  std::vector<std::uint8_t> sensed;
  std::vector<double> out;
  std::size_t begin = 0;
  for (const LoggedScan& s : log) {
    if (s.registered && begin < scan.size()) {
      std::size_t end = begin;
      while (end < scan.size() && scan[end] == scan[begin]) ++end;
      const std::vector<std::uint8_t> cells = SensedCells(
          surfaces, std::span<const Eigen::Vector3f>(points.data() + begin, end - begin), X_WM);
      if (sensed.empty()) sensed.assign(cells.size(), 0);
      for (std::size_t i = 0; i < cells.size(); ++i) sensed[i] |= cells[i];
      begin = end;
    }
    out.push_back(sensed.empty()
                      ? 0.0
                      : SummariseCoverage(surfaces, observable, sensed).room.ShareOfObservable());
  }
  return out;
}

}  // namespace

RoomEvaluation EvaluateRoom(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                            const std::string& room, const Pose3& X_WM,
                            const std::vector<LoggedScan>& scans,
                            const std::vector<sim::TlsTruth>& scan_truths,
                            const modelling::RoomModel& model,
                            const std::vector<Sm1Label>& truth_labels) {
  const auto t0 = std::chrono::steady_clock::now();
  RoomEvaluation e;
  e.room = room;
  const RoomTruth rt = ComputeRoomTruth(world, truth, room);
  const Observability& obs = rt.observability;
  e.coverage = ComputeCoverage(rt.surfaces, obs.observable, model.Points(), X_WM);
  e.coverage_per_scan = CoveragePerScan(rt.surfaces, obs.observable, scans, model, X_WM);
  e.observable_area = obs.observable_area;
  e.total_area = obs.total_area;
  for (const LoggedScan& s : scans) {
    // Every scan is scored, also those ICP refused (their pose is the prior).
    if (s.truth >= scan_truths.size())
      throw std::runtime_error("room eval: no truth kept for scan " + std::to_string(s.truth));
    const PoseError pe = ScanRegistrationError(s.X_MS, X_WM, scan_truths[s.truth]);
    e.max_translation_error = std::max(e.max_translation_error, pe.translation);
    e.max_rotation_error_deg = std::max(e.max_rotation_error_deg, pe.rotation_deg);
    e.registration.push_back(pe);
  }
  std::vector<std::uint8_t> est(model.Labels().size());
  for (std::size_t i = 0; i < est.size(); ++i)
    est[i] = static_cast<std::uint8_t>(model.Labels()[i]);
  if (truth_labels.size() != est.size())
    throw std::runtime_error("room eval: " + std::to_string(truth_labels.size()) +
                             " truth labels for " + std::to_string(est.size()) + " SM1 points");
  e.labels = CompareLabels(truth_labels, est);
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

nlohmann::ordered_json ToJson(const RoomEvaluation& e) {
  nlohmann::ordered_json j;
  j["room"] = e.room;
  j["coverage"] = CoverageJson(e.coverage);
  j["coverage_of_observable"] = e.coverage.room.ShareOfObservable();
  j["coverage_of_total"] = e.coverage.room.ShareOfTotal();
  j["coverage_of_observable_per_scan"] = e.coverage_per_scan;
  j["observable_area"] = e.observable_area;
  j["total_area"] = e.total_area;
  nlohmann::ordered_json reg = nlohmann::json::array();
  for (const auto& p : e.registration)
    reg.push_back({{"translation_m", p.translation}, {"rotation_deg", p.rotation_deg}});
  j["registration_error"] = reg;
  j["registration_error_max"] = {{"translation_m", e.max_translation_error},
                                 {"rotation_deg", e.max_rotation_error_deg}};
  j["sm1_labels"] = {{"points", e.labels.points},
                     {"correct", e.labels.correct},
                     {"accuracy", e.labels.Accuracy()},
                     {"confusion_truth_by_estimate", e.labels.confusion}};
  j["seconds"] = e.seconds;
  return j;
}

}  // namespace mopad::evaluation
