#pragma once
// Plain geometric types shared by the evaluation metrics, and the polygon
// helpers they rest on. The metrics themselves live in metrics_patches.h (SM3 detection,
// d_v, d_h, Phi), metrics_isprs.h (ISPRS completeness/correctness/accuracy),
// metrics_floorplan.h (room IoU, corners, angles) and metrics_voxels.h (DSM3 / SM1 confusion);
// definitions: ../shared/reference/metrics.md and docs in each header.
//
// These types deliberately do not use scenes::ElementClass or any model type, so the metrics are
// pure functions on plain geometry; callers convert truth and model data into them.
// World frame Z-up (REP-103), metres. Bad input throws mopad::InputError.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "common/polygon.h"

namespace mopad::evaluation {

/// Classes of the structural surfaces the metrics report on (paper §4: SM3 per class).
enum class SurfaceClass : std::uint8_t { kWall = 0, kFloor = 1, kCeiling = 2, kColumn = 3 };
inline constexpr int kNumSurfaceClasses = 4;
/// "wall", "floor", "ceiling", "column".
const char* SurfaceClassName(SurfaceClass c);
/// All classes in enum order (for loops and tables).
const std::array<SurfaceClass, kNumSurfaceClasses>& AllSurfaceClasses();

/// A planar patch of a model or of the truth: a closed simple polygon (first vertex not
/// repeated), planar, counter-clockwise seen from the tip of `normal`. `normal` need not be unit
/// length (it is normalised on use) but must agree with the winding.
struct Patch {
  std::string id;  ///< e.g. "wall_1A"; used in reports only
  SurfaceClass cls = SurfaceClass::kWall;
  std::vector<Vec3> polygon;    ///< world frame, m
  Vec3 normal = Vec3::UnitZ();  ///< world frame
};

/// `patch` moved by the rigid transform `X` (e.g. X_WM: a model's map frame into the world).
Patch Transformed(const Patch& patch, const Pose3& X);

struct PatchValidationParams {
  double planarity_tolerance = 1e-3;  ///< m, max vertex distance from the patch plane, (0, 1]
  double min_area = 1e-6;             ///< m^2, smaller polygons are rejected, (0, 1]
  template <class V>
  void Visit(V& v) {
    v("planarity_tolerance", planarity_tolerance, Bounds{1e-9, 1.0});
    v("min_area", min_area, Bounds{1e-12, 1.0});
  }
};

/// Throws InputError (naming `what`, e.g. "model patch 'wall_1A'") when the patch has < 3
/// vertices, a non-finite coordinate or normal, a zero normal, vertices off its plane by more
/// than the tolerance, an area below min_area, or clockwise winding seen from its normal.
void ValidatePatch(const Patch& patch, const PatchValidationParams& params,
                   const std::string& what);

/// "kind index 'id'" (e.g. "model patch 3 'wall_1A'"), the subject of InputError messages.
std::string NameOf(const std::string& kind, std::size_t index, const std::string& id);

/// An orthonormal right-handed frame (u, v, n) on a patch plane: origin = vertex centroid.
/// For non-horizontal planes u is horizontal and v points upward along the plane; for
/// horizontal planes (|n.z| >= 0.9) u is +x projected. A CCW polygon seen from n is CCW in (u, v).
struct PlaneFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitY(), n = Vec3::UnitZ();
  static PlaneFrame Of(const Patch& patch);
  Vec2 To2d(const Vec3& p) const { return {u.dot(p - origin), v.dot(p - origin)}; }
  Vec3 To3d(const Vec2& q) const { return origin + q.x() * u + q.y() * v; }
  double SignedDistance(const Vec3& p) const { return n.dot(p - origin); }
};

// ---- 2D polygon helpers (simple polygons, any winding unless stated) ----

// SignedArea, PolygonArea3d, DistanceToBoundary and ConvexHull: common/polygon.h.
/// Exact area of the intersection of two simple polygons (convex or not, either winding):
/// both are ear-clipped into triangles and the triangle pairs clipped (Sutherland-Hodgman).
double IntersectionArea(const std::vector<Vec2>& a, const std::vector<Vec2>& b);
/// Intersection over union of two simple polygons (0 when both are degenerate).
double PolygonIoU(const std::vector<Vec2>& a, const std::vector<Vec2>& b);
/// Drops repeated vertices and vertices whose two edges turn by less than `angle_tol` (rad):
/// a wall split into collinear pieces keeps one edge per side.
std::vector<Vec2> SimplifyPolygon(const std::vector<Vec2>& polygon, double angle_tol);
std::vector<Vec3> SimplifyPolygon3d(const std::vector<Vec3>& polygon, double angle_tol);
/// Ear-clipping triangulation (Meisters 1975) for the area metrics; triangles as vertex triples.
/// Repeated and straight vertices are dropped first (SimplifyPolygon) and the polygon made CCW;
/// a vertex that a clipped ear leaves straight stays and is clipped later. Any winding, and
/// never throws: what is left of a polygon that is not simple (a robot's outline may touch
/// itself) is finished as a fan. Not common's TriangulatePolygon, which drops vertices left
/// straight and throws on such polygons: the two make different triangles, so the intersection
/// areas (and every IoU the reports print) would change in their last bits, and a metric would
/// throw where it now scores.
std::vector<std::array<Vec2, 3>> Triangulate(const std::vector<Vec2>& polygon);

/// Mean, maximum and count of a set of non-negative errors (mean = max = 0 when n = 0).
struct ErrorStats {
  int n = 0;
  double sum = 0.0;
  double mean = 0.0;
  double max = 0.0;
  void Add(double x);
  /// Adds another set's count, sum and max (mean over the union).
  void Merge(const ErrorStats& other);
};

}  // namespace mopad::evaluation
