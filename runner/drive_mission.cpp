#include "runner/drive_mission.h"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <cstdlib>

#include "common/error.h"
#include "sim/lrf.h"
#include "sim/tls_scanner.h"

namespace mopad::runner {
namespace {

namespace fs = std::filesystem;
using perception::Compose;
using perception::Inverse;
using autonomy::PathPoint;

std::string Fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

// Robot side: a TLS scan's returns in the map frame, using the robot's own pose estimate and
// the calibrated mount. Only points that can matter for the 2D map (floor to band top) are kept.
std::vector<Eigen::Vector3d> ScanPointsInMap(const interfaces::TlsScan& scan, const Pose2& X_MB,
                                             double z_max, std::uint64_t cap) {
  const Pose3 X_MS = X_MB.To3d() * scan.X_BS;
  std::vector<Eigen::Vector3d> out;
  out.reserve(scan.points.size() / 4);
  for (const auto& p : scan.points) {
    if (!p.valid()) continue;
    const Eigen::Vector3d q = X_MS * Eigen::Vector3d(p.x, p.y, p.z);
    if (q.z() < -0.2 || q.z() > z_max) continue;
    out.push_back(q);
    if (out.size() >= cap) break;
  }
  return out;
}

// Robot side: the cell of the map's valid region (clearance >= `clearance`, known free)
// connected to `from` that is nearest to `goal`. Breadth-first over 8-neighbours (deterministic).
// nullopt if `from` has no valid cell within 0.5 m.
std::optional<Vec2> NearestReachable(const perception::OccupancyGrid& grid, const Vec2& from,
                                     const Vec2& goal, double clearance) {
  const perception::DistanceField df(grid, /*unknown_is_obstacle=*/true);
  auto valid = [&](const perception::Cell& c) {
    return grid.Contains(c) && df.IsFree(grid.CentreOf(c), clearance);
  };
  const perception::Cell c0 = grid.CellOf(from);
  const int r = static_cast<int>(std::ceil(0.5 / grid.Resolution()));
  std::optional<perception::Cell> seed;
  double best = 1e18;
  for (int dj = -r; dj <= r; ++dj)
    for (int di = -r; di <= r; ++di) {
      const perception::Cell c{c0.i + di, c0.j + dj};
      if (!valid(c)) continue;
      const double d = (grid.CentreOf(c) - from).squaredNorm();
      if (d < best) best = d, seed = c;
    }
  if (!seed) return std::nullopt;
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(grid.Width()) * grid.Height(), 0);
  std::vector<perception::Cell> queue{*seed};
  seen[grid.Index(*seed)] = 1;
  Vec2 best_p = grid.CentreOf(*seed);
  double best_d = (best_p - goal).norm();
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const perception::Cell c = queue[head];
    const Vec2 p = grid.CentreOf(c);
    const double d = (p - goal).norm();
    if (d < best_d - 1e-9) best_d = d, best_p = p;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const perception::Cell n{c.i + di, c.j + dj};
        if ((di == 0 && dj == 0) || !grid.Contains(n) || seen[grid.Index(n)]) continue;
        seen[grid.Index(n)] = 1;
        if (valid(n)) queue.push_back(n);
      }
  }
  return best_p;
}

// Fraction of the grid cells within `radius` of `p` that are known (free or occupied).
double KnownFraction(const perception::OccupancyGrid& grid, const Vec2& p, double radius) {
  const perception::Cell c0 = grid.CellOf(p);
  const int r = static_cast<int>(std::ceil(radius / grid.Resolution()));
  int known = 0, total = 0;
  for (int dj = -r; dj <= r; ++dj)
    for (int di = -r; di <= r; ++di) {
      const perception::Cell c{c0.i + di, c0.j + dj};
      if ((grid.CentreOf(c) - p).norm() > radius) continue;
      ++total;
      if (grid.State(c) != perception::CellState::kUnknown) ++known;
    }
  return total ? static_cast<double>(known) / total : 0.0;
}

double Rms(double sum_sq, std::size_t n) { return n ? std::sqrt(sum_sq / n) : 0.0; }

}  // namespace

sim::RobotBodyParams DriveParams::DefaultBody() {
  sim::RobotBodyParams p;
  // A few per mille of calibration error and slip: odometry alone drifts decimetres over 50 m.
  p.odometry.left_radius_error = 0.004;
  p.odometry.right_radius_error = -0.003;
  p.odometry.track_width_error = 0.01;
  p.odometry.slip_sigma = 0.003;
  return p;
}

perception::AmclParams DriveParams::DefaultAmcl() {
  perception::AmclParams p;
  p.min_particles = 300;
  p.max_particles = 3000;
  // No random-particle injection while tracking: offices repeat (two equal rooms look alike),
  // and a random particle in the twin room can win one poor update. Real loss is still caught
  // by the inlier test, which starts a global re-localisation.
  p.recovery_alpha_slow = 0.0;
  return p;
}

autonomy::GlobalPlannerParams DriveParams::DefaultPlanner() {
  autonomy::GlobalPlannerParams p;
  // The planner's disc is smaller than the 0.6 x 0.5 m box; 5 cm more keeps the corners off
  // furniture the base LRF cannot see (desk tops) and still passes 0.9 m doors (clearance 0.42).
  p.robot_radius = 0.35;
  return p;
}

autonomy::LocalControllerParams DriveParams::DefaultController() {
  autonomy::LocalControllerParams p;
  // 3 cm around the box (not 6): a 0.5 m wide base keeps 0.17 m a side in a 0.9 m door, enough
  // for the docking error at a doorway scan position. Contacts are still counted by the body.
  p.safety_margin = 0.03;
  return p;
}

const char* ToString(DriveStatus s) {
  switch (s) {
    case DriveStatus::kArrived: return "arrived";
    case DriveStatus::kUnreachable: return "unreachable";
    case DriveStatus::kBlocked: return "blocked";
    case DriveStatus::kLocalisationLost: return "localisation_lost";
    case DriveStatus::kTimeout: return "timeout";
  }
  return "?";
}

DriveResult RunDrive(const sim::EmbreeWorld& world, const DriveParams& params,
                     const DriveRequest& request) {
  ValidateParams(params, "drive.");
  const auto wall_start = std::chrono::steady_clock::now();
  DriveResult res;

  // ---- World side: body on the scene triangles (door leaves as the world has them), sensors.
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> triangles;
  for (const auto& part : world.scene().parts) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), part.positions.begin(), part.positions.end());
    for (const auto& t : part.triangles)
      for (int k = 0; k < 3; ++k) triangles.push_back(base + static_cast<std::uint32_t>(t[k]));
  }
  sim::RobotBody body(params.body, vertices, triangles, request.X_WB_start, request.seed);
  if (body.InCollision(request.X_WB_start))
    throw InputError("drive: start pose (" + Fmt("%.3f, %.3f", request.X_WB_start.x,
                                                 request.X_WB_start.y) +
                     ") is in collision with the scene");
  sim::TlsParams tls_params = sim::TlsProfile(params.tls_profile);
  tls_params.step_deg = params.tls_step_deg;
  sim::TlsScanner tls(world, tls_params);
  std::optional<sim::LrfSimulator> lrf_top, lrf_base;
  for (const auto& lp : sim::PaperLrfRig(params.lrf_profile)) {
    if (lp.frame == "lrf_top") lrf_top.emplace(world, lp);
    if (lp.frame == "lrf_base") lrf_base.emplace(world, lp);
  }
  if (!lrf_top || !lrf_base) throw std::runtime_error("drive: LRF rig lacks lrf_top/lrf_base");
  const Pose2 X_MW = Inverse(request.X_WB_start);  // evaluation only: truth into the map frame

  // ---- Robot side state. The goal is handed over in the robot's map frame (start = origin).
  const Pose2 goal_M = Compose(X_MW, request.X_WB_goal);
  res.goal_M = goal_M;
  std::vector<std::vector<Eigen::Vector3d>> batches;  // the robot's own map points, per scan
  std::vector<std::pair<interfaces::LrfScan, Pose2>> map_sweeps;  // LRF sweeps at scan poses
  perception::OccupancyGrid grid(params.grid, Vec2::Zero(), 1, 1);
  std::optional<perception::Amcl> amcl;
  std::optional<autonomy::GlobalPlanner> planner;
  double best_scan_target_dist = 1e18;
  autonomy::LocalController controller(params.controller);
  Pose2 target_M = goal_M;
  bool final_leg = true;
  std::uint64_t amcl_epoch = 0;

  double t = 0.0;
  std::uint64_t base_seq = 0, top_seq = 0;
  const double base_period = 1.0 / lrf_base->params().rate_hz;
  const double top_period = 1.0 / lrf_top->params().rate_hz;
  double next_base = 0.0, next_top = 0.0;
  interfaces::LrfScan base_scan, top_scan;
  Pose2 X_MB_est{};  // map frame := start pose

  auto sweep = [&](bool force) {
    const Pose3 X_WB = body.TruePose().To3d();
    bool top_new = false;
    if (force || t + 1e-9 >= next_base) {
      base_scan = lrf_base->Scan(X_WB, request.seed, base_seq++, t);
      next_base += base_period;
      ++res.lrf_sweeps;
    }
    if (force || t + 1e-9 >= next_top) {
      top_scan = lrf_top->Scan(X_WB, request.seed, top_seq++, t);
      next_top += top_period;
      ++res.lrf_sweeps;
      top_new = true;
    }
    return top_new;
  };

  // TLS scan at the current pose, registered with the robot's estimate; map rebuilt from all
  // scans; AMCL restarted on the new map about the current estimate.
  auto take_tls_scan = [&] {
    sim::ScanRequest req;
    req.seed = request.seed;
    req.scan_id = static_cast<std::uint64_t>(res.tls_scans);
    req.start_time = t;
    req.X_WB = body.TruePose().To3d();
    req.X_MS_estimate = X_MB_est.To3d() * tls.X_BS();
    const interfaces::TlsScan scan = tls.Scan(req);  // crosses the boundary: a plain TlsScan
    ++res.tls_scans;
    res.scan_poses.push_back(X_MB_est);
    batches.push_back(ScanPointsInMap(scan, X_MB_est, params.grid.obstacle_z_max + 0.1,
                                      params.max_points_per_scan));
    std::vector<Eigen::Vector3d> extent;
    for (const auto& b : batches) extent.insert(extent.end(), b.begin(), b.end());
    extent.emplace_back(goal_M.x, goal_M.y, 0.0);
    extent.emplace_back(0.0, 0.0, 0.0);
    grid = perception::OccupancyGrid::Covering(params.grid, extent, params.map_margin);
    for (const auto& b : batches) grid.InsertPoints(b);
    // The TLS cannot see the floor near the base: the LRF sweeps taken here trace free space
    // (and mark returns), and the footprint the robot stands on is free.
    map_sweeps.emplace_back(base_scan, X_MB_est);
    map_sweeps.emplace_back(top_scan, X_MB_est);
    for (const auto& [sweep_scan, X_MB] : map_sweeps) grid.InsertScan(sweep_scan, X_MB);
    for (const Pose2& s : res.scan_poses) {
      const double r = 0.5 * params.body.footprint_width;
      grid.FillBox(Vec2(s.x - r, s.y - r), Vec2(s.x + r, s.y + r), perception::CellState::kFree);
    }
    const double sxy = params.initial_sigma_xy, syaw = DegToRad(params.initial_sigma_yaw_deg);
    amcl.emplace(grid, params.amcl, request.seed * 1000003ULL + amcl_epoch++);
    amcl->SetInitialPose(X_MB_est, Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal());
    if (!planner)
      planner.emplace(grid, params.planner, request.seed);
    else
      planner->SetMap(grid);
  };

  auto finish = [&](DriveStatus s, const std::string& msg) {
    res.status = s;
    res.message = msg;
  };

  // Plans the next leg: the goal plan, driven to the end only if the map around every path
  // point is well known; else only as far as it is, then a scan. A goal outside the known free
  // space: drive to the reachable point nearest to it and scan. False = finished (status set).
  auto install = [&](const autonomy::GlobalPlan& plan, bool final) {
    final_leg = final;
    target_M = plan.path.back().pose;
    std::vector<Pose2> poses;
    for (const auto& p : plan.path) poses.push_back(p.pose);
    res.plans.push_back(std::move(poses));
    if (params.trace) {
      std::fprintf(stderr, "t=%.2f plan to (%.2f %.2f) final=%d len %.2f minclr %.2f passages %zu\n", t,
                   target_M.x, target_M.y, final, plan.length, plan.min_clearance, plan.passages.size());
      for (const auto& q : plan.passages)
        std::fprintf(stderr, "  passage (%.2f %.2f) yaw %.2f width %.2f s %.2f\n", q.centre.x(), q.centre.y(),
                     q.axis_yaw, q.width, q.s);
    }
    controller.SetPlan(plan);
  };
  auto plan_leg = [&]() -> bool {
    autonomy::GlobalPlan plan = planner->Plan(X_MB_est, goal_M);
    std::string why;
    if (!plan.ok()) {
      why = std::string(autonomy::ToString(plan.status)) + ": " + plan.message;
      if (plan.status == autonomy::PlanStatus::kStartInvalid) {
        finish(DriveStatus::kBlocked, "cannot leave the current pose: " + why);
        return false;
      }
    }
    auto well_known = [&](const PathPoint& q) {
      // Around a scan position the TLS cannot see the floor (blind cone); the LRF sweeps taken
      // there cover it.
      for (const Pose2& sp : res.scan_poses)
        if (std::hypot(q.pose.x - sp.x, q.pose.y - sp.y) < params.scan_blind_radius) return true;
      return KnownFraction(grid, Vec2(q.pose.x, q.pose.y), params.goal_known_radius) >=
             params.goal_known_fraction;
    };
    const bool all_known = plan.ok() && std::all_of(plan.path.begin(), plan.path.end(), well_known);
    if (all_known || (plan.ok() && res.tls_scans >= params.max_scans)) {
      install(plan, true);
      return true;
    }
    if (res.tls_scans >= params.max_scans) {
      finish(DriveStatus::kUnreachable,
             "no route to the goal after " + std::to_string(res.tls_scans) + " scans (" + why + ")");
      return false;
    }
    if (plan.ok()) {
      // Drive along the plan only as far as the map is well known (typically into the doorway
      // of the next room) and scan there: AMCL cannot track in a room the map lacks.
      std::size_t k = 0;
      while (k + 1 < plan.path.size() && well_known(plan.path[k + 1])) ++k;
      // A cut inside a doorway is hard to dock at from an angle: scan first in front of it
      // (clearance >= robot_radius + doorway_margin), and from the doorway only when already
      // there (the short straight approach from in front of it).
      std::size_t kb = k;
      while (kb > 0 && plan.path[kb].clearance < params.planner.robot_radius + params.doorway_margin) --kb;
      if (plan.path[kb].s >= params.min_scan_progress) k = kb;
      if (k + 1 >= plan.path.size() || plan.path[k].s < params.min_scan_progress) {
        install(plan, true);
        return true;
      }
      plan.path.resize(k + 1);
      std::erase_if(plan.passages, [&](const autonomy::Passage& q) { return q.s > plan.path[k].s; });
      plan.length = plan.path[k].s;
      install(plan, false);
      return true;
    }
    // The goal is not in the known free space: go to the reachable point nearest to it, scan.
    const Vec2 g(goal_M.x, goal_M.y);
    const auto near = NearestReachable(grid, Vec2(X_MB_est.x, X_MB_est.y), g, params.scan_target_clearance);
    const double d = near ? (*near - g).norm() : 1e18;
    if (!near || d > best_scan_target_dist - params.min_scan_progress) {
      finish(DriveStatus::kUnreachable,
             "goal not connected to the start in the robot's map after " + std::to_string(res.tls_scans) +
                 " scans (" + why + "); the closest reachable point is " +
                 Fmt("%.2f m from the goal (a closed door or an obstacle blocks the way)", d));
      return false;
    }
    best_scan_target_dist = d;
    const Pose2 t_M{near->x(), near->y(), std::atan2(g.y() - near->y(), g.x() - near->x())};
    autonomy::GlobalPlan to_scan = planner->Plan(X_MB_est, t_M);
    if (!to_scan.ok()) {
      finish(DriveStatus::kUnreachable, std::string("no route to the next scan position: ") +
                                            autonomy::ToString(to_scan.status) + ": " + to_scan.message);
      return false;
    }
    install(to_scan, false);
    return true;
  };
  controller.SetReplanner([&](const Pose2& X_MB, const std::vector<Vec2>& obstacles_M) {
    ++res.replans;
    planner->AddObstacles(obstacles_M);
    autonomy::GlobalPlan p = planner->Plan(X_MB, target_M);
    if (p.ok()) {
      std::vector<Pose2> poses;
      for (const auto& q : p.path) poses.push_back(q.pose);
      res.plans.push_back(std::move(poses));
    }
    return p;
  });

  // ---- Bookkeeping (truth side, evaluation only).
  double loc_sq = 0.0, yaw_sq = 0.0;
  std::size_t loc_n = 0;
  auto record = [&] {
    const Pose2 true_M = Compose(X_MW, body.TruePose());
    res.estimated.push_back({t, X_MB_est});
    res.truth.push_back({t, true_M});
    const double e = std::hypot(X_MB_est.x - true_M.x, X_MB_est.y - true_M.y);
    const double ey = std::abs(WrapAngle(X_MB_est.yaw - true_M.yaw));
    loc_sq += e * e;
    yaw_sq += ey * ey;
    ++loc_n;
    res.loc_max = std::max(res.loc_max, e);
    res.loc_yaw_max_deg = std::max(res.loc_yaw_max_deg, RadToDeg(ey));
  };

  // ---- Start: first scan defines the map frame; LRFs; AMCL's first update; first plan.
  sweep(true);
  take_tls_scan();
  amcl->Update(body.Odometry(), top_scan, /*force=*/true);
  ++res.amcl_updates;
  record();
  bool running = plan_leg();
  Pose2 last_true = body.TruePose();
  bool was_lost = false;
  interfaces::VelocityCommand cmd;

  while (running) {
    if (t >= params.max_time - 1e-9) {
      finish(DriveStatus::kTimeout, Fmt("no arrival within %.1f s of simulation time", params.max_time));
      break;
    }
    body.Step(cmd, params.control_dt);
    t += params.control_dt;
    const Pose2 now_true = body.TruePose();
    res.path_length += std::hypot(now_true.x - last_true.x, now_true.y - last_true.y);
    last_true = now_true;
    const interfaces::Odometry& odom = body.Odometry();
    if (sweep(false)) {
      if (amcl->Update(odom, top_scan).updated) ++res.amcl_updates;
    }
    const auto& est = amcl->Estimate();
    const bool lost = est.status == perception::LocalisationStatus::kLost ||
                      est.status == perception::LocalisationStatus::kRelocalising;
    if (lost && !was_lost) ++res.lost_events;
    if (params.trace && res.estimated.size() % 50 == 0) {
      const Pose2 tm = Compose(X_MW, body.TruePose());
      std::fprintf(stderr, "   amcl est (%.2f %.2f) %s (%s) n=%d inl=%.2f true (%.2f %.2f %.2f) odom (%.2f %.2f)\n", X_MB_est.x, X_MB_est.y, perception::ToString(est.status),
                   est.message.c_str(), est.particles, est.inlier_ratio, tm.x, tm.y, tm.yaw, odom.X_OB.x, odom.X_OB.y);
    }
    was_lost = lost;
    X_MB_est = est.PoseAt(odom.X_OB);
    record();
    const autonomy::ControlOutput out = controller.Update(t, X_MB_est, est.status, base_scan);
    cmd = out.cmd;
    if (params.trace && (res.estimated.size() % 50 == 0 || out.finished))
      std::fprintf(stderr, "t=%.2f est (%.2f %.2f %.2f) %s: %s\n", t, X_MB_est.x, X_MB_est.y, X_MB_est.yaw,
                   autonomy::ToString(out.status), out.message.c_str());
    if (!out.finished) continue;
    switch (out.status) {
      case autonomy::NavStatus::kArrived:
        if (final_leg) {
          finish(DriveStatus::kArrived, out.message);
          running = false;
        } else {
          cmd = {};
          take_tls_scan();
          if (amcl->Update(body.Odometry(), top_scan, true).updated) ++res.amcl_updates;
          running = plan_leg();
        }
        break;
      case autonomy::NavStatus::kUnreachable:
        finish(DriveStatus::kUnreachable, out.message);
        running = false;
        break;
      case autonomy::NavStatus::kLocalisationLost:
        finish(DriveStatus::kLocalisationLost, out.message);
        running = false;
        break;
      default:
        finish(DriveStatus::kBlocked, out.message);
        running = false;
        break;
    }
  }

  // ---- Figures.
  res.map = grid;
  res.sim_time = t;
  res.final_true_M = Compose(X_MW, body.TruePose());
  res.goal_error_xy = std::hypot(res.final_true_M.x - goal_M.x, res.final_true_M.y - goal_M.y);
  res.goal_error_yaw_deg = RadToDeg(std::abs(WrapAngle(res.final_true_M.yaw - goal_M.yaw)));
  res.loc_rms = Rms(loc_sq, loc_n);
  res.loc_yaw_rms_deg = RadToDeg(Rms(yaw_sq, loc_n));
  res.contacts = body.ContactCount();
  res.contact_events = body.Contacts();
  res.blocked_steps = body.BlockedSteps();
  res.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return res;
}

std::string ToTum(const std::vector<TrajectorySample>& samples) {
  std::string out;
  char buf[160];
  for (const auto& s : samples) {
    std::snprintf(buf, sizeof buf, "%.3f %.6f %.6f 0.000000 0.000000 0.000000 %.9f %.9f\n", s.t,
                  s.pose.x, s.pose.y, std::sin(0.5 * s.pose.yaw), std::cos(0.5 * s.pose.yaw));
    out += buf;
  }
  return out;
}

void WriteDriveOutputs(const DriveResult& r, const DriveParams& params, const DriveRequest& request,
                       const std::string& dir_str) {
  const fs::path dir(dir_str);
  fs::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream f(dir / name, std::ios::binary);
    f << text;
    if (!f) throw InputError((dir / name).string() + ": error: cannot write");
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
  if (!cv::imwrite((dir / "map_path.png").string(), img))
    throw InputError((dir / "map_path.png").string() + ": error: cannot write");

  nlohmann::ordered_json j;
  j["status"] = ToString(r.status);
  j["message"] = r.message;
  j["seed"] = request.seed;
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
    j["contact_events"].push_back({{"time_s", c.time}, {"X_WB", {c.X_WB.x, c.X_WB.y, c.X_WB.yaw}},
                                   {"speed_mps", c.speed}, {"impulse_Ns", c.impulse}});
  j["blocked_steps"] = r.blocked_steps;
  j["path_length_m"] = r.path_length;
  j["tls_scans"] = r.tls_scans;
  j["lrf_sweeps"] = r.lrf_sweeps;
  j["amcl_updates"] = r.amcl_updates;
  j["plans"] = r.plans.size();
  j["replans"] = r.replans;
  j["sim_time_s"] = r.sim_time;
  j["wall_time_s"] = r.wall_time;
  j["real_time_factor"] = r.RealTimeFactor();
  j["frames"] = "map = robot start pose; trajectories in map; truth expressed in map via X_WB(0)^-1";
  write("summary.json", j.dump(2) + "\n");
  write("drive.effective.yaml", YAML::Dump(SaveParams(params)) + "\n");
}

}  // namespace mopad::runner
