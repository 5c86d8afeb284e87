#pragma once
// Daylight through a room's windows (TlsParams::window_light), as the colour camera sees it: the
// scene's windows (each glass part's pane: centre, normal, area and triangles) and each part's
// room, and the factor by which daylight raises a surface point's light: the small-area form
// factor of each pane of the point's own room, times whether the pane is visible from the
// point (the caller's shadow rays, one to a random point of each pane: soft shadows, estimated
// over the pulses). No light through walls or doors.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "scenes/scene.h"

namespace mopad::sim {

class Daylight {
 public:
  /// Windows of one room that light a point, at most (one bit each in Factor's `lit`).
  static constexpr int kMaxWindows = 32;

  Daylight() = default;
  /// Daylight of `level` (in the units of `ambient`; 0 = off) in `scene`, whose own light is
  /// `ambient` plus `top_light` on up-facing surfaces.
  Daylight(const scenes::Scene& scene, float level, float ambient, float top_light);

  bool on() const { return level_ > 0.0f; }
  /// The windows of `part`'s room (indices for PanePoint, Faces), at most kMaxWindows; empty for
  /// a part without a room and for a mover's.
  std::span<const std::int32_t> WindowsOf(std::int32_t part) const;
  /// True when window w's pane faces the surface point q of unit normal n (it can light it).
  bool Faces(std::int32_t w, const Eigen::Vector3f& q, const Eigen::Vector3f& n) const;
  /// A point of window w's pane, uniform over its area, from two uniforms u, v in [0, 1).
  Eigen::Vector3f PanePoint(std::int32_t w, float u, float v) const;
  /// The light of a surface point q with the daylight over its light without; n is its unit
  /// normal turned to the viewer, `part` its part; bit k of `lit` says that the k-th window of
  /// WindowsOf(part) is visible from q (all set: no shadows). 1 for a part without a room.
  float Factor(const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::int32_t part,
               std::uint32_t lit = ~0u) const;

 private:
  struct Window {
    Eigen::Vector3f centre, normal;
    float area = 0.0f;
    std::int32_t room = -1;
    std::vector<Eigen::Vector3f> corners;  ///< the pane's triangles, 3 corners each
    std::vector<float> cdf;                ///< cumulative area of its triangles, last = 1
  };
  float level_ = 0.0f, ambient_ = 1.0f, top_light_ = 0.0f;
  std::vector<Window> windows_;
  std::vector<std::int32_t> part_room_;
  std::vector<std::vector<std::int32_t>> room_windows_;  ///< per room, its windows
};

}  // namespace mopad::sim
