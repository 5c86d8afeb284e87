#include "suite/reachable_rooms.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace mopad::suite {

double DoorClearWidth(const scenes::Opening& door) {
  const double w = door.u1 - door.u0;
  const double lambda = std::min(M_PI / 2.0, door.opening_angle);
  return w - (w * std::cos(lambda) + door.leaf_thickness * std::sin(lambda));
}

std::set<std::string> ReachableRooms(const scenes::GroundTruth& truth,
                                     const std::string& start_room, double min_clear_width) {
  std::map<std::string, std::vector<std::string>> next;
  for (const scenes::RoomConnection& c : truth.connections) {
    if (c.room_a.empty() || c.room_b.empty()) continue;  // to the outside
    if (!c.door.empty()) {
      const scenes::Opening* d = truth.FindOpening(c.door);
      if (d == nullptr || d->state == scenes::DoorState::kClosed ||
          DoorClearWidth(*d) < min_clear_width)
        continue;
    }
    next[c.room_a].push_back(c.room_b);
    next[c.room_b].push_back(c.room_a);
  }
  std::set<std::string> reached;
  if (truth.FindRoom(start_room) == nullptr) return reached;
  std::vector<std::string> stack{start_room};
  reached.insert(start_room);
  while (!stack.empty()) {
    const std::string r = stack.back();
    stack.pop_back();
    for (const std::string& b : next[r])
      if (reached.insert(b).second) stack.push_back(b);
  }
  return reached;
}

}  // namespace mopad::suite
