#pragma once
// Plane polygons, robot and world side alike: the one point-in-polygon test, the one
// point-to-segment distance, the one triangulation and the one union of tiled polygons of the tree.

#include <Eigen/Core>
#include <algorithm>
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

/// Distance (m) from `p` to the segment [a, b] (a point when a == b).
inline double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(1e-12, ab.squaredNorm()), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

/// Triangles (vertex indices) of the simple counter-clockwise polygon `poly` by ear clipping
/// (Meisters 1975; O(n^2), for small polygons); collinear vertices give no triangle.
/// std::invalid_argument when the polygon is not simple.
std::vector<Eigen::Vector3i> TriangulatePolygon(const std::vector<Eigen::Vector2d>& poly);

/// Signed area (m^2) of `poly`: positive when counter-clockwise.
double SignedArea(const std::vector<Eigen::Vector2d>& poly);

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
