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
  room_windows_.resize(rooms.size());
  // Each glass part with a room is a window: the centre, normal and area of its triangles.
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const scenes::MeshPart& part = parts[i];
    if (part.element_class != scenes::ElementClass::kWindowGlass || part_room_[i] < 0) continue;
    Window win;
    Eigen::Vector3f centre = Eigen::Vector3f::Zero(), normal = Eigen::Vector3f::Zero();
    float area2 = 0.0f;  // twice the area
    for (const Eigen::Vector3i& t : part.triangles) {
      const Eigen::Vector3f a = part.positions[t[0]], b = part.positions[t[1]],
                            c = part.positions[t[2]];
      const Eigen::Vector3f cr = (b - a).cross(c - a);
      centre += cr.norm() * (a + b + c) / 3.0f;
      normal += cr;
      area2 += cr.norm();
      win.corners.insert(win.corners.end(), {a, b, c});
      win.cdf.push_back(area2);
    }
    if (area2 <= 0.0f || normal.norm() <= 0.0f) continue;
    for (float& f : win.cdf) f /= area2;
    win.cdf.back() = 1.0f;
    win.centre = centre / area2;
    win.normal = normal.normalized();
    win.area = 0.5f * area2;
    win.room = part_room_[i];
    auto& list = room_windows_[static_cast<std::size_t>(win.room)];
    if (list.size() < kMaxWindows) list.push_back(static_cast<std::int32_t>(windows_.size()));
    windows_.push_back(std::move(win));
  }
}

std::span<const std::int32_t> Daylight::WindowsOf(std::int32_t part) const {
  if (part < 0 || static_cast<std::size_t>(part) >= part_room_.size()) return {};  // a mover
  const std::int32_t room = part_room_[static_cast<std::size_t>(part)];
  if (room < 0) return {};
  return room_windows_[static_cast<std::size_t>(room)];
}

bool Daylight::Faces(std::int32_t w, const Eigen::Vector3f& q, const Eigen::Vector3f& n) const {
  return n.dot(windows_[static_cast<std::size_t>(w)].centre - q) > 0.0f;
}

Eigen::Vector3f Daylight::PanePoint(std::int32_t w, float u, float v) const {
  const Window& win = windows_[static_cast<std::size_t>(w)];
  // The triangle by area, then a uniform point of it (u reused within the triangle's share).
  const auto it = std::upper_bound(win.cdf.begin(), win.cdf.end(), u);
  const std::size_t k = std::min<std::size_t>(it - win.cdf.begin(), win.cdf.size() - 1);
  const float lo = k == 0 ? 0.0f : win.cdf[k - 1];
  float s = (u - lo) / std::max(win.cdf[k] - lo, 1e-12f), t = v;
  if (s + t > 1.0f) s = 1.0f - s, t = 1.0f - t;
  const Eigen::Vector3f& a = win.corners[3 * k];
  return a + s * (win.corners[3 * k + 1] - a) + t * (win.corners[3 * k + 2] - a);
}

float Daylight::Factor(const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::int32_t part,
                       std::uint32_t lit) const {
  const std::span<const std::int32_t> mine = WindowsOf(part);
  if (mine.empty()) return 1.0f;
  float e = 0.0f;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    if (!((lit >> k) & 1u)) continue;
    const Window& w = windows_[static_cast<std::size_t>(mine[k])];
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
