#pragma once
// A BIM model (IFC 2x3 through assimp) becomes a scene folder with exact truth
// (docs/scene-import.md): the same scene.glb + scene.truth.json the generator writes.
//
// What comes from where (one storey per import):
//  - rooms: IfcSpace volumes of the storey (footprint = outline of the space's bottom face,
//    floor_z / ceiling_z = its lowest / highest point);
//  - walls: every room polygon edge whose vertical plane carries IfcWall* faces facing the room
//    becomes `wall_<room>_<edge>`; those wall triangles are cut to the room's edge and height
//    and relabelled, so the truth is the geometry's own faces (openings are already cut);
//  - floors / ceilings: upward (downward) slab or covering faces at the room's floor (ceiling)
//    height, cut to the room polygon; missing ones refused or, with floor_from_spaces /
//    ceiling_from_spaces, made from the space footprint;
//  - doors / windows: their hole in the room-side wall faces (measured on the geometry around
//    the element's centre); a door's BIM geometry is replaced by a generated leaf hinged at the
//    hole's jamb and opened to the requested angle (BIM draws doors closed); windows keep their
//    geometry (glass = transmissive materials);
//  - service components (IfcOutlet, IfcSwitchingDevice, IfcAlarm, IfcSensor, IfcFlow*, small
//    IfcBuildingElementProxy, ...): hosted on the nearest wall face or ceiling within
//    component_snap, moved onto it, class from the catalogue or `other:<IfcClass>`;
//  - furniture (IfcFurnishingElement, IfcFurniture): furniture truth, type = IFC class;
//  - everything else of the storey (wall outsides and reveals, stairs, beams, railings, the
//    slab above) stays as class `other` with the IFC node name as id.
// World: Z-up metres, the storey's lowest room floor at z = 0. Deterministic: the same input
// gives the same bytes. Every refusal is an InputError, one line.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/params.h"
#include "scenes/door_angles.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

struct BimImportParams {
  std::string storey;  ///< IFC storey Name, node name or GlobalId; "" = lowest with spaces
  double door_angle_deg = 90.0;  ///< deg, [0, 180]: opening angle of every door
  /// Per-door angles, deg [0, 180], keyed by truth id (D1), IFC GlobalId or IFC Name.
  DoorAngles door_angles_deg;
  bool floor_from_spaces = false;    ///< make missing floors from the space footprint
  bool ceiling_from_spaces = false;  ///< make missing ceilings from the space footprint
  /// Apply every repair the file needs: floors and ceilings from the space footprints, and the
  /// wall inside an opening's rectangle made the opening's frame (docs/scene-import.md).
  bool repair = false;
  std::vector<std::string> merge;    ///< further models whose components are added (same frame)
  bool keep_site = false;            ///< keep IfcSite geometry (terrain) as `other`
  double leaf_thickness = 0.04;      ///< m, (0, 0.2]: generated door leaves
  double plane_tolerance = 0.003;    ///< m, (0, 0.05]: a face lies on a room's wall/floor plane
  double component_snap = 0.05;      ///< m, [0, 0.5]: largest gap between a component and host
  double min_face_area = 0.01;       ///< m^2, (0, 1000]: smaller wall faces are not made elements
  /// Read the model as it is, to score it (`mopad eval --model`), not to make a scene of it:
  /// heights stay the file's (no shift of the lowest room floor to z = 0); a repair the file
  /// would need is not made and not refused but reported ("as it is: ..."), so a floor or
  /// ceiling the model lacks is left out and a door hole that is wall stays wall.
  bool as_is = false;
  /// m, [0, 1], with as_is only: a room's wall face is the IfcWall face facing the room nearest
  /// its outline within this distance, in front of or behind it (0: on the outline within
  /// plane_tolerance). A model's walls need not lie on its spaces' outlines to the millimetre.
  double wall_search = 0.0;

  /// Throws InputError naming the field, its value and the allowed range (open lower bounds
  /// exactly, where Visit's closed Bounds stop just above 0).
  void Validate() const;

  template <class V>
  void Visit(V& v) {
    v("storey", storey);
    v("door_angle_deg", door_angle_deg, Bounds{0.0, 180.0});
    v("door_angles_deg", door_angles_deg, Bounds{0.0, 180.0});
    v("floor_from_spaces", floor_from_spaces);
    v("ceiling_from_spaces", ceiling_from_spaces);
    v("repair", repair);
    v("merge", merge);
    v("keep_site", keep_site);
    v("leaf_thickness", leaf_thickness, Bounds{1e-9, 0.2});
    v("plane_tolerance", plane_tolerance, Bounds{1e-9, 0.05});
    v("component_snap", component_snap, Bounds{0.0, 0.5});
    v("min_face_area", min_face_area, Bounds{1e-12, 1e3});
    v("as_is", as_is);
    v("wall_search", wall_search, Bounds{0.0, 1.0});
  }
};

struct BimImport {
  Scene scene;
  GroundTruth truth;
  /// One line each: what the file lacked, what was replaced or left out.
  std::vector<std::string> report;
  /// One line per repair made: "repair: <what> <where>: <from> -> <to>".
  std::vector<std::string> repairs;
  /// IFC class -> elements with geometry in the storey's node tree (what the file holds).
  std::map<std::string, int> storey_elements;
  /// IFC wall elements of any storey that gave at least one room-side wall face.
  int walls_with_room_faces = 0;
  /// Truth opening id -> GlobalId of the IfcDoor / IfcWindow it came from (doorways found as
  /// holes without such an element are absent).
  std::map<std::string, std::string> opening_guids;
  /// Service component id -> GlobalId of the IFC element it came from.
  std::map<std::string, std::string> component_guids;
};

/// The import's refusal when the file needs repairs that were not allowed: every one of them,
/// found in one run (what() is one line naming the first and the count).
class BimRepairsNeeded : public InputError {
 public:
  BimRepairsNeeded(const std::string& what, std::vector<std::string> repairs)
      : InputError(what), repairs(std::move(repairs)) {}
  /// "repair: <what> <where>: <from> -> <to> (<the option that applies it>)", one each.
  std::vector<std::string> repairs;
};

/// Imports `path` (.ifc IFC 2x3 or IFC4, or .glb/.gltf converted from IFC whose node names
/// carry the IFC classes and which kept the IfcSpace volumes). Throws InputError, and BimRepairsNeeded
/// when the file needs repairs the parameters do not allow.
BimImport ImportBim(const std::string& path, const BimImportParams& params = {});

/// Writes DIR/scene.glb and DIR/scene.truth.json (DIR is created).
void WriteBimImport(const BimImport& imported, const std::string& dir);

struct BimStorey {
  std::string name;        ///< IFC Name ("0. Erdgeschoss")
  std::string global_id;   ///< IFC GlobalId
  double elevation = 0.0;  ///< m, the storey's Elevation attribute in the file's units, scaled
  bool has_elevation = false;
};

/// The single-value properties of an IFC STEP file's property sets, by the GlobalId of each
/// product a set defines (IfcRelDefinesByProperties): "<set name>.<property name>" -> the value
/// as written, decoded (a label's or identifier's text; a measure's number as text, in the
/// file's units, e.g. radians for IfcPlaneAngleMeasure when the file says so). Throws InputError
/// if the file cannot be read or is not IFC.
using IfcProperties = std::map<std::string, std::map<std::string, std::string>>;
IfcProperties ReadIfcProperties(const std::string& path);

/// The IfcBuildingStorey entities of an IFC STEP file in file order (for `mopad scene info`).
/// Throws InputError if the file cannot be read or is not IFC.
std::vector<BimStorey> ListIfcStoreys(const std::string& path);

}  // namespace mopad::scenes
