#include "sim/daylight.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "common/frames.h"

namespace mopad::sim {

Daylight::Daylight(const scenes::Scene& scene, float level, float ambient, float top_light)
    : level_(level), ambient_(ambient), top_light_(top_light) {
  if (!on()) return;
  const auto& parts = scene.parts;
  std::map<std::string, std::int32_t> rooms;
  part_room_.assign(parts.size(), -1);
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (!parts[i].room.empty())
      part_room_[i] =
          rooms.emplace(parts[i].room, static_cast<std::int32_t>(rooms.size())).first->second;
  // Each glass part with a room is a window: the centre, normal and area of its triangles.
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const scenes::MeshPart& part = parts[i];
    if (part.element_class != scenes::ElementClass::kWindowGlass || part_room_[i] < 0) continue;
    Eigen::Vector3f centre = Eigen::Vector3f::Zero(), normal = Eigen::Vector3f::Zero();
    float area2 = 0.0f;  // twice the area
    for (const Eigen::Vector3i& t : part.triangles) {
      const Eigen::Vector3f a = part.positions[t[0]], b = part.positions[t[1]],
                            c = part.positions[t[2]];
      const Eigen::Vector3f cr = (b - a).cross(c - a);
      centre += cr.norm() * (a + b + c) / 3.0f;
      normal += cr;
      area2 += cr.norm();
    }
    if (area2 <= 0.0f || normal.norm() <= 0.0f) continue;
    windows_.push_back({centre / area2, normal.normalized(), 0.5f * area2, part_room_[i]});
  }
}

float Daylight::Factor(const Eigen::Vector3f& q, const Eigen::Vector3f& n,
                       std::int32_t part) const {
  if (part < 0 || static_cast<std::size_t>(part) >= part_room_.size()) return 1.0f;  // a mover
  const std::int32_t room = part_room_[static_cast<std::size_t>(part)];
  if (room < 0) return 1.0f;
  float e = 0.0f;
  for (const Window& w : windows_) {
    if (w.room != room) continue;
    const Eigen::Vector3f d = w.centre - q;
    const float cos_p = n.dot(d);  // times |d|, as the next
    if (cos_p <= 0.0f) continue;
    const float cos_w = std::abs(w.normal.dot(d));
    // A cos cos / (pi r^2), r kept at least the window's size (the small-area form factor).
    const float r2 = std::max(d.squaredNorm(), w.area);
    e += w.area * cos_p * cos_w / (r2 * r2);
  }
  const float base = ambient_ + top_light_ * std::max(0.0f, n.z());
  return base > 0.0f ? 1.0f + level_ * e / (static_cast<float>(kPi) * base) : 1.0f;
}

}  // namespace mopad::sim
