#pragma once
// Semantic glTF 2.0 binary of a BuildingModel (docs/exports.md), written with io::WriteGlb
// (Z-up export frame under one root node rotated to glTF's Y-up): one node per element, named
// by its id, with extras {"mopad": {"id", "class", "kind", "room", "ifc_class", "host",
// "properties"}} (properties: the model files' figures: state, opening angle, confidence, alpha,
// found_by, support, ...). Geometry: walls, floors and ceilings their SM3 polygons, columns
// their plan-hull prisms, doors and windows their holes (a quad 5 mm in front of the wall, so it
// is not coplanar with it), components their boxes. One material per class, in a fixed order
// (structure, openings, then component classes sorted by name). Deterministic.

#include <string>

#include "exports/building_model.h"
#include "io/glb_writer.h"

namespace mopad::exports {

/// The scene WriteSemanticGlb writes: one mesh per element that could be triangulated (its
/// name the element id, its extras the semantics), materials per class present.
io::GlbScene SemanticScene(const BuildingModel& model);

/// Writes `model` to `path`; returns the number of element nodes. InputError when no element
/// could be triangulated or the file cannot be written.
int WriteSemanticGlb(const BuildingModel& model, const std::string& path);

}  // namespace mopad::exports
