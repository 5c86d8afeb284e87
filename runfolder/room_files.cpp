#include "runfolder/room_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "common/atomic_file.h"
#include "common/error.h"
#include "io/text_file.h"
#include "io/tum.h"
#include "modelling/model_io.h"
#include "modelling/sm5_io.h"
#include "runfolder/layout.h"

namespace mopad::runfolder {
namespace {

namespace fs = std::filesystem;

void CreateFolder(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), "cannot create the folder", ec.message());
}

nlohmann::ordered_json PoseJson(const Pose3& X) {
  const Eigen::Quaterniond q(X.rotation());
  return {{"t", {X.translation().x(), X.translation().y(), X.translation().z()}},
          {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

nlohmann::ordered_json ScanJson(const autonomy::RoomScanLog& s) {
  nlohmann::ordered_json j;
  j["index"] = s.index;
  j["detail"] = s.detail;
  j["step_deg"] = s.step_deg;
  j["registered"] = s.registered;
  j["at_prior"] = s.at_prior;
  j["sim_time"] = s.sim_time;
  j["X_MS_prior"] = PoseJson(s.X_MS_prior);
  j["X_MS"] = PoseJson(s.X_MS);
  if (s.index > 0 || !s.registration.message.empty()) {
    const auto& r = s.registration;
    j["registration"] = {{"ok", r.ok},
                         {"converged", r.converged},
                         {"fitness", r.fitness},
                         {"raw_fitness", r.raw_fitness},
                         {"expected_overlap", r.expected_overlap},
                         {"rmse", r.rmse},
                         {"free_space_violation", r.free_space_violation},
                         {"degenerate", r.degenerate},
                         {"information", r.information},
                         {"constrained_directions", r.constrained_directions.cols()},
                         {"iterations", r.iterations},
                         {"message", r.message}};
    if (s.registered) {
      // Std of the used pose along x, y (m) and yaw (deg), from its covariance.
      const auto& C = s.covariance;
      j["registration"]["sigma_x_y_yaw"] = {std::sqrt(std::max(0.0, C(3, 3))),
                                            std::sqrt(std::max(0.0, C(4, 4))),
                                            RadToDeg(std::sqrt(std::max(0.0, C(2, 2))))};
    }
  }
  j["range_bias"] = {{"applied", s.range_bias.ok},
                     {"bias_m", s.range_bias.bias},
                     {"sigma_m", s.range_bias.sigma},
                     {"message", s.range_bias.message}};
  // Only when the room model changed the scan's colours (modelling/colour_alignment.h).
  if (s.colour_gain != std::array<double, 3>{1.0, 1.0, 1.0}) j["colour_gain"] = s.colour_gain;
  j["coverage"] = {{"ratio", s.coverage.ratio},
                   {"observable_ratio", s.coverage.observable_ratio},
                   {"hidden_area", s.coverage.hidden_area},
                   {"increment", s.coverage.increment},
                   {"sensed_area", s.coverage.sensed_area},
                   {"total_area", s.coverage.total_area},
                   {"opening_area", s.coverage.opening_area}};
  j["stopping"] = s.stop_message;
  if (s.has_next) {
    j["next"] = {{"goal", {s.next_goal.x, s.next_goal.y, s.next_goal.yaw}},
                 {"expected_gain", s.expected_gain},
                 {"candidates", s.candidates},
                 {"nav_status", s.nav_status},
                 {"nav_message", s.nav_message}};
  }
  j["seconds"] = {{"scan", s.t_scan},
                  {"registration", s.t_registration},
                  {"model", s.t_model},
                  {"nbs", s.t_nbs},
                  {"processing", s.t_registration + s.t_model + s.t_nbs},
                  {"drive", s.t_drive}};
  return j;
}

nlohmann::ordered_json SummaryJson(const autonomy::RoomScanResult& log, const DriveFigures& d) {
  nlohmann::ordered_json j;
  j["scans"] = log.scans.size();
  j["stop_reason"] = log.stop_reason;
  j["registration_failed"] = log.registration_failed;
  j["path_length_m"] = d.path_length;
  j["contacts"] = d.contacts;
  j["localisation_rms_m"] = d.loc_rms;
  j["localisation_max_m"] = d.loc_max;
  j["sim_time_s"] = log.sim_time;
  j["wall_time_s"] = log.wall_time;
  return j;
}

}  // namespace

nlohmann::ordered_json ScanLogJson(const autonomy::RoomScanResult& log) {
  nlohmann::ordered_json scans = nlohmann::json::array();
  for (const auto& s : log.scans) scans.push_back(ScanJson(s));
  nlohmann::ordered_json out;
  out["scans"] = std::move(scans);
  out["stop_reason"] = log.stop_reason;
  out["detail"] = {{"scans", log.detail_scans},
                   {"sim_time", log.detail_sim_time},
                   {"wall_time", log.detail_wall_time},
                   {"log", log.detail_log}};
  out["registration_failed"] = log.registration_failed;
  out["sim_time"] = log.sim_time;
  out["wall_time"] = log.wall_time;
  return out;
}

void WriteRoomScanFiles(const std::string& dir, const RoomScanFiles& f) {
  if (!f.model || !f.dsm3 || !f.images || !f.log || !f.map)
    throw std::invalid_argument("WriteRoomScanFiles: a part of the room is missing");
  const fs::path d(dir);
  CreateFolder(d);
  f.model->WriteSm1(Join(dir, kSm1));
  io::WriteTextFile(Join(dir, kSm2), modelling::Sm2Json(f.model->GetRoi(), f.room));
  modelling::WriteDsm3Ply(*f.dsm3, Join(dir, kDsm3));
  if (!f.images->empty()) {
    const fs::path images = d / fs::path(kOrthoimages);
    CreateFolder(images);
    for (const auto& [id, image] : *f.images)
      modelling::WriteOrthoimagePngs(image, (images / id).string());
  }
  io::WriteTextFile(Join(dir, kModelFigures), f.model->FiguresJson());
  std::string poses;
  for (const auto& [t, X] : f.door_scans) poses += io::TumLine(t, X);
  for (const auto& s : f.log->scans) poses += io::TumLine(s.sim_time, s.X_MS);
  WriteWholeFile(Join(dir, kScanPoses), poses);
  io::WriteTextFile(Join(dir, kSummary), SummaryJson(*f.log, f.drive).dump(2));
  WriteWholeFile(Join(dir, kTrajectoryEstimated), f.trajectory_estimated_tum);
  WriteWholeFile(Join(dir, kTrajectoryTrue), f.trajectory_true_tum);
  perception::WriteMap(*f.map, Join(dir, kMapYaml));
  io::WriteTextFile(Join(dir, kEffectiveConfig), f.effective_config_yaml);
  io::WriteTextFile(Join(dir, kScansLog), ScanLogJson(*f.log).dump(2));
  WriteRunJson(dir, f.run);
  if (!f.evaluation_json.empty()) WriteRoomEvaluation(dir, f.evaluation_json);
}

void WriteRoomEvaluation(const std::string& dir, const std::string& evaluation_json) {
  io::WriteTextFile(Join(dir, kRoomEvaluation), evaluation_json);
}

void WriteRoomModelFiles(const std::string& dir, const RoomModelFiles& f) {
  if (!f.sm3 || !f.sm4 || !f.sm5)
    throw std::invalid_argument("WriteRoomModelFiles: a model of the room is missing");
  io::WriteTextFile(Join(dir, kSm3), modelling::Sm3Json(*f.sm3));
  io::WriteTextFile(Join(dir, kSm4), modelling::Sm4Json(*f.sm4));
  modelling::WriteSm5File(dir, *f.sm5);
  modelling::WriteModelsGlb(*f.sm3, f.sm4, f.room, Join(dir, kModelsGlb), f.sm5);
}

void WriteRoomFiles(const std::string& dir, const RoomScanFiles& scans,
                    const RoomModelFiles& models) {
  WriteRoomScanFiles(dir, scans);
  WriteRoomModelFiles(dir, models);
}

}  // namespace mopad::runfolder
