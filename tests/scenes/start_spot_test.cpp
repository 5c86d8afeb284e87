// The harness's start: chosen from the scene (a closet or a room cut off is never it), checked
// when given (in a wall or outside the building: one line naming the nearest free spot).
#include "scenes/start_spot.h"

#include <gtest/gtest.h>

#include <string>

#include "common/error.h"
#include "common/polygon.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {
namespace {

// R1 a 1.4 x 1.4 m closet (first in the truth: the old default start), R2 a 6 x 5 m hall, R3 a
// 4 x 5 m office off the hall, R4 a 7 x 5 m store larger than the hall whose only door is shut.
GeneratedScene ClosetHallOfficeStore() {
  const std::string yaml = R"(
name: closet_hall
seed: 3
storey_height: 3.0
ceiling_height: 2.7
wall_thickness: 0.2
rooms:
  - id: R1
    polygon: [[0, 3.6], [1.4, 3.6], [1.4, 5], [0, 5]]
  - id: R2
    polygon: [[1.6, 0], [7.6, 0], [7.6, 5], [1.6, 5]]
  - id: R3
    polygon: [[7.8, 0], [11.8, 0], [11.8, 5], [7.8, 5]]
  - id: R4
    polygon: [[1.6, 5.2], [8.6, 5.2], [8.6, 10.2], [1.6, 10.2]]
doors:
  - {id: D1, between: [R1, R2], at: [1.5, 4.3], swing_into: R2, hinge: left, angle_deg: 90}
  - {id: D2, between: [R2, R3], at: [7.7, 2.5], swing_into: R3, hinge: left, angle_deg: 90}
  - {id: D3, between: [R2, R4], at: [4.6, 5.1], swing_into: R4, hinge: left, angle_deg: 0}
furniture:
  - {room: R2, type: desk, count: 2}
)";
  return Generate(ParseSceneSpec(yaml, "closet_hall"));
}

TEST(StartSpot, TheLargestConnectedRoomIsChosenNeverTheClosetNorARoomCutOff) {
  const GeneratedScene g = ClosetHallOfficeStore();
  const RobotFootprint robot;
  const StartSpot s = ChooseStart(g.scene, g.truth, robot);
  EXPECT_EQ(s.room, "R2") << s.how;
  EXPECT_TRUE(PointInPolygon(Eigen::Vector2d(s.X_WB.x, s.X_WB.y), g.truth.rooms[1].polygon));
  EXPECT_GE(s.clearance, robot.TurnRadius());
  EXPECT_NE(s.how.find("of the 3 of 4 rooms"), std::string::npos) << s.how;
  // Free where it says, and a pure function of the scene.
  const FreeSpace space(g.scene, g.truth, robot);
  EXPECT_TRUE(space.Free({s.X_WB.x, s.X_WB.y}));
  EXPECT_EQ(space.Problem(s.X_WB), "");
  const StartSpot again = ChooseStart(g.scene, g.truth, robot);
  EXPECT_EQ(again.X_WB.x, s.X_WB.x);
  EXPECT_EQ(again.X_WB.y, s.X_WB.y);
  EXPECT_EQ(again.how, s.how);
  // The room mission's start lies in its room.
  const StartSpot closet = StartInRoom(g.scene, g.truth, robot, "R1");
  EXPECT_TRUE(PointInPolygon(Eigen::Vector2d(closet.X_WB.x, closet.X_WB.y),
                             g.truth.rooms[0].polygon));
}

TEST(StartSpot, AGivenStartInAWallOrOutsideIsOneLineNamingTheNearestFreeSpot) {
  const GeneratedScene g = ClosetHallOfficeStore();
  const RobotFootprint robot;
  auto message = [&](const Pose2& X) {
    try {
      CheckStart(g.scene, g.truth, robot, X);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // In the wall between hall and office (x 7.6-7.8, away from the door).
  const std::string wall = message(Pose2{7.7, 4.2, 0.0});
  EXPECT_EQ(wall.rfind("--start 7.70,4.20,0.0: error: in collision with the scene (wall_", 0), 0u)
      << wall;
  EXPECT_NE(wall.find("; nearest free spot "), std::string::npos) << wall;
  EXPECT_EQ(wall.find('\n'), std::string::npos) << wall;
  // Outside the building.
  const std::string out = message(Pose2{20.0, 20.0, 0.0});
  EXPECT_NE(out.find("outside the building"), std::string::npos) << out;
  EXPECT_NE(out.find("nearest free spot"), std::string::npos) << out;
  // The nearest free spot it names is a start the check accepts.
  const std::size_t at = wall.find("nearest free spot ") + 18;
  const double x = std::stod(wall.substr(at));
  const double y = std::stod(wall.substr(wall.find(',', at) + 1));
  const StartSpot ok = CheckStart(g.scene, g.truth, robot, Pose2{x, y, 0.0});
  EXPECT_EQ(ok.how, "given by --start");
  EXPECT_FALSE(ok.room.empty());
}

}  // namespace
}  // namespace mopad::scenes
