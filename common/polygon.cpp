#include "common/polygon.h"

#include <cmath>
#include <stdexcept>

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

}  // namespace mopad
