#include "autonomy/room_scan.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/format.h"
#include "perception/point_cloud_ops.h"

namespace mopad::autonomy {
namespace {

using Clock = std::chrono::steady_clock;

// Std of the levelled mast's roll and pitch (the VZ-400's inclinometer, IcpParams::dof) and of
// its height (a rigid mast on a flat floor), for the prior's covariance in 4 DoF.
constexpr double kLevellingSigmaDeg = 0.01;
constexpr double kMastHeightSigma = 0.005;  // m

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Registration (paper step (3)): the first scan defines the room's frame, unless a floor
// target holds earlier rooms (then it is registered against them as a door scan, and used with
// its prior when refused); later ones are refined against the accumulated cloud S(t-1) from the
// odometry/AMCL prior and used when the acceptance policy says so (the navigator's pose then
// takes the registered one). A later scan that is not used stays out of S(t) (it would smear it
// by the prior's error). Returns whether the scan is used.
// The model's coverage with the area no reachable position can see (the stopping rule's basis).
modelling::CoverageFigures CoverageOf(const modelling::RoomModel& model, Navigator& navigator,
                                      const RoomScanParams& params,
                                      const modelling::OrthoPoints& no_return) {
  modelling::CoverageFigures f = model.Coverage();
  if (model.ScanCount() > 0) {
    f.SetHiddenArea(EstimateHiddenArea(model, navigator.Map(), navigator.EstimatedPose(),
                                       params.nbs, &no_return)
                        .area);
  }
  return f;
}

bool RegisterRoomScan(Navigator& navigator, const RoomScanParams& params,
                      const interfaces::TlsScan& scan, bool first, RegistrationTarget& target,
                      RoomScanLog& log, bool allow_prior = true) {
  if (!target.Map().empty()) {
    const bool used =
        RegisterLastScan(navigator, target.Map(), first ? params.entry_icp : params.icp,
                         first ? params.entry_acceptance : params.acceptance, log.registration,
                         &log.covariance);
    log.registered = used || first;
    if (used) log.X_MS = log.registration.X_MS;
    if (!log.registered && allow_prior && params.refused_scan_max_sigma > 0.0) {
      const perception::Points at_prior = perception::Transform(
          perception::VoxelDownsample(perception::ScanPoints(scan), params.icp.source_voxel_size),
          log.X_MS_prior);
      std::string why;
      log.at_prior = RefusedScanUsable(params, navigator.Localisation().covariance,
                                       target.Map().FreeSpaceViolation(at_prior), &why);
      log.registration.message += "; " + why;
      if (log.at_prior) log.X_MS = log.X_MS_prior;
    }
  }
  // A scan at its prior stays out of the target: later scans register against what was
  // registered.
  if (log.registered) target.Add(perception::ScanPoints(scan), log.X_MS);
  return log.registered || log.at_prior;
}

// The next best scan's candidates in the order they are tried: the chosen one, then the others
// with a gain by gain; none within `exclusion` of a position whose scan failed (the model did
// not change, so the same spot would win again).
std::vector<int> CandidateOrder(const NbsResult& nbs, const std::vector<Vec2>& failed_scans,
                                double exclusion) {
  auto spent = [&](int i) {
    for (const Vec2& f : failed_scans)
      if ((nbs.candidates[i].position - f).norm() < exclusion) return true;
    return false;
  };
  std::vector<int> order;
  if (!nbs.found) return order;
  if (!spent(nbs.chosen)) order.push_back(nbs.chosen);
  std::vector<int> rest;
  for (int i = 0; i < static_cast<int>(nbs.candidates.size()); ++i)
    if (i != nbs.chosen && nbs.candidates[i].gain > 0 && !spent(i)) rest.push_back(i);
  std::stable_sort(rest.begin(), rest.end(),
                   [&](int a, int b) { return nbs.candidates[a].gain > nbs.candidates[b].gain; });
  order.insert(order.end(), rest.begin(), rest.end());
  return order;
}

// The drive to the next best scan (step (2)): the candidates in `order`, at most nav_attempts,
// until one is reached. Returns whether the robot arrived.
bool DriveToNextBestScan(Navigator& navigator, const RoomScanParams& params, const NbsResult& nbs,
                         const std::vector<int>& order, RoomScanLog& log) {
  for (int attempt = 0; attempt < params.nav_attempts && attempt < static_cast<int>(order.size());
       ++attempt) {
    const NbsCandidate& c = nbs.candidates[order[attempt]];
    const Pose2 goal{c.position.x(), c.position.y(),
                     order[attempt] == nbs.chosen ? nbs.goal.yaw : navigator.EstimatedPose().yaw};
    log.has_next = true;
    log.next_goal = goal;
    log.expected_gain = c.gain;
    const auto t0 = Clock::now();
    const DriveStatus st = navigator.NavigateTo(goal);
    log.t_drive += Since(t0);
    log.nav_status = ToString(st);
    log.nav_message = navigator.Log().message;
    if (st == DriveStatus::kArrived) return true;
    if (st == DriveStatus::kLocalisationLost) return false;
  }
  return false;
}

// The detail pass (autonomy/detail_pass.h) after the room loop: plan on the model's SE cells,
// drive, scan, register, add; until nothing worth a scan is left or detail.max_scans.
// `steps_rad` holds the angular step of every scan of the model (one is appended per scan the
// model accepts); `scan_seconds` is the platform time of one scan at the room step.
void RunDetailPass(Navigator& session, const RoomScanParams& params, modelling::RoomModel& model,
                   const ScanHook& on_scan, RegistrationTarget& target,
                   std::vector<double>& steps_rad, double scan_seconds, RoomScanResult& res) {
  const DetailPassParams& P = params.detail;
  const auto wall0 = Clock::now();
  const double sim0 = session.Time();
  const double room_step = DegToRad(params.scan_step_deg);
  DetailView view;
  view.range_min = params.nbs.range_min;
  view.range_max = params.nbs.range_max;
  view.elevation_min = DegToRad(params.nbs.elevation_min_deg);
  view.elevation_max = DegToRad(params.nbs.elevation_max_deg);
  view.ref_step_rad = room_step;
  view.seconds_at_ref = scan_seconds;
  std::vector<double> steps{room_step};
  if (P.fine_step_deg > 0.0 && std::abs(P.fine_step_deg - params.scan_step_deg) > 1e-9)
    steps.push_back(DegToRad(P.fine_step_deg));
  // The structure the stopping rule accepted stays: a detail scan adds data (points, labels,
  // SE samples for SM5), never structure. It may see through a door or into a corner no
  // structural scan saw, and a perimeter moved by data-quality scans would change SM3, the
  // floor model and the route.
  model.FreezeStructure();
  for (int d = 0; d < P.max_scans && model.ScanCount() > 0; ++d) {
    RoomScanLog log;
    log.index = static_cast<int>(res.scans.size());
    log.detail = true;
    auto t0 = Clock::now();
    const std::vector<DetailSurface> surfaces = DetailSurfacesOf(model.GetRoi());
    DetailScans ds;
    for (const Pose3& X : model.ScanPoses()) ds.origins.push_back(X.translation());
    ds.step_rad = steps_rad;
    const std::vector<DetailCell> cells =
        AnalyseDetailCells(model.Points(), model.ScanIndices(), ds, surfaces, P);
    // Candidate bases: where the robot stands (no drive) and the next best scan's safe,
    // reachable grid; each at every step.
    const Pose2 here = session.EstimatedPose();
    const double scanner_z = model.ScanPoses().back().translation().z();
    std::vector<Vec2> bases{Vec2(here.x, here.y)};
    const NbsResult nbs =
        NextBestScan(model, session.Map(), here, params.scan_step_deg, params.nbs);
    for (const NbsCandidate& c : nbs.candidates) bases.push_back(c.position);
    std::vector<DetailCandidate> candidates;
    for (const Vec2& b : bases)
      for (double s : steps)
        candidates.push_back({b, scanner_z, s, (b - Vec2(here.x, here.y)).norm()});
    const modelling::VoxelSpace& vox = model.Voxels();
    const double stop_short = params.nbs.stop_short;
    const DetailPlan plan = PlanDetailScan(cells, surfaces, candidates, view, P, ds,
                                           [&vox, stop_short](const Vec3& a, const Vec3& b) {
                                             return vox.SegmentFree(a, b, stop_short);
                                           });
    log.t_nbs = Since(t0);
    res.detail_log.push_back(plan.message);
    if (!plan.found) break;
    const DetailCandidate& c = candidates[plan.chosen];
    if (c.drive_distance > 0.0) {
      const Pose2 goal{c.base.x(), c.base.y(), here.yaw};
      log.has_next = true;
      log.next_goal = goal;
      log.expected_gain = plan.gain_area;
      t0 = Clock::now();
      const DriveStatus st = session.NavigateTo(goal);
      log.t_drive = Since(t0);
      log.nav_status = ToString(st);
      log.nav_message = session.Log().message;
      if (st != DriveStatus::kArrived) {
        res.detail_log.push_back("detail: drive failed (" + log.nav_message + ")");
        break;
      }
    }
    log.step_deg = RadToDeg(c.step_rad);
    t0 = Clock::now();
    const interfaces::TlsScan& scan = session.TakeScan(log.step_deg);
    log.t_scan = Since(t0);
    log.range_bias = session.LastRangeBias();
    log.session_scan = session.ScanCount() - 1;
    log.sim_time = session.Time();
    log.X_MS_prior = scan.X_MS_estimate;
    log.X_MS = scan.X_MS_estimate;
    t0 = Clock::now();
    // A detail scan adds data for SM5's precision: only registered ones.
    const bool used = RegisterRoomScan(session, params, scan, false, target, log, false);
    log.t_registration = Since(t0);
    ++res.detail_scans;
    if (used) {
      t0 = Clock::now();
      model.AddScan(scan, log.X_MS);  // data only: the structure is frozen (above)
      log.colour_gain = model.ColourGains().back();
      steps_rad.push_back(c.step_rad);
      modelling::AddNoReturnRays(scan, log.X_MS, static_cast<std::uint16_t>(model.ScanCount() - 1),
                                 res.no_return, params.sm4.orthoimage);
      if (on_scan) on_scan(log.session_scan, scan);
      log.t_model = Since(t0);
    } else {
      res.registration_failed = true;
    }
    log.registered = used;
    log.coverage = CoverageOf(model, session, params, res.no_return);
    log.stop_message = plan.message;
    res.scans.push_back(std::move(log));
    if (!used) break;  // the same plan would win again
  }
  res.detail_sim_time = session.Time() - sim0;
  res.detail_wall_time = Since(wall0);
}

}  // namespace

bool RefusedScanUsable(const RoomScanParams& params, const Eigen::Matrix3d& loc_cov,
                       double violation_at_prior, std::string* why) {
  const double sigma_xy = std::sqrt(std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(loc_cov.topLeftCorner<2, 2>())
               .eigenvalues()
               .maxCoeff()));
  const double sigma_yaw_deg = RadToDeg(std::sqrt(std::max(0.0, loc_cov(2, 2))));
  const bool usable = params.refused_scan_max_sigma > 0.0 &&
                      sigma_xy <= params.refused_scan_max_sigma &&
                      sigma_yaw_deg <= params.refused_scan_max_sigma_deg &&
                      violation_at_prior <= params.icp.max_free_space_violation;
  if (why)
    *why = FormatNumbers(usable ? "joins the room model at its prior (sigma %.4f m, %.3f deg, "
                                  "free-space violation %.4f there)"
                                : "left out: its prior is not good enough (sigma %.4f m, %.3f "
                                  "deg, free-space violation %.4f there)",
                         sigma_xy, sigma_yaw_deg, violation_at_prior);
  return usable;
}

bool RegisterLastScan(Navigator& navigator, const perception::PointMap& target,
                      const perception::IcpParams& icp,
                      const perception::RegistrationAcceptanceParams& acceptance,
                      perception::RegistrationResult& r, Mat6* covariance) {
  const interfaces::TlsScan& scan = navigator.LastScan();
  const Pose3 prior = scan.X_MS_estimate;
  r = perception::RegisterScan(perception::ScanPoints(scan), target, prior, icp);
  const Eigen::Matrix3d& loc_cov = navigator.Localisation().covariance;  // x, y, yaw
  const Eigen::Matrix2d cov = loc_cov.topLeftCorner<2, 2>();
  const double sigma = std::sqrt(
      std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().maxCoeff()));
  const perception::RegistrationDecision d =
      perception::AcceptRegistration(r, prior, icp, acceptance, sigma);
  r.message = d.message;  // the logs say whether the result was used, and why not
  r.X_MS = d.X_MS;        // and carry the pose used
  // The prior's covariance in the registration's coordinates (rx, ry, rz, tx, ty, tz): the
  // localiser's x, y, yaw; roll, pitch and height as the levelled mast holds them.
  Mat6 prior_cov = Mat6::Zero();
  prior_cov.diagonal().head<3>().setConstant(DegToRad(kLevellingSigmaDeg) *
                                             DegToRad(kLevellingSigmaDeg));
  prior_cov(5, 5) = kMastHeightSigma * kMastHeightSigma;
  const int xyyaw[3] = {3, 4, 2};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) prior_cov(xyyaw[a], xyyaw[b]) = loc_cov(a, b);
  if (covariance) *covariance = d.use ? perception::RegistrationCovariance(r, prior_cov) : prior_cov;
  if (d.use) {
    // What the scan could not constrain keeps the prior's uncertainty: AMCL restarts with it.
    const Mat6 weak = perception::RegistrationCovariance(r, prior_cov) -
                      perception::RegistrationCovariance(r, Mat6::Zero());
    Eigen::Matrix3d extra;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) extra(a, b) = weak(xyyaw[a], xyyaw[b]);
    navigator.CorrectLastScanPose(r.X_MS, r.degenerate ? extra : Eigen::Matrix3d::Zero());
  }
  return d.use;
}

RoomScanResult RunRoomScan(Navigator& session, const RoomScanParams& params,
                           modelling::RoomModel& model, const ScanHook& on_scan,
                           RegistrationTarget* floor_target) {
  ValidateParams(params, "room.");
  params.icp.Validate();
  params.entry_icp.Validate();
  const auto wall0 = Clock::now();
  RoomScanResult res;
  RegistrationTarget own_target(params.icp);
  RegistrationTarget& target = floor_target ? *floor_target : own_target;
  std::vector<Vec2> failed_scans;  // base positions whose scan could not be registered
  std::vector<double> steps_rad;   // angular step of each scan of the model
  double scan_seconds = 0.0;       // platform seconds of one scan at the room step

  for (int k = 0; k < params.max_scans; ++k) {
    RoomScanLog log;
    log.index = k;
    auto t0 = Clock::now();
    const double sim_before = session.Time();
    const interfaces::TlsScan& scan = session.TakeScan(params.scan_step_deg);
    log.t_scan = Since(t0);
    log.range_bias = session.LastRangeBias();
    if (k == 0) scan_seconds = session.Time() - sim_before;
    log.step_deg = params.scan_step_deg;
    log.session_scan = session.ScanCount() - 1;
    log.sim_time = session.Time();
    log.X_MS_prior = scan.X_MS_estimate;
    log.X_MS = scan.X_MS_estimate;

    t0 = Clock::now();
    const bool used = RegisterRoomScan(session, params, scan, k == 0, target, log);
    log.t_registration = Since(t0);
    if (!log.registered) res.registration_failed = true;
    if (used) {
      // Preprocessing, RoI, voxels, coverage (steps (3)-(5)).
      t0 = Clock::now();
      model.AddScan(scan, log.X_MS);
      log.colour_gain = model.ColourGains().back();
      steps_rad.push_back(DegToRad(params.scan_step_deg));
      modelling::AddNoReturnRays(scan, log.X_MS, static_cast<std::uint16_t>(model.ScanCount() - 1),
                                 res.no_return, params.sm4.orthoimage);
      log.t_model = Since(t0);
      if (on_scan) on_scan(log.session_scan, scan);
    } else {
      res.registration_failed = true;
      const Pose2 here = session.EstimatedPose();
      failed_scans.emplace_back(here.x, here.y);
    }
    // The stopping rule (step (6)).
    t0 = Clock::now();
    log.coverage = CoverageOf(model, session, params, res.no_return);
    log.t_model += Since(t0);
    const modelling::StopDecision stop = modelling::CheckStopping(log.coverage, params.stopping);
    log.stop_message = stop.message;
    if (stop.stop || k + 1 == params.max_scans) {
      res.stop_reason = stop.stop ? stop.message
                                  : "stop: scan cap of " + std::to_string(params.max_scans) +
                                        " reached (" + stop.message + ")";
      res.scans.push_back(std::move(log));
      break;
    }

    // Next best scan (step (1)) and the drive there (step (2)).
    t0 = Clock::now();
    const NbsResult nbs = NextBestScan(model, session.Map(), session.EstimatedPose(),
                                       params.scan_step_deg, params.nbs);
    log.t_nbs = Since(t0);
    log.candidates = static_cast<int>(nbs.candidates.size());
    log.nav_message = nbs.message;
    // The paper's epsilon2 applied before moving: a scan expected to add less than epsilon2 of
    // the structural area is not worth the drive.
    const double min_gain = params.stopping.epsilon2 * log.coverage.total_area;
    if (nbs.found && nbs.expected_gain < min_gain) {
      res.stop_reason =
          FormatNumbers("stop: best expected gain %.2f m2 < epsilon2 x estimated total (%.2f m2)",
                        nbs.expected_gain, min_gain);
      res.scans.push_back(std::move(log));
      break;
    }
    const std::vector<int> order = CandidateOrder(nbs, failed_scans, params.failed_scan_exclusion);
    const bool moved = DriveToNextBestScan(session, params, nbs, order, log);
    res.scans.push_back(std::move(log));
    if (!moved) {
      const RoomScanLog& last = res.scans.back();
      res.stop_reason =
          "stop: no reachable next-best-scan position (" +
          (last.nav_message.empty() ? std::string("no candidate") : last.nav_message) + ")";
      break;
    }
  }
  if (params.detail.enabled)
    RunDetailPass(session, params, model, on_scan, target, steps_rad, scan_seconds, res);
  res.sim_time = session.Time();
  res.wall_time = Since(wall0);
  return res;
}

}  // namespace mopad::autonomy
