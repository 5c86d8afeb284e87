#pragma once
// Daylight through a room's windows (TlsParams::window_light), as the colour camera sees it: the
// scene's windows (each glass part's centre, normal and area) and each part's room, and the
// factor by which daylight raises a surface point's light. The small-area form factor of each
// pane of the point's own room; no shadows, no light through walls or doors.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "scenes/scene.h"

namespace mopad::sim {

class Daylight {
 public:
  Daylight() = default;
  /// Daylight of `level` (in the units of `ambient`; 0 = off) in `scene`, whose own light is
  /// `ambient` plus `top_light` on up-facing surfaces.
  Daylight(const scenes::Scene& scene, float level, float ambient, float top_light);

  bool on() const { return level_ > 0.0f; }
  /// The light of a surface point q with the daylight over its light without; n is its unit
  /// normal turned to the viewer, `part` its part. 1 for a part without a room (and a mover's).
  float Factor(const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::int32_t part) const;

 private:
  struct Window {
    Eigen::Vector3f centre, normal;
    float area = 0.0f;
    std::int32_t room = -1;
  };
  float level_ = 0.0f, ambient_ = 1.0f, top_light_ = 0.0f;
  std::vector<Window> windows_;
  std::vector<std::int32_t> part_room_;
};

}  // namespace mopad::sim
