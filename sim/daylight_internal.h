#pragma once
// Internal to sim/: daylight's shadow rays, cast with Embree in the building's scene. Never
// include from a public header.

#include <embree3/rtcore.h>

#include <cstdint>

#include "sim/daylight.h"

namespace mopad::sim {

/// Daylight::Factor's `lit` for a surface point q (unit normal n, turned to the viewer) of `part`
/// at pulse `pulse`: one shadow ray in `scene` per window of its room, to a random point of the
/// pane (PulseStream(key, pulse), two uniforms per window whether or not it faces q), from 1 mm
/// off the surface to 2 cm short of the pane (a pane modelled as a slab does not shade itself).
/// What is in `scene` occludes (the building: people are movers, not in it).
std::uint32_t LitWindows(const Daylight& day, RTCScene scene, std::uint64_t key,
                         const Eigen::Vector3f& q, const Eigen::Vector3f& n, std::int32_t part,
                         std::uint64_t pulse);
/// LitWindows for the lanes of `mask` (bit j: lane j), 16 shadow rays at a time (one window
/// slot per packet); lit[j] = 0 for the other lanes. Each lane's result is LitWindows'.
void LitWindows16(const Daylight& day, RTCScene scene, std::uint64_t key, std::uint32_t mask,
                  const Eigen::Vector3f* q, const Eigen::Vector3f* n, const std::int32_t* part,
                  const std::uint64_t* pulse, std::uint32_t* lit);

}  // namespace mopad::sim
