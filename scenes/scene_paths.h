#pragma once
// Resolving a SCENE argument: a generated scene folder (scene.glb + scene.truth.json) or any
// loadable file (.glb, .gltf, .obj, .ifc, ...). A truth sidecar is picked up when present.

#include <filesystem>
#include <optional>
#include <string>

namespace mopad::scenes {

struct ScenePaths {
  std::string geometry;              ///< file to load
  std::optional<std::string> truth;  ///< scene.truth.json if present
};

/// Throws InputError if the path does not exist or a folder lacks scene.glb.
ScenePaths ResolveScene(const std::string& arg);

}  // namespace mopad::scenes
