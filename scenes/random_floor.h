#pragma once
// Random office floors for `mopad scene random --seed N --rooms K`: a rectangular footprint cut
// by a corridor and recursive subdivision into offices, some merged into L-shapes; a spanning
// tree of open doors (>= 0.9 m wide) so every room is reachable, extra doors to neighbours and
// outside in mixed states, windows on outer walls, BSCs and furniture. All randomness comes
// from mopad::CounterRng keyed by the seed, so a seed always gives the same spec.

#include <cstdint>

#include "scenes/scene_spec.h"

namespace mopad::scenes {

inline constexpr int kMinRandomRooms = 2;
inline constexpr int kMaxRandomRooms = 10;

/// A valid spec with exactly `rooms` rooms ([2, 10]; InputError otherwise). Generate() on it
/// succeeds and CheckScene() reports no errors.
SceneSpec RandomFloorSpec(std::uint64_t seed, int rooms);

}  // namespace mopad::scenes
