#pragma once
// Semantic classes of scene geometry. Every triangle of a loaded scene carries one, exactly
// (from glTF node extras written by our generator, or from the IFC class of imported BIM).

#include <string>
#include <string_view>

namespace mopad::scenes {

enum class ElementClass {
  kUnknown = 0,
  kWall,
  kFloor,
  kCeiling,
  kColumn,
  kDoorFrame,  ///< door casing / jambs (part of the opening, not the leaf)
  kDoorLeaf,   ///< the moving leaf; hinged, angle in the ground truth
  kWindowFrame,
  kWindowGlass,       ///< transmits rays with the material's transmission probability
  kServiceComponent,  ///< BSC: socket, switch, sign, extinguisher, smoke detector, ...
  kFurniture,         ///< desks, cabinets, shelves, chairs
  kClutter,           ///< other movable objects
  kBeam,
  kSlab,  ///< IFC slabs that are not known to be a floor or ceiling (e.g. roof slabs)
  kRoof,
  kStair,
  kRailing,
  kSite,    ///< terrain
  kSpace,   ///< IfcSpace volumes (only when imported on purpose)
  kOther,   ///< known element of a class we do not model (e.g. IfcBuildingElementProxy)
  kPerson,  ///< a person walking during a mission (sim/people.h): never in a scene or its truth
};

/// Stable lower-case names used in files: "wall", "door_leaf", "service_component", ...
std::string_view ToString(ElementClass c);
/// Inverse of ToString; returns false for an unknown name.
bool ParseElementClass(std::string_view name, ElementClass* out);
/// Structural elements in the paper's sense (SEs): wall, floor, ceiling, column.
bool IsStructural(ElementClass c);
/// Maps an IFC entity name ("IfcWallStandardCase", case-insensitive) to our class.
ElementClass FromIfcClass(std::string_view ifc_class);

}  // namespace mopad::scenes
