#include "mission/drive_mission.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "common/atomic_file.h"
#include "common/error.h"
#include "io/image_codec.h"
#include "io/tum.h"
#include "mission/robot_session.h"
#include "sim/lrf.h"
#include "sim/tls_params.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;
using perception::Compose;

// "a, b, c" for an error message.
std::string JoinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

void DriveParams::Validate() const {
  const std::vector<std::string> tls = sim::TlsProfileNames(), lrf = sim::LrfProfileNames();
  if (std::find(tls.begin(), tls.end(), tls_profile) == tls.end())
    throw InputError("", "parameter 'tls_profile' unknown", "'" + tls_profile + "'",
                     "one of " + JoinNames(tls));
  if (std::find(lrf.begin(), lrf.end(), lrf_profile) == lrf.end())
    throw InputError("", "parameter 'lrf_profile' unknown", "'" + lrf_profile + "'",
                     "one of " + JoinNames(lrf));
}

DriveResult RunDrive(const sim::EmbreeWorld& world, const DriveParams& params,
                     const DriveRequest& request) {
  RobotSession session(world, params, request.X_WB_start);
  session.SetKeepScanTruths(false);
  // The goal is handed over in the robot's map frame (map := the start pose).
  const Pose2 goal_M = Compose(session.X_MW(), request.X_WB_goal);
  session.ExtendMap(Vec2(goal_M.x, goal_M.y));
  if (request.kidnap_time > 0.0) session.ScheduleTeleport(request.kidnap_time, request.kidnap_to);
  for (const Pose2& v : request.via) {
    const Pose2 v_M = Compose(session.X_MW(), v);
    session.ExtendMap(Vec2(v_M.x, v_M.y));
  }
  session.TakeScan();
  std::string message;
  for (std::size_t k = 0; k < request.via.size(); ++k) {
    const DriveStatus s = session.NavigateTo(Compose(session.X_MW(), request.via[k]), &message);
    if (s != DriveStatus::kArrived) {
      DriveResult r = session.Result();
      r.message = "waypoint " + std::to_string(k + 1) + ": " + r.message;
      r.goal_M = goal_M;  // figures against the mission's goal
      r.goal_error_xy = std::hypot(r.final_true_M.x - goal_M.x, r.final_true_M.y - goal_M.y);
      r.goal_error_yaw_deg = RadToDeg(std::abs(WrapAngle(r.final_true_M.yaw - goal_M.yaw)));
      return r;
    }
  }
  session.NavigateTo(goal_M);
  return session.Result();
}

std::string ToTum(const std::vector<TrajectorySample>& samples) {
  std::string out;
  for (const auto& s : samples) out += io::TumLinePlanar(s.t, s.pose.x, s.pose.y, s.pose.yaw);
  return out;
}

void WriteDriveOutputs(const DriveResult& r, const DriveParams& params, const DriveRequest& request,
                       const std::string& dir_str) {
  const fs::path dir(dir_str);
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    WriteWholeFile((dir / name).string(), text);
  };
  write("trajectory_estimated.tum", ToTum(r.estimated));
  write("trajectory_true.tum", ToTum(r.truth));
  perception::WriteMap(r.map, (dir / "map.yaml").string());

  // map_path.png: the map (2 px per cell) with plans (blue), truth (green), estimate (red),
  // scan positions (orange) and the goal (magenta).
  const int k = 2;
  const auto& g = r.map;
  cv::Mat img(g.Height() * k, g.Width() * k, CV_8UC3);
  for (int j = 0; j < g.Height(); ++j)
    for (int i = 0; i < g.Width(); ++i) {
      const auto s = g.State({i, j});
      const cv::Vec3b c = s == perception::CellState::kOccupied ? cv::Vec3b(0, 0, 0)
                          : s == perception::CellState::kFree   ? cv::Vec3b(254, 254, 254)
                                                                : cv::Vec3b(205, 205, 205);
      img(cv::Rect(i * k, (g.Height() - 1 - j) * k, k, k)).setTo(c);
    }
  auto px = [&](const Pose2& p) {
    return cv::Point(static_cast<int>((p.x - g.Origin().x()) / g.Resolution() * k),
                     static_cast<int>((g.Height() - (p.y - g.Origin().y()) / g.Resolution()) * k));
  };
  auto poly = [&](const std::vector<Pose2>& ps, cv::Scalar colour) {
    for (std::size_t i = 1; i < ps.size(); ++i) cv::line(img, px(ps[i - 1]), px(ps[i]), colour, 1);
  };
  for (const auto& p : r.plans) poly(p, {255, 128, 0});
  std::vector<Pose2> tr, es;
  for (const auto& s : r.truth) tr.push_back(s.pose);
  for (const auto& s : r.estimated) es.push_back(s.pose);
  poly(tr, {0, 160, 0});
  poly(es, {0, 0, 220});
  for (const auto& s : r.scan_poses) cv::circle(img, px(s), 5, {0, 140, 255}, 2);
  cv::circle(img, px(r.goal_M), 5, {255, 0, 255}, 2);
  WriteWholeFile((dir / "map_path.png").string(),
                 io::EncodePng({img.data, img.cols, img.rows, img.channels(), 8, img.step}));

  nlohmann::ordered_json j;
  j["status"] = ToString(r.status);
  j["message"] = r.message;
  j["seed"] = params.seed;
  j["start_world"] = {request.X_WB_start.x, request.X_WB_start.y, request.X_WB_start.yaw};
  j["goal_world"] = {request.X_WB_goal.x, request.X_WB_goal.y, request.X_WB_goal.yaw};
  j["goal_map"] = {r.goal_M.x, r.goal_M.y, r.goal_M.yaw};
  j["final_true_map"] = {r.final_true_M.x, r.final_true_M.y, r.final_true_M.yaw};
  j["final_error_xy_m"] = r.goal_error_xy;
  j["final_error_yaw_deg"] = r.goal_error_yaw_deg;
  j["localisation_error_rms_m"] = r.loc_rms;
  j["localisation_error_max_m"] = r.loc_max;
  j["localisation_yaw_error_rms_deg"] = r.loc_yaw_rms_deg;
  j["localisation_yaw_error_max_deg"] = r.loc_yaw_max_deg;
  j["localisation_lost_events"] = r.lost_events;
  j["contacts"] = r.contacts;
  j["contact_events"] = nlohmann::json::array();
  for (const auto& c : r.contact_events)
    j["contact_events"].push_back({{"time_s", c.time},
                                   {"X_WB", {c.X_WB.x, c.X_WB.y, c.X_WB.yaw}},
                                   {"speed_mps", c.speed},
                                   {"impulse_Ns", c.impulse}});
  j["blocked_steps"] = r.blocked_steps;
  j["path_length_m"] = r.path_length;
  j["tls_scans"] = r.tls_scans;
  j["lrf_sweeps"] = r.lrf_sweeps;
  j["amcl_updates"] = r.amcl_updates;
  j["plans"] = r.plans.size();
  j["replans"] = r.replans;
  j["teleports"] = r.teleports;
  j["scan_registration"] = {{"ok", r.scan_registrations_ok},
                            {"degenerate_used", r.scan_registrations_degenerate},
                            {"failed", r.scan_registrations_failed},
                            {"messages", r.scan_registration_messages}};
  j["tls_time_s"] = r.tls_time;
  j["tls_wall_time_s"] = r.tls_wall_time;
  j["sim_time_s"] = r.sim_time;
  j["wall_time_s"] = r.wall_time;
  j["real_time_factor"] = r.RealTimeFactor();
  j["frames"] =
      "map = robot start pose; trajectories in map; truth expressed in map via X_WB(0)^-1";
  write("summary.json", j.dump(2) + "\n");
  write("drive.effective.yaml", YAML::Dump(SaveParams(params)) + "\n");
}

}  // namespace mopad::mission
