// mission::WriteFloorModel: floor/ from the robot's rooms, and an explained refusal that leaves
// no half-written floor/ behind.
#include "mission/floor_model_job.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "modelling/model_io.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;

autonomy::FloorRoom Room(const std::string& name, double y0, double y1) {
  autonomy::FloorRoom r;
  r.room = name;
  r.sm3.room = name;
  r.sm4.room = name;
  const Vec2 c[4] = {{0, y0}, {4, y0}, {4, y1}, {0, y1}};
  for (int k = 0; k < 4; ++k) {
    const Vec3 a(c[k].x(), c[k].y(), 0), b(c[(k + 1) % 4].x(), c[(k + 1) % 4].y(), 0);
    const Vec3 d = (b - a).normalized();
    modelling::StructuralPatch p;
    p.id = "wall_" + std::to_string(k + 1);
    p.plane.n = Vec3(-d.y(), d.x(), 0);
    p.plane.d = -p.plane.n.dot(a);
    p.polygon = {b, a, a + Vec3(0, 0, 2.8), b + Vec3(0, 0, 2.8)};
    r.sm3.patches.push_back(p);
  }
  return r;
}

TEST(FloorModelJob, WritesTheFloorOfTheModelledRoomsAndRefusesBadModelsExplained) {
  const std::string dir =
      (fs::temp_directory_path() / ("mopad_floor_model_job_" + std::to_string(::getpid())))
          .string();
  fs::remove_all(dir);
  autonomy::FloorScanResult mission;
  mission.rooms = {Room("room_1", 0, 3), Room("room_2", 3.2, 6), Room("room_3", 7, 9)};
  mission.rooms[2].error = "sm3: error: no points";  // a failed room is left out
  std::string said;
  auto progress = [&said](const std::string& line) { said += line + "\n"; };
  ASSERT_TRUE(WriteFloorModel(mission, {}, dir, progress)) << said;
  const modelling::FloorModel m = modelling::ReadFloorModel(dir + "/floor");
  EXPECT_EQ(m.rooms.size(), 2u);
  EXPECT_EQ(m.walls.size(), 7u);
  // An opening on a patch its room does not have: no floor/, and the reason said.
  mission.rooms[0].sm4.openings.emplace_back();
  mission.rooms[0].sm4.openings.back().id = "opening_1";
  mission.rooms[0].sm4.openings.back().host = "wall_9";
  EXPECT_FALSE(WriteFloorModel(mission, {}, dir, progress));
  EXPECT_FALSE(fs::exists(dir + "/floor"));
  EXPECT_NE(said.find("host 'wall_9' is not a wall"), std::string::npos) << said;
  fs::remove_all(dir);
}

TEST(FloorModelJob, ADoorOneRoomFoundIsSharedWithTheRoomBehindItsWall) {
  const std::string dir =
      (fs::temp_directory_path() / ("mopad_floor_model_job_share_" + std::to_string(::getpid())))
          .string();
  fs::remove_all(dir);
  autonomy::FloorScanResult mission;
  mission.rooms = {Room("room_1", 0, 3), Room("room_2", 3.2, 6)};
  modelling::DetectedOpening door;
  door.id = "opening_1";
  door.host = "wall_1";  // room_2's south wall, y = 3.2
  door.corners = {Vec3(2, 3.2, 0), Vec3(1, 3.2, 0), Vec3(1, 3.2, 2), Vec3(2, 3.2, 2)};
  door.state = modelling::DoorState::kSemiOpen;
  door.opening_angle_deg = 45.0;
  mission.rooms[1].sm4.openings = {door};
  ASSERT_TRUE(WriteFloorModel(mission, {}, dir));
  ASSERT_EQ(mission.rooms[1].sm4.openings.size(), 1u);  // the finder's own reading stays
  EXPECT_EQ(mission.rooms[1].sm4.openings[0].host, "wall_1");
  ASSERT_EQ(mission.rooms[0].sm4.openings.size(), 1u);
  EXPECT_EQ(mission.rooms[0].sm4.openings[0].host, "wall_3");
  EXPECT_EQ(mission.rooms[0].sm4.openings[0].found_from, "room_2");
  EXPECT_EQ(mission.rooms[0].sm4.openings[0].state, modelling::DoorState::kSemiOpen);
  // floor/ keeps each room's own reading: the door from room_2 only.
  const modelling::FloorModel m = modelling::ReadFloorModel(dir + "/floor");
  ASSERT_EQ(m.openings.size(), 1u);
  EXPECT_EQ(m.openings[0].rooms, std::vector<std::string>{"room_2"});
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mopad::mission
