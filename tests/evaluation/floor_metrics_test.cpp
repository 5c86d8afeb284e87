// The floor model's evaluation (evaluation/metrics_floor.h) on two rooms built in code with a
// known thickness error and door offset.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/error.h"
#include "evaluation/metrics_floor.h"

namespace mopad::evaluation {
namespace {

using modelling::StructuralModel;
using modelling::StructuralPatch;

// A wall from a to b with its room on the left of a -> b, 2.8 m high.
StructuralPatch Wall(const std::string& id, Vec2 a, Vec2 b) {
  StructuralPatch p;
  p.id = id;
  const Vec3 A(a.x(), a.y(), 0), B(b.x(), b.y(), 0);
  const Vec3 d = (B - A).normalized();
  p.plane.n = Vec3(-d.y(), d.x(), 0);
  p.plane.d = -p.plane.n.dot(A);
  p.polygon = {B, A, A + Vec3(0, 0, 2.8), B + Vec3(0, 0, 2.8)};
  return p;
}

StructuralModel Room(const std::string& name, double x0, double y0, double x1, double y1) {
  StructuralModel m;
  m.room = name;
  const Vec2 c[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  for (int k = 0; k < 4; ++k)
    m.patches.push_back(Wall("wall_" + std::to_string(k + 1), c[k], c[(k + 1) % 4]));
  return m;
}

modelling::DetectedOpening Door(const std::string& host, double x0, double x1, double y) {
  modelling::DetectedOpening o;
  o.id = "opening_1";
  o.host = host;
  o.corners = {Vec3(x0, y, 0), Vec3(x1, y, 0), Vec3(x1, y, 2), Vec3(x0, y, 2)};
  o.confidence = 0.9;
  return o;
}

// Truth: A [0, 4] x [0, 3] and B [0, 4] x [3.2, 6] in the world, a door at x 1..2 between
// them. The model, in a map frame X_WM away: B 1 cm further from A than the truth (the wall
// 0.21 m thick, B's offset (0, 0.01)), B's side of the door 2 cm along the wall from A's.
TEST(FloorEvaluation, ThicknessErrorAndDoorOffsetAreTheRoomsMisalignment) {
  FloorTruth truth;
  for (const StructuralModel& r : {Room("A", 0, 0, 4, 3), Room("B", 0, 3.2, 4, 6)})
    for (const StructuralPatch& p : r.patches) {
      truth.faces.push_back(Patch{r.room + "/" + p.id, SurfaceClass::kWall, p.polygon, p.plane.n});
      truth.face_rooms.push_back(r.room);
    }
  truth.doors.push_back({"D1", {"A", "B"}, Vec3(1.5, 3.1, 1.0)});

  Pose3 X_WM = Pose3::Identity();
  X_WM.linear() = Eigen::AngleAxisd(0.5, Vec3::UnitZ()).toRotationMatrix();
  X_WM.translation() = Vec3(2, -1, 0);
  const Pose3 X_MW = X_WM.inverse();
  std::vector<StructuralModel> sm3 = {Room("room_1", 0, 0, 4, 3), Room("room_2", 0, 3.21, 4, 6.01)};
  std::vector<modelling::Sm4Model> sm4 = {{"room_1", {Door("wall_3", 1.0, 2.0, 3.0)}},
                                          {"room_2", {Door("wall_1", 1.02, 2.02, 3.21)}}};
  for (StructuralModel& m : sm3)
    for (StructuralPatch& p : m.patches) {
      for (Vec3& v : p.polygon) v = X_MW * v;
      p.plane.n = X_MW.linear() * p.plane.n;
      p.plane.d = -p.plane.n.dot(p.polygon[0]);
    }
  for (modelling::Sm4Model& m : sm4)
    for (Vec3& c : m.openings[0].corners) c = X_MW * c;
  const modelling::FloorModel model = modelling::BuildFloorModel(sm3, sm4);

  const FloorEvaluation e = EvaluateFloor(model, X_WM, {{"room_1", "A"}, {"room_2", "B"}}, truth);
  const ClassDetection& w = e.faces.detection[static_cast<int>(SurfaceClass::kWall)];
  EXPECT_EQ(w.n_truth, 8);
  EXPECT_EQ(w.tp, 8);
  EXPECT_EQ(w.fp, 0);
  EXPECT_EQ(e.walls, 7);
  EXPECT_EQ(e.two_sided_walls, 1);
  EXPECT_EQ(e.truth_pairs, 1);
  EXPECT_EQ(e.model_pairs, 1);
  EXPECT_EQ(e.correct_pairs, 1);
  EXPECT_EQ(e.truth_pairs_found, 1);
  EXPECT_NEAR(e.thickness_error.max, 0.01, 1e-9);
  EXPECT_NEAR(e.pairs.at(0).truth_thickness, 0.2, 1e-9);
  ASSERT_EQ(e.room_offsets.size(), 2u);
  EXPECT_TRUE(e.room_offsets[1].solved);
  EXPECT_EQ(e.room_offsets[1].faces, 4);
  EXPECT_NEAR((e.room_offsets[1].offset - Vec2(0, 0.01)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(e.room_offsets[0].offset.norm(), 0.0, 1e-9);
  EXPECT_EQ(e.room_alignment.n, 1);
  EXPECT_NEAR(e.room_alignment.max, 0.01, 1e-9);
  EXPECT_EQ(e.truth_doors, 1);
  EXPECT_EQ(e.merged_doors, 1);
  EXPECT_EQ(e.merged_correct, 1);
  EXPECT_EQ(e.one_sided_doors, 0);
  EXPECT_NEAR(e.door_side_offset.max, 0.02, 1e-9);
  EXPECT_EQ(e.doors.at(0).truth, "D1");
  // With the truth door elsewhere the merged door matches nothing.
  FloorTruth far = truth;
  far.doors[0].centre += Vec3(5, 0, 0);
  const FloorEvaluation f = EvaluateFloor(model, X_WM, {{"room_1", "A"}, {"room_2", "B"}}, far);
  EXPECT_EQ(f.merged_correct, 0);
  EXPECT_EQ(f.doors.at(0).truth, "");
  EXPECT_THROW(EvaluateFloor(model, X_WM, {{"room_1", "A"}}, truth), InputError);
}

}  // namespace
}  // namespace mopad::evaluation
