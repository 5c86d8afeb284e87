#include "scenes/scene.h"

namespace mopad::scenes {

std::size_t Scene::TriangleCount() const {
  std::size_t n = 0;
  for (const auto& p : parts) n += p.triangles.size();
  return n;
}

Eigen::AlignedBox3d Scene::Bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& p : parts)
    for (const auto& v : p.positions) box.extend(v.cast<double>());
  return box;
}

}  // namespace mopad::scenes
