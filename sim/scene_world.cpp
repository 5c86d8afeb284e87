#include "sim/scene_world.h"

#include <algorithm>
#include <filesystem>

#include "common/error.h"
#include "common/polygon.h"
#include "scenes/door_angles.h"
#include "scenes/generator.h"
#include "scenes/scene_loader.h"
#include "scenes/scene_paths.h"
#include "scenes/scene_spec.h"

namespace mopad::sim {
SceneWorld LoadSceneWorld(const std::string& scene_arg,
                          const std::vector<std::string>& door_overrides) {
  SceneWorld out;
  out.source = std::filesystem::absolute(scene_arg).lexically_normal().string();
  out.door_overrides = door_overrides;
  const std::string ext = std::filesystem::path(scene_arg).extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    scenes::SceneSpec spec = scenes::LoadSceneSpec(scene_arg);
    scenes::SetDoorAngles(scenes::ParseDoorAngles(door_overrides, "--door"), "--door", &spec);
    scenes::GeneratedScene g = scenes::Generate(spec);
    out.truth = std::move(g.truth);
    out.world = std::make_unique<EmbreeWorld>(std::move(g.scene), &*out.truth);
    return out;
  }
  if (!door_overrides.empty()) throw InputError("--door: error: only with a scene spec (.yaml)");
  const scenes::ScenePaths paths = scenes::ResolveScene(scene_arg);
  if (paths.truth) out.truth = scenes::ReadGroundTruth(*paths.truth);
  out.world = std::make_unique<EmbreeWorld>(scenes::LoadScene(paths.geometry),
                                            out.truth ? &*out.truth : nullptr);
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
