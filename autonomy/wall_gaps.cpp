#include "autonomy/wall_gaps.h"

#include <cmath>

#include "common/polygon.h"

namespace mopad::autonomy {
namespace {

enum class Sample { kBlocked, kUnseen, kSeenThrough };

using perception::CellState;

CellState StateAt(const perception::OccupancyGrid& grid, const Vec2& p) {
  const perception::Cell c = grid.CellOf(p);
  return grid.Contains(c) ? grid.State(c) : CellState::kUnknown;
}

}  // namespace

std::vector<WallGap> WallGaps(const perception::OccupancyGrid& grid,
                              const std::vector<Vec2>& perimeter, const WallGapParams& params) {
  std::vector<WallGap> gaps;
  const std::size_t n = perimeter.size();
  if (n < 3) return gaps;
  const double step = 0.5 * grid.Resolution();
  for (std::size_t e = 0; e < n; ++e) {
    const Vec2 p0 = perimeter[e], p1 = perimeter[(e + 1) % n];
    const double len = (p1 - p0).norm();
    if (len < params.min_width) continue;
    const Vec2 t = (p1 - p0) / len;
    Vec2 inward(-t.y(), t.x());
    const Vec2 mid = 0.5 * (p0 + p1);
    if (!PointInPolygon(mid + 2.0 * grid.Resolution() * inward, perimeter)) inward = -inward;

    const int count = static_cast<int>(std::floor(len / step)) + 1;
    std::vector<Sample> s(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) {
      const Vec2 q = p0 + (k * step) * t;
      Sample v = Sample::kUnseen;
      for (double d = -params.inside_tolerance; d <= params.wall_band + 1e-9; d += step)
        if (StateAt(grid, q - d * inward) == CellState::kOccupied) v = Sample::kBlocked;
      if (v != Sample::kBlocked)
        for (double d = grid.Resolution(); d <= params.wall_band + params.see_through_depth + 1e-9;
             d += step)
          if (StateAt(grid, q - d * inward) == CellState::kFree) v = Sample::kSeenThrough;
      s[static_cast<std::size_t>(k)] = v;
    }

    // Runs of unblocked samples framed by blocked ones.
    int k = 0;
    while (k < count && s[static_cast<std::size_t>(k)] != Sample::kBlocked) ++k;
    while (k < count) {
      int a = k + 1;  // first unblocked sample after a blocked one
      while (a < count && s[static_cast<std::size_t>(a)] == Sample::kBlocked) ++a;
      if (a >= count) break;
      int b = a;
      bool seen = false;
      while (b < count && s[static_cast<std::size_t>(b)] != Sample::kBlocked) {
        seen = seen || s[static_cast<std::size_t>(b)] == Sample::kSeenThrough;
        ++b;
      }
      if (b >= count) break;  // runs to the edge's end: no jamb there
      WallGap g;
      g.edge = static_cast<int>(e);
      g.a = p0 + (a * step) * t;
      g.b = p0 + ((b - 1) * step) * t;
      g.inward = inward;
      if (seen && g.width() >= params.min_width && g.width() <= params.max_width) gaps.push_back(g);
      k = b;
    }
  }
  return gaps;
}

}  // namespace mopad::autonomy
