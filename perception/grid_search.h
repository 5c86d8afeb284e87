#pragma once
// The one shortest-path search over grid cells (the planner's seed path, the exploration
// route): Dijkstra over 8-connected cells, settled in (distance, index) order, so the result is
// deterministic and does not depend on the container's tie-breaking.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace mopad::perception {

/// A step to a neighbour cell (offsets in i and j).
struct GridStep {
  int di = 0, dj = 0;
  bool Diagonal() const { return di != 0 && dj != 0; }
};

/// Neighbours row by row from (-1, -1) to (1, 1).
inline constexpr std::array<GridStep, 8> kNeighboursRowMajor = {
    {{-1, -1}, {0, -1}, {1, -1}, {-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}}};
/// The four axis neighbours first, then the diagonals.
inline constexpr std::array<GridStep, 8> kNeighboursAxesFirst = {
    {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}};

/// Cells from `start` to `goal` (indices j * width + i of a width x height grid) along the
/// cheapest 8-connected route, empty when `goal` cannot be reached. `step_cost(from, to, step)`
/// is the cost of one step, or negative when `to` cannot be entered; neighbours are tried in
/// `order` (it decides between routes of equal cost). A cell's distance is replaced only when
/// the new one is smaller by more than `min_improvement`.
template <class StepCost>
std::vector<std::size_t> GridShortestPath(int width, int height, std::size_t start,
                                          std::size_t goal, const std::array<GridStep, 8>& order,
                                          StepCost&& step_cost, double min_improvement = 0.0) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> parent(n, n);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[start] = 0.0;
  open.emplace(0.0, start);
  while (!open.empty()) {
    const auto [d, k] = open.top();
    open.pop();
    if (d > dist[k]) continue;
    if (k == goal) break;
    const int i = static_cast<int>(k % static_cast<std::size_t>(width));
    const int j = static_cast<int>(k / static_cast<std::size_t>(width));
    for (const GridStep& s : order) {
      const int ni = i + s.di, nj = j + s.dj;
      if (ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
      const std::size_t nk = static_cast<std::size_t>(nj) * width + ni;
      const double c = step_cost(k, nk, s);
      if (c < 0.0) continue;
      const double nd = d + c;
      if (nd < dist[nk] - min_improvement) dist[nk] = nd, parent[nk] = k, open.emplace(nd, nk);
    }
  }
  std::vector<std::size_t> path;
  if (!std::isfinite(dist[goal])) return path;
  for (std::size_t k = goal; k != n; k = parent[k]) path.push_back(k);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace mopad::perception
