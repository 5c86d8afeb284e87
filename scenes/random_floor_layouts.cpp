// The layout families of random floors beyond the office family (scenes/random_floor.h): a long
// corridor, an L or T corridor junction, a hall with a column grid. Each returns the blocks of
// one floor on wall centre lines, the hub (corridor or hall) first, or an empty layout when the
// draw does not fit (the caller draws again).

#include <algorithm>
#include <cmath>

#include "scenes/random_floor_internal.h"

namespace mopad::scenes::random_floor {

Polygon2 RectPoly(const Cell& c) {
  return {{c.x0, c.y0}, {c.x1, c.y0}, {c.x1, c.y1}, {c.x0, c.y1}};
}

std::vector<double> Cuts(CounterRng& rng, double lo, double hi, int n, double min_len) {
  std::vector<double> w(static_cast<std::size_t>(n));
  double total = 0.0;
  for (auto& x : w) total += (x = rng.Uniform(1.0, 1.8));
  const double spare = (hi - lo) - n * min_len;
  std::vector<double> cuts{lo};
  double acc = lo;
  for (int i = 0; i + 1 < n; ++i) {
    acc += min_len + spare * w[static_cast<std::size_t>(i)] / total;
    cuts.push_back(Round(acc));
  }
  cuts.push_back(hi);
  return cuts;
}

namespace {

constexpr double kMaxCorridor = 40.0;  // m, the longest corridor (centre lines)
constexpr double kMaxOffice = 9.0;     // m, the widest office along its corridor

/// Corridor width on centre lines: 1.5-2.5 m clear between the wall faces.
double CorridorWidth(CounterRng& rng) { return Round(rng.Uniform(1.5, 2.5)) + kWall; }

/// Offices of one strip: [lo, hi] cut along x (y in [a0, a1]) or, with along_y, along y (x in
/// [a0, a1]).
void Strip(CounterRng& rng, double lo, double hi, double a0, double a1, int n, Layout* L,
           bool along_y = false) {
  if (n <= 0) return;
  const auto cuts = Cuts(rng, lo, hi, n, kMinCell);
  for (int i = 0; i < n; ++i)
    L->blocks.push_back({along_y ? RectPoly({a0, cuts[i], a1, cuts[i + 1]})
                                 : RectPoly({cuts[i], a0, cuts[i + 1], a1})});
}

}  // namespace

Layout CorridorLayout(CounterRng& rng, int rooms) {
  Layout L;
  L.doors_from_hub = true;
  L.extra_door_probability = 0.15;
  L.hub_ceiling = Round(rng.Uniform(2.5, 2.7));
  const int offices = rooms - 1;
  const int south = (offices + 1) / 2, north = offices - south;
  // Office widths along the corridor: 4.5-8 m on the fuller side; the other side's offices
  // share the same length, so they stay within kMaxOffice on average.
  const double hi = north > 0 ? std::min(8.0, 8.0 * north / south) : 8.0;
  const double length =
      std::min(kMaxCorridor, Round(south * rng.Uniform(std::min(4.5, hi), hi)));
  if (length / south > kMaxOffice + 1e-9 || (north > 0 && length / north > kMaxOffice + 1e-9))
    return {};
  const double c = CorridorWidth(rng);
  const double ds = Round(rng.Uniform(4.5, 7.0));
  const double dn = north > 0 ? Round(rng.Uniform(4.5, 7.0)) : 0.0;
  L.W = length;
  L.D = ds + c + dn;
  L.blocks.push_back({RectPoly({0.0, ds, L.W, ds + c}), BlockKind::kCorridor});
  Strip(rng, 0.0, L.W, 0.0, ds, south, &L);
  Strip(rng, 0.0, L.W, ds + c, L.D, north, &L);
  return L;
}

Layout JunctionLayout(CounterRng& rng, int rooms) {
  const int offices = rooms - 1;
  if (offices < 2) return CorridorLayout(rng, rooms);
  Layout L;
  L.doors_from_hub = true;
  L.extra_door_probability = 0.15;
  L.hub_ceiling = Round(rng.Uniform(2.5, 2.7));
  const bool tee = offices >= 4 && rng.Bernoulli(0.5);
  const double c = CorridorWidth(rng);
  const double ds = Round(rng.Uniform(4.5, 7.0));  // south offices' depth
  const double dw = Round(rng.Uniform(4.5, 7.0));  // west of the arm
  const double de = tee ? Round(rng.Uniform(4.5, 7.0)) : 0.0;
  // The corridor runs across the floor at y in [ds, ds + c]; its arm goes north at x in
  // [xv, xv + c]: in the middle (T, offices both sides) or at the east end (L).
  L.W = dw + c + de;
  const double xv = dw;
  const int max_south = std::max(1, static_cast<int>(L.W / 3.5));
  const int south = std::clamp(static_cast<int>(std::lround(L.W / rng.Uniform(4.5, 7.0))), 1,
                               std::min(max_south, offices - (tee ? 2 : 1)));
  const int arm = offices - south;
  const int west = tee ? (arm + 1) / 2 : arm, east = arm - west;
  const double arm_len = Round(std::max(west, east) * rng.Uniform(3.5, 6.0));
  if (arm_len > kMaxCorridor) return {};
  L.D = ds + c + arm_len;
  const double y1 = ds + c;
  Polygon2 hub = {{0.0, ds}, {L.W, ds}};
  if (tee) hub.insert(hub.end(), {{L.W, y1}, {xv + c, y1}});
  hub.push_back({xv + c, L.D});
  hub.push_back({xv, L.D});
  hub.push_back({xv, y1});
  hub.push_back({0.0, y1});
  L.blocks.push_back({hub, BlockKind::kCorridor});
  Strip(rng, 0.0, L.W, 0.0, ds, south, &L);
  Strip(rng, y1, L.D, 0.0, xv, west, &L, true);
  Strip(rng, y1, L.D, xv + c, L.W, east, &L, true);
  return L;
}

Layout HallLayout(CounterRng& rng, int rooms) {
  Layout L;
  L.doors_from_hub = true;
  L.extra_door_probability = 0.3;
  L.hub_ceiling = Round(rng.Uniform(3.4, 4.0));
  const int offices = rooms - 1;
  // Offices along the south side, and the north side too when one side would crowd them.
  const double hall_w = Round(rng.Uniform(20.0, 26.0)) + kWall;
  const double hall_d = Round(rng.Uniform(14.0, 17.0)) + kWall;
  const int south = offices > 6 ? (offices + 1) / 2 : offices, north = offices - south;
  L.W = std::max(hall_w, Round(std::max(south, north) * 3.6));
  const double ds = Round(rng.Uniform(4.5, 6.5));
  const double dn = north > 0 ? Round(rng.Uniform(4.5, 6.5)) : 0.0;
  L.D = ds + hall_d + dn;
  L.blocks.push_back({RectPoly({0.0, ds, L.W, ds + hall_d}), BlockKind::kHall});
  Strip(rng, 0.0, L.W, 0.0, ds, south, &L);
  Strip(rng, 0.0, L.W, ds + hall_d, L.D, north, &L);
  return L;
}

std::vector<Eigen::Vector2d> HallColumnGrid(const Polygon2& hall_interior) {
  Eigen::AlignedBox2d box;
  for (const auto& p : hall_interior) box.extend(p);
  const Eigen::Vector2d size = box.sizes();
  // A structural grid of 6-8 m spans: the columns sit at the centres of equal bays.
  const int nx = std::max(1, static_cast<int>(std::lround(size.x() / 7.0)));
  const int ny = std::max(1, static_cast<int>(std::lround(size.y() / 7.0)));
  std::vector<Eigen::Vector2d> out;
  for (int j = 1; j < ny + 1; ++j)
    for (int i = 1; i < nx + 1; ++i) {
      const Eigen::Vector2d at(Round(box.min().x() + size.x() * i / (nx + 1)),
                               Round(box.min().y() + size.y() * j / (ny + 1)));
      if (PointInPolygon(at, hall_interior) && DistanceToBoundary(at, hall_interior) >= 1.5)
        out.push_back(at);
    }
  return out;
}

}  // namespace mopad::scenes::random_floor
