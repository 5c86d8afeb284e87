#include "common/polygon.h"

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

std::optional<std::vector<Eigen::Vector2d>> UnionOfTiledPolygons(
    const std::vector<std::vector<Eigen::Vector2d>>& polygons, double tolerance) {
  using V2 = Eigen::Vector2d;
  // Vertices within `tolerance` are one point (index into `pts`).
  std::vector<V2> pts;
  auto id_of = [&](const V2& p) {
    for (std::size_t i = 0; i < pts.size(); ++i)
      if ((pts[i] - p).norm() <= tolerance) return static_cast<int>(i);
    pts.push_back(p);
    return static_cast<int>(pts.size() - 1);
  };
  std::vector<std::vector<int>> loops;
  double total = 0.0, perimeter = 0.0;
  for (const auto& poly : polygons) {
    const double a = SignedArea(poly);
    std::vector<int> loop;
    for (const V2& p : poly) {
      const int i = id_of(p);
      if (loop.empty() || loop.back() != i) loop.push_back(i);
    }
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    if (loop.size() < 3 || !(std::abs(a) > 0.0)) return std::nullopt;
    if (a < 0.0) std::reverse(loop.begin(), loop.end());
    total += std::abs(a);
    for (std::size_t k = 0; k < poly.size(); ++k)
      perimeter += (poly[(k + 1) % poly.size()] - poly[k]).norm();
    loops.push_back(std::move(loop));
  }
  if (loops.empty()) return std::nullopt;
  // Directed edge pieces, split at every vertex lying on an edge.
  std::map<std::pair<int, int>, int> count;
  for (const auto& loop : loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      const V2 d = pts[b] - pts[a];
      std::vector<std::pair<double, int>> on;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const int c = static_cast<int>(i);
        if (c == a || c == b || DistanceToSegment(pts[i], pts[a], pts[b]) > tolerance) continue;
        on.emplace_back((pts[i] - pts[a]).dot(d) / d.squaredNorm(), c);
      }
      std::sort(on.begin(), on.end());
      int from = a;
      for (const auto& [t, c] : on) {
        ++count[{from, c}];
        from = c;
      }
      ++count[{from, b}];
    }
  // Pieces two polygons share (met in opposite directions) are inside the union; a piece met
  // twice in one direction means the polygons overlap.
  std::map<int, std::vector<int>> next;
  for (const auto& [e, n] : count) {
    if (n > 1) return std::nullopt;
    const auto back = count.find({e.second, e.first});
    if (back != count.end() && back->second > 0) continue;
    next[e.first].push_back(e.second);
  }
  std::size_t edges = 0;
  for (const auto& [v, out] : next) {
    if (out.size() != 1) return std::nullopt;  // the outline would touch itself
    ++edges;
  }
  if (next.empty()) return std::nullopt;
  std::vector<int> outline{next.begin()->first};
  while (outline.size() <= edges) {
    const auto it = next.find(outline.back());
    if (it == next.end()) return std::nullopt;
    if (it->second[0] == outline.front()) break;
    outline.push_back(it->second[0]);
  }
  if (outline.size() != edges) return std::nullopt;  // more than one outline: a hole or apart
  std::vector<V2> out;
  for (std::size_t k = 0; k < outline.size(); ++k) {
    const V2& p = pts[outline[(k + outline.size() - 1) % outline.size()]];
    const V2& c = pts[outline[k]];
    const V2& q = pts[outline[(k + 1) % outline.size()]];
    if (DistanceToSegment(c, p, q) > tolerance) out.push_back(c);
  }
  if (out.size() < 3) return std::nullopt;
  if (std::abs(SignedArea(out) - total) > tolerance * perimeter + 1e-12) return std::nullopt;
  return out;
}

}  // namespace mopad
