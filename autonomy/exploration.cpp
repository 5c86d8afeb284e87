#include "autonomy/exploration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "perception/grid_search.h"

namespace mopad::autonomy {

namespace {

// The cell nearest to `p` among those of the square of half-side `radius` around it that `ok`
// accepts and that lie within sqrt(max_d2) of it (ties: row by row, the first).
template <class Ok>
std::optional<perception::Cell> NearestCell(const perception::OccupancyGrid& grid, const Vec2& p,
                                            double radius, double max_d2, Ok&& ok) {
  const perception::Cell c0 = grid.CellOf(p);
  const int r = static_cast<int>(std::ceil(radius / grid.Resolution()));
  std::optional<perception::Cell> best;
  double best_d = max_d2;
  for (int dj = -r; dj <= r; ++dj)
    for (int di = -r; di <= r; ++di) {
      const perception::Cell c{c0.i + di, c0.j + dj};
      if (!grid.Contains(c) || !ok(c)) continue;
      const double d = (grid.CentreOf(c) - p).squaredNorm();
      if (d < best_d) best_d = d, best = c;
    }
  return best;
}

}  // namespace

std::vector<Vec2> ExplorationTargets(const perception::OccupancyGrid& grid, const Vec2& from,
                                     const Vec2& goal, const ExplorationParams& p,
                                     const std::vector<Pose2>& scan_poses, std::string* why) {
  const double pass_clearance = p.pass_clearance, target_clearance = p.target_clearance;
  const double exclusion = p.exclusion, blind_radius = p.blind_radius;
  const perception::DistanceField known(grid, /*unknown_is_obstacle=*/true);
  const perception::DistanceField optimistic(grid, /*unknown_is_obstacle=*/false);
  const double res = grid.Resolution();
  auto passable = [&](const perception::Cell& c) {
    return grid.Contains(c) && grid.State(c) != perception::CellState::kOccupied &&
           optimistic.ClearanceOfCell(c) >= pass_clearance;
  };
  auto nearest_passable = [&](const Vec2& p, double radius) {
    return NearestCell(grid, p, radius, 1e18, passable);
  };
  const auto start = nearest_passable(from, 0.5);
  const auto target = nearest_passable(goal, 1.0);
  if (!start || !target) {
    *why = start ? "the goal is inside obstacles" : "no passable cell near the robot";
    return {};
  }
  // Unknown (or too narrow when unknown is an obstacle) costs unknown_cost per metre: the
  // route keeps to what the scans saw (e.g. the wedge of a room seen through its door) rather
  // than cutting a corner through a shadow it cannot scan from.
  auto step_cost = [&](std::size_t, std::size_t to, const perception::GridStep& st) {
    const perception::Cell nb{static_cast<int>(to % grid.Width()),
                              static_cast<int>(to / grid.Width())};
    if (!passable(nb)) return -1.0;
    const bool known_ok = grid.State(nb) == perception::CellState::kFree &&
                          known.ClearanceOfCell(nb) >= pass_clearance;
    return res * (st.Diagonal() ? std::sqrt(2.0) : 1.0) * (known_ok ? 1.0 : p.unknown_cost);
  };
  const std::vector<std::size_t> path = perception::GridShortestPath(
      grid.Width(), grid.Height(), grid.Index(*start), grid.Index(*target),
      perception::kNeighboursRowMajor, step_cost, 1e-12);
  if (path.empty()) {
    *why = "no route to the goal even through unexplored space";
    return {};
  }
  auto centre = [&](std::size_t k) {
    return grid.CentreOf({static_cast<int>(k % grid.Width()), static_cast<int>(k / grid.Width())});
  };
  auto spent = [&](const Vec2& p) {
    for (const Pose2& sp : scan_poses)
      if (std::hypot(p.x() - sp.x, p.y() - sp.y) < exclusion) return true;
    return false;
  };
  std::vector<Vec2> wide, any;  // along the route, in order
  for (const std::size_t k : path) {
    const perception::Cell c{static_cast<int>(k % grid.Width()),
                             static_cast<int>(k / grid.Width())};
    // Around a scan position the map is known (the LRF sweeps cover the TLS blind cone, all
    // but the LRFs' rear gap).
    bool near_scan = false;
    for (const Pose2& sp : scan_poses)
      near_scan =
          near_scan || std::hypot(centre(k).x() - sp.x, centre(k).y() - sp.y) < blind_radius;
    if (!near_scan && (grid.State(c) != perception::CellState::kFree ||
                       known.ClearanceOfCell(c) < pass_clearance))
      break;
    if (spent(centre(k))) continue;
    any.push_back(centre(k));
    if (known.ClearanceOfCell(c) >= target_clearance) wide.push_back(centre(k));
  }
  // Preference: the farthest wide point first, then nearer ones, then the narrow ones (the
  // caller takes the first its planner can reach).
  std::vector<Vec2> out(wide.rbegin(), wide.rend());
  for (auto it = any.rbegin(); it != any.rend(); ++it)
    if (std::find(out.begin(), out.end(), *it) == out.end()) out.push_back(*it);
  if (out.empty())
    *why = "no progress: the route leaves the known space where the robot has already scanned";
  return out;
}

std::vector<double> RouteLengths(const perception::OccupancyGrid& grid, const Vec2& from,
                                 const std::vector<Vec2>& goals, double clearance,
                                 bool through_unknown) {
  const perception::DistanceField field(grid, /*unknown_is_obstacle=*/!through_unknown);
  auto passable = [&](const perception::Cell& c) {
    const perception::CellState st = grid.State(c);
    return (st == perception::CellState::kFree ||
            (through_unknown && st == perception::CellState::kUnknown)) &&
           field.ClearanceOfCell(c) >= clearance;
  };
  std::vector<double> out(goals.size(), std::numeric_limits<double>::infinity());
  const auto start = NearestCell(grid, from, 0.5, 0.25 + 1e-12, passable);
  if (!start) return out;
  const double res = grid.Resolution();
  auto step_cost = [&](std::size_t, std::size_t to, const perception::GridStep& st) {
    const perception::Cell nb{static_cast<int>(to % grid.Width()),
                              static_cast<int>(to / grid.Width())};
    return passable(nb) ? res * (st.Diagonal() ? std::sqrt(2.0) : 1.0) : -1.0;
  };
  for (std::size_t g = 0; g < goals.size(); ++g) {
    const auto target = NearestCell(grid, goals[g], 0.5, 0.25 + 1e-12, passable);
    if (!target) continue;
    const std::vector<std::size_t> path = perception::GridShortestPath(
        grid.Width(), grid.Height(), grid.Index(*start), grid.Index(*target),
        perception::kNeighboursRowMajor, step_cost, 1e-12);
    if (path.empty()) continue;
    double len = 0.0;
    for (std::size_t k = 1; k < path.size(); ++k) {
      const long a = static_cast<long>(path[k - 1]), b = static_cast<long>(path[k]);
      len += res * ((a % grid.Width() != b % grid.Width() && a / grid.Width() != b / grid.Width())
                        ? std::sqrt(2.0)
                        : 1.0);
    }
    out[g] = len;
  }
  return out;
}

std::optional<Vec2> NearestClearPoint(const perception::OccupancyGrid& grid,
                                      const perception::DistanceField& known, const Vec2& p,
                                      double radius, double clearance) {
  const auto c =
      NearestCell(grid, p, radius, radius * radius + 1e-12, [&](const perception::Cell& c) {
        return grid.State(c) == perception::CellState::kFree &&
               known.ClearanceOfCell(c) >= clearance;
      });
  if (!c) return std::nullopt;
  return grid.CentreOf(*c);
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

}  // namespace mopad::autonomy
