#pragma once
// The structural surfaces of one room, from the truth scene, cut into small area cells: every
// wall, floor, ceiling and column triangle of the room (openings are already holes in the wall
// meshes) is clipped against a square grid laid in its plane. A cell is the part of one grid
// square covered by one planar face of one element. The evaluator's coverage and observability
// figures count these cells' areas.
//
// Which geometry: scene parts whose element_id names a GroundTruth element of a structural class
// (IsStructural) that lists the room; triangles are taken front side only (CCW = the visible
// side: into the room for walls/floors/ceilings, outward for columns).
//
// Grid: each plane has axes u, v (walls: u horizontal, v = +z; floors and ceilings: u = +x,
// v = +y or -y so that (u, v, normal) is right-handed); square k covers
// [i s, (i+1) s) x [j s, (j+1) s) in absolute plane coordinates (u.p, v.p), s = cell_size, so
// cells do not depend on triangulation. World frame, metres. Deterministic; pure functions.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/params.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::evaluation {

struct SurfaceSamplingParams {
  double cell_size = 0.05;  ///< m, side of the square cells, [0.005, 1]
  template <class V>
  void Visit(V& v) {
    v("cell_size", cell_size, Bounds{0.005, 1.0});
  }
};

/// One planar face of an element with its cell grid: cell (i, j) of the plane covers
/// u in [(i0 + i) s, (i0 + i + 1) s), v likewise; `index` maps (j * ni + i) to a cell, -1 = none.
struct SurfacePlane {
  int element = -1;                    ///< index into StructuralSurfaces::elements
  Eigen::Vector3d normal;              ///< unit, visible side
  double offset = 0.0;                 ///< normal . p on the plane, m
  Eigen::Vector3d u_axis, v_axis;      ///< unit, in the plane; u x v = normal
  int i0 = 0, j0 = 0, ni = 0, nj = 0;  ///< grid window in cell units
  std::vector<std::int32_t> index;     ///< ni * nj, cell index or -1
};

struct SurfaceCell {
  Eigen::Vector3d centre;     ///< m, world: area centroid of the covered part (on the surface)
  Eigen::Vector3d normal;     ///< unit, visible side
  double area = 0.0;          ///< m^2, covered part of the square
  std::int32_t element = -1;  ///< index into StructuralSurfaces::elements
  std::int32_t plane = -1;    ///< index into StructuralSurfaces::planes
  scenes::ElementClass element_class = scenes::ElementClass::kUnknown;
};

struct SurfaceElement {
  std::string id;
  scenes::ElementClass element_class = scenes::ElementClass::kUnknown;
  double area = 0.0;  ///< m^2, sum of its triangles
};

struct StructuralSurfaces {
  std::string room;
  double cell_size = 0.05;
  double floor_z = 0.0;                  ///< m, from the truth room
  std::vector<SurfaceElement> elements;  ///< in GroundTruth::elements order
  std::vector<SurfacePlane> planes;
  std::vector<SurfaceCell> cells;  ///< plane by plane, row-major (v then u) inside a plane

  double TotalArea() const;  ///< m^2, sum of cell areas (= the triangles' area, less float slivers
                             ///< below 1e-4 of a cell along hole edges)
  /// Cell containing world point p (projected on the plane within `tolerance` m of it), or -1.
  /// The lowest plane index wins when several planes qualify.
  std::int32_t FindCell(const Eigen::Vector3d& p_W, double tolerance) const;
};

/// Samples room `room`'s structural surfaces. InputError for an unknown room or a room without
/// structural geometry. A scene built off its design (truth `as_built`, scenes/as_built.h) is
/// sampled on its design surfaces: each vertex taken back through the field (p - D(p), to
/// micrometres), so a wall is one plane of cells as in the design; the as-built surfaces lie
/// within millimetres of them, inside the coverage's distance tolerance.
StructuralSurfaces SampleStructuralSurfaces(const scenes::Scene& scene,
                                            const scenes::GroundTruth& truth,
                                            const std::string& room,
                                            const SurfaceSamplingParams& params = {});

}  // namespace mopad::evaluation
