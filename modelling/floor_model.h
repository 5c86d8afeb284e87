#pragma once
// The floor model (beyond the paper, which models rooms apart): the rooms'
// SM3 and SM4, all in the one map frame of the floor mission, joined into one floor-level
// SM3/SM4.
//
// Walls. Two wall faces of different rooms are the two faces of one wall when they are
// antiparallel (horizontal normals within max_angle_deg of opposite), back to back (each lies
// behind the other's plane, i.e. against its normal, which points into its room) at a distance
// in [min_thickness, max_thickness] measured at the middle of their overlap, and overlap along
// the wall and in height by at least min_overlap. Faces joined by such pairs (a hall's wall
// may face two offices) form one FloorWall: its normal is the length-weighted mean of its
// faces' horizontal normals, oriented along the first face's (side +1; faces against it are
// side -1); its thickness is the distance between the length-weighted mean offsets of its +1
// and -1 faces along that normal; its plane is the axis (mid-)plane; its extent the union of
// its faces along the wall and in height. A face without a partner is a wall of its own with
// unknown thickness (NaN): its plane and polygon are the face's own, and only its room's side
// is known.
//
// Openings. Each room's SM4 opening belongs to the floor wall holding its host face. Two doors
// of different rooms on opposite faces of one wall whose u-intervals (along the wall) overlap by
// at least min_door_overlap of the narrower are one door seen from both rooms (pairs taken
// greedily, largest overlap share first). Its state, opening angle, clear width, confidence and
// rectangle come from the better-observed side: the side that saw the leaf (a finite opening
// angle) over one that did not, then the higher SM4 confidence, then the room listed first. Its
// corners are that side's hole moved onto the wall's axis plane. Other openings (windows, doors
// seen from one side) are kept with their one room, corners on the wall's plane.
//
// Floors, ceilings and columns are kept per room as they are.
//
// Robot side: input is the robot's own SM3/SM4 (map frame); nothing here reads the truth.
// Deterministic: rooms, faces and openings are taken in input order; no unordered container.

#include <limits>
#include <string>
#include <vector>

#include "common/params.h"
#include "modelling/openings.h"
#include "modelling/structural_model.h"

namespace mopad::modelling {

struct FloorModelParams {
  double max_angle_deg = 5.0;   ///< deg, two faces of a wall are antiparallel within this, [0, 30]
  double min_thickness = 0.05;  ///< m, thinnest wall whose faces are joined, [0, 1]
  double max_thickness = 0.5;   ///< m, thickest wall whose faces are joined, (0, 2]
  /// m, the two faces overlap along the wall and in height by at least this, [0, 10]
  double min_overlap = 0.3;
  /// share of the narrower door's width that two sides' doors overlap along the wall, (0, 1]
  double min_door_overlap = 0.5;

  template <class V>
  void Visit(V& v) {
    v("max_angle_deg", max_angle_deg, Bounds{0.0, 30.0});
    v("min_thickness", min_thickness, Bounds{0.0, 1.0});
    v("max_thickness", max_thickness, Bounds{1e-3, 2.0});
    v("min_overlap", min_overlap, Bounds{0.0, 10.0});
    v("min_door_overlap", min_door_overlap, Bounds{1e-3, 1.0});
  }
  /// InputError naming the field for a value out of range or min_thickness > max_thickness.
  void Validate() const;
};

/// One room's wall patch as a face of a floor wall.
struct WallFace {
  std::string room;       ///< the room's name (its SM3 `room`)
  StructuralPatch patch;  ///< the room's wall patch, unchanged (map frame)
  int side = 1;           ///< +1: the face's normal is along the wall's normal; -1: against it
};

/// Two faces (indices into FloorWall::faces) found to be the two faces of the wall.
struct WallFacePair {
  int a = -1, b = -1;
  double thickness = 0.0;  ///< m, between the two face planes at the middle of their overlap
  double overlap = 0.0;    ///< m, along the wall
};

struct FloorWall {
  std::string id;  ///< "wall_1", ... in the order of each wall's first face
  std::vector<WallFace> faces;
  std::vector<WallFacePair> pairs;
  /// m; NaN: one face only (the other side unseen, or an outer wall)
  double thickness = std::numeric_limits<double>::quiet_NaN();
  /// Two-sided: the axis plane, n horizontal along the side +1 faces' normals. One face: the
  /// face's own plane.
  Plane plane;
  /// Two-sided: the wall's extent on its axis plane (union along the wall, lowest to highest
  /// face point), CCW seen from the tip of n. One face: the face's polygon.
  std::vector<Vec3> polygon;
  bool TwoSided() const { return faces.size() > 1; }
};

/// An opening of the floor: one per hole, seen from one room or from both.
struct FloorOpening {
  /// The opening as the floor holds it: id "opening_<k>", host = the FloorWall id, corners on
  /// the wall's plane; type, state, angle, clear width and confidence of the chosen side.
  DetectedOpening opening;
  std::vector<std::string> rooms;      ///< the rooms that saw it; the chosen side first
  std::vector<DetectedOpening> sides;  ///< each room's own SM4 opening, same order as rooms
};

struct FloorModel {
  /// Per room, in input order: its floor, ceiling and column patches (no walls, no adjacency).
  std::vector<StructuralModel> rooms;
  std::vector<FloorWall> walls;
  std::vector<FloorOpening> openings;  ///< by wall, then along the wall
};

/// Joins the rooms' models (see the file comment). `sm4` may list fewer rooms than `sm3`
/// (matched by `room`). InputError for bad params, an empty or duplicate room name, an SM4 of
/// a room without SM3, an opening whose host is not a wall of its room, a wall patch that is
/// not vertical or has fewer than 3 vertices.
FloorModel BuildFloorModel(const std::vector<StructuralModel>& sm3,
                           const std::vector<Sm4Model>& sm4, const FloorModelParams& params = {});

/// One door, one state, on both faces (beyond the paper, which models rooms apart). For each
/// door of `floor`:
///  - seen from two rooms: the chosen (better observed) side's state, opening angle and clear
///    width go to the other room's opening in `sm4` (matched by room and opening id), which
///    keeps its own reading in own_* and names the chosen room in state_from; unless both give
///    the same state and this room measured the leaf too (or neither did): that reading
///    stands. The side a leaf swung away from often sees no leaf (only a reveal at a grazing
///    angle, or the doorway from afar); the room it swung into sees it whole.
///  - seen from one room, on a two-faced wall whose other face (another room's wall patch)
///    spans the door's width and height within `tolerance` (m) and holds no opening
///    overlapping it: a hole through a wall is on both faces, so that room gets the door (its
///    corners moved onto its face, counter-clockwise seen from it; found_from names the room
///    that found it; id after the room's last). A leaf opened into a room can hide its own
///    doorway from that room.
/// Returns the rooms (names, in `sm4` order) whose SM4 changed.
std::vector<std::string> ShareDoors(const FloorModel& floor, std::vector<Sm4Model>& sm4,
                                    double tolerance = 0.05);

}  // namespace mopad::modelling
