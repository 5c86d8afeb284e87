#pragma once
// The ground-truth sidecar of a scene (scene.truth.json, docs/scene-format.md): everything the
// evaluator compares the robot's models against, listed explicitly — never inferred from mesh
// names. World frame Z-up, metres; angles in the file in degrees (`_deg`), radians in memory.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/door_state.h"
#include "scenes/as_built_params.h"
#include "scenes/element_class.h"

namespace mopad::scenes {

/// Version the generator writes. Version 2 (written by the BIM import when it needs it) adds open
/// passages: connections with door "" between rooms that share a boundary without a wall, and
/// rooms that touch along such a boundary. Readers accept 1 and 2.
inline constexpr int kTruthFormatVersion = 1;
inline constexpr int kTruthFormatVersionPassages = 2;

struct Storey {
  std::string id;
  double elevation = 0.0;  ///< m, floor level in world z
  double height = 3.0;     ///< m, floor-to-floor
};

struct Room {
  std::string id;
  std::string storey;
  std::vector<Eigen::Vector2d> polygon;  ///< CCW plan-view outline of the interior wall faces
  double floor_z = 0.0;                  ///< m
  double ceiling_z = 3.0;                ///< m
};

/// Wall, floor, ceiling or column surface. A wall is one planar interior face of one room
/// (the paper's wall_1A); a column lists one polygon per visible face.
struct StructuralElement {
  std::string id;
  ElementClass element_class = ElementClass::kWall;
  std::vector<std::string> rooms;
  /// Planar outer boundaries in world frame (openings are listed separately, not as holes).
  std::vector<std::vector<Eigen::Vector3d>> polygons;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, pointing into the room
  /// Walls only: local frame. u runs along the wall from `origin` in `u_axis`, v is up (+z).
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();
  double length = 0.0;  ///< m, along u
  double height = 0.0;  ///< m, along v
};

enum class OpeningType { kDoor, kWindow };
using DoorState = mopad::DoorState;  // common/door_state.h

/// The paper's thresholds: open lambda >= 90 deg, semi-open 5 <= lambda < 90, closed < 5.
DoorState DoorStateFromAngle(double lambda_rad);
using mopad::ToString;

struct Opening {
  std::string id;
  OpeningType type = OpeningType::kDoor;
  std::vector<std::string> host_walls;  ///< wall element ids (1 for outer walls, 2 between rooms)
  std::vector<std::string> rooms;       ///< rooms it connects ("" entries are not used)
  /// Rectangle in the first host wall's (u, v) coordinates, metres: [u0, u1] x [v0, v1].
  double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;
  std::vector<Eigen::Vector3d> corners;  ///< the same rectangle in world frame (4, CCW)
  // Doors only:
  std::string hinge_side;      ///< "left" | "right", seen from the swing room
  std::string swing_room;      ///< room the leaf opens into ("" = outside)
  double opening_angle = 0.0;  ///< lambda, rad, [0, pi/2 .. 110 deg]
  DoorState state = DoorState::kClosed;
  Eigen::Vector3d hinge_point = Eigen::Vector3d::Zero();  ///< bottom of the hinge axis, world
  Eigen::Vector3d hinge_axis = Eigen::Vector3d::UnitZ();  ///< unit; +angle opens the leaf
  double leaf_thickness = 0.04;                           ///< m
  // Windows only:
  double sill_height = 0.0;  ///< m above the room floor
};

struct ServiceComponent {
  std::string id;
  std::string bsc_class;  ///< catalogue class, e.g. "socket_x2", "smoke_detector"
  std::string host;       ///< element id of the wall or ceiling it is mounted on
  std::string room;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();   ///< m, world, centre of the visible face's
                                                      ///< footprint on the host surface
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, out of the host surface
  Eigen::Vector3d size = Eigen::Vector3d::Zero();     ///< m: width (along host u), height, depth
};

/// A labelled box: a piece of furniture, or a building detail.
struct FurnitureItem {
  std::string id;
  std::string type;  ///< desk, cabinet, shelf, chair, ...; skirting, duct, poster, ...
  std::string room;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< m, centre of the bounding box
  double yaw = 0.0;                                  ///< rad
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    ///< m, box extents before yaw
};

/// Edge of the room connectivity graph: a door between two rooms ("" = outside), or (format
/// version 2) an open passage between two rooms (door "").
struct RoomConnection {
  std::string door;  ///< opening id; "" = open passage (version 2)
  std::string room_a;
  std::string room_b;
};

struct GroundTruth {
  int format_version = kTruthFormatVersion;
  std::string scene_name;
  std::vector<Storey> storeys;
  std::vector<Room> rooms;
  std::vector<StructuralElement> elements;
  std::vector<Opening> openings;
  std::vector<ServiceComponent> service_components;
  std::vector<FurnitureItem> furniture;
  /// Skirting boards, trims, ducts, pipes, posters, whiteboards (scenes/details_params.h): their
  /// parts are clutter; neither scored nor structure. Written as `details` only when present.
  std::vector<FurnitureItem> details;
  std::vector<RoomConnection> connections;
  /// The building as built departs from the design above by this field (scenes/as_built.h);
  /// written as `as_built` only when enabled. Everything above is the design.
  AsBuiltParams as_built;

  const Room* FindRoom(const std::string& id) const;
  const StructuralElement* FindElement(const std::string& id) const;
  const Opening* FindOpening(const std::string& id) const;
};

/// Reads and validates scene.truth.json; InputError `path: error: ...` on any problem
/// (unknown version, missing fields, dangling ids, non-finite numbers).
GroundTruth ReadGroundTruth(const std::string& path);
/// Writes deterministic, pretty-printed JSON (stable key order, fixed float formatting).
void WriteGroundTruth(const GroundTruth& truth, const std::string& path);

}  // namespace mopad::scenes
