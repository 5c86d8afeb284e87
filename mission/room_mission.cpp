#include "mission/room_mission.h"

namespace mopad::mission {

DriveParams RoomMissionParams::DefaultDrive() {
  DriveParams p;
  // Inside one room every NBS candidate lies in mapped free space: no scan-and-go stops (they
  // would be scans the room model never sees).
  p.navigator.max_scans = 1;
  p.navigator.register_scans = false;  // the room loop registers against its own S(t-1)
  return p;
}

}  // namespace mopad::mission
