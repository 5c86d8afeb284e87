#include "sim/scene_world.h"

#include <algorithm>
#include <filesystem>

#include "common/polygon.h"
#include "scenes/door_angles.h"
#include "scenes/scene_paths.h"

namespace mopad::sim {
SceneWorld LoadSceneWorld(const std::string& scene_arg,
                          const std::vector<std::string>& door_overrides) {
  SceneWorld out;
  out.source = std::filesystem::absolute(scene_arg).lexically_normal().string();
  out.door_overrides = door_overrides;
  scenes::LoadedScene loaded =
      scenes::LoadSceneArg(scene_arg, scenes::ParseDoorAngles(door_overrides, "--door"), "--door");
  out.truth = std::move(loaded.truth);
  out.world =
      std::make_unique<EmbreeWorld>(std::move(loaded.scene), out.truth ? &*out.truth : nullptr);
  return out;
}

scenes::RobotFootprint FootprintOf(const RobotBodyParams& body) {
  scenes::RobotFootprint f;
  f.length = body.footprint_length;
  f.width = body.footprint_width;
  f.offset_x = body.footprint_offset_x;
  f.ground_clearance = body.ground_clearance;
  f.body_height = body.body_height;
  return f;
}

}  // namespace mopad::sim
