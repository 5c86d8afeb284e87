#include "mission/room_job.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <span>

#include "common/error.h"
#include "evaluation/truth_models.h"
#include "mission/model_export.h"
#include "mission/robot_catalogue.h"
#include "modelling/model_io.h"
#include "modelling/openings.h"
#include "modelling/sm5_io.h"

namespace mopad::mission {

autonomy::ScanHook Sm1TruthCollector::Hook() {
  return [this](int index, const interfaces::TlsScan& scan) {
    const auto& truths = session_.ScanTruths();
    if (index < 0 || static_cast<std::size_t>(index) >= truths.size())
      throw std::runtime_error("room eval: no truth kept for scan " + std::to_string(index));
    const std::vector<evaluation::Sm1Label> grid =
        evaluation::TruthLabels(scan, truths[static_cast<std::size_t>(index)], truth_, room_);
    // RoomModel keeps every valid return column by column (the PLY order).
    const std::vector<evaluation::Sm1Label> valid = evaluation::InPlyOrder(scan, grid);
    labels_.insert(labels_.end(), valid.begin(), valid.end());
  };
}

namespace {

// The share of the observable area sensed after each scan of the log: the cells of the model's
// scans so far (a scan ICP refused is not in the model and adds none). SM1 is in scan order, so
// each scan's points are one run of ScanIndices. Empty when the log and the model disagree.
std::vector<double> CoveragePerScan(const evaluation::StructuralSurfaces& surfaces,
                                    const std::vector<std::uint8_t>& observable,
                                    const RoomMissionResult& result,
                                    const modelling::RoomModel& model, const Pose3& X_WM) {
  const auto& points = model.Points();
  const auto& scan = model.ScanIndices();
  std::size_t registered = 0;
  for (const RoomScanLog& s : result.scans) registered += s.registered ? 1 : 0;
  if (registered != static_cast<std::size_t>(model.ScanCount()) || scan.size() != points.size())
    return {};
  std::vector<std::uint8_t> sensed;
  std::vector<double> out;
  std::size_t begin = 0;
  for (const RoomScanLog& s : result.scans) {
    if (s.registered && begin < scan.size()) {
      std::size_t end = begin;
      while (end < scan.size() && scan[end] == scan[begin]) ++end;
      const std::vector<std::uint8_t> cells = evaluation::SensedCells(
          surfaces, std::span<const Eigen::Vector3f>(points.data() + begin, end - begin), X_WM);
      if (sensed.empty()) sensed.assign(cells.size(), 0);
      for (std::size_t i = 0; i < cells.size(); ++i) sensed[i] |= cells[i];
      begin = end;
    }
    out.push_back(
        sensed.empty()
            ? 0.0
            : evaluation::SummariseCoverage(surfaces, observable, sensed).room.ShareOfObservable());
  }
  return out;
}

}  // namespace

RoomEvaluation EvaluateRoom(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                            const std::string& room, const RobotSession& session,
                            const RoomMissionResult& result, const modelling::RoomModel& model,
                            const std::vector<evaluation::Sm1Label>& truth_labels) {
  const auto t0 = std::chrono::steady_clock::now();
  RoomEvaluation e;
  e.room = room;
  const Pose3 X_WM = session.X_MW().To3d().inverse();
  const evaluation::RoomTruth rt = evaluation::ComputeRoomTruth(world, truth, room);
  const evaluation::Observability& obs = rt.observability;
  e.coverage = evaluation::ComputeCoverage(rt.surfaces, obs.observable, model.Points(), X_WM);
  e.coverage_per_scan = CoveragePerScan(rt.surfaces, obs.observable, result, model, X_WM);
  e.observable_area = obs.observable_area;
  e.total_area = obs.total_area;
  const auto& truths = session.ScanTruths();
  for (const RoomScanLog& s : result.scans) {
    // Every scan is scored, also those ICP refused (their pose is the prior).
    const evaluation::PoseError pe = evaluation::ScanRegistrationError(
        s.X_MS, X_WM, truths.at(static_cast<std::size_t>(s.session_scan)));
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
  e.labels = evaluation::CompareLabels(truth_labels, est);
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

nlohmann::ordered_json ToJson(const RoomEvaluation& e) {
  nlohmann::ordered_json j;
  j["room"] = e.room;
  j["coverage"] = nlohmann::ordered_json::parse(evaluation::CoverageToJson(e.coverage));
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

RoomJob RunRoomJob(const sim::SceneWorld& mw, const std::string& room,
                   const RoomMissionParams& params, const std::optional<Pose2>& start_W,
                   const std::string& dir, bool evaluate) {
  if (!mw.truth)
    throw InputError(
        "room: error: the scene has no truth sidecar; got no rooms, expected a "
        "generated scene (scene.truth.json) or a spec");
  const scenes::Room* r = mw.truth->FindRoom(room);
  if (!r) {
    std::string ids;
    for (const auto& x : mw.truth->rooms) ids += (ids.empty() ? "" : ", ") + x.id;
    throw InputError("--room: error: unknown room; got '" + room + "', expected one of " + ids);
  }
  RoomJob job;
  job.room = room;
  if (start_W) {
    job.start_W = *start_W;
  } else {
    const Eigen::Vector2d xy = sim::FreeSpotInRoom(*mw.truth, *r);
    job.start_W = Pose2{xy.x(), xy.y(), 0.0};
  }
  RobotSession session(*mw.world, params.drive, job.start_W);
  modelling::RoomModel model(params.model);
  // The truth side scores an open-plan room (spaces joined by open passages) as the robot
  // meets it: one room (evaluation/truth_models.h, MergeOpenPlanRooms).
  const evaluation::OpenPlanTruth open_plan =
      evaluation::MergeOpenPlanRooms(*mw.truth, /*join_faces=*/false);
  const std::string truth_room = open_plan.room_of.at(room);
  Sm1TruthCollector labels(session, open_plan.truth, truth_room);
  job.mission =
      RunRoomMission(session, params, model, evaluate ? labels.Hook() : autonomy::ScanHook{});
  std::vector<std::pair<std::string, modelling::Orthoimage>> images;
  // SM5 (paper §3.4) with the recogniser trained from the robot's catalogue (once a process).
  const autonomy::RoomModels models = autonomy::BuildRoomModels(
      model, std::move(job.mission.no_return), params, room, &images, &RobotComponentRecogniser());
  const modelling::StructuralModel& sm3 = models.sm3;
  const modelling::Sm4Model& sm4 = models.sm4;
  job.sm4_seconds = models.sm4_seconds;
  job.openings = sm4.openings.size();
  modelling::VoxelSpace dsm3 = model.Voxels();
  modelling::MarkOpeningVoxels(sm4.openings, dsm3);
  WriteRoomOutputs(job.mission, params, session, model, sm3, dsm3, dir);
  modelling::WriteSm4Files(dir, sm4, images);
  job.sm5_seconds = models.sm5_seconds;
  job.components = models.sm5.components.size();
  modelling::WriteSm5File(dir, models.sm5);
  WriteRunJson(dir, mw, room, params.drive.seed, session.X_MW().To3d().inverse());
  modelling::WriteModelsGlb(sm3, &sm4, room, (std::filesystem::path(dir) / "models.glb").string(),
                            &models.sm5);
  for (const auto& t : session.ScanTruths()) job.scan_positions_W.push_back(t.X_WS.translation());
  const Pose3 X_WM = session.X_MW().To3d().inverse();
  const auto& pts = model.Points();
  const double z_lo = model.FloorZ() + 1.2, z_hi = model.FloorZ() + 1.6;
  for (std::size_t i = 0; i < pts.size(); i += 13) {
    if (pts[i].z() < z_lo || pts[i].z() > z_hi) continue;
    const Eigen::Vector3d w = X_WM * pts[i].cast<double>();
    job.plan_points_W.emplace_back(static_cast<float>(w.x()), static_cast<float>(w.y()));
  }
  job.labels = model.CountLabels();
  job.path_length = session.Result().path_length;
  job.points = model.PointCount();
  if (evaluate) {
    job.evaluation = EvaluateRoom(*mw.world, open_plan.truth, truth_room, session, job.mission,
                                  model, labels.Labels());
    std::ofstream(std::filesystem::path(dir) / "evaluation.json")
        << ToJson(*job.evaluation).dump(2) << "\n";
  }
  return job;
}

}  // namespace mopad::mission
