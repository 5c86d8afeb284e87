// The floor model (modelling/floor_model.h) on synthetic rooms built in code: rectangular rooms
// whose walls are exact vertical rectangles, with analytic thicknesses and door positions.
#include "modelling/floor_model.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/error.h"
#include "modelling/model_io.h"

namespace mopad::modelling {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Plan transform applied to every point of a synthetic floor (rotation about z, then shift).
struct PlanPose {
  double yaw = 0.0;
  Vec2 shift = Vec2::Zero();
  Vec3 operator()(double x, double y, double z) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {c * x - s * y + shift.x(), s * x + c * y + shift.y(), z};
  }
};

// A wall from a to b (plan, before the pose) with its room on the left of a -> b.
StructuralPatch Wall(const std::string& id, Vec2 a, Vec2 b, const PlanPose& X) {
  StructuralPatch p;
  p.id = id;
  p.patch_class = PatchClass::kWall;
  const Vec3 A = X(a.x(), a.y(), 0), B = X(b.x(), b.y(), 0);
  const Vec3 d = (B - A).normalized();
  p.plane.n = Vec3(-d.y(), d.x(), 0);
  p.plane.d = -p.plane.n.dot(A);
  p.polygon = {B, A, A + Vec3(0, 0, 2.8), B + Vec3(0, 0, 2.8)};
  p.fitted = true;
  return p;
}

// A rectangular room [x0, x1] x [y0, y1]: walls south, east, north, west, then floor, ceiling.
StructuralModel Room(const std::string& name, double x0, double y0, double x1, double y1,
                     const PlanPose& X = {}) {
  StructuralModel m;
  m.room = name;
  m.ceiling_z = 2.8;
  const Vec2 c[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  for (int k = 0; k < 4; ++k)
    m.patches.push_back(Wall("wall_" + std::to_string(k + 1), c[k], c[(k + 1) % 4], X));
  StructuralPatch floor;
  floor.id = "floor";
  floor.patch_class = PatchClass::kFloor;
  for (int k = 0; k < 4; ++k) floor.polygon.push_back(X(c[k].x(), c[k].y(), 0));
  m.patches.push_back(floor);
  StructuralPatch ceiling = floor;
  ceiling.id = "ceiling";
  ceiling.patch_class = PatchClass::kCeiling;
  ceiling.plane.n = -Vec3::UnitZ();
  ceiling.plane.d = 2.8;
  for (Vec3& v : ceiling.polygon) v.z() = 2.8;
  m.patches.push_back(ceiling);
  return m;
}

// A door in `host` spanning plan x in [x0, x1] at plan y (before the pose), 2.0 m high.
DetectedOpening Door(const std::string& id, const std::string& host, double x0, double x1, double y,
                     double angle_deg, double confidence, const PlanPose& X = {}) {
  DetectedOpening o;
  o.id = id;
  o.type = OpeningType::kDoor;
  o.host = host;
  o.corners = {X(x0, y, 0), X(x1, y, 0), X(x1, y, 2.0), X(x0, y, 2.0)};
  o.opening_angle_deg = angle_deg;
  o.state =
      std::isfinite(angle_deg) ? DoorStateFromAngleDeg(angle_deg, 5.0, 2.0) : DoorState::kOpen;
  o.clear_width_m = 0.8;
  o.confidence = confidence;
  return o;
}

const FloorWall* WallWithFace(const FloorModel& m, const std::string& room,
                              const std::string& patch) {
  for (const FloorWall& w : m.walls)
    for (const WallFace& f : w.faces)
      if (f.room == room && f.patch.id == patch) return &w;
  return nullptr;
}

// Room A [0, 4] x [0, 3] and room B [0, 4] x [3.2, 6]: a 0.2 m wall between them (A's
// wall_3, B's wall_1) with a door at x 1..2 that A saw without its leaf and B with it.
struct TwoRooms {
  std::vector<StructuralModel> sm3;
  std::vector<Sm4Model> sm4;
  explicit TwoRooms(const PlanPose& X = {}, double gap = 0.2) {
    sm3 = {Room("A", 0, 0, 4, 3, X), Room("B", 0, 3 + gap, 4, 6, X)};
    sm4 = {Sm4Model{"A", {Door("opening_1", "wall_3", 1.0, 2.0, 3.0, NAN, 0.9, X)}},
           Sm4Model{"B", {Door("opening_1", "wall_1", 1.02, 2.02, 3 + gap, 90.0, 0.8, X)}}};
  }
};

void ExpectSharedWallAndOneDoor(const PlanPose& X) {
  const TwoRooms in(X);
  const FloorModel m = BuildFloorModel(in.sm3, in.sm4);
  ASSERT_EQ(m.walls.size(), 7u);  // 8 faces, two of them one wall
  const FloorWall* w = WallWithFace(m, "A", "wall_3");
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->faces.size(), 2u);
  EXPECT_EQ(w, WallWithFace(m, "B", "wall_1"));
  EXPECT_NEAR(w->thickness, 0.2, 1e-9);
  ASSERT_EQ(w->pairs.size(), 1u);
  EXPECT_NEAR(w->pairs[0].thickness, 0.2, 1e-9);
  EXPECT_NEAR(w->pairs[0].overlap, 4.0, 1e-9);
  EXPECT_EQ(w->faces[0].side, 1);
  EXPECT_EQ(w->faces[1].side, -1);
  // The axis plane is y = 3.1 in the rooms' own plan; the extent spans the wall.
  EXPECT_NEAR(w->plane.n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(w->plane.Distance(X(2.0, 3.1, 1.0)), 0.0, 1e-9);
  EXPECT_NEAR(std::abs(w->plane.n.dot(X(0, 1, 0) - X(0, 0, 0))), 1.0, 1e-9);
  ASSERT_EQ(w->polygon.size(), 4u);
  EXPECT_NEAR((w->polygon[1] - w->polygon[0]).norm(), 4.0, 1e-9);
  EXPECT_NEAR((w->polygon[2] - w->polygon[1]).norm(), 2.8, 1e-9);
  for (const Vec3& v : w->polygon) EXPECT_NEAR(w->plane.Distance(v), 0.0, 1e-9);
  // One door, both rooms, taken from B (it saw the leaf), its corners on the axis plane.
  ASSERT_EQ(m.openings.size(), 1u);
  const FloorOpening& d = m.openings[0];
  EXPECT_EQ(d.rooms, (std::vector<std::string>{"B", "A"}));
  EXPECT_EQ(d.opening.host, w->id);
  EXPECT_EQ(d.opening.state, DoorState::kOpen);
  EXPECT_DOUBLE_EQ(d.opening.opening_angle_deg, 90.0);
  EXPECT_DOUBLE_EQ(d.opening.confidence, 0.8);
  EXPECT_NEAR((d.opening.corners[0] - X(1.02, 3.1, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((d.opening.corners[2] - X(2.02, 3.1, 2.0)).norm(), 0.0, 1e-9);
  // The outer walls keep unknown thickness and their own face.
  const FloorWall* south = WallWithFace(m, "A", "wall_1");
  ASSERT_NE(south, nullptr);
  EXPECT_FALSE(south->TwoSided());
  EXPECT_TRUE(std::isnan(south->thickness));
  EXPECT_EQ(south->polygon, in.sm3[0].patches[0].polygon);
  // Floors and ceilings stay per room.
  ASSERT_EQ(m.rooms.size(), 2u);
  EXPECT_EQ(m.rooms[1].room, "B");
  ASSERT_EQ(m.rooms[1].patches.size(), 2u);
  EXPECT_EQ(m.rooms[1].patches[0].patch_class, PatchClass::kFloor);
}

TEST(FloorModel, SharedWallWithADoorSeenFromBothRoomsIsOneWallOfItsThicknessAndOneDoor) {
  ExpectSharedWallAndOneDoor({});
}

TEST(FloorModel, SharedWallAt45DegreesIsOneWallOfItsThicknessAndOneDoor) {
  ExpectSharedWallAndOneDoor({kPi / 4, Vec2(3.0, -7.0)});
}

TEST(FloorModel, ParallelWallsTooFarApartStaySeparate) {
  const TwoRooms in({}, 0.8);  // 0.8 m between the faces, over max_thickness 0.5
  const FloorModel m = BuildFloorModel(in.sm3, in.sm4);
  EXPECT_EQ(m.walls.size(), 8u);
  for (const FloorWall& w : m.walls) EXPECT_FALSE(w.TwoSided()) << w.id;
  EXPECT_EQ(m.openings.size(), 2u);
  for (const FloorOpening& o : m.openings) EXPECT_EQ(o.rooms.size(), 1u);
}

TEST(FloorModel, FacesFrontToFrontAreNotOneWall) {
  // A's north face (y = 3, facing -y) and B's south face (y = 2.8, facing +y) are antiparallel
  // and 0.2 m apart, but each lies in front of the other: no wall is between them.
  std::vector<StructuralModel> sm3 = {Room("A", 0, 0, 4, 3), Room("B", 0, 2.8, 4, 6)};
  const FloorModel m = BuildFloorModel(sm3, {});
  EXPECT_EQ(m.walls.size(), 8u);
}

TEST(FloorModel, AHallWallFacingTwoOfficesIsOneWallWithThreeFaces) {
  const std::vector<StructuralModel> sm3 = {Room("H", 0, 0, 10, 2), Room("R3", 0, 2.2, 4.9, 6),
                                            Room("R4", 5.1, 2.2, 10, 6)};
  const FloorModel m = BuildFloorModel(sm3, {});
  const FloorWall* w = WallWithFace(m, "H", "wall_3");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->faces.size(), 3u);
  EXPECT_EQ(w->pairs.size(), 2u);
  EXPECT_NEAR(w->thickness, 0.2, 1e-9);
  EXPECT_EQ(w, WallWithFace(m, "R4", "wall_1"));
  // R3's east and R4's west faces are another wall.
  const FloorWall* v = WallWithFace(m, "R3", "wall_2");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v, WallWithFace(m, "R4", "wall_4"));
  EXPECT_NEAR(v->thickness, 0.2, 1e-9);
  EXPECT_EQ(m.walls.size(), 12u - 3u);
}

TEST(FloorModel, DoorsThatDoNotOverlapAlongTheWallStayTwo) {
  TwoRooms in;
  in.sm4[1].openings[0] = Door("opening_1", "wall_1", 2.6, 3.4, 3.2, 90.0, 0.8);
  const FloorModel m = BuildFloorModel(in.sm3, in.sm4);
  EXPECT_EQ(m.openings.size(), 2u);
}

TEST(FloorModel, FilesRoundTripAndAreDeterministic) {
  const TwoRooms in({kPi / 6, Vec2(1, 2)});
  const FloorModel m = BuildFloorModel(in.sm3, in.sm4);
  const std::string s3 = FloorSm3Json(m), s4 = FloorSm4Json(m);
  EXPECT_EQ(s3, FloorSm3Json(BuildFloorModel(in.sm3, in.sm4)));
  const FloorModel back = ParseFloorModel(s3, "sm3.json", s4, "sm4.json");
  EXPECT_EQ(FloorSm3Json(back), s3);
  EXPECT_EQ(FloorSm4Json(back), s4);
  EXPECT_NE(s3.find("\"thickness_m\": null"), std::string::npos);
  EXPECT_NE(s3.find("\"known_side\": \"A\""), std::string::npos);
}

TEST(FloorModel, FloorFilesAreSm3AndSm4FilesOfTheFloorWithUniqueIds) {
  // The exports read floor/ with ParseSm3/ParseSm4 as the floor's SM3/SM4 (docs/exports.md).
  TwoRooms in;
  for (StructuralModel& r : in.sm3) {
    StructuralPatch c = r.patches[0];
    c.id = "column_1_face_1";
    c.patch_class = PatchClass::kColumn;
    r.patches.push_back(c);
  }
  const FloorModel m = BuildFloorModel(in.sm3, in.sm4);
  const StructuralModel sm3 = ParseSm3(FloorSm3Json(m), "sm3.json");
  EXPECT_EQ(sm3.room, "floor");
  std::vector<std::string> ids;
  for (const StructuralPatch& p : sm3.patches) ids.push_back(p.id);
  EXPECT_EQ(
      ids, (std::vector<std::string>{"wall_1", "wall_2", "wall_3", "wall_4", "wall_5", "wall_6",
                                     "wall_7", "floor_1", "ceiling_1", "column_1_face_1", "floor_2",
                                     "ceiling_2", "column_2_face_1"}));
  const Sm4Model sm4 = ParseSm4(FloorSm4Json(m), "sm4.json");
  ASSERT_EQ(sm4.openings.size(), 1u);
  EXPECT_EQ(sm4.openings[0].host, WallWithFace(m, "A", "wall_3")->id);
  // Read back as a floor model, the rooms keep their own patch ids.
  const FloorModel back = ParseFloorModel(FloorSm3Json(m), "sm3.json", FloorSm4Json(m), "sm4.json");
  ASSERT_EQ(back.rooms.size(), 2u);
  EXPECT_EQ(back.rooms[1].patches.back().id, "column_1_face_1");
  EXPECT_EQ(FloorSm3Json(back), FloorSm3Json(m));
  // A room's own sm3.json is not a floor model.
  EXPECT_THROW(ParseFloorModel(Sm3Json(in.sm3[0]), "sm3.json", FloorSm4Json(m), "sm4.json"),
               InputError);
}

TEST(FloorModel, BadInputIsAClearError) {
  TwoRooms in;
  in.sm4[0].openings[0].host = "floor";
  try {
    BuildFloorModel(in.sm3, in.sm4);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("host 'floor' is not a wall"), std::string::npos)
        << e.what();
  }
  TwoRooms twice;
  twice.sm3[1].room = "A";
  EXPECT_THROW(BuildFloorModel(twice.sm3, {}), InputError);
  FloorModelParams p;
  p.min_thickness = 0.6;
  EXPECT_THROW(BuildFloorModel(in.sm3, {}, p), InputError);
  const std::string s3 = FloorSm3Json(BuildFloorModel(TwoRooms().sm3, TwoRooms().sm4));
  std::string bad = s3;
  bad.replace(bad.find("\"thickness_m\": null"), 19, "\"thickness_m\": 0.3");
  EXPECT_THROW(ParseFloorModel(bad, "sm3.json", FloorSm4Json({}), "sm4.json"), InputError);
}

TEST(FloorModel, ADoorSeenFromTwoRoomsHasTheBetterObservedSidesStateInBoth) {
  // A saw the doorway without a leaf and read it closed; B saw the leaf at 90 deg.
  TwoRooms in;
  in.sm4[0].openings[0].state = DoorState::kClosed;
  in.sm4[0].openings[0].clear_width_m = 0.0;
  std::vector<Sm4Model> sm4 = in.sm4;
  EXPECT_EQ(ShareDoors(BuildFloorModel(in.sm3, in.sm4), sm4), std::vector<std::string>{"A"});
  const DetectedOpening& a = sm4[0].openings[0];
  EXPECT_EQ(a.state, DoorState::kOpen);
  EXPECT_DOUBLE_EQ(a.opening_angle_deg, 90.0);
  EXPECT_DOUBLE_EQ(a.clear_width_m, 0.8);
  EXPECT_EQ(a.state_from, "B");
  EXPECT_TRUE(a.found_from.empty());
  EXPECT_EQ(a.own_state, DoorState::kClosed);
  EXPECT_TRUE(std::isnan(a.own_opening_angle_deg));
  EXPECT_DOUBLE_EQ(a.own_clear_width_m, 0.0);
  EXPECT_EQ(a.corners, in.sm4[0].openings[0].corners);  // the hole stays this room's
  EXPECT_TRUE(sm4[1].openings[0].state_from.empty());
  // Written and read back with both readings.
  const Sm4Model back = ParseSm4(Sm4Json(sm4[0]), "sm4.json");
  EXPECT_EQ(Sm4Json(back), Sm4Json(sm4[0]));
  EXPECT_EQ(back.openings[0].state_from, "B");
  EXPECT_EQ(back.openings[0].own_state, DoorState::kClosed);
  // Both measured the leaf and agree on the state: each keeps its own angle.
  TwoRooms both;
  both.sm4[0].openings[0].opening_angle_deg = 89.0;
  sm4 = both.sm4;
  EXPECT_TRUE(ShareDoors(BuildFloorModel(both.sm3, both.sm4), sm4).empty());
  EXPECT_DOUBLE_EQ(sm4[0].openings[0].opening_angle_deg, 89.0);
  EXPECT_TRUE(sm4[0].openings[0].state_from.empty());
}

TEST(FloorModel, ADoorFoundFromOneRoomIsOnTheOtherFaceOfItsWallToo) {
  // B found the door; A (its leaf stood in front of the doorway) did not.
  TwoRooms in;
  in.sm4[0].openings.clear();
  std::vector<Sm4Model> sm4 = in.sm4;
  EXPECT_EQ(ShareDoors(BuildFloorModel(in.sm3, in.sm4), sm4), std::vector<std::string>{"A"});
  ASSERT_EQ(sm4[0].openings.size(), 1u);
  const DetectedOpening& a = sm4[0].openings[0];
  EXPECT_EQ(a.id, "opening_1");
  EXPECT_EQ(a.host, "wall_3");
  EXPECT_EQ(a.found_from, "B");
  EXPECT_EQ(a.state, DoorState::kOpen);
  EXPECT_DOUBLE_EQ(a.opening_angle_deg, 90.0);
  // On A's face (y = 3), B's (u0, v0) corner second: counter-clockwise seen from A.
  const auto& b = in.sm4[1].openings[0].corners;
  EXPECT_NEAR((a.corners[0] - Vec3(b[1].x(), 3.0, b[1].z())).norm(), 0.0, 1e-9);
  EXPECT_NEAR((a.corners[1] - Vec3(b[0].x(), 3.0, b[0].z())).norm(), 0.0, 1e-9);
  EXPECT_NEAR((a.corners[2] - Vec3(b[3].x(), 3.0, b[3].z())).norm(), 0.0, 1e-9);
  // The same turn seen from A as B's corners seen from B.
  auto turn = [](const std::array<Vec3, 4>& c, const Vec3& n) {
    return (c[1] - c[0]).cross(c[2] - c[1]).dot(n);
  };
  EXPECT_DOUBLE_EQ(turn(a.corners, in.sm3[0].patches[2].plane.n),
                   turn(b, in.sm3[1].patches[0].plane.n));
  const Sm4Model back = ParseSm4(Sm4Json(sm4[0]), "sm4.json");
  EXPECT_EQ(back.openings[0].found_from, "B");
  EXPECT_EQ(Sm4Json(back), Sm4Json(sm4[0]));
  // A wall face that already has an opening there, or a door beyond the face, gets none.
  TwoRooms taken;
  taken.sm4[0].openings[0].type = OpeningType::kWindow;
  sm4 = taken.sm4;
  EXPECT_TRUE(ShareDoors(BuildFloorModel(taken.sm3, taken.sm4), sm4).empty());
  TwoRooms narrow;
  narrow.sm3[0] = Room("A", 1.5, 0, 4, 3);
  narrow.sm4[0].openings.clear();
  sm4 = narrow.sm4;
  EXPECT_TRUE(ShareDoors(BuildFloorModel(narrow.sm3, narrow.sm4), sm4).empty());
  // A door on an outer wall has no other face.
  TwoRooms outer;
  outer.sm4[0].openings[0] = Door("opening_1", "wall_1", 1.0, 2.0, 0.0, 90.0, 0.9);
  outer.sm4[1].openings.clear();
  sm4 = outer.sm4;
  EXPECT_TRUE(ShareDoors(BuildFloorModel(outer.sm3, outer.sm4), sm4).empty());
}

}  // namespace
}  // namespace mopad::modelling
