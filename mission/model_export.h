#pragma once
// Files beside a room run that are not the robot's models themselves (docs/models.md):
// run.json (how the evaluator lines the run up with the truth) and models.glb (SM3 patches,
// one material per class, for viewers; checked by the Khronos validator in the tests).

#include <string>

#include "common/frames.h"
#include "modelling/structural_model.h"
#include "sim/scene_world.h"

namespace mopad::mission {

void WriteRunJson(const std::string& dir, const sim::SceneWorld& mw, const std::string& room,
                  std::uint64_t seed, const Pose3& X_WM);

/// SM3 as glTF 2.0 binary (map frame, Z-up converted by the scene writer's root node).
void WriteModelsGlb(const modelling::StructuralModel& sm3, const std::string& room,
                    const std::string& path);

}  // namespace mopad::mission
