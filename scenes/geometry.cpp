#include "scenes/geometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

double Cross(const Vector2d& o, const Vector2d& a, const Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

int Sign(double x, double eps) { return x > eps ? 1 : (x < -eps ? -1 : 0); }

bool OnSegment(const Vector2d& p, const Vector2d& a, const Vector2d& b) {
  return std::min(a.x(), b.x()) - 1e-12 <= p.x() && p.x() <= std::max(a.x(), b.x()) + 1e-12 &&
         std::min(a.y(), b.y()) - 1e-12 <= p.y() && p.y() <= std::max(a.y(), b.y()) + 1e-12;
}

}  // namespace

bool SegmentsIntersect(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d) {
  const double eps = 1e-12;
  const int d1 = Sign(Cross(c, d, a), eps), d2 = Sign(Cross(c, d, b), eps);
  const int d3 = Sign(Cross(a, b, c), eps), d4 = Sign(Cross(a, b, d), eps);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  if (d1 == 0 && OnSegment(a, c, d)) return true;
  if (d2 == 0 && OnSegment(b, c, d)) return true;
  if (d3 == 0 && OnSegment(c, a, b)) return true;
  if (d4 == 0 && OnSegment(d, a, b)) return true;
  return false;
}

bool IsSimplePolygon(const Polygon2& poly, std::string* why) {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  const std::size_t n = poly.size();
  if (n < 3) return fail("fewer than 3 vertices");
  for (const auto& p : poly)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return fail("non-finite vertex");
  for (std::size_t i = 0; i < n; ++i) {
    if ((poly[i] - poly[(i + 1) % n]).norm() < 1e-6)
      return fail("zero-length edge at vertex " + std::to_string(i));
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const Vector2d &a = poly[i], &b = poly[(i + 1) % n];
      const Vector2d &c = poly[j], &d = poly[(j + 1) % n];
      if (adjacent) {
        // Adjacent edges may only share their common vertex: reject folding back.
        const Vector2d& shared = (j == i + 1) ? b : a;
        const Vector2d& other_i = (j == i + 1) ? a : b;
        const Vector2d& other_j = (j == i + 1) ? d : c;
        if (std::abs(Cross(shared, other_i, other_j)) < 1e-12 &&
            (other_i - shared).dot(other_j - shared) > 0.0) {
          return fail("edges " + std::to_string(i) + " and " + std::to_string(j) + " overlap");
        }
        continue;
      }
      if (SegmentsIntersect(a, b, c, d)) {
        return fail("edges " + std::to_string(i) + " and " + std::to_string(j) + " intersect");
      }
    }
  }
  if (std::abs(SignedArea(poly)) < 1e-6) return fail("zero area");
  return true;
}

bool PolygonsIntersect(const Polygon2& a, const Polygon2& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      if (SegmentsIntersect(a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()])) return true;
  return PointInPolygon(a[0], b) || PointInPolygon(b[0], a);
}

bool PolygonInside(const Polygon2& inner, const Polygon2& outer) {
  for (std::size_t i = 0; i < inner.size(); ++i)
    for (std::size_t j = 0; j < outer.size(); ++j)
      if (SegmentsIntersect(inner[i], inner[(i + 1) % inner.size()], outer[j],
                            outer[(j + 1) % outer.size()]))
        return false;
  return PointInPolygon(inner[0], outer);
}

bool ConvexOverlap(const Polygon2& a, const Polygon2& b) {
  auto separated = [](const Polygon2& p, const Polygon2& q) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vector2d e = p[(i + 1) % p.size()] - p[i];
      const Vector2d n(-e.y(), e.x());
      double pmin = 1e300, pmax = -1e300, qmin = 1e300, qmax = -1e300;
      for (const auto& v : p) {
        pmin = std::min(pmin, n.dot(v));
        pmax = std::max(pmax, n.dot(v));
      }
      for (const auto& v : q) {
        qmin = std::min(qmin, n.dot(v));
        qmax = std::max(qmax, n.dot(v));
      }
      if (pmax < qmin || qmax < pmin) return true;
    }
    return false;
  };
  return !separated(a, b) && !separated(b, a);
}

void TriangulateRectWithHoles(double length, double height, const std::vector<Rect2>& holes_in,
                              std::vector<Vector2d>* points,
                              std::vector<Eigen::Vector3i>* triangles) {
  points->clear();
  triangles->clear();
  std::vector<Rect2> holes;
  for (Rect2 h : holes_in) {
    h.u0 = std::max(h.u0, 0.0);
    h.u1 = std::min(h.u1, length);
    h.v0 = std::max(h.v0, 0.0);
    h.v1 = std::min(h.v1, height);
    if (h.u1 > h.u0 && h.v1 > h.v0) holes.push_back(h);
  }
  std::vector<double> xs{0.0, length};
  for (const auto& h : holes) {
    xs.push_back(h.u0);
    xs.push_back(h.u1);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  const std::size_t ns = xs.size() - 1;
  // Solid v-intervals of each strip.
  std::vector<std::vector<std::pair<double, double>>> solid(ns);
  for (std::size_t s = 0; s < ns; ++s) {
    const double mid = 0.5 * (xs[s] + xs[s + 1]);
    std::vector<std::pair<double, double>> cuts;
    for (const auto& h : holes)
      if (h.u0 < mid && mid < h.u1) cuts.emplace_back(h.v0, h.v1);
    std::sort(cuts.begin(), cuts.end());
    double v = 0.0;
    for (const auto& [c0, c1] : cuts) {
      if (c0 > v) solid[s].emplace_back(v, c0);
      v = std::max(v, c1);
    }
    if (v < height) solid[s].emplace_back(v, height);
  }
  // Vertices on each vertical line: endpoints of the intervals of the strips on either side.
  std::vector<std::vector<double>> line_v(xs.size());
  for (std::size_t s = 0; s < ns; ++s) {
    for (const auto& [a, b] : solid[s]) {
      for (std::size_t l : {s, s + 1}) {
        line_v[l].push_back(a);
        line_v[l].push_back(b);
      }
    }
  }
  for (auto& lv : line_v) {
    std::sort(lv.begin(), lv.end());
    lv.erase(std::unique(lv.begin(), lv.end()), lv.end());
  }
  for (std::size_t s = 0; s < ns; ++s) {
    for (const auto& span : solid[s]) {
      const double va = span.first, vb = span.second;  // a lambda captures no structured binding
      auto chain = [&](std::size_t l) {
        std::vector<int> ids;
        for (double v : line_v[l]) {
          if (v < va || v > vb) continue;
          ids.push_back(static_cast<int>(points->size()));
          points->emplace_back(xs[l], v);
        }
        return ids;
      };
      const std::vector<int> left = chain(s), right = chain(s + 1);
      std::size_t i = 0, j = 0;
      while (i + 1 < left.size() || j + 1 < right.size()) {
        const bool advance_left =
            i + 1 < left.size() &&
            (j + 1 >= right.size() || (*points)[left[i + 1]].y() <= (*points)[right[j + 1]].y());
        if (advance_left) {
          triangles->emplace_back(left[i], right[j], left[i + 1]);
          ++i;
        } else {
          triangles->emplace_back(left[i], right[j], right[j + 1]);
          ++j;
        }
      }
    }
  }
}

int PartBuilder::AddVertex(const Vector3d& p) {
  part_->positions.push_back(p.cast<float>());
  return static_cast<int>(part_->positions.size()) - 1;
}

void PartBuilder::AddTriangle(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const int i = AddVertex(a), j = AddVertex(b), k = AddVertex(c);
  part_->triangles.emplace_back(i, j, k);
}

void PartBuilder::AddQuad(const Vector3d& a, const Vector3d& b, const Vector3d& c,
                          const Vector3d& d) {
  const int i = AddVertex(a), j = AddVertex(b), k = AddVertex(c), l = AddVertex(d);
  part_->triangles.emplace_back(i, j, k);
  part_->triangles.emplace_back(i, k, l);
}

void PartBuilder::AddBox(const Eigen::Isometry3d& X_WB, const Vector3d& lo, const Vector3d& hi,
                         int skip) {
  auto P = [&](int x, int y, int z) {
    return X_WB * Vector3d(x ? hi.x() : lo.x(), y ? hi.y() : lo.y(), z ? hi.z() : lo.z());
  };
  if (!(skip & 1)) AddQuad(P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0));   // -x
  if (!(skip & 2)) AddQuad(P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1));   // +x
  if (!(skip & 4)) AddQuad(P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1));   // -y
  if (!(skip & 8)) AddQuad(P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0));   // +y
  if (!(skip & 16)) AddQuad(P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0));  // -z
  if (!(skip & 32)) AddQuad(P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1));  // +z
}

void PartBuilder::AddPrism(const Polygon2& poly, double z0, double z1, bool caps) {
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector2d& a = poly[i];
    const Vector2d& b = poly[(i + 1) % n];
    AddQuad(Vector3d(a.x(), a.y(), z0), Vector3d(b.x(), b.y(), z0), Vector3d(b.x(), b.y(), z1),
            Vector3d(a.x(), a.y(), z1));
  }
  if (!caps) return;
  for (const auto& t : TriangulatePolygon(poly)) {
    const Vector2d &a = poly[t[0]], &b = poly[t[1]], &c = poly[t[2]];
    AddTriangle(Vector3d(a.x(), a.y(), z1), Vector3d(b.x(), b.y(), z1), Vector3d(c.x(), c.y(), z1));
    AddTriangle(Vector3d(a.x(), a.y(), z0), Vector3d(c.x(), c.y(), z0), Vector3d(b.x(), b.y(), z0));
  }
}

}  // namespace mopad::scenes
