#include "common/polygon.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace mopad {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

std::vector<Eigen::Vector3i> TriangulatePolygon(const std::vector<Eigen::Vector2d>& poly) {
  // Ear clipping (Meisters 1975): O(n^2) for the small plan polygons we have.
  std::vector<int> idx(poly.size());
  for (std::size_t i = 0; i < poly.size(); ++i) idx[i] = static_cast<int>(i);
  std::vector<Eigen::Vector3i> tris;
  const double eps = 1e-12;
  auto point_in_tri = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                          const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return Cross(a, b, p) >= -eps && Cross(b, c, p) >= -eps && Cross(c, a, p) >= -eps;
  };
  std::size_t guard = 0;
  while (idx.size() > 3) {
    const std::size_t n = idx.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n; ++i) {
      const int ip = idx[(i + n - 1) % n], ic = idx[i], in = idx[(i + 1) % n];
      const Eigen::Vector2d &a = poly[ip], &b = poly[ic], &c = poly[in];
      const double cr = Cross(a, b, c);
      if (std::abs(cr) <= eps * std::max(1.0, (c - a).squaredNorm())) {
        // Collinear vertex: drop it (no triangle) if it lies between its neighbours.
        if ((b - a).dot(c - b) > 0.0) {
          idx.erase(idx.begin() + static_cast<long>(i));
          clipped = true;
          break;
        }
        continue;
      }
      if (cr < 0.0) continue;  // reflex
      bool ear = true;
      for (std::size_t k = 0; k < n && ear; ++k) {
        const int j = idx[k];
        if (j == ip || j == ic || j == in) continue;
        const Eigen::Vector2d& p = poly[j];
        if (p == a || p == b || p == c) continue;
        if (point_in_tri(p, a, b, c)) ear = false;
      }
      if (!ear) continue;
      tris.emplace_back(ip, ic, in);
      idx.erase(idx.begin() + static_cast<long>(i));
      clipped = true;
      break;
    }
    if (!clipped || ++guard > 100000) {
      throw std::invalid_argument("TriangulatePolygon: polygon is not simple");
    }
  }
  if (idx.size() == 3 && Cross(poly[idx[0]], poly[idx[1]], poly[idx[2]]) > eps) {
    tris.emplace_back(idx[0], idx[1], idx[2]);
  }
  return tris;
}

double SignedArea(const std::vector<Eigen::Vector2d>& poly) {
  double a = 0.0;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d& q = poly[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

Eigen::Vector3d NewellVector(const std::vector<Eigen::Vector3d>& poly) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) s += poly[i].cross(poly[(i + 1) % n]);
  return s;
}

double PolygonArea3d(const std::vector<Eigen::Vector3d>& poly) {
  return 0.5 * NewellVector(poly).norm();
}

std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> p, double tolerance) {
  using V2 = Eigen::Vector2d;
  std::sort(p.begin(), p.end(), [](const V2& a, const V2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end(),
                      [](const V2& a, const V2& b) { return (a - b).norm() < 1e-12; }),
          p.end());
  if (p.size() < 3) return p;
  // Lower chain left to right, then upper chain back; the last point repeats the first.
  std::vector<V2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && Cross(h[k - 2], h[k - 1], p[i]) <= tolerance) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && Cross(h[k - 2], h[k - 1], p[i - 1]) <= tolerance) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

void RemoveShallowVertices(std::vector<Eigen::Vector2d>& poly, double tolerance) {
  while (poly.size() > 3) {
    const std::size_t n = poly.size();
    std::size_t best = n;
    double best_offset = tolerance;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d& a = poly[(i + n - 1) % n];
      const Eigen::Vector2d& b = poly[i];
      const Eigen::Vector2d& c = poly[(i + 1) % n];
      const Eigen::Vector2d ac = c - a;
      const double len = ac.norm();
      if (len <= 0.0) continue;
      const double along = (b - a).dot(ac) / len;
      if (along <= 0.0 || along >= len) continue;
      const double offset = std::abs(ac.x() * (b - a).y() - ac.y() * (b - a).x()) / len;
      if (offset < best_offset) {
        best_offset = offset;
        best = i;
      }
    }
    if (best == n) return;
    poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(best));
  }
}

TiledBoundary BoundaryOfTiledPolygons(const std::vector<std::vector<Eigen::Vector2d>>& polygons,
                                      double tolerance) {
  using V2 = Eigen::Vector2d;
  TiledBoundary out;
  // Vertices within `tolerance` are one point (index into `pts`), numbered as first met.
  std::vector<V2> pts;
  auto id_of = [&](const V2& p) {
    for (std::size_t i = 0; i < pts.size(); ++i)
      if ((pts[i] - p).norm() <= tolerance) return static_cast<int>(i);
    pts.push_back(p);
    return static_cast<int>(pts.size() - 1);
  };
  std::vector<std::vector<int>> loops;
  for (const auto& poly : polygons) {
    const double a = SignedArea(poly);
    std::vector<int> loop;
    for (const V2& p : poly) {
      const int i = id_of(p);
      if (loop.empty() || loop.back() != i) loop.push_back(i);
    }
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    if (loop.size() < 3 || !(std::abs(a) > 0.0)) continue;
    if (a < 0.0) std::reverse(loop.begin(), loop.end());
    loops.push_back(std::move(loop));
  }
  // Directed edge pieces, split at every vertex lying on an edge.
  std::map<std::pair<int, int>, int> count;
  for (const auto& loop : loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      const V2 d = pts[b] - pts[a];
      std::vector<std::pair<double, int>> on;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const int c = static_cast<int>(i);
        if (c == a || c == b) continue;
        const double t = (pts[i] - pts[a]).dot(d) / d.squaredNorm();
        if (t <= 0.0 || t >= 1.0 || DistanceToSegment(pts[i], pts[a], pts[b]) > tolerance) continue;
        on.emplace_back(t, c);
      }
      std::sort(on.begin(), on.end());
      int from = a;
      for (const auto& [t, c] : on) {
        ++count[{from, c}];
        from = c;
      }
      ++count[{from, b}];
    }
  // Pieces two polygons share (met in opposite directions) are inside the union.
  std::map<int, int> next;
  for (const auto& [e, n] : count) {
    if (n > 1) out.overlap = true;
    if (count.count({e.second, e.first})) continue;
    if (next.count(e.first)) {
      out.problem = TiledBoundary::kTouchesItself;
      return out;
    }
    next[e.first] = e.second;
  }
  // Loops, each from its lowest-numbered vertex.
  std::map<int, bool> used;
  for (const auto& [start, unused] : next) {
    if (used[start]) continue;
    std::vector<V2> loop;
    for (int v = start; !used[v];) {
      used[v] = true;
      loop.push_back(pts[v]);
      const auto it = next.find(v);
      if (it == next.end()) {
        out.problem = TiledBoundary::kNotClosed;
        return out;
      }
      v = it->second;
    }
    out.loops.push_back(std::move(loop));
  }
  return out;
}

std::optional<std::vector<Eigen::Vector2d>> UnionOfTiledPolygons(
    const std::vector<std::vector<Eigen::Vector2d>>& polygons, double tolerance) {
  double total = 0.0, perimeter = 0.0;
  for (const auto& poly : polygons) {
    if (poly.size() < 3 || !(std::abs(SignedArea(poly)) > 0.0)) return std::nullopt;
    total += std::abs(SignedArea(poly));
    for (std::size_t k = 0; k < poly.size(); ++k)
      perimeter += (poly[(k + 1) % poly.size()] - poly[k]).norm();
  }
  const TiledBoundary b = BoundaryOfTiledPolygons(polygons, tolerance);
  // One outline: not apart, no hole, no overlap.
  if (b.problem != TiledBoundary::kNone || b.overlap || b.loops.size() != 1) return std::nullopt;
  const std::vector<Eigen::Vector2d>& loop = b.loops[0];
  std::vector<Eigen::Vector2d> out;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector2d& p = loop[(k + loop.size() - 1) % loop.size()];
    const Eigen::Vector2d& c = loop[k];
    const Eigen::Vector2d& q = loop[(k + 1) % loop.size()];
    if (DistanceToSegment(c, p, q) > tolerance) out.push_back(c);
  }
  if (out.size() < 3) return std::nullopt;
  if (std::abs(SignedArea(out) - total) > tolerance * perimeter + 1e-12) return std::nullopt;
  return out;
}

}  // namespace mopad
