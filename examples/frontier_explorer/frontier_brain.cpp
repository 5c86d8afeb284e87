#include "frontier_brain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "common/polygon.h"
#include "io/text_file.h"
#include "io/tum.h"
#include "modelling/model_io.h"
#include "modelling/structural_model.h"
#include "perception/amcl.h"
#include "perception/grid_search.h"
#include "perception/point_cloud_ops.h"
#include "perception/registration.h"
#include "runfolder/layout.h"

namespace frontier {

using mopad::Pose2;
using mopad::Pose3;
using mopad::Vec2;
namespace perception = mopad::perception;

void ExplorerParams::Validate() const {
  auto check = [](const char* name, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
      throw std::invalid_argument(std::string(name) + ": got " + std::to_string(v) +
                                  ", expected [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                  "]");
  };
  const double inf = std::numeric_limits<double>::infinity();
  check("scan_step_deg", scan_step_deg, 0.02, 5.0);
  check("max_scans", max_scans, 1, 100);
  check("time_budget", time_budget, 1e-3, inf);
  check("grid_resolution", grid_resolution, 0.02, 0.5);
  check("grid_size", grid_size, 1.0, 1000.0);
  check("clearance", clearance, 0.0, 5.0);
  check("wall_margin", wall_margin, 0.0, 5.0);
  check("min_frontier_cells", min_frontier_cells, 1, 1e6);
  check("goal_reach", goal_reach, 0.0, 100.0);
  check("min_scan_spacing", min_scan_spacing, 0.0, 100.0);
  check("speed", speed, 1e-3, 1.0);
  check("turn_rate", turn_rate, 1e-3, 2.0);
  check("lookahead", lookahead, 0.01, 10.0);
  check("goal_tolerance", goal_tolerance, 0.01, 5.0);
  check("leg_timeout", leg_timeout, 1e-3, inf);
  check("replan_period", replan_period, 1e-3, inf);
}

namespace {

Pose2 PlanarOf(const Pose3& X) {
  return {X.translation().x(), X.translation().y(), std::atan2(X(1, 0), X(0, 0))};
}

perception::IcpParams IcpFor(const ExplorerParams& p) {
  perception::IcpParams icp;
  // The free-space check bins directions; coarse scans need coarser bins, and scans taken
  // far apart in a large room (this brain scans at frontiers, not at next best views) leave
  // ~1-2 % of the points in space another scan saw through at the right pose (grazing views,
  // furniture seen from the other side). Fit (rmse, fitness) still decides.
  icp.free_space_bin_deg = std::max(icp.free_space_bin_deg, 2.0 * p.scan_step_deg);
  icp.max_free_space_violation = 0.025;
  return icp;
}

struct Frontier {
  Vec2 centroid = Vec2::Zero();
  int cells = 0;
};

class Explorer {
 public:
  Explorer(mopad::interfaces::RobotPlatform& robot, const ExplorerParams& p,
           const std::function<void(const std::string&)>& log)
      : robot_(robot), p_(p), log_(log), icp_(IcpFor(p)), target_(icp_) {
    perception::OccupancyGridParams gp;
    gp.resolution = p.grid_resolution;
    const int n = static_cast<int>(std::ceil(p.grid_size / p.grid_resolution));
    result_.grid = perception::OccupancyGrid(
        gp, Vec2(-0.5 * n * gp.resolution, -0.5 * n * gp.resolution), n, n);
  }

  ExplorerResult Run() {
    Scan();
    while (true) {
      const std::vector<Frontier> frontiers = Frontiers();
      result_.frontiers_left = static_cast<int>(frontiers.size());
      if (static_cast<int>(result_.scans.size()) >= p_.max_scans) {
        Stop("max_scans reached");
        break;
      }
      if (robot_.Time() >= p_.time_budget) {
        Stop("time budget spent");
        break;
      }
      Vec2 goal;
      std::vector<Vec2> path;
      if (!ChooseGoal(frontiers, &goal, &path)) {
        Stop(frontiers.empty() ? "no frontier left in the room"
                               : "no reachable frontier left in the room");
        break;
      }
      Say("goal (" + Fixed(goal.x()) + ", " + Fixed(goal.y()) + ") m, " +
          std::to_string(frontiers.size()) + " frontiers open");
      if (!DriveTo(goal, path)) {
        given_up_.push_back(goal);
        // The way was blocked by what the sweeps found on it: a scan from here still looks
        // at the frontier from nearer, unless an earlier scan stood here.
        const Vec2 here(Estimate().x, Estimate().y);
        if (NearAny(here, scan_positions_, p_.min_scan_spacing)) {
          Say("goal given up");
          continue;
        }
        Say("goal given up; scanning from here");
      }
      Scan();
    }
    result_.final_pose_M = Estimate();
    return std::move(result_);
  }

 private:
  static std::string Fixed(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
  }
  void Say(const std::string& line) const {
    if (log_) log_("[t=" + Fixed(robot_.Time()) + " s] " + line);
  }
  void Stop(const std::string& why) {
    result_.stop_reason = why;
    Say("stop: " + why);
  }

  // The pose estimate: wheel odometry, corrected at each registered scan.
  Pose2 Estimate() const { return perception::Compose(X_MO_, robot_.WheelOdometry().X_OB); }

  // One control period; the base LRF's new sweeps go into the grid.
  void Step(const mopad::interfaces::VelocityCommand& cmd) {
    const Pose2 before = robot_.WheelOdometry().X_OB;
    robot_.Step(cmd);
    const Pose2& after = robot_.WheelOdometry().X_OB;
    result_.odometry_distance += std::hypot(after.x - before.x, after.y - before.y);
    const auto& sweep = robot_.BaseSweep();
    if (sweep.seq != last_sweep_) {
      last_sweep_ = sweep.seq;
      result_.grid.InsertScan(sweep, Estimate(), kLrfRange);
    }
  }

  // A TLS scan where the robot stands: registered, added to the room model and the grid.
  void Scan() {
    double still_for = 0.0;
    const Pose2 X_MB = Estimate();
    mopad::interfaces::TlsScan scan = robot_.Scan(p_.scan_step_deg, &still_for);
    ExplorerScan rec;
    rec.time = robot_.Time();
    const Pose3 prior = X_MB.To3d() * scan.X_BS;
    rec.X_MS = prior;
    const perception::Points points_S = perception::ScanPoints(scan);
    if (result_.scans.empty()) {
      rec.registered = true;
    } else {
      const perception::RegistrationResult r =
          perception::RegisterScan(points_S, target_, prior, icp_);
      const perception::RegistrationDecision d =
          perception::AcceptRegistration(r, prior, icp_, acceptance_, kPriorSigma);
      rec.registration = d.message;
      if (d.use) {
        rec.registered = true;
        rec.X_MS = d.X_MS;
        // The odometry is re-anchored so that it agrees with the registered scan.
        X_MO_ = perception::Compose(PlanarOf(rec.X_MS * scan.X_BS.inverse()),
                                    perception::Inverse(robot_.WheelOdometry().X_OB));
      }
    }
    if (rec.registered) {
      const perception::Points points_M = perception::Transform(points_S, rec.X_MS);
      target_.Add(points_M, rec.X_MS.translation());
      result_.model.AddScan(scan, rec.X_MS);
      result_.grid.InsertPoints(points_M);
      result_.grid.InsertRays(rec.X_MS.translation(), points_M);
      scan_positions_.push_back(rec.X_MS.translation().head<2>());
    }
    Say("scan " + std::to_string(result_.scans.size() + 1) + " at (" +
        Fixed(rec.X_MS.translation().x()) + ", " + Fixed(rec.X_MS.translation().y()) +
        ") m: " + (rec.registered ? "in the model" : "not registered, left out") + ", " +
        std::to_string(result_.model.PointCount()) + " points, perimeter " +
        std::to_string(result_.model.Perimeter().size()) + " corners" +
        (rec.registered ? "" : " (" + rec.registration + ")"));
    result_.scans.push_back(rec);
    for (double t = 0.0; t < still_for; t += robot_.ControlPeriod()) Step({});
  }

  bool InRoom(const Vec2& p) const {
    const std::vector<Vec2>& perimeter = result_.model.Perimeter();
    return perimeter.size() >= 3 && mopad::PointInPolygon(p, perimeter) &&
           mopad::DistanceToBoundary(p, perimeter) >= p_.wall_margin;
  }

  // Unknown cells next to a free one, inside the room, in 8-connected clusters (index order).
  std::vector<Frontier> Frontiers() const {
    const perception::OccupancyGrid& g = result_.grid;
    const int w = g.Width(), h = g.Height();
    std::vector<std::uint8_t> is_frontier(static_cast<std::size_t>(w) * h, 0);
    for (int j = 1; j + 1 < h; ++j)
      for (int i = 1; i + 1 < w; ++i) {
        const perception::Cell c{i, j};
        if (g.State(c) != perception::CellState::kUnknown) continue;
        bool next_to_free = false;
        for (const perception::Cell n : {perception::Cell{i + 1, j}, perception::Cell{i - 1, j},
                                         perception::Cell{i, j + 1}, perception::Cell{i, j - 1}})
          next_to_free = next_to_free || g.State(n) == perception::CellState::kFree;
        if (next_to_free && InRoom(g.CentreOf(c))) is_frontier[g.Index(c)] = 1;
      }
    std::vector<Frontier> out;
    std::vector<std::size_t> stack;
    for (std::size_t k = 0; k < is_frontier.size(); ++k) {
      if (!is_frontier[k]) continue;
      Frontier f;
      is_frontier[k] = 0;
      stack.push_back(k);
      while (!stack.empty()) {
        const std::size_t q = stack.back();
        stack.pop_back();
        const int i = static_cast<int>(q % w), j = static_cast<int>(q / w);
        f.centroid += g.CentreOf({i, j});
        ++f.cells;
        for (const auto& s : perception::kNeighboursRowMajor) {
          const perception::Cell n{i + s.di, j + s.dj};
          if (!g.Contains(n) || !is_frontier[g.Index(n)]) continue;
          is_frontier[g.Index(n)] = 0;
          stack.push_back(g.Index(n));
        }
      }
      f.centroid /= f.cells;
      if (f.cells >= p_.min_frontier_cells) out.push_back(f);
    }
    return out;
  }

  // Cells the body may cross: known free with the clearance from occupied cells, and the cells
  // under the body now (the scanner cannot see the floor around itself; the LRF not behind).
  // Unknown cells are not entered, but do not push paths away: the sweeps mark what is there.
  std::vector<std::uint8_t> Passable(const Vec2& here) const {
    const perception::OccupancyGrid& g = result_.grid;
    const perception::DistanceField df(g, /*unknown_is_obstacle=*/false);
    std::vector<std::uint8_t> ok(static_cast<std::size_t>(g.Width()) * g.Height(), 0);
    for (int j = 0; j < g.Height(); ++j)
      for (int i = 0; i < g.Width(); ++i) {
        const perception::CellState s = g.State({i, j});
        const bool under_body = (g.CentreOf({i, j}) - here).norm() < kFreeAroundRobot;
        ok[g.Index({i, j})] = s != perception::CellState::kOccupied &&
                              (under_body || (s == perception::CellState::kFree &&
                                              df.ClearanceOfCell({i, j}) >= p_.clearance));
      }
    return ok;
  }

  std::vector<Vec2> PlanPath(const std::vector<std::uint8_t>& passable, const Vec2& from,
                             const Vec2& to) const {
    const perception::OccupancyGrid& g = result_.grid;
    const perception::Cell a = g.CellOf(from), b = g.CellOf(to);
    if (!g.Contains(a) || !g.Contains(b) || !passable[g.Index(b)]) return {};
    const double res = g.Resolution();
    const auto cells = perception::GridShortestPath(
        g.Width(), g.Height(), g.Index(a), g.Index(b), perception::kNeighboursAxesFirst,
        [&](std::size_t, std::size_t to_cell, const perception::GridStep& s) {
          return passable[to_cell] ? (s.Diagonal() ? res * std::sqrt(2.0) : res) : -1.0;
        });
    std::vector<Vec2> path;
    for (std::size_t k : cells)
      path.push_back(
          g.CentreOf({static_cast<int>(k % g.Width()), static_cast<int>(k / g.Width())}));
    return path;
  }

  static double Length(const std::vector<Vec2>& path) {
    double l = 0.0;
    for (std::size_t k = 1; k < path.size(); ++k) l += (path[k] - path[k - 1]).norm();
    return l;
  }

  // The frontier worth most (cells per metre of path), its goal the passable cell in the room
  // nearest its centroid (within goal_reach), away from earlier scans and given-up goals.
  bool ChooseGoal(const std::vector<Frontier>& frontiers, Vec2* goal, std::vector<Vec2>* path) {
    const perception::OccupancyGrid& g = result_.grid;
    const Vec2 here(Estimate().x, Estimate().y);
    const std::vector<std::uint8_t> passable = Passable(here);
    double best = -1.0;
    for (const Frontier& f : frontiers) {
      Vec2 candidate;
      double nearest = p_.goal_reach;
      const int reach = static_cast<int>(std::ceil(p_.goal_reach / g.Resolution()));
      const perception::Cell c0 = g.CellOf(f.centroid);
      for (int dj = -reach; dj <= reach; ++dj)
        for (int di = -reach; di <= reach; ++di) {
          const perception::Cell c{c0.i + di, c0.j + dj};
          if (!g.Contains(c) || !passable[g.Index(c)]) continue;
          const Vec2 p = g.CentreOf(c);
          const double d = (p - f.centroid).norm();
          if (d >= nearest || !InRoom(p) || NearAny(p, scan_positions_, p_.min_scan_spacing) ||
              NearAny(p, given_up_, p_.min_scan_spacing))
            continue;
          nearest = d, candidate = p;
        }
      if (nearest >= p_.goal_reach) continue;
      std::vector<Vec2> route = PlanPath(passable, here, candidate);
      if (route.empty()) continue;
      const double value = f.cells / (1.0 + Length(route));
      if (value > best) best = value, *goal = candidate, *path = std::move(route);
    }
    return best >= 0.0;
  }

  static bool NearAny(const Vec2& p, const std::vector<Vec2>& places, double radius) {
    return std::any_of(places.begin(), places.end(),
                       [&](const Vec2& q) { return (p - q).norm() < radius; });
  }

  // Pure pursuit along `path`, planned again every replan_period. False when the goal was not
  // reached within leg_timeout or no path is left.
  bool DriveTo(const Vec2& goal, std::vector<Vec2> path) {
    const double t0 = robot_.Time();
    double planned = t0;
    while (robot_.Time() - t0 < p_.leg_timeout && robot_.Time() < p_.time_budget) {
      const Pose2 X = Estimate();
      const Vec2 here(X.x, X.y);
      if ((goal - here).norm() < p_.goal_tolerance) {
        for (int k = 0; k < kSettleSteps; ++k) Step({});
        return true;
      }
      if (robot_.Time() - planned >= p_.replan_period) {
        planned = robot_.Time();
        std::vector<Vec2> again = PlanPath(Passable(here), here, goal);
        if (again.empty()) return false;
        path = std::move(again);
      }
      // The lookahead point: the first path point that far from the robot (else the goal).
      Vec2 aim = goal;
      std::size_t nearest = 0;
      for (std::size_t k = 1; k < path.size(); ++k)
        if ((path[k] - here).norm() < (path[nearest] - here).norm()) nearest = k;
      for (std::size_t k = nearest; k < path.size(); ++k)
        if ((path[k] - here).norm() >= p_.lookahead) {
          aim = path[k];
          break;
        }
      const double heading = std::atan2(aim.y() - here.y(), aim.x() - here.x());
      const double e = mopad::WrapAngle(heading - X.yaw);
      mopad::interfaces::VelocityCommand cmd;
      cmd.w = std::clamp(kTurnGain * e, -p_.turn_rate, p_.turn_rate);
      // Turn on the spot when the aim is well off the nose; slow down near the goal.
      const double align = std::max(0.0, std::cos(e));
      cmd.v = std::abs(e) > kTurnInPlace ? 0.0
                                         : std::min(p_.speed, (goal - here).norm()) * align * align;
      Step(cmd);
    }
    return false;
  }

  static constexpr double kLrfRange = 8.0;         // m, LRF returns farther are only free space
  static constexpr double kPriorSigma = 0.2;       // m, x-y std of the odometry prior at a scan
  static constexpr double kFreeAroundRobot = 0.3;  // m, cells under the body stay passable
  static constexpr double kTurnGain = 1.5;         // 1/s, yaw rate per rad of heading error
  static constexpr double kTurnInPlace = 1.0;      // rad, larger errors turn on the spot
  static constexpr int kSettleSteps = 10;          // control periods of standing before a scan

  mopad::interfaces::RobotPlatform& robot_;
  ExplorerParams p_;
  std::function<void(const std::string&)> log_;
  perception::IcpParams icp_;
  perception::PointMap target_;
  // The prior is wheel odometry alone (no localiser between scans): a turn on the spot costs
  // about 1 % of its angle in yaw, so corrections of a few degrees and decimetres are expected.
  const perception::RegistrationAcceptanceParams acceptance_{.max_correction = 0.5,
                                                             .max_correction_deg = 10.0};
  ExplorerResult result_;
  Pose2 X_MO_;  // odom -> map correction
  std::uint64_t last_sweep_ = std::numeric_limits<std::uint64_t>::max();
  std::vector<Vec2> scan_positions_, given_up_;
};

}  // namespace

ExplorerResult Explore(mopad::interfaces::RobotPlatform& robot, const ExplorerParams& params,
                       const std::function<void(const std::string&)>& log) {
  params.Validate();
  return Explorer(robot, params, log).Run();
}

std::size_t WriteRoomFiles(const ExplorerResult& result, const std::string& room,
                           const std::string& dir) {
  namespace runfolder = mopad::runfolder;
  std::filesystem::create_directories(dir);
  const mopad::modelling::RoomModel& model = result.model;
  const mopad::modelling::StructuralModel sm3 =
      mopad::modelling::BuildRoomSm3(model, mopad::modelling::Sm3Params{}, room);
  model.WriteSm1(runfolder::Join(dir, runfolder::kSm1));
  mopad::io::WriteTextFile(runfolder::Join(dir, runfolder::kSm2),
                           mopad::modelling::Sm2Json(model.GetRoi(), room));
  mopad::io::WriteTextFile(runfolder::Join(dir, runfolder::kSm3), mopad::modelling::Sm3Json(sm3));
  mopad::modelling::WriteDsm3Ply(model.Voxels(), runfolder::Join(dir, runfolder::kDsm3));
  std::string poses;
  for (const ExplorerScan& s : result.scans)
    if (s.registered) poses += mopad::io::TumLine(s.time, s.X_MS);
  mopad::io::WriteTextFile(runfolder::Join(dir, runfolder::kScanPoses), poses);
  return sm3.patches.size();
}

}  // namespace frontier
