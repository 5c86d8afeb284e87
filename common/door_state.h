#pragma once
// A door's state (paper §3.3): closed, semi-open or open, by its leaf's opening angle. One enum
// and one set of names for the robot's SM4 (modelling::DoorState) and the scene's truth
// (scenes::DoorState): the names are the paper's terms, not truth. How an angle maps to a state
// is each side's rule (the truth's fixed 5° / 90°, the robot's parameters).

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace mopad {

enum class DoorState : std::uint8_t { kClosed = 0, kSemiOpen = 1, kOpen = 2 };

/// The names, by DoorState value: what every file and table writes.
inline constexpr std::array<const char*, 3> kDoorStateNames = {"closed", "semi_open", "open"};

/// "closed", "semi_open" or "open".
const char* ToString(DoorState s);

/// The state named `name`; none for any other text.
std::optional<DoorState> DoorStateFromString(std::string_view name);

}  // namespace mopad
