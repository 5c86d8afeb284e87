// Sloped ceilings in plan (common/ceiling_planes.h).
#include "common/ceiling_planes.h"

#include <algorithm>
#include <cmath>

#include "common/polygon.h"

namespace mopad {

namespace {

using Vec2 = Eigen::Vector2d;
using Poly2 = std::vector<Vec2>;

constexpr double kCornerReach = 0.05;  // m, see WallUnderCeilings
constexpr double kSameVertex = 1e-4;   // m, a wall outline's vertices closer than this are one
// m: a wall outline's vertex this close to the line of its neighbours goes. Where a hip line
// meets a corner, the foot's first or last centimetre (the probe 1 cm into the room) lies
// under the neighbouring plane, a millimetre off.
constexpr double kJog = 0.005;

// Where `p` is lower than or level with `q`: a . x <= d in plan. False when the two are
// parallel in plan (they never cross).
bool LowerHalfPlane(const CeilingPlane& p, const CeilingPlane& q, Vec2* a, double* d) {
  // z(x, y) = c / nz - (nx / nz) x - (ny / nz) y
  *a = Vec2(q.n.x() / q.n.z() - p.n.x() / p.n.z(), q.n.y() / q.n.z() - p.n.y() / p.n.z());
  *d = q.c / q.n.z() - p.c / p.n.z();
  return a->norm() > 1e-9;
}

// The u in (0, length) where the segment a + u dir crosses an edge of `poly`.
std::vector<double> Crossings(const Poly2& poly, const Vec2& a, const Vec2& dir, double length) {
  std::vector<double> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 p = poly[i], e = poly[(i + 1) % poly.size()] - p;
    const double den = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Vec2 w = p - a;
    const double u = (w.x() * e.y() - w.y() * e.x()) / den;
    const double t = (w.x() * dir.y() - w.y() * dir.x()) / den;
    if (u > 0.0 && u < length && t >= 0.0 && t <= 1.0) out.push_back(u);
  }
  return out;
}

}  // namespace

std::vector<std::vector<Vec2>> LowestCeilingRegions(const Poly2& plan,
                                                    const std::vector<CeilingPlane>& planes,
                                                    const std::vector<Poly2>* hulls,
                                                    double min_area) {
  std::vector<Poly2> regions(planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) {
    Poly2 region = plan;
    if (hulls != nullptr && (*hulls)[i].size() >= 3) {
      const Poly2& hull = (*hulls)[i];
      for (std::size_t k = 0; k < hull.size() && !region.empty(); ++k) {
        const Vec2 e = hull[(k + 1) % hull.size()] - hull[k];
        const Vec2 out(e.y(), -e.x());  // right of a CCW edge is outside
        region = ClipHalfSpace(region, out, out.dot(hull[k]));
      }
    }
    for (std::size_t j = 0; j < planes.size() && !region.empty(); ++j) {
      Vec2 a;
      double d = 0.0;
      if (j != i && LowerHalfPlane(planes[i], planes[j], &a, &d))
        region = ClipHalfSpace(region, a, d);
    }
    if (region.size() >= 3 && std::abs(SignedArea(region)) > min_area) regions[i] = region;
  }
  return regions;
}

std::vector<Vec2> WallUnderCeilings(const Vec2& foot, const Vec2& dir, const Vec2& inward,
                                    double length, double z0, double height,
                                    const std::vector<CeilingPlane>& planes,
                                    const std::vector<Poly2>& regions) {
  const Vec2 a = foot + 0.01 * inward;
  std::vector<double> cuts{0.0, length};
  for (const Poly2& region : regions) {
    const std::vector<double> c = Crossings(region, a, dir, length);
    cuts.insert(cuts.end(), c.begin(), c.end());
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(),
                         [](double x, double y) { return std::abs(x - y) < 1e-6; }),
             cuts.end());
  std::vector<Vec2> outline{Vec2(0.0, 0.0)};  // (u, v), then along the top, u ascending
  bool cut = false;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const Vec2 mid = a + 0.5 * (cuts[k] + cuts[k + 1]) * dir;
    const CeilingPlane* over = nullptr;
    for (std::size_t i = 0; i < planes.size() && i < regions.size(); ++i)
      if (regions[i].size() >= 3 && PointInPolygon(mid, regions[i]) &&
          (over == nullptr || planes[i].ZAt(mid) < over->ZAt(mid)))
        over = &planes[i];
    // At a corner the probe 1 cm in from the foot can pass beyond the neighbouring wall, out of
    // every region: the region within kCornerReach there holds it.
    double nearest = kCornerReach;
    const CeilingPlane* near = nullptr;
    for (std::size_t i = 0; i < planes.size() && i < regions.size() && over == nullptr; ++i)
      if (regions[i].size() >= 3 && DistanceToBoundary(mid, regions[i]) < nearest) {
        nearest = DistanceToBoundary(mid, regions[i]);
        near = &planes[i];
      }
    if (over == nullptr) over = near;
    for (double u : {cuts[k], cuts[k + 1]}) {
      double v = height;
      if (over != nullptr) v = std::clamp(over->ZAt(foot + u * dir) - z0, 0.0, height);
      cut = cut || v < height - 1e-6;
      // Where two planes meet at a cut their heights agree to float rounding: one vertex.
      if ((outline.back() - Vec2(u, v)).norm() > kSameVertex) outline.emplace_back(u, v);
    }
  }
  if (!cut) return {};
  outline.emplace_back(length, 0.0);
  RemoveShallowVertices(outline, kJog);
  return outline;
}

}  // namespace mopad
