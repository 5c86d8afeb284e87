#pragma once
// Door opening angles given by hand as "ID=DEG" items (`mopad drive --door`, `mopad scan|lrf
// --door`, `mopad scene import --doors`, a run record's "doors"): the one parser, and setting
// them on a scene spec before it is generated.

#include <map>
#include <string>
#include <vector>

namespace mopad::scenes {

struct SceneSpec;

/// Door id -> opening angle, deg in [0, 180] (0 closed, 90 square to the wall, 180 folded back
/// against it). Ordered by id; an id appears once.
using DoorAngles = std::map<std::string, double>;

/// Parses items "ID=DEG": ID is everything before the last '=' (not empty), DEG a finite number
/// in [0, 180] with nothing after it. `option` (e.g. "--door") starts every message. Throws
/// InputError for a malformed item ("OPTION: error: malformed door angle; got 'ITEM', expected
/// ID=DEG with DEG in [0, 180]") and for an id given twice.
DoorAngles ParseDoorAngles(const std::vector<std::string>& items, const std::string& option);

/// Sets the opening angle of each door in `angles` on `spec` (before Generate: the layout and the
/// truth follow the angle). Throws InputError "OPTION: error: unknown door; got 'ID', expected a
/// door of the spec" when the spec has no door of that id.
void SetDoorAngles(const DoorAngles& angles, const std::string& option, SceneSpec* spec);

}  // namespace mopad::scenes
