#pragma once
// Small computational-geometry helpers for the scene generator: plan-view polygons (area,
// orientation, simplicity, containment, ear-clipping triangulation), rectangles with
// rectangular holes (wall faces with openings) and a MeshPart builder for quads, boxes and
// prisms. Units metres; plan-view polygons are in the world x-y plane; all functions are pure.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "common/polygon.h"
#include "scenes/scene.h"

namespace mopad::scenes {

using Polygon2 = std::vector<Eigen::Vector2d>;

using mopad::SignedArea;  // positive for counter-clockwise vertex order, m^2
/// True if the polygon has >= 3 vertices, non-zero area, no repeated vertices, no zero-length
/// edges and no two non-adjacent edges that touch or cross. `why` (optional) says what failed.
bool IsSimplePolygon(const Polygon2& poly, std::string* why = nullptr);
using mopad::PointInPolygon;

using mopad::DistanceToBoundary;  // m, to the closed polygon's edges, inside or outside
/// True if closed segments [a, b] and [c, d] share a point.
bool SegmentsIntersect(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                       const Eigen::Vector2d& d);
/// True if the interiors of two simple polygons overlap or their boundaries touch.
bool PolygonsIntersect(const Polygon2& a, const Polygon2& b);
/// True if polygon `inner` lies inside `outer` (no boundary contact).
bool PolygonInside(const Polygon2& inner, const Polygon2& outer);
/// True if two convex polygons overlap (separating-axis test; touching counts as overlap).
bool ConvexOverlap(const Polygon2& a, const Polygon2& b);

using mopad::TriangulatePolygon;

/// Axis-aligned rectangle in a face's (u, v) coordinates, metres.
struct Rect2 {
  double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;
  bool Overlaps(const Rect2& o, double margin = 0.0) const {
    return u0 < o.u1 + margin && o.u0 < u1 + margin && v0 < o.v1 + margin && o.v0 < v1 + margin;
  }
  Rect2 Expanded(double m) const { return {u0 - m, u1 + m, v0 - m, v1 + m}; }
};

/// Triangulates [0, length] x [0, height] minus non-overlapping rectangular holes (holes are
/// clipped to the face). Vertical strips between hole edges, each solid interval joined to its
/// neighbours' vertices, so the mesh has no T-junctions (watertight for ray casting). Output
/// (u, v) points and triangles CCW in (u, v).
void TriangulateRectWithHoles(double length, double height, const std::vector<Rect2>& holes,
                              std::vector<Eigen::Vector2d>* points,
                              std::vector<Eigen::Vector3i>* triangles);

/// Appends geometry to a MeshPart (positions are converted to float once, here).
class PartBuilder {
 public:
  explicit PartBuilder(MeshPart* part) : part_(part) {}
  int AddVertex(const Eigen::Vector3d& p);
  /// Triangle with front face CCW.
  void AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
  /// Planar quad a-b-c-d, CCW seen from the front.
  void AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
               const Eigen::Vector3d& d);
  /// Box [lo, hi] in the frame X_WB, faces outward. `skip` bit mask: 1 -x, 2 +x, 4 -y, 8 +y,
  /// 16 -z, 32 +z faces are left out (hidden against another surface).
  void AddBox(const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
              int skip = 0);
  /// Vertical prism over a CCW plan polygon from z0 to z1 (world frame), faces outward.
  void AddPrism(const Polygon2& poly, double z0, double z1, bool caps);

 private:
  MeshPart* part_;
};

}  // namespace mopad::scenes
