#pragma once
// Loading a scene file of any supported format into a Scene (world frame, Z-up, metres).
//   .glb/.gltf  -> tinygltf (Draco-compressed files fall back to assimp)
//   .obj/.ply/.fbx/.dae/.stl -> assimp
//   .ifc (IFC 2x3) -> assimp, with conversion-based units applied; IFC4 refused
// Every rejection throws mopad::InputError with one line: `path: error: what; got X, expected Y`.

#include <string>

#include "scenes/scene.h"

namespace mopad::scenes {

struct LoadOptions {
  /// Drop zero-area triangles instead of keeping them (they never hit anything).
  bool drop_degenerate_triangles = true;
  /// Use assimp for glTF files tinygltf cannot decode (Draco).
  bool allow_assimp_fallback = true;
};

/// Dispatches on the file extension; validates the result (finite vertices, indices in range,
/// acyclic node graph, at least one triangle).
Scene LoadScene(const std::string& path, const LoadOptions& options = {});

}  // namespace mopad::scenes
