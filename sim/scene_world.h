#pragma once
// The world a mission runs in, from a SCENE argument (truth side): a SCENE argument
// (generated folder, scene file, or spec .yaml with optional door-angle overrides) becomes an
// Embree world plus the truth sidecar when there is one, and the robot body for the harness's
// start placement (scenes/start_spot.h).

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "scenes/ground_truth.h"
#include "scenes/start_spot.h"
#include "sim/embree_world.h"
#include "sim/robot_body.h"

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

/// The robot body as the harness's start placement sees it (scenes/start_spot.h).
scenes::RobotFootprint FootprintOf(const RobotBodyParams& body);

}  // namespace mopad::sim
