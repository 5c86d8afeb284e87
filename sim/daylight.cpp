#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "common/frames.h"
#include "sim/daylight_internal.h"
#include "sim/scan_model.h"

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

namespace {

// A shadow ray from the surface point q (unit normal n, turned to the viewer) to a random point
// of window w's pane; false when the pane does not face q. The ray starts 1 mm off the surface
// and ends 2 cm short of the pane (a pane modelled as a slab does not shade itself).
bool ShadowRay(const Daylight& day, std::int32_t w, const Eigen::Vector3f& q,
               const Eigen::Vector3f& n, float u, float v, Eigen::Vector3f* org,
               Eigen::Vector3f* dir, float* tfar) {
  if (!day.Faces(w, q, n)) return false;
  *org = q + 1e-3f * n;
  const Eigen::Vector3f to = day.PanePoint(w, u, v) - *org;
  const float dist = to.norm();
  if (dist <= 0.03f) return false;
  *dir = to / dist;
  *tfar = dist - 0.02f;
  return true;
}

}  // namespace

std::uint32_t LitWindows(const Daylight& day, RTCScene scene, std::uint64_t key,
                         const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::int32_t part,
                         std::uint64_t pulse) {
  const std::span<const std::int32_t> windows = day.WindowsOf(part);
  PulseStream rng(key, pulse);
  std::uint32_t lit = 0;
  RTCIntersectContext rctx;
  rtcInitIntersectContext(&rctx);
  for (std::size_t k = 0; k < windows.size(); ++k) {
    const float u = static_cast<float>(rng.Uniform()), v = static_cast<float>(rng.Uniform());
    Eigen::Vector3f org, dir;
    float tfar = 0.0f;
    if (!ShadowRay(day, windows[k], q, n, u, v, &org, &dir, &tfar)) continue;
    RTCRay ray{};
    ray.org_x = org.x(), ray.org_y = org.y(), ray.org_z = org.z();
    ray.dir_x = dir.x(), ray.dir_y = dir.y(), ray.dir_z = dir.z();
    ray.tnear = 0.0f;
    ray.tfar = tfar;
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &rctx, &ray);
    if (ray.tfar >= 0.0f) lit |= 1u << k;
  }
  return lit;
}

void LitWindows16(const Daylight& day, RTCScene scene, std::uint64_t key, std::uint32_t mask,
                  const Eigen::Vector3f* q, const Eigen::Vector3f* n, const std::int32_t* part,
                  const std::uint64_t* pulse, std::uint32_t* lit) {
  std::span<const std::int32_t> windows[16];
  float uv[16][2 * Daylight::kMaxWindows];
  std::size_t slots = 0;
  for (int j = 0; j < 16; ++j) {
    lit[j] = 0;
    if (!((mask >> j) & 1u)) continue;
    windows[j] = day.WindowsOf(part[j]);
    PulseStream rng(key, pulse[j]);
    for (std::size_t k = 0; k < 2 * windows[j].size(); ++k)
      uv[j][k] = static_cast<float>(rng.Uniform());
    slots = std::max(slots, windows[j].size());
  }
  RTCIntersectContext rctx;
  rtcInitIntersectContext(&rctx);
  for (std::size_t k = 0; k < slots; ++k) {
    alignas(64) RTCRay16 ray;
    alignas(64) int valid[16];
    bool any = false;
    for (int j = 0; j < 16; ++j) {
      Eigen::Vector3f org = Eigen::Vector3f::Zero(), dir = Eigen::Vector3f::UnitZ();
      float tfar = 0.0f;
      valid[j] = ((mask >> j) & 1u) && k < windows[j].size() &&
                         ShadowRay(day, windows[j][k], q[j], n[j], uv[j][2 * k], uv[j][2 * k + 1],
                                   &org, &dir, &tfar)
                     ? -1
                     : 0;
      any |= valid[j] != 0;
      ray.org_x[j] = org.x(), ray.org_y[j] = org.y(), ray.org_z[j] = org.z();
      ray.dir_x[j] = dir.x(), ray.dir_y[j] = dir.y(), ray.dir_z[j] = dir.z();
      ray.tnear[j] = 0.0f;
      ray.tfar[j] = tfar;
      ray.time[j] = 0.0f;
      ray.mask[j] = 0xFFFFFFFFu;
      ray.id[j] = 0;
      ray.flags[j] = 0;
    }
    if (!any) continue;
    rtcOccluded16(valid, scene, &rctx, &ray);
    for (int j = 0; j < 16; ++j)
      if (valid[j] && ray.tfar[j] >= 0.0f) lit[j] |= 1u << k;
  }
}

}  // namespace mopad::sim
