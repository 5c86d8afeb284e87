#pragma once
// The region of interest of a room (paper §3.1 step (4)): the polyhedron enclosing the
// accumulated cloud, kept as a small B-rep (vertices, edges, faces, face adjacency). It is the
// prism of the plan-view perimeter polygon between the floor and ceiling heights, with one
// prism hole per detected column; after the last scan it is the raw SM2 (§3.2).
//
// Frames and units: map frame (REP-105 `map`, z up), metres. Face normals point *out of the
// room's free space* (the usual outward B-rep convention): a wall's normal points into the
// wall, a column face's normal into the column, the floor's down, the ceiling's up.
//
// Every face is rasterised into square cells (RoomModelParams::face_cell) in its own (u, v)
// frame; each cell is off the face, not yet sensed, sensed (structural points fall in it), or
// an opening (beams went through it to something beyond).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/ceiling_planes.h"
#include "common/frames.h"
#include "common/polygon.h"

namespace mopad::modelling {

enum class FaceKind : std::uint8_t { kFloor = 0, kCeiling = 1, kWall = 2, kColumn = 3 };
const char* ToString(FaceKind kind);

/// State of one face cell.
enum class FaceCell : std::uint8_t {
  kOff = 0,       ///< the cell centre is not on the face (outside the polygon, in a hole)
  kUnsensed = 1,  ///< on the face, no structural point in it yet
  kSensed = 2,    ///< structural points fall in it
  kOpening = 3,   ///< beams passed through it to surfaces beyond the room (door, window)
};

struct RoiFace {
  FaceKind kind = FaceKind::kWall;
  int element = -1;       ///< wall: perimeter edge index; column face: column index; else -1
  std::vector<int> loop;  ///< vertex indices, CCW seen from outside (normal)
  std::vector<std::vector<int>> holes;  ///< floor/ceiling: column footprints
  Vec3 normal = Vec3::UnitZ();          ///< unit, outward (away from the room's free space)
  double area = 0.0;                    ///< m^2, exact polygon area (holes removed)
  /// True when the face holds structural-element data: sensed share >= structural_share.
  bool structural = false;
  double sensed_share = 0.0;  ///< sensed cell area / face cell area

  // Raster: cell (iu, iv) covers origin + [iu, iu+1) * cell * u_axis + [iv, iv+1) * cell * v_axis.
  Vec3 origin = Vec3::Zero();
  Vec3 u_axis = Vec3::UnitX(), v_axis = Vec3::UnitZ();  ///< unit, in the face plane
  double cell = 0.1;                                    ///< m
  int nu = 0, nv = 0;
  std::vector<FaceCell> cells;   ///< nu * nv, index iv * nu + iu
  std::vector<float> cell_area;  ///< m^2 of face inside each cell (0 for kOff)

  Vec3 CellCentre(int iu, int iv) const {
    return origin + (iu + 0.5) * cell * u_axis + (iv + 0.5) * cell * v_axis;
  }
  /// Cell containing the projection of `p_M` on the face plane, or -1 outside the raster.
  int CellIndexOf(const Vec3& p_M) const;
};

struct RoiEdge {
  int v0 = -1, v1 = -1;        ///< vertex indices
  int face0 = -1, face1 = -1;  ///< the two faces sharing the edge
};

struct Roi {
  double floor_z = 0.0, ceiling_z = 0.0;   ///< m
  /// Sloped ceilings under or beside the level one (an attic's roof, RoomModel::DetectSlopes),
  /// and whether the level ceiling at ceiling_z is one (false: the roof is the whole ceiling,
  /// ceiling_z its highest point seen).
  std::vector<CeilingPlane> slopes;
  bool level_ceiling = true;
  std::vector<Vec2> perimeter;             ///< plan polygon, CCW (interior wall faces)
  std::vector<std::vector<Vec2>> columns;  ///< column footprints, each CCW
  std::vector<Vec3> vertices;
  std::vector<RoiEdge> edges;
  std::vector<RoiFace> faces;  ///< floor, ceiling, walls (perimeter order), column faces
  std::vector<std::vector<int>> face_adjacency;  ///< per face, sorted neighbour face indices

  bool empty() const { return perimeter.size() < 3; }
  /// m, the ceiling over plan point p: ceiling_z, or the lowest of the slopes (and the level
  /// ceiling, when there is one) there.
  double CeilingAt(const Vec2& p) const;
  /// True if the plan point lies inside the perimeter and outside every column.
  bool ContainsPlan(const Vec2& p) const;
  /// Volume (m^3) of the prism minus the column prisms.
  double Volume() const;
};

}  // namespace mopad::modelling
