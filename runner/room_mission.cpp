#include "runner/room_mission.h"

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "modelling/model_io.h"
#include "perception/point_cloud_ops.h"

namespace mopad::runner {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string TumLine(double t, const Pose3& X) {
  const Eigen::Quaterniond q(X.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", t, X.translation().x(),
                X.translation().y(), X.translation().z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

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
  p.max_scans = 1;
  p.register_scans = false;  // RunRoomMission registers against its own S(t-1)
  return p;
}

autonomy::NextBestScanParams RoomMissionParams::DefaultNbs() {
  autonomy::NextBestScanParams p;
  // The planner only accepts goals in known free space (unknown counts as obstacle there), so
  // the NBS candidates must come from the same space.
  p.unknown_is_obstacle = true;
  p.angular_step_deg = 0.2;  // RunRoomMission sets it to scan_step_deg
  return p;
}

perception::IcpParams RoomMissionParams::DefaultIcp() {
  perception::IcpParams p = DriveParams::DefaultIcp();
  // The room acceptance (issue 5) was measured with these.
  p.min_fitness = 0.3;
  p.max_free_space_violation = perception::IcpParams{}.max_free_space_violation;
  return p;
}

RoomMissionResult RunRoomMission(RobotSession& session, const RoomMissionParams& params,
                                 modelling::RoomModel& model, const ScanHook& on_scan) {
  ValidateParams(params, "room.");
  params.icp.Validate();
  autonomy::NextBestScanParams nbs_params = params.nbs;
  nbs_params.angular_step_deg = params.scan_step_deg;  // the sensing chance uses the real step
  const auto wall0 = Clock::now();
  RoomMissionResult res;
  perception::PointMap target(params.icp);
  std::vector<Vec2> failed_scans;  // base positions whose scan could not be registered

  for (int k = 0; k < params.max_scans; ++k) {
    RoomScanLog log;
    log.index = k;
    auto t0 = Clock::now();
    const interfaces::TlsScan& scan = session.TakeScan(params.scan_step_deg);
    log.t_scan = Since(t0);
    log.session_scan = session.ScanCount() - 1;
    log.sim_time = session.SimTime();
    log.X_MS_prior = scan.X_MS_estimate;
    log.X_MS = scan.X_MS_estimate;

    // Registration (paper step (3)): the first scan defines the map; later ones are refined
    // against the accumulated cloud S(t-1) from the odometry/AMCL prior.
    t0 = Clock::now();
    const perception::Points source_S = perception::ScanPoints(scan);
    if (k > 0) {
      log.registration = perception::RegisterScan(source_S, target, log.X_MS_prior, params.icp);
      log.registered = log.registration.ok;
      if (log.registration.ok) {
        log.X_MS = log.registration.X_MS;
        session.CorrectLastScanPose(log.X_MS);
      } else {
        res.registration_failed = true;
        const Pose2 here = session.EstimatedPose();
        failed_scans.emplace_back(here.x, here.y);
      }
    }
    // A scan that could not be registered stays out of S(t) and of the model (it would smear
    // both by the prior's error); the mission goes on from the next best scan.
    if (log.registered) {
      target.Add(perception::Transform(source_S, log.X_MS), log.X_MS.translation());
      log.t_registration = Since(t0);
      // Preprocessing, RoI, voxels, coverage (steps (3)-(5)).
      t0 = Clock::now();
      model.AddScan(scan, log.X_MS);
      log.t_model = Since(t0);
      if (on_scan) on_scan(log.session_scan, scan);
    } else {
      log.t_registration = Since(t0);
    }
    // The stopping rule (step (6)).
    log.coverage = model.Coverage();
    const modelling::StopDecision stop = modelling::CheckStopping(log.coverage, params.stopping);
    log.stop_message = stop.message;
    if (stop.stop) {
      res.stop_reason = stop.message;
      res.scans.push_back(std::move(log));
      break;
    }
    if (k + 1 == params.max_scans) {
      res.stop_reason = "stop: scan cap of " + std::to_string(params.max_scans) +
                        " reached (" + stop.message + ")";
      res.scans.push_back(std::move(log));
      break;
    }

    // Next best scan (step (1)) and the drive there (step (2)). When the robot cannot reach the
    // chosen candidate, the next best ones (by expected gain) are tried.
    bool moved = false;
    t0 = Clock::now();
    const autonomy::NbsResult nbs =
        autonomy::NextBestScan(model, session.Map(), session.EstimatedPose(), nbs_params);
    log.t_nbs = Since(t0);
    log.candidates = static_cast<int>(nbs.candidates.size());
    log.nav_message = nbs.message;
    // The paper's epsilon2 applied before moving: a scan expected to add less than epsilon2 of
    // the structural area is not worth the drive.
    const double min_gain = params.stopping.epsilon2 * log.coverage.total_area;
    if (nbs.found && nbs.expected_gain < min_gain) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "stop: best expected gain %.2f m2 < epsilon2 x estimated total (%.2f m2)",
                    nbs.expected_gain, min_gain);
      res.stop_reason = buf;
      res.scans.push_back(std::move(log));
      break;
    }
    auto spent = [&](int i) {
      for (const Vec2& f : failed_scans)
        if ((nbs.candidates[i].position - f).norm() < params.failed_scan_exclusion) return true;
      return false;
    };
    std::vector<int> order;
    if (nbs.found) {
      if (!spent(nbs.chosen)) order.push_back(nbs.chosen);
      std::vector<int> rest;
      for (int i = 0; i < static_cast<int>(nbs.candidates.size()); ++i)
        if (i != nbs.chosen && nbs.candidates[i].gain > 0 && !spent(i)) rest.push_back(i);
      std::stable_sort(rest.begin(), rest.end(), [&](int a, int b) {
        return nbs.candidates[a].gain > nbs.candidates[b].gain;
      });
      order.insert(order.end(), rest.begin(), rest.end());
    }
    for (int attempt = 0; attempt < params.nav_attempts &&
                          attempt < static_cast<int>(order.size()) && !moved;
         ++attempt) {
      const autonomy::NbsCandidate& c = nbs.candidates[order[attempt]];
      const Pose2 goal{c.position.x(), c.position.y(),
                       order[attempt] == nbs.chosen ? nbs.goal.yaw : session.EstimatedPose().yaw};
      log.has_next = true;
      log.next_goal = goal;
      log.expected_gain = c.gain;
      t0 = Clock::now();
      std::string msg;
      const DriveStatus st = session.NavigateTo(goal, &msg);
      log.t_drive += Since(t0);
      log.nav_status = ToString(st);
      log.nav_message = msg;
      if (st == DriveStatus::kArrived) moved = true;
      if (st == DriveStatus::kLocalisationLost) break;
    }
    res.scans.push_back(std::move(log));
    if (!moved) {
      const RoomScanLog& last = res.scans.back();
      res.stop_reason = "stop: no reachable next-best-scan position (" +
                        (last.nav_message.empty() ? std::string("no candidate") : last.nav_message) +
                        ")";
      break;
    }
  }
  res.sim_time = session.SimTime();
  res.wall_time = Since(wall0);
  return res;
}

modelling::StructuralModel BuildRoomSm3(const modelling::RoomModel& model,
                                        const modelling::Sm3Params& params,
                                        const std::string& room) {
  const auto& labels = model.Labels();
  const auto& pts = model.Points();
  std::size_t inliers = 0;
  for (auto l : labels) inliers += l == modelling::PointLabel::kInlier;
  const std::size_t stride = std::max<std::size_t>(1, inliers / 1000000);
  std::vector<Eigen::Vector3d> in;
  in.reserve(inliers / stride + 1);
  std::size_t n = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (labels[i] == modelling::PointLabel::kInlier && n++ % stride == 0)
      in.push_back(pts[i].cast<double>());
  modelling::Sm3Input input;
  input.room = room;
  input.points = &in;
  input.perimeter = model.Perimeter();
  input.columns = model.Columns();
  return modelling::BuildStructuralModel(input, params);
}

void WriteRoomOutputs(const RoomMissionResult& result, const RoomMissionParams& params,
                      const RobotSession& session, const modelling::RoomModel& model,
                      const modelling::StructuralModel& sm3, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": error: cannot create the output folder; " + ec.message());
  const fs::path d(dir);
  model.WriteSm1((d / "sm1.ply").string());
  modelling::WriteTextFile((d / "sm2.json").string(), modelling::Sm2Json(model.GetRoi(), sm3.room));
  modelling::WriteTextFile((d / "sm3.json").string(), modelling::Sm3Json(sm3));
  modelling::WriteDsm3Ply(model.Voxels(), (d / "dsm3.ply").string());
  {
    std::ofstream f(d / "model.json");
    f << model.FiguresJson() << "\n";
  }
  {
    std::ofstream f(d / "scan_poses.tum");
    for (const auto& s : result.scans) f << TumLine(s.sim_time, s.X_MS);
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
  std::ofstream(d / "trajectory_estimated.tum") << ToTum(drive.estimated);
  std::ofstream(d / "trajectory_true.tum") << ToTum(drive.truth);
  perception::WriteMap(session.Map(), (d / "map.yaml").string());
  {
    std::ofstream f(d / "room.effective.yaml");
    f << YAML::Dump(SaveParams(params)) << "\n";
  }
  nlohmann::ordered_json scans = nlohmann::json::array();
  for (const auto& s : result.scans) {
    nlohmann::ordered_json j;
    j["index"] = s.index;
    j["registered"] = s.registered;
    j["sim_time"] = s.sim_time;
    j["X_MS_prior"] = PoseJson(s.X_MS_prior);
    j["X_MS"] = PoseJson(s.X_MS);
    if (s.index > 0) {
      const auto& r = s.registration;
      j["registration"] = {{"ok", r.ok},           {"converged", r.converged},
                           {"fitness", r.fitness}, {"rmse", r.rmse},
                           {"degenerate", r.degenerate}, {"iterations", r.iterations},
                           {"message", r.message}};
    }
    j["coverage"] = {{"ratio", s.coverage.ratio},
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
    j["seconds"] = {{"scan", s.t_scan},   {"registration", s.t_registration},
                    {"model", s.t_model}, {"nbs", s.t_nbs},
                    {"processing", s.t_registration + s.t_model + s.t_nbs},
                    {"drive", s.t_drive}};
    scans.push_back(std::move(j));
  }
  nlohmann::ordered_json out;
  out["scans"] = std::move(scans);
  out["stop_reason"] = result.stop_reason;
  out["registration_failed"] = result.registration_failed;
  out["sim_time"] = result.sim_time;
  out["wall_time"] = result.wall_time;
  std::ofstream(d / "scans.json") << out.dump(2) << "\n";
}

}  // namespace mopad::runner
