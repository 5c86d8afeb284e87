#pragma once
// The procedural scene specification (docs/scene-spec.md): a YAML description of one office
// storey — rooms as plan polygons, doors, windows, columns, furniture and building service
// components (BSCs) — from which scenes::Generate builds the geometry and its exact ground
// truth. World frame Z-up, metres; angles in the file in degrees (`_deg`). Loading rejects
// unknown keys and wrong types with `file:line: error: ...`; every item remembers where it was
// declared (`where`) so that geometric errors found later (a door not on a shared wall) point
// at the right line too.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scenes/as_built_params.h"
#include "scenes/details_params.h"

namespace YAML {
class Node;
}

namespace mopad::scenes {

using Rgb = std::array<double, 3>;  ///< linear RGB, each in [0, 1]

/// Surface appearance of one class of geometry (a glTF PBR material).
struct MaterialSpec {
  Rgb colour{0.8, 0.8, 0.8};      ///< linear RGB, [0, 1]
  double roughness = 0.9;         ///< [0, 1]
  double metallic = 0.0;          ///< [0, 1]
  double transmission = 0.0;      ///< [0, 1], laser pass-through probability (glass)
  double nir_reflectance = -1.0;  ///< [0, 1] at the scanner wavelength; < 0 = from colour
};

/// Default appearance per class; doors may override frame and leaf colours.
struct MaterialsSpec {
  MaterialSpec wall{{0.86, 0.85, 0.80}, 0.9, 0.0, 0.0, -1.0};
  MaterialSpec floor{{0.35, 0.33, 0.30}, 0.8, 0.0, 0.0, -1.0};
  MaterialSpec ceiling{{0.90, 0.90, 0.90}, 0.9, 0.0, 0.0, -1.0};
  MaterialSpec column{{0.75, 0.75, 0.73}, 0.9, 0.0, 0.0, -1.0};
  MaterialSpec facade{{0.60, 0.55, 0.50}, 0.9, 0.0, 0.0, -1.0};
  MaterialSpec door_frame{{0.25, 0.25, 0.27}, 0.5, 0.3, 0.0, -1.0};
  MaterialSpec door_leaf{{0.45, 0.28, 0.15}, 0.6, 0.0, 0.0, -1.0};
  MaterialSpec window_frame{{0.85, 0.85, 0.85}, 0.5, 0.0, 0.0, -1.0};
  MaterialSpec glass{{0.80, 0.90, 0.95}, 0.05, 0.0, 0.9, -1.0};
  MaterialSpec desk{{0.60, 0.45, 0.30}, 0.6, 0.0, 0.0, -1.0};
  MaterialSpec cabinet{{0.50, 0.52, 0.55}, 0.5, 0.2, 0.0, -1.0};
  MaterialSpec shelf{{0.70, 0.62, 0.48}, 0.7, 0.0, 0.0, -1.0};
  MaterialSpec chair{{0.15, 0.20, 0.35}, 0.7, 0.0, 0.0, -1.0};
};

struct RoomSpec {
  std::string id;
  std::vector<Eigen::Vector2d> polygon;  ///< CCW interior wall-face outline, m, >= 3 vertices
  double ceiling_height = 0.0;           ///< m above the floor; 0 = SceneSpec::ceiling_height
  std::string where;                     ///< "file:line" of the declaration
};

/// Where an opening sits on a wall: either a plan point near the wall (`at`, the opening's
/// centre is its projection on the nearest suitable wall) or an edge index of the room's
/// polygon plus the distance of the opening's centre from the edge's start vertex.
struct WallPosition {
  bool has_at = false;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  ///< m, plan point
  int wall = -1;                                 ///< edge i runs from vertex i to i+1
  double offset = 0.0;                           ///< m, centre along edge `wall`
};

struct DoorSpec {
  std::string id;
  std::string room_a;  ///< first room (hosts `wall` / is searched with `at`)
  std::string room_b;  ///< second room, or "outside"
  WallPosition position;
  double width = 0.9;              ///< m, clear opening width, [0.5, 3]
  double height = 2.1;             ///< m, [1.5, ceiling - 0.1]
  double frame_width = 0.08;       ///< m, casing width on the wall face, [0.01, 0.3]
  double frame_protrusion = 0.02;  ///< m, casing protrusion from the wall face, [0.002, 0.1]
  double leaf_thickness = 0.04;    ///< m, [0.01, 0.1]
  bool has_frame_colour = false;
  Rgb frame_colour{0, 0, 0};
  bool has_leaf_colour = false;
  Rgb leaf_colour{0, 0, 0};
  std::string hinge = "left";  ///< "left" | "right", seen from the swing room
  std::string swing_into;      ///< room the leaf opens into; "" = room_a
  double angle_deg = 0.0;      ///< opening angle lambda, [0, 110]; 0 = closed
  std::string where;
};

struct WindowSpec {
  std::string id;
  std::string room;
  WallPosition position;           ///< must be on an outer wall
  double width = 1.2;              ///< m, [0.3, 6]
  double height = 1.2;             ///< m, [0.3, 3]
  double sill_height = 0.9;        ///< m above the floor, [0, 2.5]
  double frame_width = 0.06;       ///< m, frame bar / casing width, [0.01, 0.2]
  double frame_protrusion = 0.01;  ///< m, casing protrusion from the wall face, [0.002, 0.1]
  double transmission = -1.0;      ///< glass transmission [0, 1]; < 0 = materials.glass
  std::string where;
};

struct ColumnSpec {
  std::string id;
  std::string room;
  std::string shape = "rect";                          ///< "rect" | "round"
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, plan centre
  Eigen::Vector2d size{0.4, 0.4};                      ///< m, rect width (x) and depth (y)
  double radius = 0.2;                                 ///< m, round
  int segments = 16;                                   ///< round: facets, [6, 64]
  double yaw_deg = 0.0;                                ///< rect: rotation about z
  std::string where;
};

/// Furniture: `count` items of `type` placed by the seed, or one item at `position`.
struct FurnitureSpec {
  std::string room;
  std::string type;  ///< desk | cabinet | shelf | chair
  int count = 1;     ///< [1, 200], random placement when has_position is false
  bool has_position = false;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< m, plan centre
  double yaw_deg = 0.0;
  std::string where;
};

/// Building service components: `count` instances of `class_name` placed by a rule, or one
/// explicit instance (wall: room + wall + u; ceiling: room + position).
struct BscSpecEntry {
  std::string class_name;          ///< catalogue class (scenes/bsc_catalogue.h)
  int count = 1;                   ///< [1, 500]
  std::vector<std::string> rooms;  ///< rooms to spread over; empty = all rooms
  /// wall | ceiling | beside_door | under_window | above_door | above; "" = wall or ceiling
  /// from the catalogue's mounting. `above` stacks each instance over one of class `above`.
  std::string placement;
  std::string above;     ///< target class for placement `above`
  double height = -1.0;  ///< m, centre above floor; < 0 = catalogue default
  // Explicit placement:
  bool is_explicit = false;
  std::string room;
  int wall = -1;   ///< edge index of `room`
  double u = 0.0;  ///< m, centre along the edge from its start vertex
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< ceiling: plan point
  std::string where;
};

struct SceneSpec {
  std::string name = "scene";
  std::uint64_t seed = 1;       ///< drives furniture and rule-based BSC placement
  double storey_height = 3.0;   ///< m, floor-to-floor, [2, 10]
  double ceiling_height = 2.8;  ///< m, default room height, [2, storey_height]
  double wall_thickness = 0.2;  ///< m, between rooms and of outer walls, [0.05, 1]
  MaterialsSpec materials;
  std::vector<RoomSpec> rooms;
  std::vector<DoorSpec> doors;
  std::vector<WindowSpec> windows;
  std::vector<ColumnSpec> columns;
  std::vector<FurnitureSpec> furniture;
  std::vector<BscSpecEntry> bscs;
  /// The building as built departs from this design (scenes/as_built.h); off by default.
  AsBuiltParams as_built;
  /// Skirting, trims, ducts, pipes, posters, frames in the wall's colour, glazed doors
  /// (scenes/details_params.h); none by default.
  DetailsParams details;
  std::string source;  ///< file it came from (for messages), or a generator name

  const RoomSpec* FindRoom(const std::string& id) const;
};

/// Reads and validates a spec file; InputError `file:line: error: ...` on any problem.
SceneSpec LoadSceneSpec(const std::string& path);
/// Parses a spec from YAML text; `name` is used as the file name in messages.
SceneSpec ParseSceneSpec(const std::string& yaml_text, const std::string& name);
/// Checks ranges, id uniqueness, references and polygon validity (simple, CCW, rooms
/// disjoint). Throws InputError at the offending item's `where`. Placement on walls is checked
/// by Generate, which needs the wall adjacency.
void ValidateSceneSpec(const SceneSpec& spec);
/// The effective spec as YAML (every field, defaults filled in); ParseSceneSpec reads it back
/// to an equal spec.
std::string SceneSpecToYaml(const SceneSpec& spec);

}  // namespace mopad::scenes
