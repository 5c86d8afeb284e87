#pragma once
// Non-glTF formats (and Draco-compressed glTF) through assimp 5.2.5: .obj, .ply, .fbx, .dae,
// .stl, .gltf/.glb, .ifc (IFC 2x3; IFC4 is handed to scenes/ifc4_loader.h).
// The node tree is flattened here (not with aiProcess_PreTransformVertices, which loses node
// names); each mesh instanced by a node becomes one MeshPart named by its node path.
// Axes: see UpAxis in scenes/scene_loader.h (assimp delivers glTF, IFC and DAE as Y-up).
// IFC specifics (assimp names nodes `<IfcClass>_<Name>_<GlobalId>`):
//  - a mesh's class is that of its nearest self-or-ancestor node named Ifc* other than
//    IfcMappedItem (doors, windows and furniture hang their geometry on IfcMappedItem
//    children); element_id = that node's name, subclass = its IFC entity name;
//  - assimp ignores conversion-based length units (FOOT, INCH): they are read from the STEP
//    text (IFCUNITASSIGNMENT) and applied here; SI prefixes assimp applies itself;
//  - IFC4 / IFC4X* can crash assimp 5.2.5: FILE_SCHEMA is sniffed and they go to IfcPlusPlus
//    (LoadIfc4), other schemas are refused;
//  - IfcSpace volumes are skipped unless LoadOptions::import_ifc_spaces.
// Materials: base/diffuse colour, metallic, roughness, transmission (or 1 - opacity when a
// material is only transparent, as IFC glass is), two-sided; diffuse/base textures decoded.
// Every rejection: mopad::InputError, one line `path: error: what; got X, expected Y`.

#include <string>
#include <string_view>

#include "scenes/scene.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {

/// Loads any file assimp reads, flattens and validates it (ValidateScene). Throws InputError.
Scene LoadWithAssimp(const std::string& path, const LoadOptions& options = {});

/// The schema named in an IFC STEP header's FILE_SCHEMA(('IFC2X3')), upper-cased ("IFC2X3",
/// "IFC4", "IFC4X3_ADD2"); "" if the text has no FILE_SCHEMA in its HEADER section.
std::string IfcSchemaOf(std::string_view step_text);

/// The factor (metres per file length unit) that assimp does NOT apply: for a conversion-based
/// LENGTHUNIT in the first IFCUNITASSIGNMENT (FOOT: 0.3048, INCH: 0.0254, times the SI prefix of
/// its IFCMEASUREWITHUNIT's unit) that factor; 1.0 for SI length units (assimp applies SI
/// prefixes) or when no length unit is assigned. Throws InputError (naming `where`) when the
/// unit is assigned but its entities cannot be parsed.
double IfcUnappliedLengthScale(std::string_view step_text, const std::string& where = "");

/// For an assimp-style IFC node name `IfcWallStandardCase_Wand-1_3rPX...` returns the IFC
/// entity name ("IfcWallStandardCase"); "" if the name is not of that form. Also used by the
/// glTF loader for glTF files converted from IFC by assimp.
std::string IfcClassFromNodeName(std::string_view node_name);

}  // namespace mopad::scenes
