#include "autonomy/local_controller.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "common/error.h"
#include "common/format.h"
#include "common/statistics.h"

namespace mopad::autonomy {

using perception::LocalisationStatus;

void LocalControllerParams::Validate() const {
  ValidateParams(*this, "local_controller.");
  if (min_speed > max_linear_speed || passage_speed > max_linear_speed) {
    throw InputError("",
                     "local_controller min_speed and passage_speed must not exceed "
                     "max_linear_speed",
                     std::to_string(std::max(min_speed, passage_speed)),
                     "<= " + std::to_string(max_linear_speed));
  }
  if (slowdown_distance < stop_distance) {
    throw InputError("", "parameter 'local_controller.slowdown_distance' below stop_distance",
                     std::to_string(slowdown_distance), ">= " + std::to_string(stop_distance));
  }
  if (range_median_window % 2 == 0) {
    throw InputError("", "parameter 'local_controller.range_median_window' must be odd",
                     std::to_string(range_median_window), "1, 3, 5, ...");
  }
}

const char* ToString(NavStatus s) {
  switch (s) {
    case NavStatus::kIdle:
      return "idle";
    case NavStatus::kFollowing:
      return "following";
    case NavStatus::kDoorPassage:
      return "door_passage";
    case NavStatus::kRecovering:
      return "recovering";
    case NavStatus::kBlocked:
      return "blocked";
    case NavStatus::kArrived:
      return "arrived";
    case NavStatus::kUnreachable:
      return "unreachable";
    case NavStatus::kLocalisationLost:
      return "localisation_lost";
  }
  return "?";
}

namespace {

// m: map obstacles farther than this from base_link cannot meet the footprint in one check
// (half diagonal 0.39 m + margin + the 0.3 m back-up horizon).
constexpr double kMapObstacleRadius = 1.0;
// m: obstacles an escape manoeuvre (two arcs of at most 0.8 m) can meet.
constexpr double kEscapeRadius = 2.2;
// Checks of the recovery motions: back-up free travel looked at (m) and the least that lets it
// go on (m), the turn a recovery rotation must have free (rad), the free travel an escape arc
// needs to go on (m), and how close to its length an arc counts as driven (m).
constexpr double kBackUpCheck = 0.3;
constexpr double kBackUpMinFree = 0.05;
constexpr double kRotateCheck = 0.2;
constexpr double kEscapeMinFree = 0.02;
constexpr double kArcEndTolerance = 0.005;

/// Pose after moving along the arc (v, w) for time t from the identity.
Pose2 Arc(double v, double w, double t) {
  const double th = w * t;
  if (std::abs(th) < 1e-9) return {v * t, 0.0, th};
  const double r = v / w;
  return {r * std::sin(th), r * (1.0 - std::cos(th)), th};
}

/// `p` (in the parent frame of `X`) expressed in the frame X.
Vec2 InFrame(const Pose2& X, const Vec2& p) {
  const double c = std::cos(X.yaw), s = std::sin(X.yaw);
  const Vec2 d = p - Vec2(X.x, X.y);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

}  // namespace

LocalController::LocalController(const LocalControllerParams& params) : params_(params) {
  params_.Validate();
  terminal_.status = NavStatus::kIdle;
  terminal_.message = "no path";
}

void LocalController::InstallPlan(const GlobalPlan& plan) {
  path_ = plan.path;
  passages_.clear();
  for (const Passage& p : plan.passages) passages_.push_back({p, false, false});
  closest_ = 0;
}

void LocalController::SetPlan(const GlobalPlan& plan, bool align_yaw) {
  if (!plan.ok() || plan.path.empty()) {
    throw InputError("", "LocalController::SetPlan needs a found plan", ToString(plan.status),
                     "found");
  }
  InstallPlan(plan);
  goal_ = plan.path.back().pose;
  align_yaw_ = align_yaw;
  mode_ = Mode::kFollow;
  recoveries_ = 0;
  s_at_last_recovery_ = 0.0;
  blocked_since_.reset();
  lost_since_.reset();
  last_time_.reset();
  last_cmd_ = {};
  terminal_ = {};
}

ControlOutput LocalController::Finish(NavStatus s, const std::string& message) {
  mode_ = Mode::kDone;
  terminal_.cmd = {};
  terminal_.status = s;
  terminal_.message = message;
  terminal_.finished = true;
  terminal_.recoveries = recoveries_;
  last_cmd_ = {};
  return terminal_;
}

std::vector<double> LocalController::MedianFiltered(const interfaces::LrfScan& scan, int window) {
  const std::size_t n = scan.ranges.size();
  auto valid = [&](double r) {
    return std::isfinite(r) && r >= scan.range_min && r < scan.range_max;
  };
  std::vector<double> out(n, std::numeric_limits<double>::quiet_NaN());
  const long h = std::max(0, window / 2);
  std::vector<double> w;
  for (std::size_t k = 0; k < n; ++k) {
    if (!valid(scan.ranges[k])) continue;  // a gap stays a gap
    w.clear();
    for (long j = static_cast<long>(k) - h; j <= static_cast<long>(k) + h; ++j)
      if (j >= 0 && j < static_cast<long>(n) && valid(scan.ranges[static_cast<std::size_t>(j)]))
        w.push_back(scan.ranges[static_cast<std::size_t>(j)]);
    out[k] = UpperMedian(w);
  }
  return out;
}

double LocalController::JambDistance(const std::vector<Vec2>& points_B, double side) const {
  const double half_len = 0.5 * params_.footprint_length + 0.05;
  const double half_w = 0.5 * params_.footprint_width;
  std::vector<double> lateral;
  for (const Vec2& p : points_B) {
    const double x = p.x() - params_.footprint_offset_x, y = side * p.y();
    if (std::abs(x) <= half_len && y >= 0.5 * half_w && y <= 1.0) lateral.push_back(y);
  }
  if (lateral.empty()) return std::numeric_limits<double>::infinity();
  // The nearest surface: the returns from just below the 10th percentile to 8 cm above it
  // (a jamb face; a wall face or furniture farther out stays outside), their median.
  std::sort(lateral.begin(), lateral.end());
  const double q = lateral[lateral.size() / 10];
  const auto lo = std::lower_bound(lateral.begin(), lateral.end(), q - 0.05);
  const auto hi = std::upper_bound(lateral.begin(), lateral.end(), q + 0.08);
  return *(lo + (hi - lo) / 2);
}

double LocalController::BoxDistance(const Vec2& q_B) const {
  return std::max(std::abs(q_B.x() - params_.footprint_offset_x) - 0.5 * params_.footprint_length,
                  std::abs(q_B.y()) - 0.5 * params_.footprint_width);
}

double LocalController::FreeTravel(const std::vector<Vec2>& points_B, double v, double w,
                                   double margin, double horizon) const {
  const double radius =
      std::hypot(0.5 * params_.footprint_length + std::abs(params_.footprint_offset_x),
                 0.5 * params_.footprint_width) +
      margin;
  const double reach = std::abs(v) < 1e-9 ? radius : radius + horizon;
  // A point already within the margin (the base stopped close beside a cabinet, or was
  // pushed there) blocks only motions that bring it closer still: otherwise every motion,
  // backing straight out included, would count as blocked and the base would be wedged where
  // it stands (a scan stop in a niche between two cabinets, 0.8 m wide, is such a place).
  std::vector<Vec2> near;
  std::vector<double> start;  // box distance at the start pose
  for (const Vec2& p : points_B)
    if (p.norm() <= reach) near.push_back(p), start.push_back(BoxDistance(p));
  if (near.empty()) return horizon;
  // Any approach counts (a tolerance here would be a ratchet: the check runs again every
  // control step from the pose reached).
  constexpr double kCloser = 1e-4;  // m
  auto hits = [&](const Pose2& X_B0B) {
    for (std::size_t k = 0; k < near.size(); ++k) {
      const double d = BoxDistance(InFrame(X_B0B, near[k]));
      if (d <= margin && (start[k] > margin || d < start[k] - kCloser)) return true;
    }
    return false;
  };
  if (std::abs(v) < 1e-9) {  // rotation in place: horizon is an angle
    const double dir = w >= 0 ? 1.0 : -1.0;
    for (double a = 0.0; a <= horizon; a += 0.02)
      if (hits({0.0, 0.0, dir * a})) return a;
    return horizon;
  }
  const double speed = std::abs(v);
  for (double s = 0.0; s <= horizon; s += 0.02)
    if (hits(Arc(v, w, s / speed))) return s;
  return horizon;
}

std::vector<ArcMove> LocalController::EscapeManoeuvre(const std::vector<Vec2>& points_B,
                                                      const Vec2& target_B) const {
  const LocalControllerParams& P = params_;
  if (P.escape_arc_length <= 0.0) return {};
  constexpr double kStep = 0.1;           // m, arc lengths tried
  constexpr double kSecondArcCost = 0.3;  // m, a direction change costs as much as this
  constexpr double kAhead = 0.3;          // m free ahead when it already faces the target
  const double turn_margin = std::min(P.safety_margin, P.passage_side_margin);  // as Update's
  const double radius = std::hypot(0.5 * P.footprint_length + std::abs(P.footprint_offset_x),
                                   0.5 * P.footprint_width);
  std::vector<Vec2> near;  // the points an arc (or the turn after it) can meet
  const double reach = radius + P.stop_distance + 2.0 * P.escape_arc_length;
  for (const Vec2& p : points_B)
    if (p.norm() <= reach) near.push_back(p);
  // Arcs: forward and back, straight or curving either way (radius 1, 0.5, 0.3 m).
  std::vector<ArcMove> arcs;
  for (double dir : {-1.0, 1.0})
    for (double kappa : {0.0, 1.0, -1.0, 2.0, -2.0, 3.3, -3.3})
      arcs.push_back({dir * P.backup_speed, dir * P.backup_speed * kappa, 0.0});
  auto moved = [](const std::vector<Vec2>& pts, const Pose2& X) {
    std::vector<Vec2> out;
    out.reserve(pts.size());
    for (const Vec2& p : pts) out.push_back(InFrame(X, p));
    return out;
  };
  // Can the base, at pose X (in the start frame), go on toward the target?
  auto can_go_on = [&](const Pose2& X) {
    const std::vector<Vec2> pts = moved(near, X);
    const Vec2 t = InFrame(X, target_B);
    const double alpha = std::atan2(t.y(), t.x());
    if (std::abs(alpha) <= DegToRad(P.rotate_in_place_deg))
      return FreeTravel(pts, P.backup_speed, 0.0, P.stop_distance, kAhead) >= kAhead - 1e-9;
    return FreeTravel(pts, 0.0, alpha >= 0 ? 1.0 : -1.0, turn_margin, std::abs(alpha)) >=
           std::abs(alpha) - 1e-9;
  };
  std::vector<ArcMove> best;
  double best_cost = std::numeric_limits<double>::infinity();
  // One arc.
  std::vector<std::pair<ArcMove, Pose2>> firsts;  // feasible first arcs, for two-arc ones
  for (const ArcMove& a : arcs) {
    const double free = FreeTravel(near, a.v, a.w, P.stop_distance, P.escape_arc_length);
    for (double len = kStep; len <= free - P.stop_distance + 1e-9; len += kStep) {
      const Pose2 X = Arc(a.v, a.w, len / std::abs(a.v));
      firsts.push_back({{a.v, a.w, len}, X});
      if (len < best_cost && can_go_on(X)) {
        best = {{a.v, a.w, len}};
        best_cost = len;
      }
    }
  }
  // Two arcs (a three-point turn), only if shorter than the best single arc.
  for (const auto& [a1, X1] : firsts) {
    if (a1.length + kSecondArcCost + kStep >= best_cost) continue;
    const std::vector<Vec2> pts1 = moved(near, X1);
    for (const ArcMove& a : arcs) {
      if (a.v * a1.v > 0.0 && std::abs(a.w - a1.w) < 1e-9) continue;  // the same arc, longer
      const double free = FreeTravel(pts1, a.v, a.w, P.stop_distance, P.escape_arc_length);
      for (double len = kStep; len <= free - P.stop_distance + 1e-9; len += kStep) {
        const double cost = a1.length + len + kSecondArcCost;
        if (cost >= best_cost) break;
        if (can_go_on(perception::Compose(X1, Arc(a.v, a.w, len / std::abs(a.v))))) {
          best = {a1, {a.v, a.w, len}};
          best_cost = cost;
          break;
        }
      }
    }
  }
  return best;
}

std::vector<Vec2> LocalController::BasePoints(const interfaces::LrfScan& scan) const {
  std::vector<Vec2> pts;
  pts.reserve(scan.ranges.size());
  const std::vector<double> ranges = MedianFiltered(scan, params_.range_median_window);
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const double r = ranges[k];
    if (!std::isfinite(r)) continue;
    const double a = scan.angle_min + scan.angle_increment * static_cast<double>(k);
    const Eigen::Vector3d q = scan.X_BL * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0.0);
    pts.emplace_back(q.x(), q.y());
  }
  return pts;
}

bool LocalController::CanTurn(const Pose2& X_MB, const interfaces::LrfScan& scan,
                              double angle) const {
  std::vector<Vec2> pts = BasePoints(scan);
  if (map_obstacles_)
    for (const Vec2& q : map_obstacles_(X_MB, kMapObstacleRadius)) pts.push_back(InFrame(X_MB, q));
  const double a = std::abs(angle);
  return FreeTravel(pts, 0.0, angle >= 0.0 ? 1.0 : -1.0, params_.passage_side_margin, a) >= a;
}

Vec2 LocalController::HeadingTarget(const Pose2& X_MB) const {
  for (const PassageState& p : passages_)
    if (!p.done && !p.aligned && closest_ < path_.size() && Approaching(p, path_[closest_].s))
      return Vec2(X_MB.x, X_MB.y) +
             Vec2(std::cos(p.passage.axis_yaw), std::sin(p.passage.axis_yaw));
  std::size_t k = std::min(closest_, path_.size() - 1);
  const double s_to = path_[k].s + 1.0;
  while (k + 1 < path_.size() && path_[k].s < s_to) ++k;
  return {path_[k].pose.x, path_[k].pose.y};
}

interfaces::VelocityCommand LocalController::Limit(interfaces::VelocityCommand cmd,
                                                   double dt) const {
  const LocalControllerParams& P = params_;
  cmd.v = std::clamp(cmd.v, -P.max_linear_speed, P.max_linear_speed);
  cmd.w = std::clamp(cmd.w, -P.max_angular_speed, P.max_angular_speed);
  if (dt > 0.0) {
    // Acceleration limits on speeding up only: stopping must never be delayed here.
    if (std::abs(cmd.v) > std::abs(last_cmd_.v) && cmd.v * last_cmd_.v >= 0.0)
      cmd.v = std::copysign(
          std::min(std::abs(cmd.v), std::abs(last_cmd_.v) + P.max_linear_acceleration * dt), cmd.v);
    if (std::abs(cmd.w) > std::abs(last_cmd_.w) && cmd.w * last_cmd_.w >= 0.0)
      cmd.w = std::copysign(
          std::min(std::abs(cmd.w), std::abs(last_cmd_.w) + P.max_angular_acceleration * dt),
          cmd.w);
  }
  return cmd;
}

ControlOutput LocalController::StartRecovery(double time, const Pose2& X_MB,
                                             const std::string& reason,
                                             const std::vector<Vec2>& points_B) {
  const LocalControllerParams& P = params_;
  blocked_since_.reset();
  if (recoveries_ >= P.max_recoveries) {
    return Finish(NavStatus::kBlocked,
                  reason + "; giving up after " + std::to_string(recoveries_) + " recoveries");
  }
  ++recoveries_;
  recovery_reason_ = reason;
  recovery_start_ = X_MB;
  recovery_turned_ = 0.0;
  recovery_last_yaw_ = X_MB.yaw;
  s_at_last_recovery_ = closest_ < path_.size() ? path_[closest_].s : 0.0;
  mode_ = recoveries_ % 2 == 1 ? Mode::kBackUp : Mode::kRotate;
  anchor_pose_ = X_MB;
  anchor_time_ = time;
  ControlOutput out;
  out.status = NavStatus::kRecovering;
  out.recoveries = recoveries_;
  if (turn_blocked_ && !path_.empty()) {
    // It cannot turn where it stands: backing straight up may not free it either (a corner
    // of the niche behind it), so look for arcs after which it can.
    std::vector<Vec2> pts = points_B;
    if (map_obstacles_)
      for (const Vec2& q : map_obstacles_(X_MB, kEscapeRadius)) pts.push_back(InFrame(X_MB, q));
    escape_ = EscapeManoeuvre(pts, InFrame(X_MB, HeadingTarget(X_MB)));
    if (!escape_.empty()) {
      mode_ = Mode::kEscape;
      escape_arc_ = 0;
      escape_arc_start_ = X_MB;
      double length = 0.0;
      for (const ArcMove& a : escape_) length += a.length;
      escape_deadline_ = time + 2.0 * length / P.backup_speed + 4.0;
      std::string arcs;
      for (const ArcMove& a : escape_)
        arcs +=
            std::string(arcs.empty() ? "" : ", then ") + FormatNumbers("%.1f m ", a.length) +
            (a.v < 0 ? "back" : "forward") +
            (std::abs(a.w) < 1e-9 ? "" : FormatNumbers(" on a %.2f m radius", std::abs(a.v / a.w)));
      out.message = "recovery " + std::to_string(recoveries_) + "/" +
                    std::to_string(P.max_recoveries) + ": escape manoeuvre, " + arcs + " (" +
                    reason + ")";
      return out;
    }
  }
  out.message = "recovery " + std::to_string(recoveries_) + "/" + std::to_string(P.max_recoveries) +
                (mode_ == Mode::kBackUp ? ": backing up" : ": rotating in place") + " (" + reason +
                ")";
  return out;
}

ControlOutput LocalController::AfterRecoveryMotion(double time, const Pose2& X_MB,
                                                   const std::vector<Vec2>& points_B) {
  const LocalControllerParams& P = params_;
  mode_ = Mode::kFollow;
  anchor_pose_ = X_MB;
  anchor_time_ = time;
  ControlOutput out;
  out.status = NavStatus::kRecovering;
  out.recoveries = recoveries_;
  if (!replan_) {
    out.message =
        "recovery " + std::to_string(recoveries_) + ": motion done, resuming (no replanner)";
    return out;
  }
  std::vector<Vec2> obstacles;
  const double c = std::cos(X_MB.yaw), s = std::sin(X_MB.yaw);
  for (const Vec2& p : points_B) {
    if (p.norm() > P.replan_radius) continue;
    obstacles.emplace_back(X_MB.x + c * p.x() - s * p.y(), X_MB.y + s * p.x() + c * p.y());
  }
  const GlobalPlan plan = replan_(X_MB, obstacles);
  if (plan.ok()) {
    InstallPlan(plan);
    out.message = "recovery " + std::to_string(recoveries_) + ": replanned around " +
                  std::to_string(obstacles.size()) + " LRF points (" + plan.message + ")";
    return out;
  }
  if (plan.status == PlanStatus::kUnreachable || plan.status == PlanStatus::kGoalInvalid) {
    return Finish(NavStatus::kUnreachable,
                  recovery_reason_ + "; replanning with the LRF obstacles: " + plan.message);
  }
  out.message = "recovery " + std::to_string(recoveries_) + ": replan failed (" + plan.message +
                "), resuming the old path";
  return out;
}

// ---- One control step: one function per mode, in the order Update runs them.

LocalController::Step LocalController::BeginStep(double time, const Pose2& X_MB,
                                                 const interfaces::LrfScan& scan) {
  Step c;
  c.time = time;
  c.X_MB = X_MB;
  c.dt = last_time_ ? std::max(0.0, time - *last_time_) : 0.0;
  if (!last_time_) {
    anchor_pose_ = X_MB;
    anchor_time_ = time;
  }
  last_time_ = time;
  // LRF returns in base_link, each range the median of its neighbours' (a scanner's range
  // noise would otherwise put the nearest of many returns 2-3 sigma too close).
  c.pts = BasePoints(scan);
  return c;
}

// The map's obstacles near the base, in base_link, with the LRF returns: for the motions the
// LRFs do not cover (looked up only when such a motion is checked).
const std::vector<Vec2>& LocalController::Around(Step& c) const {
  if (!c.around) {
    c.around = c.pts;
    if (map_obstacles_)
      for (const Vec2& q : map_obstacles_(c.X_MB, kMapObstacleRadius))
        c.around->push_back(InFrame(c.X_MB, q));
  }
  return *c.around;
}

ControlOutput LocalController::Emit(const Step& c, ControlOutput out, bool limit) {
  out.cmd = limit ? Limit(out.cmd, c.dt) : out.cmd;
  out.recoveries = recoveries_;
  last_cmd_ = out.cmd;
  return out;
}

void LocalController::ResetAnchor(const Step& c) {
  anchor_pose_ = c.X_MB;
  anchor_time_ = c.time;
}

// Localisation first: never drive on a pose the filter does not trust.
std::optional<ControlOutput> LocalController::LocalisationStep(Step& c, LocalisationStatus loc) {
  const LocalControllerParams& P = params_;
  if (loc == LocalisationStatus::kLost || loc == LocalisationStatus::kRelocalising ||
      loc == LocalisationStatus::kNotInitialised) {
    if (!lost_since_) lost_since_ = c.time;
    if (c.time - *lost_since_ > P.lost_timeout) {
      return Finish(NavStatus::kLocalisationLost,
                    FormatNumbers("localisation lost for %.0f s (AMCL: ", c.time - *lost_since_) +
                        perception::ToString(loc) + "); stopped");
    }
    ControlOutput out;
    out.status = NavStatus::kLocalisationLost;
    const bool can_turn =
        FreeTravel(Around(c), 0.0, 1.0, P.stop_distance, P.lost_turn_check) >= P.lost_turn_check;
    out.cmd = {0.0, can_turn ? P.lost_rotation_speed : 0.0};
    out.message =
        std::string("localisation ") + perception::ToString(loc) +
        (can_turn ? ": rotating in place to re-localise" : ": stopped (no room to rotate)");
    ResetAnchor(c);
    return Emit(c, out);
  }
  if (lost_since_) {  // re-localised: the pose may have jumped, so pick the path up again
    lost_since_.reset();
    closest_ = 0;
    ResetAnchor(c);
    if (replan_) {
      const GlobalPlan plan = replan_(c.X_MB, {});
      if (plan.ok()) InstallPlan(plan);
    }
  }
  return std::nullopt;
}

ControlOutput LocalController::BackUpStep(Step& c) {
  const LocalControllerParams& P = params_;
  const double moved = std::hypot(c.X_MB.x - recovery_start_.x, c.X_MB.y - recovery_start_.y);
  const double free = FreeTravel(Around(c), -P.backup_speed, 0.0, P.stop_distance, kBackUpCheck);
  if (moved >= P.backup_distance || free < kBackUpMinFree ||
      c.time - anchor_time_ > P.stuck_timeout)
    return Emit(c, AfterRecoveryMotion(c.time, c.X_MB, c.pts));
  ControlOutput out;
  out.status = NavStatus::kRecovering;
  out.cmd = {-P.backup_speed, 0.0};
  out.message = FormatNumbers("recovery %.0f: backing up (%.2f of %.2f m)", recoveries_, moved,
                              P.backup_distance);
  return Emit(c, out);
}

ControlOutput LocalController::EscapeStep(Step& c) {
  const LocalControllerParams& P = params_;
  // Length driven along this arc, from the chord and the turn since its start.
  const double chord = std::hypot(c.X_MB.x - escape_arc_start_.x, c.X_MB.y - escape_arc_start_.y);
  const double half_turn = 0.5 * std::abs(WrapAngle(c.X_MB.yaw - escape_arc_start_.yaw));
  double driven = half_turn > 1e-3 ? chord * half_turn / std::sin(half_turn) : chord;
  if (driven >= escape_[escape_arc_].length - kArcEndTolerance) {
    if (++escape_arc_ == escape_.size()) {
      // Done: a path from here (the old one may start with the narrow stretch just left).
      turn_blocked_ = false;
      return Emit(c, AfterRecoveryMotion(c.time, c.X_MB, c.pts));
    }
    escape_arc_start_ = c.X_MB;
    driven = 0.0;
  }
  const ArcMove& b = escape_[escape_arc_];
  const double left = b.length - driven;
  const double free =
      FreeTravel(Around(c), b.v, b.w, P.passage_side_margin, std::clamp(left, 0.05, 0.3));
  if (free < kEscapeMinFree || c.time > escape_deadline_)
    return Emit(c,
                AfterRecoveryMotion(c.time, c.X_MB, c.pts));  // the map or the LRF disagree: replan
  ControlOutput out;
  out.status = NavStatus::kRecovering;
  out.cmd = {b.v, b.w};
  out.message =
      FormatNumbers("recovery %.0f: escape manoeuvre, arc %.0f of %.0f", recoveries_,
                    static_cast<double>(escape_arc_ + 1), static_cast<double>(escape_.size()));
  return Emit(c, out);
}

ControlOutput LocalController::RotateStep(Step& c) {
  const LocalControllerParams& P = params_;
  recovery_turned_ += std::abs(WrapAngle(c.X_MB.yaw - recovery_last_yaw_));
  recovery_last_yaw_ = c.X_MB.yaw;
  const bool can_turn =
      FreeTravel(Around(c), 0.0, 1.0, P.stop_distance, kRotateCheck) >= kRotateCheck;
  if (recovery_turned_ >= 2.0 * kPi || !can_turn ||
      c.time - anchor_time_ > 4.0 * kPi / P.lost_rotation_speed)
    return Emit(c, AfterRecoveryMotion(c.time, c.X_MB, c.pts));
  ControlOutput out;
  out.status = NavStatus::kRecovering;
  out.cmd = {0.0, std::max(P.lost_rotation_speed, P.min_recovery_rotation_speed)};
  out.message = FormatNumbers("recovery %.0f: rotating in place (%.0f of 360 deg)", recoveries_,
                              RadToDeg(recovery_turned_));
  return Emit(c, out);
}

// Progress along the path: the closest point within a forward window (the whole path when
// the base is far off it, e.g. after a jump of the estimate).
void LocalController::TrackProgress(const Pose2& X_MB) {
  const LocalControllerParams& P = params_;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = closest_;
  const double s_max = path_[closest_].s + P.path_search_window;
  for (std::size_t k = closest_; k < path_.size() && path_[k].s <= s_max; ++k) {
    const double d = std::hypot(path_[k].pose.x - X_MB.x, path_[k].pose.y - X_MB.y);
    if (d < best) {
      best = d;
      best_k = k;
    }
  }
  if (best > P.path_reacquire_distance) {
    for (std::size_t k = 0; k < path_.size(); ++k) {
      const double d = std::hypot(path_[k].pose.x - X_MB.x, path_[k].pose.y - X_MB.y);
      if (d < best) {
        best = d;
        best_k = k;
      }
    }
  }
  closest_ = best_k;
}

// The passage the base is in or approaching; passages it is through are marked done.
LocalController::PassageState* LocalController::CurrentPassage(const Vec2& here, double s_here) {
  const LocalControllerParams& P = params_;
  for (auto& p : passages_) {
    if (p.done) continue;
    // Through: the body's rear past the narrowest point, along the path or along the passage
    // axis; or at the end of a path that ends in or just beyond the passage (a scan stop after
    // a door): the crossing only follows the axis and would drive on past the goal.
    const double through = 0.5 * P.footprint_length + P.passage_exit_clearance;
    const Vec2 ax(std::cos(p.passage.axis_yaw), std::sin(p.passage.axis_yaw));
    if (s_here > p.passage.s + through || ax.dot(here - p.passage.centre) > through ||
        (closest_ + 1 == path_.size() && s_here >= p.passage.s)) {
      p.done = true;
      continue;
    }
    if (Approaching(p, s_here)) return &p;
  }
  return nullptr;
}

interfaces::VelocityCommand LocalController::TurnOnTheSpot(double heading_error) const {
  const LocalControllerParams& P = params_;
  const double w =
      std::clamp(P.heading_gain * heading_error, -P.max_angular_speed, P.max_angular_speed);
  return {0.0, std::copysign(std::max(std::abs(w), P.min_turn_speed), w)};
}

// Door passage: align with the axis first, then cross it centred between the jambs the LRF
// sees. `margin` becomes the crossing's side margin; `turn_needed` the alignment that must be
// free as a whole (facing away from the passage).
void LocalController::PassageStep(const Step& c, PassageState& passage, double s_here,
                                  ControlOutput& out, double& margin, double& turn_needed) const {
  const LocalControllerParams& P = params_;
  const Vec2 here(c.X_MB.x, c.X_MB.y);
  const double axis_yaw = passage.passage.axis_yaw;
  const Vec2 axis(std::cos(axis_yaw), std::sin(axis_yaw));
  // Onto the axis first, when the path goes through (its end lies past the narrowest point
  // along the axis; a goal in front of a gap, a scan stop beside a desk, is reached by the
  // crossing's hand-over to the final approach, not by a crossing): the point of the axis
  // level with the base (at least 0.3 m before the narrowest point), reached by turning
  // towards it and driving there.
  if (!passage.on_axis && !path_.empty() &&
      axis.dot(Vec2(path_.back().pose.x, path_.back().pose.y) - passage.passage.centre) <= 0.0)
    passage.on_axis = true;
  if (!passage.on_axis && !passage.aligned) {
    const Vec2 off = here - passage.passage.centre;
    const double along = std::min(axis.dot(off), -0.3);
    const Vec2 target = passage.passage.centre + along * axis;
    const double slack =
        std::max(0.02, 0.5 * (passage.passage.width - P.footprint_width) - P.passage_side_margin);
    const double d = (target - here).norm();
    if (d <= std::max(0.02, P.passage_axis_share * slack)) {
      passage.on_axis = true;
    } else {
      out.status = NavStatus::kDoorPassage;
      const double herr =
          WrapAngle(std::atan2(target.y() - here.y(), target.x() - here.x()) - c.X_MB.yaw);
      if (std::abs(herr) > DegToRad(10.0)) {
        out.cmd = TurnOnTheSpot(herr);
        if (std::abs(herr) > 0.5 * kPi) turn_needed = std::abs(herr);
      } else {
        out.cmd = {std::min(P.passage_speed, d),
                   std::clamp(P.heading_gain * herr, -P.max_angular_speed, P.max_angular_speed)};
      }
      out.message = FormatNumbers(
          "door passage: moving onto the passage axis (%.3f m off it), %.2f m before its centre", d,
          -along);
      return;
    }
  }
  if (!passage.aligned) {
    const double herr = WrapAngle(axis_yaw - c.X_MB.yaw);
    if (std::abs(herr) < DegToRad(P.passage_align_deg)) {
      passage.aligned = true;
    } else {
      out.status = NavStatus::kDoorPassage;
      out.cmd = TurnOnTheSpot(herr);
      if (std::abs(herr) > 0.5 * kPi) turn_needed = std::abs(herr);  // facing away: see Update
      out.message = FormatNumbers(
          "door passage: aligning with the passage axis (%.1f deg to go), %.2f m "
          "before its centre",
          RadToDeg(herr), passage.passage.s - s_here);
      return;
    }
  }
  // Crossing: follow the axis, centred between the jambs the LRF sees.
  out.status = NavStatus::kDoorPassage;
  margin = P.passage_side_margin;
  const Vec2 off = here - passage.passage.centre;
  const double lateral = axis.x() * off.y() - axis.y() * off.x();  // + = left of the axis
  // Jambs: returns beside the body, per slice the median lateral distance (JambDistance). They
  // are not the jambs when they stand farther apart than the passage is wide: before the base
  // reaches the doorway, what is beside it (an opened leaf, a cabinet) is not, and centring
  // between those would steer it into a jamb; it then follows the map's centre line. Nearer
  // than the map's jambs, they are something the map lacks, and the base keeps clear of it.
  const double d_left = JambDistance(c.pts, +1.0), d_right = JambDistance(c.pts, -1.0);
  const double half_w = 0.5 * P.footprint_width;
  double centring = -lateral;  // desired leftward shift (m)
  std::string source = "map";
  if (std::isfinite(d_left) && std::isfinite(d_right) &&
      d_left + d_right <= passage.passage.width + P.passage_width_tolerance) {
    centring = 0.5 * (d_left - d_right);
    source = "LRF";
    if (std::min(d_left, d_right) - half_w < P.passage_side_margin) {
      out.cmd = {};
      out.status = NavStatus::kBlocked;
      out.message = FormatNumbers(
          "door passage: side clearance %.3f m (left %.2f, right %.2f) below "
          "the %.2f m margin",
          std::min(d_left, d_right) - half_w, d_left, d_right, P.passage_side_margin);
      return;
    }
  }
  const double herr = WrapAngle(axis_yaw - c.X_MB.yaw);
  const double w = P.heading_gain * herr + P.centring_gain * centring;
  out.cmd = {P.passage_speed, std::clamp(w, -0.5 * P.max_angular_speed, 0.5 * P.max_angular_speed)};
  out.message = FormatNumbers("door passage: crossing at %.2f m/s, %.3f m off centre (",
                              P.passage_speed, -centring) +
                source + ")";
}

// Pure pursuit along the path, a turn on the spot toward it when it lies too far off the
// heading, and the final approach onto the goal point.
void LocalController::PursuitStep(const Step& c, double s_here, double d_goal, ControlOutput& out,
                                  double& turn_needed) const {
  const LocalControllerParams& P = params_;
  std::size_t t = closest_;
  while (t + 1 < path_.size() && path_[t].s < s_here + P.lookahead) ++t;
  const Vec2 target = InFrame(c.X_MB, Vec2(path_[t].pose.x, path_[t].pose.y));
  const double alpha = std::atan2(target.y(), target.x());
  const double L2 = std::max(target.squaredNorm(), 1e-6);
  if (d_goal < P.final_approach_distance && t + 1 == path_.size()) {
    // Final approach to a point: drive forward or back onto it, then rotate.
    const double limit = P.final_approach_turn_rate;
    const double v = std::clamp(0.8 * target.x(), -P.final_approach_speed, P.final_approach_speed);
    const double w = std::abs(target.x()) > 0.02 || std::abs(target.y()) > 0.02
                         ? P.heading_gain * std::atan2(target.y(), std::abs(target.x())) *
                               (target.x() >= 0 ? 1.0 : -1.0)
                         : 0.0;
    if (std::abs(target.y()) > 0.5 * std::abs(target.x()) + 0.02 && d_goal > 0.08) {
      out.cmd = {0.0, std::clamp(P.heading_gain * alpha, -limit, limit)};
    } else {
      out.cmd = {std::copysign(std::max(std::abs(v), 0.02), v), std::clamp(w, -limit, limit)};
    }
    out.message = FormatNumbers("final approach: %.3f m to the goal", d_goal);
  } else if (std::abs(alpha) > DegToRad(P.rotate_in_place_deg)) {
    const double w = std::clamp(P.heading_gain * alpha, -P.max_angular_speed, P.max_angular_speed);
    out.cmd = {0.0, std::copysign(std::max(std::abs(w), P.min_path_turn_speed), w)};
    turn_needed = std::abs(alpha) - DegToRad(P.rotate_in_place_deg) + 0.1;
    out.message = FormatNumbers("turning toward the path (%.0f deg)", RadToDeg(alpha));
  } else {
    const double kappa = 2.0 * target.y() / L2;
    double v = P.max_linear_speed * std::min(1.0, d_goal / P.approach_distance);
    // Slow for an upcoming passage.
    for (const auto& p : passages_) {
      const double to_go = p.passage.s - s_here;
      if (!p.done && to_go > 0.0 && to_go < P.passage_entry_distance + 1.0)
        v = std::min(v, std::max(P.passage_speed, v * (to_go - P.passage_entry_distance)));
    }
    v = std::max(P.min_speed, v * std::max(0.3, std::cos(alpha)));
    double w = v * kappa;
    if (std::abs(w) > P.max_angular_speed) {
      v = P.max_angular_speed / std::abs(kappa);
      w = std::copysign(P.max_angular_speed, w);
    }
    out.cmd = {v, w};
    out.message =
        FormatNumbers("following: %.2f m along the path, %.2f m to the goal", s_here, d_goal);
  }
}

// Obstacles the map lacks: the footprint swept along the commanded arc against the base LRF
// (and, backing up or turning, the map). Blocks or slows `out`.
void LocalController::CheckMotion(Step& c, ControlOutput& out, double margin, double turn_needed) {
  const LocalControllerParams& P = params_;
  const double v = out.cmd.v, w = out.cmd.w;
  if (std::abs(v) > 1e-6) {
    const double horizon = std::max(0.3, std::abs(v) * P.collision_horizon);
    const double free = FreeTravel(v < 0.0 ? Around(c) : c.pts, v, w, margin, horizon);
    if (free < P.stop_distance + 1e-9) {
      out.cmd = {};
      out.status = NavStatus::kBlocked;
      out.message = FormatNumbers(
          "blocked: an obstacle in the base LRF (not in the map) leaves %.2f m "
          "of free travel",
          free);
    } else if (free < P.slowdown_distance && free < horizon) {
      const double k = (free - P.stop_distance) / (P.slowdown_distance - P.stop_distance);
      const double vmin = std::min(P.min_speed, std::abs(v));
      const double vs = std::max(vmin, std::abs(v) * k);
      out.cmd.w *= vs / std::abs(v);
      out.cmd.v = std::copysign(vs, v);
    }
  } else if (std::abs(w) > 1e-6) {
    // Begun in the mouth of a niche and stopped half way, a turn wedges the base's corners
    // against both sides, where not even an escape manoeuvre gets it out (at least the next
    // min_turn_check rad are checked).
    const double turn = std::max(P.min_turn_check, turn_needed);
    if (FreeTravel(Around(c), 0.0, w, std::min(margin, P.passage_side_margin), turn) < turn) {
      out.cmd = {};
      out.status = NavStatus::kBlocked;
      out.message = "blocked: no room to rotate in place (obstacle in the base LRF)";
      turn_blocked_ = mode_ == Mode::kFollow;  // not at the goal's final rotation
    }
  }
}

// Blocked: wait, then recover. Stuck: no progress while commanding motion.
ControlOutput LocalController::BlockedOrStuck(Step& c, ControlOutput out) {
  const LocalControllerParams& P = params_;
  if (out.status != NavStatus::kBlocked) turn_blocked_ = false;
  if (out.status == NavStatus::kBlocked) {
    last_blocked_time_ = c.time;
    if (!blocked_since_) blocked_since_ = c.time;
    if (c.time - *blocked_since_ >= P.blocked_wait) {
      return Emit(c,
                  StartRecovery(
                      c.time, c.X_MB,
                      out.message + FormatNumbers(" for %.1f s", c.time - *blocked_since_), c.pts),
                  false);
    }
    out.message += FormatNumbers("; waiting %.1f s before recovery",
                                 P.blocked_wait - (c.time - *blocked_since_));
    ResetAnchor(c);
    return Emit(c, out);
  }
  // Hysteresis: a base creeping at the edge of the stop distance stays "blocked" for the
  // recovery timer until it has been free for blocked_release_time.
  if (c.time - last_blocked_time_ > P.blocked_release_time) blocked_since_.reset();
  const double moved = std::hypot(c.X_MB.x - anchor_pose_.x, c.X_MB.y - anchor_pose_.y);
  const double turned = std::abs(WrapAngle(c.X_MB.yaw - anchor_pose_.yaw));
  if (moved > P.progress_distance || turned > P.progress_turn ||
      (std::abs(out.cmd.v) < 1e-6 && std::abs(out.cmd.w) < 1e-6)) {
    ResetAnchor(c);
  } else if (c.time - anchor_time_ > P.stuck_timeout) {
    return Emit(c,
                StartRecovery(c.time, c.X_MB,
                              FormatNumbers("stuck: moved %.3f m in %.1f s while commanded", moved,
                                            c.time - anchor_time_),
                              c.pts),
                false);
  }
  return Emit(c, out);
}

ControlOutput LocalController::Update(double time, const Pose2& X_MB, LocalisationStatus loc,
                                      const interfaces::LrfScan& scan) {
  const LocalControllerParams& P = params_;
  if (mode_ == Mode::kDone) return terminal_;
  Step c = BeginStep(time, X_MB, scan);
  if (auto out = LocalisationStep(c, loc)) return *out;
  if (mode_ == Mode::kBackUp) return BackUpStep(c);
  if (mode_ == Mode::kEscape) return EscapeStep(c);
  if (mode_ == Mode::kRotate) return RotateStep(c);

  TrackProgress(X_MB);
  const double s_here = path_[closest_].s;
  if (recoveries_ > 0 && s_here - s_at_last_recovery_ > P.recovery_reset_progress)
    recoveries_ = 0;  // made good
  const Vec2 here(X_MB.x, X_MB.y);
  const double d_goal = (Vec2(goal_.x, goal_.y) - here).norm();
  const double yaw_err_goal = WrapAngle(goal_.yaw - X_MB.yaw);

  ControlOutput out;
  out.status = NavStatus::kFollowing;
  double margin = P.safety_margin;
  // rad: the whole of a turn on the spot that the step starts, where it must be free before
  // it starts: a turn toward the path, and aligning with a passage the base faces away from
  // (more than 90 deg off its axis: it stands in the narrow stretch or just past it). A
  // smaller alignment and the final rotation turn as far as they can: a doorway seldom leaves
  // room for all of it at once, and the crossing centres the base as it goes.
  double turn_needed = 0.0;

  // Goal: final approach and rotation.
  if (mode_ == Mode::kFinalRotate && d_goal > P.final_rotate_release * P.goal_tolerance_xy)
    mode_ = Mode::kFollow;
  if (mode_ != Mode::kFinalRotate && d_goal < P.goal_tolerance_xy) mode_ = Mode::kFinalRotate;
  if (mode_ == Mode::kFinalRotate) {
    if (!align_yaw_ || std::abs(yaw_err_goal) < DegToRad(P.goal_tolerance_yaw_deg)) {
      return Finish(NavStatus::kArrived, FormatNumbers("arrived: %.3f m and %.2f deg from the goal",
                                                       d_goal, RadToDeg(std::abs(yaw_err_goal))));
    }
    out.cmd = TurnOnTheSpot(yaw_err_goal);
    out.message = FormatNumbers("at the goal (%.3f m); rotating to its yaw (%.1f deg to go)",
                                d_goal, RadToDeg(yaw_err_goal));
  } else if (PassageState* passage = CurrentPassage(here, s_here)) {
    PassageStep(c, *passage, s_here, out, margin, turn_needed);
  } else {
    PursuitStep(c, s_here, d_goal, out, turn_needed);
  }
  if (out.status != NavStatus::kBlocked) CheckMotion(c, out, margin, turn_needed);
  return BlockedOrStuck(c, out);
}

}  // namespace mopad::autonomy
