#pragma once
// Checks a scene's ground truth against its geometry (what `mopad scene validate DIR` runs):
//  - every truth id (element, opening, BSC, furniture) has triangles carrying it, every
//    labelled triangle's id is in the truth, and the part's class agrees with the truth;
//  - openings are cut into their host walls (no wall triangle covers the opening's interior);
//  - every BSC's back lies on its host wall or ceiling within 1 mm and inside its extent;
//  - rooms do not overlap;
//  - every door leaf lies at the angle the truth gives (within 0.5 deg; the direction of the
//    leaf's own width) and states match angles; a door with leaf_thickness 0 is a doorway
//    without a leaf.
// Errors are defects of the scene. Warnings are properties of the building the scene holds:
//  - a room not reachable from the first through open doors (lambda >= 90 deg) whose clear
//    width (opening width minus leaf thickness) is at least kMinClearDoorWidth (a locked room);
//  - a door leaf more than 3 cm narrower or wider than its opening.
// Pure function of its inputs; results are reported, never thrown.

#include <map>
#include <string>
#include <vector>

#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::scenes {

/// m: a 0.6 m robot plus 0.1 m margin.
inline constexpr double kMinClearDoorWidth = 0.7;

struct CheckReport {
  std::vector<std::string> errors;    ///< one line each; empty = the scene is valid
  std::vector<std::string> warnings;  ///< suspicious but allowed
  // Counts, for summaries.
  int rooms = 0, walls = 0, floors = 0, ceilings = 0, columns = 0, doors = 0, windows = 0;
  int doors_open = 0, doors_semi_open = 0, doors_closed = 0;
  int service_components = 0, furniture = 0;
  std::size_t triangles = 0;
  int unreachable_rooms = 0;  ///< rooms open doors do not reach from the first (warnings)

  bool ok() const { return errors.empty(); }
  /// Multi-line human-readable summary (counts, then errors and warnings).
  std::string Summary() const;
};

CheckReport CheckScene(const Scene& scene, const GroundTruth& truth);

/// Room id -> the rooms one step away through an open door of clear width >=
/// kMinClearDoorWidth or an open passage (in connection order; a room may repeat).
std::map<std::string, std::vector<std::string>> OpenDoorGraph(const GroundTruth& truth);

}  // namespace mopad::scenes
