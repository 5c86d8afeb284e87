#pragma once
// Loading a scene file of any supported format into a Scene (world frame, Z-up, metres).
//   .glb/.gltf  -> tinygltf (Draco-compressed files fall back to assimp)
//   .obj/.ply/.fbx/.dae/.stl -> assimp
//   .ifc (IFC 2x3) -> assimp, with conversion-based units applied; IFC4 -> IfcPlusPlus
//   (scenes/ifc4_loader.h), the same node naming
// Every rejection throws mopad::InputError with one line: `path: error: what; got X, expected Y`.

#include <string>

#include "scenes/scene.h"

namespace mopad::scenes {

/// Which axis of the coordinates a file (as its importer delivers them) points up. The world is
/// Z-up; Y-up data is rotated by mopad::ZupFromYup(), Z-up data is taken as is.
enum class UpAxis {
  kAuto,  ///< per format: Y for .gltf/.glb (the spec), .ifc (assimp turns IFC's Z-up into Y-up),
          ///< .dae (assimp applies <up_axis> and delivers Y-up), .obj/.ply/.fbx (no reliable
          ///< convention; Y-up is what Blender and most DCC exporters write); Z for .stl (CAD).
  kY,     ///< force Y-up (e.g. a PLY from a Y-up tool)
  kZ,     ///< force Z-up (e.g. an OBJ written by a Z-up CAD or our own Z-up OBJ export)
};

struct LoadOptions {
  /// Drop zero-area triangles instead of keeping them (they never hit anything).
  bool drop_degenerate_triangles = true;
  /// Use assimp for glTF files tinygltf cannot decode (Draco).
  bool allow_assimp_fallback = true;
  /// Up axis of the file's coordinates; kAuto picks the per-format default above. Only override
  /// it for files that break their format's convention.
  UpAxis up_axis = UpAxis::kAuto;
  /// IFC: also import IfcSpace volumes (class kSpace). Off by default: spaces are air, and a
  /// ray caster would hit their closed shells.
  bool import_ifc_spaces = false;
};

/// Dispatches on the file extension; validates the result (finite vertices, indices in range,
/// acyclic node graph, at least one triangle).
Scene LoadScene(const std::string& path, const LoadOptions& options = {});

}  // namespace mopad::scenes
