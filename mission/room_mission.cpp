#include "mission/room_mission.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "io/text_file.h"
#include "io/tum.h"
#include "modelling/model_io.h"
#include "perception/point_cloud_ops.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;

nlohmann::ordered_json PoseJson(const Pose3& X) {
  const Eigen::Quaterniond q(X.rotation());
  return {{"t", {X.translation().x(), X.translation().y(), X.translation().z()}},
          {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

}  // namespace

DriveParams RoomMissionParams::DefaultDrive() {
  DriveParams p;
  // Inside one room every NBS candidate lies in mapped free space: no scan-and-go stops (they
  // would be scans the room model never sees).
  p.navigator.max_scans = 1;
  p.navigator.register_scans = false;  // the room loop registers against its own S(t-1)
  return p;
}

void WriteRoomOutputs(const RoomMissionResult& result, const RoomMissionParams& params,
                      const RobotSession& session, const modelling::RoomModel& model,
                      const modelling::StructuralModel& sm3, const modelling::VoxelSpace& dsm3,
                      const std::string& dir, const RoomOutputExtras& extras) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": error: cannot create the output folder; " + ec.message());
  const fs::path d(dir);
  model.WriteSm1((d / "sm1.ply").string());
  io::WriteTextFile((d / "sm2.json").string(), modelling::Sm2Json(model.GetRoi(), sm3.room));
  io::WriteTextFile((d / "sm3.json").string(), modelling::Sm3Json(sm3));
  modelling::WriteDsm3Ply(dsm3, (d / "dsm3.ply").string());
  {
    std::ofstream f(d / "model.json");
    f << model.FiguresJson() << "\n";
  }
  {
    std::ofstream f(d / "scan_poses.tum");
    for (const auto& [t, X] : extras.door_scans) f << io::TumLine(t, X);
    for (const auto& s : result.scans) f << io::TumLine(s.sim_time, s.X_MS);
  }
  const DriveResult drive = session.Result();
  {
    nlohmann::ordered_json j;
    j["scans"] = result.scans.size();
    j["stop_reason"] = result.stop_reason;
    j["registration_failed"] = result.registration_failed;
    j["path_length_m"] = drive.path_length;
    j["contacts"] = drive.contacts;
    j["localisation_rms_m"] = drive.loc_rms;
    j["localisation_max_m"] = drive.loc_max;
    j["sim_time_s"] = result.sim_time;
    j["wall_time_s"] = result.wall_time;
    std::ofstream(d / "summary.json") << j.dump(2) << "\n";
  }
  auto window = [&](const std::vector<TrajectorySample>& all) {
    std::vector<TrajectorySample> out;
    for (const auto& x : all)
      if (x.t >= extras.t_begin && x.t <= extras.t_end) out.push_back(x);
    return out;
  };
  std::ofstream(d / "trajectory_estimated.tum") << ToTum(window(drive.estimated));
  std::ofstream(d / "trajectory_true.tum") << ToTum(window(drive.truth));
  perception::WriteMap(session.Map(), (d / "map.yaml").string());
  {
    std::ofstream f(d / "room.effective.yaml");
    f << YAML::Dump(SaveParams(params)) << "\n";
  }
  nlohmann::ordered_json scans = nlohmann::json::array();
  for (const auto& s : result.scans) {
    nlohmann::ordered_json j;
    j["index"] = s.index;
    j["detail"] = s.detail;
    j["step_deg"] = s.step_deg;
    j["registered"] = s.registered;
    j["sim_time"] = s.sim_time;
    j["X_MS_prior"] = PoseJson(s.X_MS_prior);
    j["X_MS"] = PoseJson(s.X_MS);
    if (s.index > 0 || !s.registration.message.empty()) {
      const auto& r = s.registration;
      j["registration"] = {
          {"ok", r.ok},          {"converged", r.converged},   {"fitness", r.fitness},
          {"rmse", r.rmse},      {"degenerate", r.degenerate}, {"iterations", r.iterations},
          {"message", r.message}};
    }
    j["range_bias"] = {{"applied", s.range_bias.ok},
                       {"bias_m", s.range_bias.bias},
                       {"sigma_m", s.range_bias.sigma},
                       {"message", s.range_bias.message}};
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
    scans.push_back(std::move(j));
  }
  nlohmann::ordered_json out;
  out["scans"] = std::move(scans);
  out["stop_reason"] = result.stop_reason;
  out["detail"] = {{"scans", result.detail_scans},
                   {"sim_time", result.detail_sim_time},
                   {"wall_time", result.detail_wall_time},
                   {"log", result.detail_log}};
  out["registration_failed"] = result.registration_failed;
  out["sim_time"] = result.sim_time;
  out["wall_time"] = result.wall_time;
  std::ofstream(d / "scans.json") << out.dump(2) << "\n";
}

}  // namespace mopad::mission
