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

Eigen::Vector2d FreeSpotInRoom(const scenes::GroundTruth& truth, const scenes::Room& room) {
  Eigen::AlignedBox2d box;
  for (const auto& p : room.polygon) box.extend(p);
  Eigen::Vector2d best = box.center();
  double best_clear = -1.0;
  for (double x = box.min().x() + 0.05; x < box.max().x(); x += 0.1) {
    for (double y = box.min().y() + 0.05; y < box.max().y(); y += 0.1) {
      const Eigen::Vector2d p(x, y);
      if (!PointInPolygon(p, room.polygon)) continue;
      double clear = 1e9;
      for (std::size_t i = 0; i < room.polygon.size(); ++i)
        clear = std::min(clear, DistanceToSegment(p, room.polygon[i],
                                                  room.polygon[(i + 1) % room.polygon.size()]));
      for (const auto& f : truth.furniture) {
        const double r = 0.5 * f.size.head<2>().norm();
        clear = std::min(clear, (p - f.centre.head<2>()).norm() - r);
      }
      for (const auto& e : truth.elements) {
        if (e.element_class != scenes::ElementClass::kColumn) continue;
        for (const auto& poly : e.polygons)
          for (const auto& v : poly) clear = std::min(clear, (p - v.head<2>()).norm());
      }
      if (clear > best_clear + 1e-9) {
        best_clear = clear;
        best = p;
      }
    }
  }
  return best;
}

}  // namespace mopad::sim
