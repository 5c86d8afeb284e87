#pragma once
// run.json beside a room run (docs/models.md): how the evaluator lines the run up with the
// truth. The robot's models.glb is modelling::WriteModelsGlb.

#include <string>

#include "common/frames.h"
#include "sim/scene_world.h"

namespace mopad::mission {

void WriteRunJson(const std::string& dir, const sim::SceneWorld& mw, const std::string& room,
                  std::uint64_t seed, const Pose3& X_WM);

}  // namespace mopad::mission
