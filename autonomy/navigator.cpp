#include "autonomy/navigator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <set>

#include "autonomy/exploration.h"
#include "common/error.h"
#include "common/format.h"
#include "perception/point_cloud_ops.h"
#include "perception/range_image.h"

namespace mopad::autonomy {
namespace {

using perception::Compose;
using perception::Inverse;

// Robot side: a TLS scan's returns in the map frame, using the robot's own pose estimate and
// the calibrated mount. Only points that can matter for the 2D map (floor to band top) are kept;
// beyond `cap` they are thinned uniformly (every k-th in scan order), never truncated (the grid
// is row-major from the top: a cut would drop the floor rows near the robot).
std::vector<Eigen::Vector3d> ScanPointsInMap(const interfaces::TlsScan& scan, const Pose3& X_MS,
                                             double z_max, std::uint64_t cap) {
  std::vector<Eigen::Vector3d> all;
  all.reserve(scan.points.size() / 2);
  for (const auto& p : scan.points) {
    if (!p.valid()) continue;
    const Eigen::Vector3d q = X_MS * Eigen::Vector3d(p.x, p.y, p.z);
    if (q.z() < -0.2 || q.z() > z_max) continue;
    all.push_back(q);
  }
  if (all.size() <= cap || cap == 0) return all;
  const std::size_t stride = (all.size() + cap - 1) / cap;
  std::vector<Eigen::Vector3d> out;
  out.reserve(all.size() / stride + 1);
  for (std::size_t k = 0; k < all.size(); k += stride) out.push_back(all[k]);
  return out;
}

Pose2 Pose2Of(const Pose3& X) {
  const Eigen::Vector3d x_axis = X.linear().col(0);
  return Pose2{X.translation().x(), X.translation().y(), std::atan2(x_axis.y(), x_axis.x())};
}

ExplorationParams ExplorationParamsOf(const NavigatorParams& p) {
  ExplorationParams e;
  e.pass_clearance = p.planner.robot_radius;
  e.target_clearance = p.scan_target_clearance;
  e.exclusion = p.frontier_exclusion;
  e.blind_radius = p.scan_blind_radius;
  e.unknown_cost = p.exploration_unknown_cost;
  return e;
}

}  // namespace

const char* ToString(DriveStatus s) {
  switch (s) {
    case DriveStatus::kArrived:
      return "arrived";
    case DriveStatus::kUnreachable:
      return "unreachable";
    case DriveStatus::kBlocked:
      return "blocked";
    case DriveStatus::kLocalisationLost:
      return "localisation_lost";
    case DriveStatus::kTimeout:
      return "timeout";
  }
  return "?";
}

struct Navigator::Impl {
  static constexpr int kMaxMapReplans = 30;  // per NavigateTo

  interfaces::RobotPlatform& platform;
  NavigatorParams params;
  std::uint64_t seed;

  interfaces::TlsScan last_scan;
  perception::RangeBiasEstimate last_range_bias;
  // The robot's own map points as grid evidence, one per scan (band and floor cells, the cells
  // its low beams clear), made once: a rebuild does not go back to the points.
  std::vector<perception::CloudEvidence> clouds;
  std::optional<perception::PointMap> scan_map;       // ICP target: every scan (register_scans)
  struct MapSweep {
    interfaces::LrfScan scan;
    Pose2 X_MB;
  };
  std::vector<MapSweep> map_sweeps;  // the two LRF sweeps taken at each scan pose
  // The sweeps taken while driving, accumulated once in a grid of their own (log-odds, returns)
  // on the map's cell lattice, covering the map and map_lrf_range around it; laid over the
  // scans' map (Compose) rather than traced again at every rebuild.
  std::optional<perception::OccupancyGrid> driving;
  double next_map_sweep = 0.0;       // s, next driving sweep into the map
  bool leg_blocked = false;          // the driving sweeps put an obstacle on the leg
  std::vector<Eigen::Vector3d> extent_extra{Eigen::Vector3d::Zero()};  // map must cover these
  perception::OccupancyGrid grid{perception::OccupancyGridParams{}, Vec2::Zero(), 1, 1};
  perception::OccupancyGrid localiser_grid = grid;  // AMCL's: without the driving sweeps
  std::optional<perception::Amcl> amcl;
  std::optional<GlobalPlanner> planner;
  std::optional<LocalController> controller;
  std::uint64_t amcl_epoch = 0;
  Pose2 goal_M{};
  Pose2 target_M{};
  bool final_leg = true;
  int nav_scans = 0;           // scans taken by the current NavigateTo
  int relegs = 0;              // legs planned again by the current NavigateTo since its last scan
  int map_replans = 0;         // legs replanned because the driving sweeps put an obstacle on them
  bool looked_around = false;  // since the last scan (LookAround)
  std::vector<Vec2> leg_path;  // the path being followed (map)

  double t = 0.0;           // s, platform time
  double call_start = 0.0;  // s, platform time when the current NavigateTo began
  Pose2 X_MB_est{};         // map frame := base_link at the first scan
  interfaces::VelocityCommand cmd;
  bool was_lost = false;
  NavigatorLog log;

  Impl(interfaces::RobotPlatform& p, const NavigatorParams& np, std::uint64_t s)
      : platform(p), params(np), seed(s) {
    ValidateParams(params, "navigator.");
    params.icp.Validate();
    t = platform.Time();
    controller.emplace(params.controller);
    controller->SetReplanner([this](const Pose2& X_MB, const std::vector<Vec2>& obstacles_M) {
      ++log.replans;
      planner->SetMap(grid);  // with the LRF evidence gathered while driving
      planner->AddObstacles(obstacles_M);
      GlobalPlan plan = planner->Plan(X_MB, target_M);
      if (plan.ok()) {
        leg_path.clear();
        for (const auto& q : plan.path) leg_path.emplace_back(q.pose.x, q.pose.y);
        std::vector<Pose2> poses;
        for (const auto& q : plan.path) poses.push_back(q.pose);
        log.plans.push_back(std::move(poses));
      }
      return plan;
    });
    controller->SetMapObstacles(
        [this](const Pose2& X_MB, double radius) { return MapObstaclesNear(X_MB, radius); });
  }

  // Robot side: occupied cells of the map (centres, map frame) within `radius` of the base.
  std::vector<Vec2> MapObstaclesNear(const Pose2& X_MB, double radius) const {
    std::vector<Vec2> out;
    const Vec2 p(X_MB.x, X_MB.y);
    const perception::Cell c0 = grid.CellOf(p);
    const int r = static_cast<int>(std::ceil(radius / grid.Resolution()));
    for (int dj = -r; dj <= r; ++dj)
      for (int di = -r; di <= r; ++di) {
        const perception::Cell c{c0.i + di, c0.j + dj};
        if (!grid.Contains(c) || grid.State(c) != perception::CellState::kOccupied) continue;
        const Vec2 q = grid.CentreOf(c);
        if ((q - p).norm() <= radius) out.push_back(q);
      }
    return out;
  }

  // Robot side: a scan's map points (band and floor, below obstacle_z_max + 0.1 m) as grid
  // evidence, its beams from the scanner centre.
  perception::CloudEvidence CloudOf(const interfaces::TlsScan& scan, const Pose3& X_MS) const {
    const std::vector<Eigen::Vector3d> pts = ScanPointsInMap(
        scan, X_MS, params.grid.obstacle_z_max + 0.1, params.max_points_per_scan);
    const Eigen::Vector3d o = X_MS.translation();
    return perception::OccupancyGrid::Evidence(params.grid, pts, &o);
  }

  // Robot side: what the last scan (taken at X_MS) saw through is gone from the map: the band
  // cells of the earlier clouds whose lowest and highest band points it saw through and the
  // obstacles mapped while driving. The newest look wins: what a scan sees now is there now (a
  // door shut since is an obstacle), what it sees through is gone (a person who walked on).
  void MarkTransients(const Pose3& X_MS) {
    if (!params.transient_points) return;
    const perception::RangeImage image(last_scan, X_MS);
    const double margin = params.transient_margin;
    for (std::size_t i = 0; i + 1 < clouds.size(); ++i)
      for (auto& pc : clouds[i].cells) {
        if (pc.band == 0 || pc.transient) continue;
        // Both of the cell's surfaces it keeps, lowest and highest, gone.
        pc.transient = image.SeesThrough(Eigen::Vector3d(pc.lo[0], pc.lo[1], pc.lo[2]), margin) &&
                       image.SeesThrough(Eigen::Vector3d(pc.hi[0], pc.hi[1], pc.hi[2]), margin);
      }
    // The sweeps mapped while driving: an obstacle there that the scan saw through at the
    // heights of both LRFs is gone; the scans' own evidence decides the cell again.
    if (!driving) return;
    const double z_base = platform.BaseSweep().X_BL.translation().z();
    const double z_top = platform.TopSweep().X_BL.translation().z();
    for (int j = 0; j < driving->Height(); ++j)
      for (int i = 0; i < driving->Width(); ++i) {
        const perception::Cell c{i, j};
        if (driving->State(c) != perception::CellState::kOccupied) continue;
        const Vec2 q = driving->CentreOf(c);
        if (image.SeesThrough(Eigen::Vector3d(q.x(), q.y(), z_base), margin) &&
            image.SeesThrough(Eigen::Vector3d(q.x(), q.y(), z_top), margin))
          driving->SetState(c, perception::CellState::kUnknown);
      }
  }

  // Robot side: one turn on the spot, mapping the LRF sweeps. The LRFs see 270 deg and the TLS
  // nothing within its minimum range (1.5 m for the VZ-400), so a wall close behind the base
  // stays unknown at a scan position, and an optimistic route can leave the room through it
  // (docs/navigation.md, the look-around). Turns as far as the base LRF and the map leave room, up
  // to 360 deg.
  void LookAround() {
    looked_around = true;
    const double start_time = t;
    double turned = 0.0, last_yaw = X_MB_est.yaw;
    // Bounded in time too: a base that does not turn (a wheel caught) must not sit here.
    const double time_limit = start_time + 2.0 * kPi / params.look_around_rate + 5.0;
    while (turned < 2.0 * kPi - 0.05 && t - call_start < params.max_time - 1e-9 && t < time_limit) {
      if (!controller->CanTurn(X_MB_est, platform.BaseSweep(), 0.15)) break;
      cmd = {0.0, params.look_around_rate};
      const perception::LocalisationEstimate& est = StepOnce();
      MapDrivingSweeps(est);
      turned += std::abs(WrapAngle(X_MB_est.yaw - last_yaw));
      last_yaw = X_MB_est.yaw;
    }
    cmd = {};
    if (params.trace)
      std::fprintf(stderr, "t=%.2f looked around: turned %.0f deg in %.1f s\n", t, RadToDeg(turned),
                   t - start_time);
    planner->SetMap(grid);
  }

  // Robot side: the grid from all scans' band points, the LRF sweeps taken at the scan poses
  // (the TLS cannot see the floor near the base) and the footprints stood on (free).
  void RebuildMap() {
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& c : clouds) lo = lo.cwiseMin(c.lo), hi = hi.cwiseMax(c.hi);
    for (const auto& e : extent_extra) lo = lo.cwiseMin(e.head<2>()), hi = hi.cwiseMax(e.head<2>());
    grid = perception::OccupancyGrid::Covering(params.grid, lo, hi, params.map_margin);
    for (const auto& c : clouds) grid.InsertPoints(c);
    // Beams clear the floor they cross (after all band points: those cells stay protected).
    for (const auto& c : clouds) grid.InsertRays(c);
    // AMCL's map: the scans and the sweeps taken at scan positions only. The sweeps taken
    // while driving were placed with the estimate of that moment; in AMCL's field they would
    // confirm its own drift.
    for (const MapSweep& m : map_sweeps) grid.InsertScan(m.scan, m.X_MB);
    MarkFootprints();
    localiser_grid = grid;
    // The driving sweeps' grid covers the map and the range of a sweep taken inside it.
    const Vec2 m = Vec2::Constant(params.map_lrf_range + 1.0);
    const Vec2 need_lo = grid.Origin() - m,
               need_hi = grid.Origin() + grid.Resolution() * Vec2(grid.Width(), grid.Height()) + m;
    if (!driving) {
      driving.emplace(perception::OccupancyGrid::Covering(params.grid, need_lo, need_hi, 0.0));
    } else {
      const Vec2 have_lo = driving->Origin(),
                 have_hi = have_lo + driving->Resolution() * Vec2(driving->Width(), driving->Height());
      if ((need_lo.array() < have_lo.array()).any() || (need_hi.array() > have_hi.array()).any())
        driving = driving->Resized(need_lo.cwiseMin(have_lo), need_hi.cwiseMax(have_hi));
    }
    grid.Compose(localiser_grid, *driving, need_lo, need_hi);
    MarkFootprints();
  }

  // The cells under the base at every scan pose are free: the robot stood there. When `at` is
  // given, only the footprints that reach the cells of the box of half-edge `reach` (m) about it
  // (those a Compose of that box rewrote; the rest of the grid already has them).
  void MarkFootprints(const Vec2* at = nullptr, double reach = 0.0) {
    const double r = 0.5 * params.controller.footprint_width;
    const double near = reach + r + grid.Resolution();  // the box's edge cells reach a cell out
    for (const Pose2& s : log.scan_poses) {
      if (at && (std::abs(s.x - at->x()) > near || std::abs(s.y - at->y()) > near)) continue;
      grid.FillBox(Vec2(s.x - r, s.y - r), Vec2(s.x + r, s.y + r), perception::CellState::kFree);
    }
  }

  // AMCL restarted on the current map about X_MB; the planner gets the map.
  void RestartLocaliser(const Pose2& X_MB,
                        const Eigen::Matrix3d& extra_cov = Eigen::Matrix3d::Zero()) {
    const double sxy = params.initial_sigma_xy, syaw = DegToRad(params.initial_sigma_yaw_deg);
    amcl.emplace(localiser_grid, params.amcl, seed * 1000003ULL + amcl_epoch++);
    const Eigen::Matrix3d cov =
        Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal().toDenseMatrix() +
        extra_cov;
    amcl->SetInitialPose(X_MB, cov);
    if (!planner)
      planner.emplace(grid, params.planner, seed);
    else
      planner->SetMap(grid);
  }

  // One control step under `cmd`: the platform steps, AMCL updates on a new top sweep, the
  // estimate is logged.
  const perception::LocalisationEstimate& StepOnce() {
    const bool top_new = platform.Step(cmd);
    t = platform.Time();
    const interfaces::Odometry& odom = platform.WheelOdometry();
    if (top_new) {
      if (amcl->Update(odom, platform.TopSweep()).updated) ++log.amcl_updates;
    }
    const auto& est = amcl->Estimate();
    const bool lost = est.status == perception::LocalisationStatus::kLost ||
                      est.status == perception::LocalisationStatus::kRelocalising;
    if (lost && !was_lost) ++log.lost_events;
    if (params.trace && log.estimated.size() % 50 == 0)
      std::fprintf(stderr, "   amcl est (%.2f %.2f) %s (%s) n=%d inl=%.2f odom (%.2f %.2f)\n",
                   X_MB_est.x, X_MB_est.y, perception::ToString(est.status), est.message.c_str(),
                   est.particles, est.inlier_ratio, odom.X_OB.x, odom.X_OB.y);
    was_lost = lost;
    X_MB_est = est.PoseAt(odom.X_OB);
    log.estimated.push_back({t, X_MB_est});
    return est;
  }

  const interfaces::TlsScan& TakeScan(double step_override) {
    const bool first = log.tls_scans == 0 && log.estimated.empty();
    cmd = {};
    const double step_deg = step_override > 0.0 ? step_override : params.tls_step_deg;
    double still_for = 0.0;
    last_scan = platform.Scan(step_deg, &still_for);
    last_range_bias = {};
    if (params.range_bias.estimate) {
      last_range_bias = perception::EstimateRangeBias(last_scan, params.range_bias);
      if (last_range_bias.ok) perception::RemoveRangeBias(last_scan, last_range_bias.bias);
    }
    last_scan.X_MS_estimate = X_MB_est.To3d() * last_scan.X_BS;
    if (params.register_scans) RegisterLastScan();
    ++log.tls_scans;
    ++nav_scans;
    looked_around = false;
    log.scan_poses.push_back(X_MB_est);
    clouds.push_back(CloudOf(last_scan, last_scan.X_MS_estimate));
    MarkTransients(last_scan.X_MS_estimate);
    map_sweeps.push_back({platform.BaseSweep(), X_MB_est});
    map_sweeps.push_back({platform.TopSweep(), X_MB_est});
    RebuildMap();
    RestartLocaliser(X_MB_est);
    if (amcl->Update(platform.WheelOdometry(), platform.TopSweep(), /*force=*/true).updated)
      ++log.amcl_updates;
    if (first) log.estimated.push_back({t, X_MB_est});
    // The base stands still while the head turns, stepped like any other time.
    const double t_end = t + still_for;
    while (t + 0.5 * platform.ControlPeriod() < t_end) StepOnce();
    return last_scan;
  }

  // ICP of the scan just taken against the earlier ones (from its AMCL-stamped prior), through
  // the acceptance policy; on success the scan and the pose estimate take the registered pose
  // (the base has not moved since the scan started). Every scan then joins the registration map.
  void RegisterLastScan() {
    const perception::Points pts = perception::ScanPoints(last_scan);
    if (!scan_map) scan_map.emplace(params.icp);
    if (!scan_map->empty()) {
      const perception::RegistrationResult r =
          perception::RegisterScan(pts, *scan_map, last_scan.X_MS_estimate, params.icp);
      double amcl_sigma = 0.0;  // m, largest std of AMCL's position at the scan
      if (amcl) {
        const Eigen::Matrix2d cov_xy = amcl->Estimate().covariance.topLeftCorner<2, 2>();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov_xy);
        amcl_sigma = std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
      }
      const perception::RegistrationDecision d = perception::AcceptRegistration(
          r, last_scan.X_MS_estimate, params.icp, params.acceptance, amcl_sigma);
      log.scan_registration_messages.push_back("scan " + std::to_string(log.tls_scans) + ": " +
                                               d.message);
      if (!d.use) {
        ++log.scan_registrations_failed;
        if (params.trace)
          std::fprintf(stderr, "t=%.2f scan registration refused: %s\n", t, r.message.c_str());
      } else {
        r.ok || d.creeping ? ++log.scan_registrations_ok : ++log.scan_registrations_degenerate;
        last_scan.X_MS_estimate = d.X_MS;
        X_MB_est = Pose2Of(d.X_MS * last_scan.X_BS.inverse());
      }
    }
    // A refused scan joins too, with its AMCL pose: it is usually the first look into new
    // space (a room entered through its door), and without it no later scan there would find
    // a counterpart. Its error is what the map would carry without registration.
    scan_map->Add(perception::Transform(pts, last_scan.X_MS_estimate),
                  last_scan.X_MS_estimate.translation());
  }

  void CorrectLastScanPose(const Pose3& X_MS, const Eigen::Matrix3d& extra_cov) {
    if (clouds.empty()) throw InputError("drive: CorrectLastScanPose before any scan");
    const Pose2 X_MB_scan = Pose2Of(X_MS * last_scan.X_BS.inverse());
    last_scan.X_MS_estimate = X_MS;
    clouds.back() = CloudOf(last_scan, X_MS);
    MarkTransients(X_MS);
    const Pose2 old = log.scan_poses.back();
    log.scan_poses.back() = X_MB_scan;
    for (std::size_t k = map_sweeps.size() - 2; k < map_sweeps.size(); ++k)
      map_sweeps[k].X_MB = X_MB_scan;
    RebuildMap();
    // The base may have moved since the scan: carry the odometry offset over.
    const Pose2 now = Compose(Compose(X_MB_scan, Inverse(old)), X_MB_est);
    X_MB_est = now;
    RestartLocaliser(now, extra_cov);
    if (amcl->Update(platform.WheelOdometry(), platform.TopSweep(), /*force=*/true).updated)
      ++log.amcl_updates;
  }

  // Robot side: both LRF sweeps into the map every map_lrf_period while localised (not into
  // AMCL's field, which restarts only at scans).
  void MapDrivingSweeps(const perception::LocalisationEstimate& est) {
    if (params.map_lrf_period <= 0.0 || t + 1e-9 < next_map_sweep) return;
    if (est.status != perception::LocalisationStatus::kLocalised || !driving) return;
    next_map_sweep = t + params.map_lrf_period;
    for (const interfaces::LrfScan* sc : {&platform.BaseSweep(), &platform.TopSweep()})
      driving->InsertScan(*sc, X_MB_est, params.map_lrf_range);
    const double reach = params.map_lrf_range + 1.0;
    const Vec2 at(X_MB_est.x, X_MB_est.y), box = Vec2::Constant(reach);
    grid.Compose(localiser_grid, *driving, at - box, at + box);
    MarkFootprints(&at, reach);
    leg_blocked = LegBlockedInMap();
  }

  // Robot side: an occupied cell within `r` of a point of the rest of the leg (from the point
  // nearest to the robot, `map_lrf_range` ahead) or within robot_radius of its end: the leg
  // must be planned again on the updated map before the base runs into it.
  bool LegBlockedInMap() const {
    if (leg_path.empty()) return false;
    const double res = grid.Resolution();
    auto occupied_near = [&](const Vec2& p, double r) {
      const perception::Cell c0 = grid.CellOf(p);
      const int n = static_cast<int>(std::ceil(r / res));
      for (int dj = -n; dj <= n; ++dj)
        for (int di = -n; di <= n; ++di) {
          const perception::Cell c{c0.i + di, c0.j + dj};
          if (grid.State(c) == perception::CellState::kOccupied &&
              (grid.CentreOf(c) - p).norm() < r + 0.5 * res)
            return true;
        }
      return false;
    };
    const Vec2 here(X_MB_est.x, X_MB_est.y);
    std::size_t k0 = 0;
    for (std::size_t k = 1; k < leg_path.size(); ++k)
      if ((leg_path[k] - here).squaredNorm() < (leg_path[k0] - here).squaredNorm()) k0 = k;
    const double r = params.planner.robot_radius - 0.05;
    double along = 0.0;
    for (std::size_t k = k0; k < leg_path.size() && along <= params.map_lrf_range; ++k) {
      if (k > k0) along += (leg_path[k] - leg_path[k - 1]).norm();
      if ((leg_path[k] - here).norm() < 0.4) continue;  // the controller's LRF check is closer
      if (occupied_near(leg_path[k], r)) return true;
    }
    return (leg_path.back() - here).norm() <= params.map_lrf_range &&
           (leg_path.back() - here).norm() >= 0.4 &&
           occupied_near(leg_path.back(), params.planner.robot_radius);
  }

  // A leg ended blocked or unreachable: plan it again (true) with what the LRFs added to the
  // map, after a TLS scan here if the pose is new (a closer look at the doorway) and the
  // localisation matches the map. False when the re-legs are spent.
  bool Releg(const std::string& why) {
    if (relegs >= params.max_relegs) return false;
    ++relegs;
    cmd = {};
    if (params.trace) std::fprintf(stderr, "t=%.2f re-leg %d after: %s\n", t, relegs, why.c_str());
    bool fresh = nav_scans + 1 < params.max_scans;
    for (const Pose2& sp : log.scan_poses)
      fresh =
          fresh && std::hypot(X_MB_est.x - sp.x, X_MB_est.y - sp.y) >= params.frontier_exclusion;
    if (fresh) {
      if (amcl->Update(platform.WheelOdometry(), platform.TopSweep(), /*force=*/true).updated)
        ++log.amcl_updates;
      const auto& e = amcl->Estimate();
      fresh = e.status == perception::LocalisationStatus::kLocalised &&
              e.inlier_ratio >= params.amcl.lost_inlier_ratio;
    }
    if (fresh) {
      TakeScan(0.0);
      relegs = 0;  // progress: a new scan position (bounded by max_scans)
    } else {
      planner->SetMap(grid);
    }
    return true;
  }

  void Finish(DriveStatus s, const std::string& msg) {
    log.status = s;
    log.message = msg;
  }

  void Install(GlobalPlan plan, bool final) {
    final_leg = final;
    // A scan position needs no particular heading (the TLS turns 360 deg): arrive along the
    // path instead of turning on the spot, which a doorway may not allow.
    if (!final && plan.path.size() >= 2)
      plan.path.back().pose.yaw = plan.path[plan.path.size() - 2].pose.yaw;
    target_M = plan.path.back().pose;
    leg_path.clear();
    for (const auto& q : plan.path) leg_path.emplace_back(q.pose.x, q.pose.y);
    std::vector<Pose2> poses;
    for (const auto& p : plan.path) poses.push_back(p.pose);
    log.plans.push_back(std::move(poses));
    if (params.trace) {
      std::fprintf(
          stderr, "t=%.2f plan to (%.2f %.2f) final=%d len %.2f minclr %.2f passages %zu\n", t,
          target_M.x, target_M.y, final, plan.length, plan.min_clearance, plan.passages.size());
      for (const auto& q : plan.passages)
        std::fprintf(stderr, "  passage (%.2f %.2f) yaw %.2f width %.2f s %.2f\n", q.centre.x(),
                     q.centre.y(), q.axis_yaw, q.width, q.s);
    }
    controller->SetPlan(plan, /*align_yaw=*/final);
  }

  // The plan up to and including path point k (its passages and length with it).
  static void TruncatePlan(GlobalPlan& plan, std::size_t k) {
    const double s_end = plan.path[k].s;
    plan.path.resize(k + 1);
    std::erase_if(plan.passages, [&](const Passage& q) { return q.s > s_end; });
    plan.length = s_end;
  }

  // Robot side: MoPAD's two scans at a doorframe, on a leg that ends with a scan and crosses
  // a doorway. The first: with no scan near the doorway's near end, the leg stops in front of
  // it. The second: the leg is cut just beyond it (that scan still sees the room behind
  // through the door and registers against it, where a scan deep in the new room sees almost
  // nothing the map has), unless a scan was taken near there on that side. A doorway is a
  // stretch of the path with less clearance than a scan stop needs (the planner's passages
  // are only the narrowest gaps).
  void CutAtDoorway(GlobalPlan& plan) const {
    if (plan.path.size() < 2) return;
    const std::size_t k = plan.path.size() - 1;
    const double narrow = params.planner.robot_radius + params.doorway_margin;
    std::size_t b = 0;
    while (b < k) {
      std::size_t a = b;
      while (a < k && (plan.path[a].s < 0.3 || plan.path[a].clearance >= narrow)) ++a;
      b = a;
      while (b < k && plan.path[b].clearance < narrow) ++b;
      if (a >= k) return;
      const Vec2 entry(plan.path[a].pose.x, plan.path[a].pose.y);
      if (params.door_entry_scan_distance > 0.0 &&
          std::none_of(log.scan_poses.begin(), log.scan_poses.end(), [&](const Pose2& sp) {
            return std::hypot(entry.x() - sp.x, entry.y() - sp.y) < params.door_entry_scan_distance;
          })) {
        std::size_t ka = a;
        while (ka > 0 && (plan.path[ka].clearance < narrow ||
                          plan.path[ka].s > plan.path[a].s - params.door_entry_standoff))
          --ka;
        if (params.trace)
          std::fprintf(
              stderr,
              "t=%.2f narrow stretch at s %.2f-%.2f, no scan near its entry: stop at s %.2f\n", t,
              plan.path[a].s, plan.path[b].s, plan.path[ka].s);
        if (plan.path[ka].s >= params.min_scan_progress) {
          TruncatePlan(plan, ka);
          return;
        }
      }
      if (params.door_exit_scan_distance <= 0.0 || b >= k) return;
      const double s_exit =
          0.5 * (plan.path[a].s + plan.path[b].s) + params.door_exit_scan_distance;
      std::size_t ke = b;
      while (ke < k && (plan.path[ke].s < s_exit || plan.path[ke].clearance < narrow)) ++ke;
      if (ke >= k) return;
      const PathPoint& e = plan.path[ke];
      // Near the exit and on its side (the scan in front of the doorway does not count).
      const bool scanned_near =
          std::any_of(log.scan_poses.begin(), log.scan_poses.end(), [&](const Pose2& sp) {
            const double d = std::hypot(e.pose.x - sp.x, e.pose.y - sp.y);
            return d < 2.0 * params.door_exit_scan_distance &&
                   d < std::hypot(entry.x() - sp.x, entry.y() - sp.y);
          });
      if (params.trace)
        std::fprintf(stderr, "t=%.2f narrow stretch at s %.2f-%.2f, exit s %.2f%s\n", t,
                     plan.path[a].s, plan.path[b].s, e.s, scanned_near ? " (scanned near)" : "");
      if (!scanned_near && e.s >= params.min_scan_progress) {
        TruncatePlan(plan, ke);
        return;
      }
    }
  }

  // Plans the next leg: the goal plan, driven to the end only if the map around every path
  // point is well known; else only as far as it is, then a scan. A goal outside the known free
  // space: drive to the reachable point nearest to it and scan. False = finished (status set).
  bool PlanLeg() {
    GlobalPlan plan = planner->Plan(X_MB_est, goal_M);
    std::string why;
    if (!plan.ok()) {
      why = std::string(ToString(plan.status)) + ": " + plan.message;
      if (plan.status == PlanStatus::kStartInvalid) {
        Finish(DriveStatus::kBlocked, "cannot leave the current pose: " + why);
        return false;
      }
    }
    auto well_known = [&](const PathPoint& q) {
      // Around a scan position the TLS cannot see the floor (blind cone); the LRF sweeps taken
      // there cover it.
      for (const Pose2& sp : log.scan_poses)
        if (std::hypot(q.pose.x - sp.x, q.pose.y - sp.y) < params.scan_blind_radius) return true;
      return KnownFraction(grid, Vec2(q.pose.x, q.pose.y), params.goal_known_radius) >=
             params.goal_known_fraction;
    };
    // Near enough to a scan position for AMCL's map to be complete around it.
    auto near_scans = [&](const PathPoint& q) {
      if (params.max_distance_from_scans <= 0.0) return true;
      for (const Pose2& sp : log.scan_poses)
        if (std::hypot(q.pose.x - sp.x, q.pose.y - sp.y) <= params.max_distance_from_scans)
          return true;
      return false;
    };
    auto drivable = [&](const PathPoint& q) { return well_known(q) && near_scans(q); };
    // The scan the mission took before navigating counts towards the budget.
    const bool budget_spent = nav_scans + 1 >= params.max_scans;
    const bool all_known = plan.ok() && std::all_of(plan.path.begin(), plan.path.end(), drivable);
    if (all_known || (plan.ok() && budget_spent)) {
      Install(plan, true);
      return true;
    }
    if (budget_spent) {
      Finish(DriveStatus::kUnreachable, "no route to the goal after " +
                                            std::to_string(log.tls_scans) + " scans (" + why + ")");
      return false;
    }
    if (plan.ok()) {
      // Drive along the plan only as far as the map is well known (typically into the doorway
      // of the next room) and near the scans, and scan there: AMCL cannot track in a room the
      // map lacks.
      std::size_t k = 0;
      while (k + 1 < plan.path.size() && drivable(plan.path[k + 1])) ++k;
      // A cut inside a doorway is hard to dock at from an angle: scan first in front of it
      // (clearance >= robot_radius + doorway_margin), and from the doorway only when already
      // there (the short straight approach from in front of it).
      std::size_t kb = k;
      while (kb > 0 &&
             plan.path[kb].clearance < params.planner.robot_radius + params.doorway_margin)
        --kb;
      if (plan.path[kb].s >= params.min_scan_progress) k = kb;
      if (k + 1 >= plan.path.size() || plan.path[k].s < params.min_scan_progress) {
        Install(plan, true);
        return true;
      }
      TruncatePlan(plan, k);
      CutAtDoorway(plan);
      Install(plan, false);
      return true;
    }
    // The goal is not in the known free space: explore. Go to the frontier on the shortest
    // estimated route to the goal and scan there.
    const Vec2 g(goal_M.x, goal_M.y);
    std::string no_target;
    const std::vector<Vec2> targets =
        ExplorationTargets(grid, Vec2(X_MB_est.x, X_MB_est.y), g, ExplorationParamsOf(params),
                           log.scan_poses, &no_target);
    if (targets.empty() && params.look_around && !looked_around &&
        no_target.rfind("no progress", 0) == 0) {
      LookAround();
      return PlanLeg();
    }
    if (targets.empty()) {
      Finish(DriveStatus::kUnreachable,
             "goal not connected to the start in the robot's map after " +
                 std::to_string(log.tls_scans) + " scans (" + why + "); exploring: " + no_target +
                 " (a closed door or an obstacle blocks the way)");
      return false;
    }
    // The first candidate the planner reaches (its disc and the map's unknown-as-obstacle
    // rule are stricter than the exploration walk); unreachable ones fail fast (flood fill).
    std::string last_fail;
    const std::size_t tries = std::min<std::size_t>(targets.size(), 40);
    for (std::size_t k = 0; k < tries; ++k) {
      const std::size_t pick = k * targets.size() / tries;  // spread over the candidates
      const Vec2& near = targets[pick];
      const Pose2 t_M{near.x(), near.y(), std::atan2(g.y() - near.y(), g.x() - near.x())};
      GlobalPlan to_scan = planner->Plan(X_MB_est, t_M);
      if (to_scan.ok()) {
        CutAtDoorway(to_scan);
        Install(to_scan, false);
        return true;
      }
      last_fail = std::string(ToString(to_scan.status)) + ": " + to_scan.message;
    }
    Finish(DriveStatus::kUnreachable, "no route to any of " + std::to_string(targets.size()) +
                                          " exploration scan positions (" + last_fail + ")");
    return false;
  }

  DriveStatus NavigateTo(const Pose2& goal) {
    if (!amcl) throw InputError("drive: NavigateTo before the first TLS scan (no map)");
    goal_M = goal;
    log.goal_M = goal;
    target_M = goal;
    final_leg = true;
    nav_scans = 0;
    relegs = 0;
    map_replans = 0;
    leg_blocked = false;
    log.status = DriveStatus::kTimeout;
    log.message.clear();
    call_start = t;
    const Eigen::Vector3d g3(goal.x, goal.y, 0.0);
    if (std::find(extent_extra.begin(), extent_extra.end(), g3) == extent_extra.end()) {
      extent_extra.push_back(g3);
      if (!grid.Contains(grid.CellOf(Vec2(goal.x, goal.y)))) {
        RebuildMap();
        planner->SetMap(grid);
      }
    }
    bool running = PlanLeg();
    // Progress watchdog: 0.5 m cells of the estimated base position visited by this call.
    std::set<std::pair<long, long>> visited;
    double last_new_cell = t;
    auto mark_visited = [&] {
      const std::pair<long, long> c{std::lround(std::floor(X_MB_est.x / 0.5)),
                                    std::lround(std::floor(X_MB_est.y / 0.5))};
      if (visited.insert(c).second) last_new_cell = t;
    };
    mark_visited();
    while (running) {
      if (t - call_start >= params.max_time - 1e-9) {
        Finish(DriveStatus::kTimeout,
               FormatNumbers("no arrival within %.1f s of simulation time", params.max_time));
        break;
      }
      if (params.stall_time > 0.0 && t - last_new_cell > params.stall_time) {
        Finish(DriveStatus::kBlocked,
               FormatNumbers(
                   "no progress: for %.0f s the base only revisited places it had been to in this "
                   "drive (plans alternating between blocked routes)",
                   params.stall_time));
        break;
      }
      const perception::LocalisationEstimate& est = StepOnce();
      mark_visited();
      MapDrivingSweeps(est);
      if (leg_blocked && map_replans < kMaxMapReplans) {
        leg_blocked = false;
        ++map_replans;
        if (params.trace)
          std::fprintf(stderr, "t=%.2f leg blocked in the updated map: replanning\n", t);
        planner->SetMap(grid);
        cmd = {};
        running = PlanLeg();
        continue;
      }
      const ControlOutput out = controller->Update(t, X_MB_est, est.status, platform.BaseSweep());
      cmd = out.cmd;
      if (params.trace && (log.estimated.size() % 50 == 0 || out.finished))
        std::fprintf(stderr, "t=%.2f est (%.2f %.2f %.2f) %s: %s\n", t, X_MB_est.x, X_MB_est.y,
                     X_MB_est.yaw, ToString(out.status), out.message.c_str());
      if (!out.finished) continue;
      switch (out.status) {
        case NavStatus::kArrived:
          if (final_leg) {
            Finish(DriveStatus::kArrived, out.message);
            running = false;
          } else {
            // A scan is registered with the estimate: check it first (a forced update at the
            // stop). A scan that does not match the map means the robot is lost (e.g.
            // kidnapped while driving): stop with the reason rather than map a wrong room.
            cmd = {};
            if (amcl->Update(platform.WheelOdometry(), platform.TopSweep(), /*force=*/true).updated)
              ++log.amcl_updates;
            const auto& e = amcl->Estimate();
            if (e.status == perception::LocalisationStatus::kLost ||
                e.status == perception::LocalisationStatus::kRelocalising ||
                e.inlier_ratio < params.amcl.lost_inlier_ratio) {
              if (!was_lost) ++log.lost_events;
              Finish(DriveStatus::kLocalisationLost,
                     "at a scan stop the LRF does not match the map (" + e.message +
                         "); not scanning with a wrong pose");
              running = false;
              break;
            }
            TakeScan(0.0);
            running = PlanLeg();
          }
          break;
        case NavStatus::kUnreachable:
          if (Releg(out.message)) {
            running = PlanLeg();
            break;
          }
          Finish(DriveStatus::kUnreachable, out.message);
          running = false;
          break;
        case NavStatus::kLocalisationLost:
          Finish(DriveStatus::kLocalisationLost, out.message);
          running = false;
          break;
        default:
          if (out.status == NavStatus::kBlocked && Releg(out.message)) {
            running = PlanLeg();
            break;
          }
          Finish(DriveStatus::kBlocked, out.message);
          running = false;
          break;
      }
    }
    return log.status;
  }
};

Navigator::Navigator(interfaces::RobotPlatform& platform, const NavigatorParams& params,
                     std::uint64_t seed)
    : impl_(std::make_unique<Impl>(platform, params, seed)) {}
Navigator::~Navigator() = default;

const interfaces::TlsScan& Navigator::TakeScan(double step_deg_override) {
  return impl_->TakeScan(step_deg_override);
}
const interfaces::TlsScan& Navigator::LastScan() const { return impl_->last_scan; }
const perception::RangeBiasEstimate& Navigator::LastRangeBias() const {
  return impl_->last_range_bias;
}
void Navigator::CorrectLastScanPose(const Pose3& X_MS, const Eigen::Matrix3d& extra_cov) {
  impl_->CorrectLastScanPose(X_MS, extra_cov);
}
void Navigator::ExtendMap(const Vec2& p_M) {
  const Eigen::Vector3d p3(p_M.x(), p_M.y(), 0.0);
  auto& e = impl_->extent_extra;
  if (std::find(e.begin(), e.end(), p3) == e.end()) e.push_back(p3);
}
DriveStatus Navigator::NavigateTo(const Pose2& goal_M) { return impl_->NavigateTo(goal_M); }
Pose2 Navigator::EstimatedPose() const { return impl_->X_MB_est; }
const perception::LocalisationEstimate& Navigator::Localisation() const {
  if (!impl_->amcl) throw InputError("navigator: no localisation before the first TLS scan");
  return impl_->amcl->Estimate();
}
const perception::OccupancyGrid& Navigator::Map() const { return impl_->grid; }
int Navigator::ScanCount() const { return impl_->log.tls_scans; }
double Navigator::Time() const { return impl_->platform.Time(); }
const NavigatorParams& Navigator::Params() const { return impl_->params; }
const NavigatorLog& Navigator::Log() const { return impl_->log; }

}  // namespace mopad::autonomy
