#pragma once
// Sloped ceilings (a roof's underside over an attic) in plan: which of a room's ceiling planes is
// the ceiling where, and where a wall face under them ends. One home for the import's truth
// (scenes/bim_sloped_ceilings.cpp) and the robot's SM3 (modelling/structural_model.cpp).
// World frame Z-up, metres.

#include <Eigen/Core>
#include <vector>

namespace mopad {

/// One ceiling plane: n . x = c, n unit and facing down into the room (n.z() < 0).
struct CeilingPlane {
  Eigen::Vector3d n = -Eigen::Vector3d::UnitZ();
  double c = 0.0;
  /// m, the plane's height over plan point p.
  double ZAt(const Eigen::Vector2d& p) const { return (c - n.x() * p.x() - n.y() * p.y()) / n.z(); }
};

/// Per plane, the part of the CCW plan polygon `plan` where it is the lowest of `planes` (planes
/// parallel in plan do not cut each other) and, when `hulls` is given (one CCW convex polygon
/// per plane, or an empty one for none), within its hull. An empty polygon where a plane is
/// nowhere the lowest over more than `min_area` m^2. Sutherland-Hodgman clipping: exact for a
/// convex `plan`; a concave one keeps zero-width bridges between disjoint parts.
std::vector<std::vector<Eigen::Vector2d>> LowestCeilingRegions(
    const std::vector<Eigen::Vector2d>& plan, const std::vector<CeilingPlane>& planes,
    const std::vector<std::vector<Eigen::Vector2d>>* hulls, double min_area);

/// A vertical wall face whose foot runs from `foot` along the unit plan direction `dir` for
/// `length` m, `height` m high from `z0`, ended under the ceilings: along the foot, the top is
/// the lowest plane whose region (LowestCeilingRegions) holds the foot 1 cm towards `inward`,
/// else `height`. The face's outline in its own (u, v) — (0, 0), the top from u = 0 to
/// `length`, (length, 0) — or empty when no plane comes under `height`.
std::vector<Eigen::Vector2d> WallUnderCeilings(
    const Eigen::Vector2d& foot, const Eigen::Vector2d& dir, const Eigen::Vector2d& inward,
    double length, double z0, double height, const std::vector<CeilingPlane>& planes,
    const std::vector<std::vector<Eigen::Vector2d>>& regions);

}  // namespace mopad
