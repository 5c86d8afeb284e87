#pragma once
// Polygons, robot and world side alike: the one point-in-polygon test, the one point-to-segment
// and point-to-boundary distance, the one triangulation, the one convex hull, the one union of
// tiled polygons, the one half-space clip (2-D or 3-D) and the one area of a 3-D polygon of
// the tree.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace mopad {

/// True when `p` lies inside the simple polygon `polygon` (any winding, even-odd rule; points
/// exactly on an edge may go either way). An empty polygon contains nothing.
inline bool PointInPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

/// Squared distance (m^2) from `p` to the segment [a, b]: to the orthogonal projection of `p`
/// clamped to the segment, to `a` when a == b. For comparisons against a squared radius.
inline double SquaredDistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

/// Distance (m) from `p` to the segment [a, b] (to `a` when a == b).
inline double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                const Eigen::Vector2d& b) {
  return std::sqrt(SquaredDistanceToSegment(p, a, b));
}

/// Distance (m) from `p` to the boundary of the closed polygon `polygon` (its edges, the last
/// vertex joined to the first), inside or outside alike; infinity for an empty polygon.
inline double DistanceToBoundary(const Eigen::Vector2d& p,
                                 const std::vector<Eigen::Vector2d>& polygon) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i)
    best = std::min(best, SquaredDistanceToSegment(p, polygon[i], polygon[(i + 1) % n]));
  return std::sqrt(best);
}

/// Triangles (vertex indices) of the simple counter-clockwise polygon `poly` by ear clipping
/// (Meisters 1975; O(n^2), for small polygons); collinear vertices give no triangle.
/// std::invalid_argument when the polygon is not simple.
std::vector<Eigen::Vector3i> TriangulatePolygon(const std::vector<Eigen::Vector2d>& poly);

/// Signed area (m^2) of `poly`: positive when counter-clockwise.
double SignedArea(const std::vector<Eigen::Vector2d>& poly);

/// Newell's vector of the 3-D polygon `poly`: the sum over its edges of p_i x p_(i+1). For a
/// planar polygon it is normal to the plane, points to the side the polygon is seen
/// counter-clockwise from, and its length is twice the area (m^2). Zero for fewer than 3
/// vertices. Robust to non-convex and slightly non-planar polygons (Sutherland, Sproull &
/// Schumacker 1974, crediting M. Newell).
Eigen::Vector3d NewellVector(const std::vector<Eigen::Vector3d>& poly);

/// Area (m^2) of the planar 3-D polygon `poly`, any winding: half the length of its Newell
/// vector. 0 for fewer than 3 vertices.
double PolygonArea3d(const std::vector<Eigen::Vector3d>& poly);

/// Convex hull of plan points (Andrew's monotone chain, 1979): counter-clockwise, starting at the
/// lowest-x (then lowest-y) point. A point where the hull turns by a cross product
/// (b - a) x (c - a) <= `tolerance` (m^2) is dropped, so collinear points are never hull
/// vertices; points within 1e-12 m of the previous one in (x, y) order are one point. Fewer
/// than 3 distinct points come back as they are (sorted, distinct).
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points,
                                        double tolerance = 0.0);

/// The part of the closed polygon `poly` (2-D or 3-D, any winding) within the half-space
/// a . x <= d (Sutherland-Hodgman): vertices inside kept, each edge crossing the boundary cut
/// there. Empty when nothing of it is inside. (`a` is not deduced: an Eigen expression will do.)
template <class V>
std::vector<V> ClipHalfSpace(const std::vector<V>& poly,
                             const typename std::vector<V>::value_type& a, double d) {
  std::vector<V> out;
  const std::size_t k = poly.size();
  for (std::size_t i = 0; i < k; ++i) {
    const V& p = poly[i];
    const V& q = poly[(i + 1) % k];
    const double dp = a.dot(p) - d, dq = a.dot(q) - d;
    if (dp <= 0.0) out.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0))
      out.push_back(p + dp / (dp - dq) * (q - p));
  }
  return out;
}

/// Removes, one at a time (the shallowest first) and keeping at least 3 vertices, every
/// vertex of the closed polygon `poly` that lies within `tolerance` (m) of the segment joining
/// its two neighbours and between them along it: jogs smaller than `tolerance` in an
/// otherwise straight line. A spike (a vertex beyond its neighbours' span) stays.
void RemoveShallowVertices(std::vector<Eigen::Vector2d>& poly, double tolerance);

/// The boundary of polygons that meet only along shared boundary pieces (vertices within
/// `tolerance`, m, being one point; any winding, polygons with fewer than 3 distinct vertices or
/// no area skipped): their edges, split where another polygon's vertex lies on them, without
/// the pieces two polygons share (met in opposite directions), chained into loops —
/// counter-clockwise for outlines, clockwise for holes, each from its first-met vertex.
struct TiledBoundary {
  enum Problem { kNone, kTouchesItself, kNotClosed };
  std::vector<std::vector<Eigen::Vector2d>> loops;  ///< empty when `problem` is set
  Problem problem = kNone;  ///< a vertex starts two boundary pieces; a chain does not close
  bool overlap = false;     ///< a piece met twice in one direction: polygons overlap
};
TiledBoundary BoundaryOfTiledPolygons(const std::vector<std::vector<Eigen::Vector2d>>& polygons,
                                      double tolerance);

/// The union of simple polygons that tile a region: they meet only along shared boundary
/// pieces (rooms of a building split by a boundary without a wall), vertices within
/// `tolerance` (m) being the same point. Edges are split where another polygon's vertex lies on
/// them, edge pieces shared by two polygons (opposite directions) cancel, and the rest is
/// chained into one counter-clockwise outline without collinear vertices. nullopt when the
/// result is not one simple polygon of the polygons' total area: they overlap, do not all
/// touch, meet only at a point or enclose a hole. Any winding in; O(n^2) in the vertex count.
std::optional<std::vector<Eigen::Vector2d>> UnionOfTiledPolygons(
    const std::vector<std::vector<Eigen::Vector2d>>& polygons, double tolerance = 1e-3);

}  // namespace mopad
