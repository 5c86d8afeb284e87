#include "autonomy/wall_gaps.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/polygon.h"

namespace mopad::autonomy {
namespace {

enum class Sample { kBlocked, kUnseen, kSeenThrough };

using perception::CellState;

CellState StateAt(const perception::OccupancyGrid& grid, const Vec2& p) {
  const perception::Cell c = grid.CellOf(p);
  return grid.Contains(c) ? grid.State(c) : CellState::kUnknown;
}

// The perimeter as wall lines: runs of consecutive edges that stay within `offset` of the
// line through the run's first edge and turn by less than `max_turn` from it (a shadow step or
// a kink the outline makes in a doorway is not a corner). Each run: first edge, edge count.
std::vector<std::pair<std::size_t, std::size_t>> WallLines(const std::vector<Vec2>& poly,
                                                           double max_turn, double offset) {
  const std::size_t n = poly.size();
  auto dir = [&](std::size_t e) { return Vec2((poly[(e + 1) % n] - poly[e % n]).normalized()); };
  auto continues = [&](std::size_t first, std::size_t e) {
    const Vec2 t = dir(first);
    const Vec2 q = poly[(e + 1) % n] - poly[first % n];
    return dir(e).dot(t) >= std::cos(max_turn) && std::abs(t.x() * q.y() - t.y() * q.x()) <= offset;
  };
  // Start at an edge that does not continue its predecessor (a true corner), if any.
  std::size_t start = 0;
  for (std::size_t e = 0; e < n; ++e)
    if (!continues((e + n - 1) % n, e)) {
      start = e;
      break;
    }
  std::vector<std::pair<std::size_t, std::size_t>> lines;
  for (std::size_t done = 0; done < n;) {
    const std::size_t first = (start + done) % n;
    std::size_t count = 1;
    while (done + count < n && continues(first, first + count)) ++count;
    lines.emplace_back(first, count);
    done += count;
  }
  return lines;
}

}  // namespace

std::vector<WallGap> WallGaps(const perception::OccupancyGrid& grid,
                              const std::vector<Vec2>& perimeter, const WallGapParams& params) {
  std::vector<WallGap> gaps;
  const std::size_t n = perimeter.size();
  if (n < 3) return gaps;
  const double step = 0.5 * grid.Resolution();
  for (const auto& [first, count] :
       WallLines(perimeter, DegToRad(params.collinear_deg), params.collinear_offset)) {
    const Vec2 p0 = perimeter[first], p1 = perimeter[(first + count) % n];
    const double len = (p1 - p0).norm();
    if (len < params.min_width) continue;
    const Vec2 t = (p1 - p0) / len;
    Vec2 inward(-t.y(), t.x());
    const Vec2 e0 = perimeter[(first + 1) % n];
    const Vec2 mid = 0.5 * (p0 + e0);
    if (!PointInPolygon(mid + 2.0 * grid.Resolution() * inward, perimeter)) inward = -inward;

    // Samples every half cell along the line's edges (on the perimeter itself), the wall band
    // taken across the whole line's direction.
    std::vector<Vec2> at;
    std::vector<std::size_t> edge_of;
    for (std::size_t k = 0; k < count; ++k) {
      const Vec2 a = perimeter[(first + k) % n], b = perimeter[(first + k + 1) % n];
      const double l = (b - a).norm();
      const int m = std::max(1, static_cast<int>(std::floor(l / step)));
      for (int i = 0; i < m; ++i) {
        at.push_back(a + (l * i / m) * (b - a).normalized());
        edge_of.push_back((first + k) % n);
      }
    }
    at.push_back(p1);
    edge_of.push_back((first + count - 1) % n);
    const int samples = static_cast<int>(at.size());
    std::vector<Sample> s(static_cast<std::size_t>(samples));
    for (int k = 0; k < samples; ++k) {
      const Vec2& q = at[static_cast<std::size_t>(k)];
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
    while (k < samples && s[static_cast<std::size_t>(k)] != Sample::kBlocked) ++k;
    while (k < samples) {
      int a = k + 1;  // first unblocked sample after a blocked one
      while (a < samples && s[static_cast<std::size_t>(a)] == Sample::kBlocked) ++a;
      if (a >= samples) break;
      int b = a;
      bool seen = false;
      while (b < samples && s[static_cast<std::size_t>(b)] != Sample::kBlocked) {
        seen = seen || s[static_cast<std::size_t>(b)] == Sample::kSeenThrough;
        ++b;
      }
      if (b >= samples) break;  // runs to the line's end: no jamb there
      WallGap g;
      g.edge = static_cast<int>(edge_of[static_cast<std::size_t>(a)]);
      g.a = at[static_cast<std::size_t>(a)];
      g.b = at[static_cast<std::size_t>(b - 1)];
      g.inward = inward;
      if (seen && g.width() >= params.min_width && g.width() <= params.max_width) gaps.push_back(g);
      k = b;
    }
  }
  return gaps;
}

}  // namespace mopad::autonomy
