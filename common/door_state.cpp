#include "common/door_state.h"

namespace mopad {

const char* ToString(DoorState s) {
  const auto i = static_cast<std::size_t>(s);
  return i < kDoorStateNames.size() ? kDoorStateNames[i] : kDoorStateNames[0];
}

std::optional<DoorState> DoorStateFromString(std::string_view name) {
  for (std::size_t i = 0; i < kDoorStateNames.size(); ++i)
    if (name == kDoorStateNames[i]) return static_cast<DoorState>(i);
  return std::nullopt;
}

}  // namespace mopad
