#pragma once
// IFC4 (and later IFC4 add-ons) through IfcPlusPlus (Debian libifcplusplus-dev, carve
// tessellation): the same Scene the assimp path gives for IFC 2x3 (scenes/assimp_loader.h), so
// the BIM import reads both schemas the same way (docs/scene-import.md, "IFC4").
//  - one MeshPart per representation item of a product, named by its node path as assimp names
//    it: `IfcSite_<Name>_<GlobalId>/$RelAggregates/IfcBuilding_…/$RelAggregates/`
//    `IfcBuildingStorey_<Name>_<GlobalId>/IfcWall_<Name>_<GlobalId>` (spaces aggregated by a
//    storey under `…/$RelAggregates/IfcSpace_…`; names without white space);
//    element_id = the product's node name, subclass = its IFC class, element_class from it;
//  - the Body representation (others only when a product has no Body); openings cut from their
//    hosts by IfcPlusPlus; IfcOpeningElement and IfcAnnotation make no parts; IfcSpace volumes
//    only with LoadOptions::import_ifc_spaces;
//  - Z-up metres: the file's length unit (SI prefix or conversion-based, read from the STEP
//    text) is applied;
//  - materials from the items' surface styles (name, diffuse colour, transparency as
//    transmission), one Material per style.
// IfcPlusPlus and carve can crash on bad geometry: the file is read in a child process, and a
// crash, a failed read or a file without geometry becomes one InputError naming the file.

#include <string>

#include "scenes/scene.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {

/// Loads an IFC4 STEP file (FILE_SCHEMA 'IFC4…'), flattens and validates it (ValidateScene).
/// Throws InputError.
Scene LoadIfc4(const std::string& path, const LoadOptions& options = {});

}  // namespace mopad::scenes
