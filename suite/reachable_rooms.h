#pragma once
// The rooms a floor mission can reach (truth side): a search from the start room over the
// truth's connections, through open passages and through doors that are not closed and leave
// at least `min_clear_width` between the frame and the opened leaf. Furniture and the leaf's
// swing into the room are not considered, so the count is an upper bound on what a robot can
// visit (docs/floor-mission.md, Known limits). The suite's rooms_reachable and rooms_missed
// figures (suite/figures.h) come from it.

#include <set>
#include <string>

#include "scenes/ground_truth.h"

namespace mopad::suite {

/// The clear width of a door of width w opened by angle lambda with a leaf of thickness t:
/// w - (w cos(lambda) + t sin(lambda)), lambda capped at 90 deg. Metres.
double DoorClearWidth(const scenes::Opening& door);

/// The truth rooms reachable from `start_room` (included when it exists).
std::set<std::string> ReachableRooms(const scenes::GroundTruth& truth,
                                     const std::string& start_room, double min_clear_width);

}  // namespace mopad::suite
