#pragma once
// Resolving a SCENE argument: a scene spec (.yaml/.yml, generated in memory), a generated scene
// folder (scene.glb + scene.truth.json) or any loadable file (.glb, .gltf, .obj, .ifc, ...). A
// truth sidecar is picked up when present.

#include <filesystem>
#include <optional>
#include <string>

#include "scenes/door_angles.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

struct ScenePaths {
  std::string geometry;              ///< file to load
  std::optional<std::string> truth;  ///< scene.truth.json if present
};

/// A folder or a file (not a spec). Throws InputError if the path does not exist or a folder
/// lacks scene.glb.
ScenePaths ResolveScene(const std::string& arg);

/// A SCENE argument loaded.
struct LoadedScene {
  Scene scene;
  std::optional<GroundTruth> truth;  ///< absent for a file without a sidecar
  std::string description;           ///< "ARG (generated)" or "GEOMETRY[ + TRUTH]", for messages
};

/// Loads `arg`: a spec is generated with `spec_door_angles` set on its doors first (the layout
/// and the truth follow them); a folder or file is read through ResolveScene, truth first.
/// `option` (e.g. "--door") names the door angles' source in messages. Throws InputError for a
/// bad scene, an unknown door, or door angles with anything but a spec.
LoadedScene LoadSceneArg(const std::string& arg, const DoorAngles& spec_door_angles = {},
                         const std::string& option = "");

}  // namespace mopad::scenes
