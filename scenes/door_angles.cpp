#include "scenes/door_angles.h"

#include <cmath>
#include <cstdlib>

#include "common/error.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {

DoorAngles ParseDoorAngles(const std::vector<std::string>& items, const std::string& option) {
  DoorAngles out;
  for (const std::string& item : items) {
    // The last '=': an IFC Name used as the id may itself hold one.
    const std::size_t eq = item.rfind('=');
    char* end = nullptr;
    const std::string num = eq == std::string::npos ? "" : item.substr(eq + 1);
    const double deg = std::strtod(num.c_str(), &end);
    if (eq == std::string::npos || eq == 0 || num.empty() || *end != '\0' || !std::isfinite(deg) ||
        deg < 0.0 || deg > 180.0)
      throw InputError(option, "malformed door angle", "'" + item + "'",
                       "ID=DEG with DEG in [0, 180]");
    const std::string id = item.substr(0, eq);
    if (!out.emplace(id, deg).second)
      throw InputError(option, "door given twice", "'" + id + "'", "once");
  }
  return out;
}

void SetDoorAngles(const DoorAngles& angles, const std::string& option, SceneSpec* spec) {
  for (const auto& [id, deg] : angles) {
    bool found = false;
    for (DoorSpec& door : spec->doors)
      if (door.id == id) {
        door.angle_deg = deg;
        found = true;
      }
    if (!found) throw InputError(option, "unknown door", "'" + id + "'", "a door of the spec");
  }
}

}  // namespace mopad::scenes
