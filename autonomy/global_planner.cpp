#include "autonomy/global_planner.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/objectives/StateCostIntegralObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <mutex>
#include <queue>

#include "common/error.h"
#include "common/format.h"
#include "common/rng.h"
#include "perception/grid_search.h"

namespace mopad::autonomy {

namespace ob = ompl::base;
namespace og = ompl::geometric;
using perception::Cell;
using perception::DistanceField;
using perception::OccupancyGrid;

void GlobalPlannerParams::Validate() const {
  ValidateParams(*this, "global_planner.");
  if (min_start_clearance > robot_radius) {
    throw InputError("", "parameter 'global_planner.min_start_clearance' exceeds robot_radius",
                     std::to_string(min_start_clearance), "<= " + std::to_string(robot_radius));
  }
}

const char* ToString(PlanStatus s) {
  switch (s) {
    case PlanStatus::kFound:
      return "found";
    case PlanStatus::kStartInvalid:
      return "start_invalid";
    case PlanStatus::kGoalInvalid:
      return "goal_invalid";
    case PlanStatus::kUnreachable:
      return "unreachable";
    case PlanStatus::kNoPathInBudget:
      return "no_path_in_budget";
  }
  return "?";
}

namespace {

/// Seeds OMPL's global generator once per process, before any planner exists (PITFALLS.md).
void SeedOmplOnce(std::uint64_t seed) {
  static std::once_flag once;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    // OMPL treats 0 as "from the clock": keep the seed non-zero.
    ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(Mix64(seed) % 0x7FFFFFFFull) + 1);
  });
}

/// What the sampler draws from: valid cells of the start's component, and its medial axis.
struct SamplerData {
  std::vector<Vec2> cells, medial;
  Vec2 goal;
  double resolution = 0.05;
  double goal_bias = 0.0, medial_bias = 0.0;
  std::uint64_t key = 0;
  std::uint64_t draws = 0;  // sequential draw counter: samples are a function of (key, draw)
};

/// MAPRM-style sampler over the component (see header). Only the planner's thread calls it.
class ComponentSampler : public ob::StateSampler {
 public:
  ComponentSampler(const ob::StateSpace* space, std::shared_ptr<SamplerData> data)
      : ob::StateSampler(space), data_(std::move(data)) {}

  void sampleUniform(ob::State* state) override {
    CounterRng rng(DeriveKey(data_->key, data_->draws++));
    Vec2 p;
    const double u = rng.Uniform();
    if (u < data_->goal_bias) {
      p = data_->goal;
    } else {
      const bool medial = u < data_->goal_bias + data_->medial_bias && !data_->medial.empty();
      const auto& from = medial ? data_->medial : data_->cells;
      p = from[rng.Below(from.size())];
      // Jitter within the cell (medial samples stay near the axis).
      const double r = data_->resolution;
      p += Vec2(rng.Uniform(-0.5, 0.5) * r, rng.Uniform(-0.5, 0.5) * r);
    }
    Set(state, p);
  }
  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override {
    CounterRng rng(DeriveKey(data_->key, data_->draws++));
    const auto* n = near->as<ob::RealVectorStateSpace::StateType>();
    Set(state, Vec2(n->values[0] + rng.Uniform(-distance, distance),
                    n->values[1] + rng.Uniform(-distance, distance)));
  }
  void sampleGaussian(ob::State* state, const ob::State* mean, double sigma) override {
    CounterRng rng(DeriveKey(data_->key, data_->draws++));
    const auto* m = mean->as<ob::RealVectorStateSpace::StateType>();
    Set(state, Vec2(m->values[0] + sigma * rng.Normal(), m->values[1] + sigma * rng.Normal()));
  }

 private:
  void Set(ob::State* state, const Vec2& p) const {
    auto* s = state->as<ob::RealVectorStateSpace::StateType>();
    s->values[0] = p.x();
    s->values[1] = p.y();
    space_->enforceBounds(state);
  }
  std::shared_ptr<SamplerData> data_;
};

Vec2 ToVec(const ob::State* s) {
  const auto* r = s->as<ob::RealVectorStateSpace::StateType>();
  return {r->values[0], r->values[1]};
}

}  // namespace

struct GlobalPlanner::Impl {
  OccupancyGrid map;
  DistanceField field;
  /// The planner on map.Refined(narrow_refinement) at the narrow radius, built on first need.
  std::unique_ptr<GlobalPlanner> refined;
  Impl(const OccupancyGrid& m, bool unknown_is_obstacle) : map(m), field(m, unknown_is_obstacle) {}

  bool Valid(const Vec2& p, double radius) const { return field.IsFree(p, radius); }

  /// Minimum clearance along the straight segment a-b, sampled every half cell.
  double SegmentClearance(const Vec2& a, const Vec2& b) const {
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * map.Resolution()))));
    double c = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= n; ++k)
      c = std::min(c, field.Clearance(Vec2(a + (b - a) * (double(k) / n))));
    return c;
  }
};

GlobalPlanner::GlobalPlanner(const OccupancyGrid& map, const GlobalPlannerParams& params,
                             std::uint64_t seed)
    : params_(params), seed_(seed) {
  params_.Validate();
  SeedOmplOnce(seed);
  impl_ = std::make_unique<Impl>(map, params_.unknown_is_obstacle);
}

GlobalPlanner::~GlobalPlanner() = default;
GlobalPlanner::GlobalPlanner(GlobalPlanner&&) noexcept = default;
GlobalPlanner& GlobalPlanner::operator=(GlobalPlanner&&) noexcept = default;

void GlobalPlanner::SetMap(const OccupancyGrid& map) {
  impl_ = std::make_unique<Impl>(map, params_.unknown_is_obstacle);
}

void GlobalPlanner::AddObstacles(const std::vector<Vec2>& points_M) {
  OccupancyGrid map = impl_->map;
  // A point within one cell of a mapped obstacle is that obstacle seen again (a door jamb a
  // centimetre off through the pose estimate): marking its free neighbour would narrow a
  // mapped doorway by a cell, enough to close a 0.85 m door to a 0.33 m robot radius.
  auto near_mapped = [&](const perception::Cell& c) {
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        if (impl_->map.State({c.i + di, c.j + dj}) == perception::CellState::kOccupied) return true;
    return false;
  };
  for (const auto& p : points_M) {
    const perception::Cell c = map.CellOf(p);
    if (!near_mapped(c)) map.SetState(c, perception::CellState::kOccupied);
  }
  impl_ = std::make_unique<Impl>(map, params_.unknown_is_obstacle);
}

double GlobalPlanner::Clearance(const Vec2& p) const { return impl_->field.Clearance(p); }

namespace {

// Arc length at each vertex of a polyline.
std::vector<double> Cumulative(const std::vector<Vec2>& v) {
  std::vector<double> s(v.size(), 0.0);
  for (std::size_t k = 1; k < v.size(); ++k) s[k] = s[k - 1] + (v[k] - v[k - 1]).norm();
  return s;
}

// The point at arc length sq of polyline v (cs = Cumulative(v)), clamped to it.
Vec2 PointAt(const std::vector<Vec2>& v, const std::vector<double>& cs, double sq) {
  std::size_t k = 1;
  while (k + 1 < v.size() && cs[k] < sq) ++k;
  const double seg = cs[k] - cs[k - 1];
  const double f = seg > 0 ? std::clamp((sq - cs[k - 1]) / seg, 0.0, 1.0) : 0.0;
  return Vec2(v[k - 1] + f * (v[k] - v[k - 1]));
}

}  // namespace

// 4a. Doorways along the path `vertices`: runs of low clearance no longer than a door,
// measured across at their narrowest point between the jambs on the map.
std::vector<Passage> GlobalPlanner::FindPassages(const std::vector<Vec2>& vertices) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  const double res = map.Resolution();
  // Jambs are mapped obstacles: unknown cells (the edge of what the robot has seen) are not.
  auto is_obstacle = [&](const Cell& c) {
    return map.Contains(c) && map.State(c) == perception::CellState::kOccupied;
  };
  std::vector<Passage> passages;
  const std::vector<double> cs = Cumulative(vertices);
  const double total = cs.back();
  const double step_s = 0.5 * res;
  std::vector<std::pair<double, double>> runs;  // (s_begin, s_end) of low clearance
  double run_begin = -1.0;
  for (double sq = 0.0; sq <= total + 1e-9; sq += step_s) {
    const bool low = m.field.Clearance(PointAt(vertices, cs, sq)) < P.passage_clearance;
    if (low && run_begin < 0.0) run_begin = sq;
    if (!low && run_begin >= 0.0) {
      runs.emplace_back(run_begin, sq);
      run_begin = -1.0;
    }
  }
  // A doorway at the very end of the path (a goal just inside or behind a door) is a passage
  // too: close the run at the goal (the jamb test below still rejects a goal by one wall).
  if (run_begin >= 0.0) runs.emplace_back(run_begin, total);
  for (const auto& [b, e] : runs) {
    if (e - b > P.max_passage_length) continue;  // corridor
    double s_c = b, best = std::numeric_limits<double>::infinity();
    for (double sq = b; sq <= e; sq += step_s) {
      const double c = m.field.Clearance(PointAt(vertices, cs, sq));
      if (c < best) {
        best = c;
        s_c = sq;
      }
    }
    const Vec2 c = PointAt(vertices, cs, s_c);
    Vec2 d = PointAt(vertices, cs, s_c + 0.2) - PointAt(vertices, cs, s_c - 0.2);
    if (d.norm() < 1e-9) continue;
    d.normalize();
    // Nearest obstacle cells left and right of the path (the jambs).
    // The narrowest point of a slanted approach can lie before the doorway: look far enough
    // for both jambs.
    const double reach = std::max(best + 3.0 * res, P.passage_clearance + 0.3);
    const Cell cc = map.CellOf(c);
    const int rc = static_cast<int>(std::ceil(reach / res)) + 1;
    // The jambs: the closest pair of obstacle cells on opposite sides of the path (the
    // narrowest cross-section). Not simply the nearest cell on each side: an open leaf
    // standing beside the doorway is nearer to a slanted approach than its own jamb.
    std::vector<Vec2> left, right;
    for (int dj2 = -rc; dj2 <= rc; ++dj2) {
      for (int di2 = -rc; di2 <= rc; ++di2) {
        const Cell q{cc.i + di2, cc.j + dj2};
        if (!is_obstacle(q)) continue;
        const Vec2 qc = map.CentreOf(q);
        const Vec2 off = qc - c;
        if (off.norm() > reach) continue;
        const double side = d.x() * off.y() - d.y() * off.x();
        if (side > 0)
          left.push_back(qc);
        else if (side < 0)
          right.push_back(qc);
      }
    }
    double dl = std::numeric_limits<double>::infinity(), dr = dl, gap = dl;
    Vec2 jl = Vec2::Zero(), jr = Vec2::Zero();
    for (const Vec2& l : left)
      for (const Vec2& rr : right) {
        const double g = (l - rr).squaredNorm();
        if (g < gap) gap = g, jl = l, jr = rr, dl = (l - c).norm(), dr = (rr - c).norm();
      }
    if (!std::isfinite(dl) || !std::isfinite(dr)) continue;
    const Vec2 u = jl - jr;
    if (u.norm() > 2.0 * (P.passage_clearance + res)) continue;  // not a narrow gap
    Vec2 a(u.y(), -u.x());
    a.normalize();
    if (a.dot(d) < 0) a = -a;
    if (a.dot(d) < 0.5) continue;  // not a doorway across the path
    // A run from the start (a narrow start area) is a doorway only when its narrowest point
    // lies ahead and the start is before it (a replan 0.3 m in front of a door, which must
    // still cross it aligned); a start inside the doorway is not.
    if (b <= 0.0) {
      const double along0 = (vertices.front() - 0.5 * (jl + jr)).dot(a);
      if (s_c < 0.2 || along0 > -0.15) continue;
    }
    // A run that reaches the end of the path is a passage only if the goal lies in or beyond
    // the doorway, between its jambs (a goal beside a door does not cross it).
    if (e >= total - 1e-9) {
      const Vec2 off = vertices.back() - 0.5 * (jl + jr);
      const double along = off.dot(a), lateral = std::abs(a.x() * off.y() - a.y() * off.x());
      if (along < -P.passage_straight || lateral > 0.5 * (u.norm() - res)) continue;
    }
    Passage pass;
    pass.centre = 0.5 * (jl + jr);
    pass.axis_yaw = std::atan2(a.y(), a.x());
    pass.width = u.norm() - res;
    pass.s = s_c;
    passages.push_back(pass);
  }
  return passages;
}

// 4b. The path rerouted straight through each passage along its axis, last first (earlier arc
// lengths stay valid), where the straight crossing keeps robot_radius.
void GlobalPlanner::RouteThroughPassages(const std::vector<Passage>& passages,
                                         std::vector<Vec2>& vertices) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  for (auto it = passages.rbegin(); it != passages.rend(); ++it) {
    const std::vector<double> cv = Cumulative(vertices);
    const double L = P.passage_straight;
    const double s_in = it->s - L, s_out = it->s + L;
    if (s_in <= 0.0 || L <= 0.0) continue;
    const Vec2 a(std::cos(it->axis_yaw), std::sin(it->axis_yaw));
    const Vec2 p_in = it->centre - L * a, p_out = it->centre + L * a;
    const Vec2 q_in = PointAt(vertices, cv, s_in);
    const double need = P.robot_radius;
    std::vector<Vec2> next;
    for (std::size_t k = 0; k < vertices.size() && cv[k] < s_in; ++k) next.push_back(vertices[k]);
    if (s_out >= cv.back()) {
      // A doorway at the end of the path: approach along its axis, then straight to the goal.
      const Vec2 goal_p = vertices.back();
      if ((goal_p - it->centre).dot(a) > 0.0) {
        if (!m.Valid(it->centre, need) || m.SegmentClearance(q_in, p_in) < need ||
            m.SegmentClearance(p_in, it->centre) < need ||
            m.SegmentClearance(it->centre, goal_p) < need)
          continue;
        next.insert(next.end(), {q_in, p_in, it->centre, goal_p});
      } else {  // the goal is in the doorway, before its centre
        if (m.SegmentClearance(q_in, p_in) < need || m.SegmentClearance(p_in, goal_p) < need)
          continue;
        next.insert(next.end(), {q_in, p_in, goal_p});
      }
    } else {
      const Vec2 q_out = PointAt(vertices, cv, s_out);
      if (!m.Valid(it->centre, need) || m.SegmentClearance(q_in, p_in) < need ||
          m.SegmentClearance(p_in, p_out) < need || m.SegmentClearance(p_out, q_out) < need)
        continue;
      next.insert(next.end(), {q_in, p_in, it->centre, p_out, q_out});
      for (std::size_t k = 0; k < vertices.size(); ++k)
        if (cv[k] > s_out) next.push_back(vertices[k]);
    }
    // Drop zero-length steps.
    std::vector<Vec2> clean{next.front()};
    for (std::size_t k = 1; k < next.size(); ++k)
      if ((next[k] - clean.back()).norm() > 1e-6) clean.push_back(next[k]);
    vertices.swap(clean);
  }
}

namespace {

// The RRT* objective: the path integral of the cell cost (1 + clearance_weight x shortfall of
// clearance below preferred_clearance), per metre.
class ClearanceObjective : public ob::StateCostIntegralObjective {
 public:
  ClearanceObjective(const ob::SpaceInformationPtr& si, const OccupancyGrid& map,
                     const std::vector<float>& cost)
      : ob::StateCostIntegralObjective(si, true), map_(map), cost_(cost) {}
  ob::Cost stateCost(const ob::State* s) const override { return ob::Cost(Cost(ToVec(s))); }
  // Trapezoidal integral of the state cost along the segment, sampled every 10 cm on plain
  // vectors (OMPL's generic interpolation allocates a state per sample: far slower).
  ob::Cost motionCost(const ob::State* s1, const ob::State* s2) const override {
    const Vec2 a = ToVec(s1), b = ToVec(s2);
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.1)));
    double sum = 0.5 * (Cost(a) + Cost(b));
    for (int k = 1; k < n; ++k) sum += Cost(Vec2(a + (b - a) * (double(k) / n)));
    return ob::Cost(sum * len / n);
  }

 private:
  double Cost(const Vec2& p) const {
    const Cell c = map_.CellOf(p);
    if (!map_.Contains(c)) return 1e3;
    return cost_[map_.Index(c)];
  }
  const OccupancyGrid& map_;
  const std::vector<float>& cost_;
};

}  // namespace

// 3a. The farthest vertex j reachable from i by a straight segment that keeps min(robot_radius
// + shortcut_margin, the clearance of the replaced sub-path); deterministic.
void GlobalPlanner::ShortcutPath(std::vector<Vec2>& vertices) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  std::vector<Vec2> out{vertices.front()};
  std::size_t i = 0;
  std::vector<double> seg(vertices.size() - 1);
  for (std::size_t k = 0; k + 1 < vertices.size(); ++k)
    seg[k] = m.SegmentClearance(vertices[k], vertices[k + 1]);
  while (i + 1 < vertices.size()) {
    // The farthest j whose straight segment keeps min(robot_radius + margin, clearance
    // of the replaced sub-path); i + 1 always qualifies.
    std::size_t best = i + 1;
    double sub = seg[i];
    for (std::size_t j = i + 2; j < vertices.size(); ++j) {
      sub = std::min(sub, seg[j - 1]);
      const double need = std::min(P.robot_radius + P.shortcut_margin, sub);
      if (need >= P.robot_radius && m.SegmentClearance(vertices[i], vertices[j]) >= need) best = j;
    }
    out.push_back(vertices[best]);
    i = best;
  }
  vertices.swap(out);
}

// 5. The plan's path: `vertices` resampled every waypoint_spacing with the yaw of each
// segment, passages placed at their nearest path point, length, the smallest clearance (the
// lead-out from a start inside the margin exempt), status and message.
void GlobalPlanner::FinishPlan(const std::vector<Vec2>& vertices, std::vector<Passage> passages,
                               const Pose2& goal, double goal_clear, const Vec2& s0, const Vec2& s,
                               GlobalPlan& plan) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const double step = P.waypoint_spacing;
  double s_acc = 0.0;
  for (std::size_t k = 0; k + 1 < vertices.size(); ++k) {
    const Vec2 a = vertices[k], b = vertices[k + 1];
    const double len = (b - a).norm();
    if (len < 1e-9) continue;
    const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int q = 0; q < n; ++q) {
      const Vec2 p = a + (b - a) * (double(q) / n);
      plan.path.push_back({{p.x(), p.y(), yaw}, m.field.Clearance(p), s_acc + len * q / n});
    }
    s_acc += len;
  }
  plan.path.push_back({goal, goal_clear, s_acc});
  for (auto& pass : passages) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& pp : plan.path) {
      const double dd = (Vec2(pp.pose.x, pp.pose.y) - pass.centre).norm();
      if (dd < best) {
        best = dd;
        pass.s = pp.s;
      }
    }
  }
  plan.passages = passages;
  plan.length = s_acc;
  plan.min_clearance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < plan.path.size(); ++k) {
    // The lead-out from a start inside the margin is exempt (it is where the robot already is).
    if ((Vec2(plan.path[k].pose.x, plan.path[k].pose.y) - s0).norm() <= (s - s0).norm() + 1e-9 &&
        !(s - s0).isZero(0.0))
      continue;
    plan.min_clearance = std::min(plan.min_clearance, plan.path[k].clearance);
  }
  plan.status = PlanStatus::kFound;
  plan.message =
      FormatNumbers("path %.2f m, min clearance %.2f m, ", plan.length, plan.min_clearance) +
      std::to_string(plan.passages.size()) + " passages, " + std::to_string(plan.iterations) +
      " RRT* iterations";
}

namespace {
constexpr int kDi[8] = {1, -1, 0, 0, 1, 1, -1, -1}, kDj[8] = {0, 0, 1, -1, 1, -1, 1, -1};
}  // namespace

// The nearest valid cell within 1 m of a start inside the clearance margin, reached through
// cells with min_start_clearance (breadth first, kDi/kDj order); nullopt when there is none.
std::optional<Cell> GlobalPlanner::LeadOutCell(const Vec2& s0, Cell sc,
                                               const std::vector<std::uint8_t>& valid) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  const int w = map.Width();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  std::vector<int> seen(valid.size(), 0);
  std::deque<Cell> q{sc};
  seen[idx(sc)] = 1;
  bool found = false;
  while (!q.empty() && !found) {
    const Cell c = q.front();
    q.pop_front();
    for (int k = 0; k < 8; ++k) {
      const Cell n{c.i + kDi[k], c.j + kDj[k]};
      if (!map.Contains(n) || seen[idx(n)]) continue;
      seen[idx(n)] = 1;
      if ((map.CentreOf(n) - s0).norm() > 1.0) continue;
      if (valid[idx(n)]) {
        sc = n;
        found = true;
        break;
      }
      if (m.field.IsFree(map.CentreOf(n), P.min_start_clearance)) q.push_back(n);
    }
  }
  if (!found) return std::nullopt;
  return sc;
}

// The 8-connected component of valid cells that holds `sc` (1 = in it).
std::vector<std::uint8_t> GlobalPlanner::Component(Cell sc,
                                                   const std::vector<std::uint8_t>& valid) const {
  const OccupancyGrid& map = impl_->map;
  const int w = map.Width();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  std::vector<std::uint8_t> comp(valid.size(), 0);
  std::deque<Cell> q{sc};
  comp[idx(sc)] = 1;
  while (!q.empty()) {
    const Cell c = q.front();
    q.pop_front();
    for (int k = 0; k < 8; ++k) {
      const Cell n{c.i + kDi[k], c.j + kDj[k]};
      if (!map.Contains(n) || comp[idx(n)] || !valid[idx(n)]) continue;
      comp[idx(n)] = 1;
      q.push_back(n);
    }
  }
  return comp;
}

// The largest clearance c such that `gc` is reached from `sc` through 8-connected cells of
// clearance >= c (a widest-path search: cells are settled in decreasing order of the smallest
// clearance on their best route; ties by cell index, so the result is deterministic). 0 when
// the goal is cut off from the start by obstacles or unknown cells.
double GlobalPlanner::WidestRouteClearance(Cell sc, Cell gc) const {
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  const int w = map.Width();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  std::vector<double> best(static_cast<std::size_t>(w) * map.Height(), -1.0);
  using Entry = std::pair<double, std::size_t>;  // (bottleneck, cell index)
  auto lower = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower)> open(lower);
  const double s_clear = m.field.ClearanceOfCell(sc);
  if (s_clear <= 0.0) return 0.0;
  best[idx(sc)] = s_clear;
  open.push({s_clear, idx(sc)});
  while (!open.empty()) {
    const auto [b, k] = open.top();
    open.pop();
    if (b < best[k]) continue;
    const Cell c{static_cast<int>(k % w), static_cast<int>(k / w)};
    if (c.i == gc.i && c.j == gc.j) return b;
    for (int d = 0; d < 8; ++d) {
      const Cell n{c.i + kDi[d], c.j + kDj[d]};
      if (!map.Contains(n)) continue;
      const double nb = std::min(b, m.field.ClearanceOfCell(n));
      if (nb <= 0.0 || nb <= best[idx(n)]) continue;
      best[idx(n)] = nb;
      open.push({nb, idx(n)});
    }
  }
  return 0.0;
}

// Cost per metre of every cell (index j * width + i), precomputed: the objective samples it
// millions of times. 1 + clearance_weight x the shortfall of clearance below
// preferred_clearance.
std::vector<float> GlobalPlanner::CellCosts() const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const int w = m.map.Width(), h = m.map.Height();
  std::vector<float> cell_cost(static_cast<std::size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      cell_cost[static_cast<std::size_t>(j) * w + i] = static_cast<float>(
          1.0 + P.clearance_weight *
                    std::max(0.0, 1.0 - m.field.ClearanceOfCell({i, j}) / P.preferred_clearance));
  return cell_cost;
}

// 2-3. A path from s to g0 through the start's component `comp`: the grid seed path or OMPL
// RRT* (keyed by `query`), shortcut and B-spline smoothed where valid. False (plan's status and
// message set) when RRT* finds none within its budget.
bool GlobalPlanner::SearchPath(const Vec2& s, const Vec2& g0, Cell sc, Cell gc,
                               const std::vector<std::uint8_t>& comp, std::uint64_t query,
                               std::vector<Vec2>& vertices, GlobalPlan& plan) const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  const double res = map.Resolution();
  const int w = map.Width(), h = map.Height();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  std::vector<Vec2> cells;
  auto data = std::make_shared<SamplerData>();
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      if (!comp[idx({i, j})]) continue;
      cells.push_back(map.CentreOf({i, j}));
      // Medial axis: a local maximum of clearance along x or along y.
      const double c = m.field.ClearanceOfCell({i, j});
      const bool ridge_x =
          c >= m.field.ClearanceOfCell({i - 1, j}) && c >= m.field.ClearanceOfCell({i + 1, j});
      const bool ridge_y =
          c >= m.field.ClearanceOfCell({i, j - 1}) && c >= m.field.ClearanceOfCell({i, j + 1});
      if (ridge_x || ridge_y) data->medial.push_back(cells.back());
    }
  }
  data->cells = cells;
  data->goal = g0;
  data->resolution = res;
  data->goal_bias = P.goal_bias;
  data->medial_bias = P.medial_axis_bias;

  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, map.Origin().x());
  bounds.setLow(1, map.Origin().y());
  bounds.setHigh(0, map.Origin().x() + w * res);
  bounds.setHigh(1, map.Origin().y() + h * res);
  space->setBounds(bounds);
  space->setStateSamplerAllocator(
      [data](const ob::StateSpace* sp) { return std::make_shared<ComponentSampler>(sp, data); });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  const double radius = P.robot_radius;
  si->setStateValidityChecker(
      [&m, radius](const ob::State* st) { return m.Valid(ToVec(st), radius); });
  si->setStateValidityCheckingResolution(0.5 * res / space->getMaximumExtent());
  si->setup();
  const std::vector<float> cell_cost = CellCosts();
  if (P.grid_seed) {
    // Cheapest route over the component, edge cost = length x mean cell cost (exact for the
    // grid and deterministic).
    const std::vector<std::size_t> chain = perception::GridShortestPath(
        w, h, idx(sc), idx(gc), perception::kNeighboursAxesFirst,
        [&](std::size_t from, std::size_t to, const perception::GridStep& st) {
          if (!comp[to]) return -1.0;
          return res * (st.Diagonal() ? std::sqrt(2.0) : 1.0) * 0.5 *
                 (cell_cost[from] + cell_cost[to]);
        });
    if (!chain.empty()) {
      vertices.push_back(s);
      // Every 4th cell is enough for the shortcuts (they only remove vertices).
      for (std::size_t k = 1; k + 1 < chain.size(); k += 4)
        vertices.push_back(
            map.CentreOf({static_cast<int>(chain[k] % w), static_cast<int>(chain[k] / w)}));
      vertices.push_back(g0);
    }
  }
  for (int attempt = 0; attempt < P.max_attempts && vertices.empty() && !P.grid_seed; ++attempt) {
    data->key = DeriveKey(DeriveKey(DeriveKey(Mix64(seed_), HashName("planner/samples")), query),
                          static_cast<std::uint64_t>(attempt));
    data->draws = 0;
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    ob::ScopedState<ob::RealVectorStateSpace> st(space), gl(space);
    st->values[0] = s.x();
    st->values[1] = s.y();
    gl->values[0] = g0.x();
    gl->values[1] = g0.y();
    pdef->setStartAndGoalStates(st, gl, P.goal_tolerance);
    pdef->setOptimizationObjective(std::make_shared<ClearanceObjective>(si, map, cell_cost));
    auto rrt = std::make_shared<og::RRTstar>(si);
    rrt->setRange(P.range);
    rrt->setGoalBias(0.0);  // the sampler does goal biasing from our keyed stream
    rrt->setProblemDefinition(pdef);
    rrt->setup();
    ob::IterationTerminationCondition itc(static_cast<unsigned>(P.max_iterations));
    rrt->solve(itc);
    plan.iterations += static_cast<int>(rrt->numIterations());
    if (pdef->hasExactSolution()) {
      const auto& path = static_cast<const og::PathGeometric&>(*pdef->getSolutionPath());
      for (std::size_t k = 0; k < path.getStateCount(); ++k)
        vertices.push_back(ToVec(path.getState(k)));
    }
  }
  if (vertices.empty()) {
    plan.status = PlanStatus::kNoPathInBudget;
    plan.message = "goal is connected to the start but RRT* found no path in " +
                   std::to_string(plan.iterations) + " iterations (raise max_iterations)";
    return false;
  }
  // 3a. Deterministic shortcutting that keeps local clearance.
  ShortcutPath(vertices);
  // 3b. B-spline smoothing (OMPL; only valid changes are kept).
  if (P.smoothing_steps > 0 && vertices.size() > 2) {
    og::PathGeometric path(si);
    for (const auto& v : vertices) {
      ob::ScopedState<ob::RealVectorStateSpace> x(space);
      x->values[0] = v.x();
      x->values[1] = v.y();
      path.append(x.get());
    }
    og::PathSimplifier simplifier(si);
    simplifier.smoothBSpline(path, static_cast<unsigned>(P.smoothing_steps));
    std::vector<Vec2> smooth;
    bool ok = true;
    for (std::size_t k = 0; k < path.getStateCount(); ++k)
      smooth.push_back(ToVec(path.getState(k)));
    for (std::size_t k = 0; k + 1 < smooth.size() && ok; ++k)
      ok = m.SegmentClearance(smooth[k], smooth[k + 1]) >= P.robot_radius;
    if (ok && smooth.size() >= 2) vertices.swap(smooth);
  }
  return true;
}

std::vector<std::uint8_t> GlobalPlanner::ValidCells() const {
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  const int w = map.Width(), h = map.Height();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(w) * h, 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      valid[idx({i, j})] = m.field.ClearanceOfCell({i, j}) >= P.robot_radius &&
                           m.field.IsFree(map.CentreOf({i, j}), P.robot_radius);
  return valid;
}

void GlobalPlanner::ReportUnreachable(perception::Cell sc, perception::Cell gc, const Vec2& g0,
                                      double refined_widest, GlobalPlan& plan) const {
  const GlobalPlannerParams& P = params_;
  plan.status = PlanStatus::kUnreachable;
  // The refined map measures a squeeze closer to its width (where the 5 cm map has a route
  // at all: inside a solid, behind its returns, the refined map reads free).
  plan.widest_clearance = WidestRouteClearance(sc, gc);
  if (plan.widest_clearance > 0.0)
    plan.widest_clearance = std::max(plan.widest_clearance, refined_widest);
  plan.message = FormatNumbers(
      "goal (%.2f, %.2f) is not connected to the start in free space with "
      "%.2f m clearance",
      g0.x(), g0.y(), P.robot_radius);
  plan.message +=
      plan.widest_clearance > 0.0
          ? FormatNumbers(": the widest route keeps %.2f m (a passage about %.2f m wide)",
                          plan.widest_clearance, 2.0 * plan.widest_clearance)
          : std::string(
                ": no route through known free space (a closed door or an unseen "
                "passage)");
}

GlobalPlan GlobalPlanner::Plan(const Pose2& start, const Pose2& goal) {
  const std::uint64_t query = query_++;
  const GlobalPlannerParams& P = params_;
  const Impl& m = *impl_;
  const OccupancyGrid& map = m.map;
  GlobalPlan plan;
  const Vec2 s0(start.x, start.y), g0(goal.x, goal.y);

  // 1. Start and goal.
  const double start_clear = m.field.Clearance(s0);
  if (!map.Contains(map.CellOf(s0)) || !m.field.IsFree(s0, P.min_start_clearance) ||
      start_clear < P.min_start_clearance) {
    plan.status = PlanStatus::kStartInvalid;
    plan.message = FormatNumbers(
                       "start (%.2f, %.2f) is off the map, not known free, or too close to an "
                       "obstacle (clearance %.2f m)",
                       s0.x(), s0.y(), start_clear) +
                   FormatNumbers(", needs >= %.2f m", P.min_start_clearance);
    return plan;
  }
  const double goal_clear = m.field.Clearance(g0);
  if (!m.Valid(g0, P.robot_radius)) {
    plan.status = PlanStatus::kGoalInvalid;
    plan.message = FormatNumbers(
                       "goal (%.2f, %.2f) is off the map, not known free, or too close to an "
                       "obstacle (clearance %.2f m)",
                       g0.x(), g0.y(), goal_clear) +
                   FormatNumbers(", needs >= %.2f m (robot radius)", P.robot_radius);
    return plan;
  }
  const int w = map.Width();
  auto idx = [&](const Cell& c) { return static_cast<std::size_t>(c.j) * w + c.i; };
  const std::vector<std::uint8_t> valid = ValidCells();
  // A start inside the clearance margin is led out along cells with min_start_clearance.
  Vec2 s = s0;
  Cell sc = map.CellOf(s0);
  if (!valid[idx(sc)] || !m.Valid(s0, P.robot_radius)) {
    const std::optional<Cell> out = LeadOutCell(s0, sc, valid);
    const bool found = out.has_value();
    if (!found) {
      plan.status = PlanStatus::kStartInvalid;
      plan.message = FormatNumbers(
          "start (%.2f, %.2f) has clearance %.2f m and no cell within 1 m has the "
          "robot radius",
          s0.x(), s0.y(), start_clear);
      return plan;
    }
    sc = *out;
    s = map.CentreOf(sc);
  }
  // Flood fill of the start's component (8-connected).
  const std::vector<std::uint8_t> comp = Component(sc, valid);
  const Cell gc = map.CellOf(g0);
  if (!comp[idx(gc)] && P.narrow_radius < P.robot_radius &&
      P.narrow_radius >= P.min_start_clearance) {
    // Once more with the narrow radius (params_ restored on every path out; the refined map
    // is tried below, not in there).
    const GlobalPlannerParams saved = params_;
    params_.robot_radius = P.narrow_radius;
    params_.narrow_refinement = 1;
    GlobalPlan narrow = Plan(start, goal);
    params_ = saved;
    if (narrow.ok()) {
      narrow.message += FormatNumbers(
          " (through a passage narrower than %.2f m: planned with a "
          "%.2f m radius)",
          2 * saved.robot_radius, saved.narrow_radius);
      return narrow;
    }
  }
  double refined_widest = 0.0;
  if (!comp[idx(gc)] && P.narrow_refinement > 1) {
    // Once more on the map refined around its returns, at the narrow radius.
    const double radius = std::min(P.narrow_radius, P.robot_radius);
    if (!impl_->refined) {
      GlobalPlannerParams fine = P;
      fine.robot_radius = fine.narrow_radius = radius;
      fine.min_start_clearance = std::min(P.min_start_clearance, radius);
      fine.narrow_refinement = 1;
      impl_->refined =
          std::make_unique<GlobalPlanner>(map.Refined(P.narrow_refinement), fine, seed_);
    }
    impl_->refined->query_ = query;
    GlobalPlan fine_plan = impl_->refined->Plan(start, goal);
    if (fine_plan.ok()) {
      fine_plan.message += FormatNumbers(
          " (through a passage narrower than %.2f m on the %.3f m map: planned with a %.2f m "
          "radius on its returns at %.3f m)",
          2 * radius, map.Resolution(), radius, map.Resolution() / P.narrow_refinement);
      return fine_plan;
    }
    refined_widest = fine_plan.widest_clearance;
  }
  if (!comp[idx(gc)]) {
    ReportUnreachable(sc, gc, g0, refined_widest, plan);
    return plan;
  }
  // 2. OMPL RRT* in R^2 over the map's extent (or the grid seed path), then 3. shortcuts and
  // smoothing.
  std::vector<Vec2> vertices;
  if ((g0 - s).norm() < P.goal_tolerance ||
      m.SegmentClearance(s, g0) >= P.robot_radius + P.shortcut_margin) {
    vertices = {s, g0};  // trivially straight
  } else if (!SearchPath(s, g0, sc, gc, comp, query, vertices, plan)) {
    return plan;
  }
  if (!(vertices.front() - s0).isZero(0.0)) vertices.insert(vertices.begin(), s0);
  if (!(vertices.back() - g0).isZero(0.0)) vertices.push_back(g0);

  // 4. Doorways: measure the jambs on the map and cross straight through their midpoint.
  std::vector<Passage> passages = FindPassages(vertices);
  RouteThroughPassages(passages, vertices);

  // 5. Resample with yaw along the path; passages, length and clearance.
  FinishPlan(vertices, std::move(passages), goal, goal_clear, s0, s, plan);
  return plan;
}

}  // namespace mopad::autonomy
