#pragma once
// The world a mission runs in, from a SCENE argument (truth side): a SCENE argument
// (generated folder, scene file, or spec .yaml with optional door-angle overrides) becomes an
// Embree world plus the truth sidecar when there is one. Also the harness's start placement.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"

namespace mopad::sim {

struct SceneWorld {
  std::string source;                        ///< the SCENE argument, absolute
  std::vector<std::string> door_overrides;   ///< "ID=DEG" applied to a spec
  std::optional<scenes::GroundTruth> truth;  ///< absent for scenes without a sidecar
  std::unique_ptr<EmbreeWorld> world;
};

/// Loads `scene_arg`. `door_overrides` are "ID=DEG" strings, allowed with a spec only.
/// Throws InputError on unknown doors, bad syntax or unloadable scenes.
SceneWorld LoadSceneWorld(const std::string& scene_arg,
                          const std::vector<std::string>& door_overrides = {});

/// Harness placement from the truth (never given to the robot as knowledge): the point of a
/// 10 cm grid inside the room that is farthest from walls, furniture and columns (a "pole of
/// inaccessibility"). Deterministic.
Eigen::Vector2d FreeSpotInRoom(const scenes::GroundTruth& truth, const scenes::Room& room);

}  // namespace mopad::sim
