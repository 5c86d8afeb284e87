#pragma once
// Random office floors for `mopad scene random --seed N --rooms K [--family F]`: a rectangular
// footprint cut into rooms by one of several families (docs/scene-spec.md "Random floors"):
//   office   — a corridor band or recursive subdivision into offices, some merged into L-shapes;
//   corridor — one long corridor (up to 40 m, 1.5-2.5 m wide) with offices up to 9 m wide on
//              both sides, each entered from the corridor (sparse doors between offices);
//   junction — an L or T corridor junction with offices along both arms;
//   hall     — a hall of at least 20 m x 14 m under a 3.4-4.0 m ceiling, a column grid, offices
//              along its sides;
//   mixed    — the family drawn from the seed (office 40 %, the others 20 % each).
// Always a spanning tree of open doors (>= 0.9 m wide) so every room is reachable, extra doors
// to neighbours and outside in mixed states, windows on outer walls, BSCs and furniture. All
// randomness comes from mopad::CounterRng keyed by the seed, so a seed always gives the same
// spec; the office family's specs do not depend on the other families' existence.

#include <cstdint>
#include <string>

#include "scenes/scene_spec.h"

namespace mopad::scenes {

inline constexpr int kMinRandomRooms = 2;
inline constexpr int kMaxRandomRooms = 10;        ///< every family
inline constexpr int kMaxRandomOfficeRooms = 40;  ///< the office family (scaling benchmarks)

enum class FloorFamily { kOffice, kCorridor, kJunction, kHall, kMixed };

/// "office", "corridor", "junction", "hall", "mixed".
std::string FloorFamilyName(FloorFamily family);
/// The family named `name`; InputError naming the choices otherwise.
FloorFamily ParseFloorFamily(const std::string& name);
/// The family a (seed, rooms) floor of `family` has: `family` itself, or for kMixed the one the
/// seed draws.
FloorFamily ResolveFloorFamily(std::uint64_t seed, int rooms, FloorFamily family);

/// The most rooms a floor of `family` can have: kMaxRandomOfficeRooms for office floors (a
/// corridor band with offices on both sides grows as long as it must, or a subdivision),
/// kMaxRandomRooms for the others (a corridor is at most 40 m long, a hall's sides hold a few).
int MaxRandomRooms(FloorFamily family);

/// A valid spec with exactly `rooms` rooms ([2, MaxRandomRooms(family)]; InputError
/// otherwise). Generate() on it succeeds and CheckScene() reports no errors.
SceneSpec RandomFloorSpec(std::uint64_t seed, int rooms,
                          FloorFamily family = FloorFamily::kOffice);

}  // namespace mopad::scenes
