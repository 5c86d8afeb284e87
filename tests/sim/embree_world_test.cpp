#include "sim/embree_world.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "common/frames.h"
#include "tests/sim/test_scenes.h"

namespace mopad::sim {
namespace {

using testing::AddQuad;
using testing::AddRoomBox;
using V = Eigen::Vector3f;

// Room [-5,5]^2 x [0,3] with a 1 m door leaf in the plane y = 0, x in [2, 3], hinged at x = 2.
struct DoorFixture {
  scenes::Scene scene;
  scenes::GroundTruth truth;
  DoorFixture() {
    AddRoomBox(scene, V(-5, -5, 0), V(5, 5, 3));
    AddQuad(scene, V(2, 0, 0), V(3, 0, 0), V(3, 0, 2), V(2, 0, 2), scenes::ElementClass::kDoorLeaf,
            "door_1");
    scenes::Opening o;
    o.id = "door_1";
    o.type = scenes::OpeningType::kDoor;
    o.hinge_point = Eigen::Vector3d(2, 0, 0);
    o.hinge_axis = Eigen::Vector3d::UnitZ();
    o.opening_angle = 0.0;
    truth.openings.push_back(o);
  }
};

TEST(EmbreeWorld, RayHitsTheNearestSurfaceWithItsPartAndNormal) {
  scenes::Scene s;
  AddRoomBox(s, V(-2, -3, -1), V(4, 5, 2));
  EmbreeWorld world(std::move(s));
  const RayHit h = world.Intersect(V(0, 0, 0), V(1, 0, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 4.0f, 1e-6f);
  EXPECT_EQ(world.scene().parts[h.part].element_id, "wall_e");
  EXPECT_NEAR(std::abs(h.normal.x()), 1.0f, 1e-6f);
  EXPECT_EQ(h.door, -1);
  EXPECT_EQ(world.ElementIds()[world.ElementIndex(h.part)], "wall_e");
  // Rays respect [t_near, t_far].
  EXPECT_FALSE(world.Intersect(V(0, 0, 0), V(1, 0, 0), 0.0f, 3.9f).hit());
}

TEST(EmbreeWorld, PacketsAgreeWithSingleRays) {
  scenes::Scene s;
  AddRoomBox(s, V(-2, -3, -1), V(4, 5, 2));
  AddQuad(s, V(1, -1, -1), V(1, 1, -1), V(1, 1, 1), V(1, -1, 1), scenes::ElementClass::kFurniture,
          "panel");
  EmbreeWorld world(std::move(s));
  std::vector<Eigen::Vector3f> o, d;
  for (int i = 0; i < 37; ++i) {  // not a multiple of 16: a partial packet
    const float a = 0.17f * i;
    o.push_back(V(0.1f, 0.2f, 0.3f));
    d.push_back(V(std::cos(a), std::sin(a), 0.1f * std::sin(3 * a)).normalized());
  }
  std::vector<RayHit> hits(o.size());
  world.IntersectMany(o, d, 0.0f, 1e30f, hits);
  for (std::size_t i = 0; i < o.size(); ++i) {
    const RayHit h = world.Intersect(o[i], d[i]);
    EXPECT_EQ(h.part, hits[i].part);
    EXPECT_FLOAT_EQ(h.t, hits[i].t);
  }
}

TEST(EmbreeWorld, DoorAngleChangeMovesHits) {
  DoorFixture f;
  EmbreeWorld world(f.scene, &f.truth);
  ASSERT_EQ(world.DoorIds(), std::vector<std::string>{"door_1"});
  // Closed: a ray from the south at x = 2.5 meets the leaf at y = 0.
  RayHit h = world.Intersect(V(2.5f, -3, 1), V(0, 1, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 3.0f, 1e-5f);
  EXPECT_EQ(h.door, 0);
  EXPECT_EQ(world.scene().parts[h.part].element_class, scenes::ElementClass::kDoorLeaf);
  // Open 90 deg: the leaf now lies in x = 2, y in [0, 1]; the ray passes to the north wall.
  world.SetDoorAngle("door_1", DegToRad(90));
  EXPECT_NEAR(world.DoorAngle("door_1"), DegToRad(90), 1e-12);
  h = world.Intersect(V(2.5f, -3, 1), V(0, 1, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 8.0f, 1e-5f);
  EXPECT_EQ(h.door, -1);
  // ... and a ray along +x at y = 0.5 meets the leaf at x = 2, its normal rotated to +-x.
  h = world.Intersect(V(0, 0.5f, 1), V(1, 0, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 2.0f, 1e-5f);
  EXPECT_EQ(h.door, 0);
  EXPECT_NEAR(std::abs(h.normal.x()), 1.0f, 1e-5f);
  // Half open (45 deg): the leaf edge is at (2 + cos45, sin45).
  world.SetDoorAngle("door_1", DegToRad(45));
  const float c = std::sqrt(0.5f);
  h = world.Intersect(V(2 + 0.5f * c, -3, 1), V(0, 1, 0));
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 3.0f + 0.5f * c, 1e-4f);
  EXPECT_THROW(world.SetDoorAngle("nope", 0.1), InputError);
}

TEST(EmbreeWorld, LeafWithoutHingeIsStatic) {
  DoorFixture f;
  EmbreeWorld world(f.scene);  // no truth
  EXPECT_TRUE(world.DoorIds().empty());
  const RayHit h = world.Intersect(V(2.5f, -3, 1), V(0, 1, 0));
  EXPECT_NEAR(h.t, 3.0f, 1e-5f);
  EXPECT_EQ(h.door, -1);
}

TEST(EmbreeWorld, RejectsBadGeometry) {
  scenes::Scene s;
  s.source = "bad.glb";
  AddQuad(s, V(0, 0, 0), V(1, 0, 0), V(1, 1, 0), V(0, 1, 0), scenes::ElementClass::kFloor, "f");
  s.parts[0].triangles.push_back(Eigen::Vector3i(0, 1, 7));
  try {
    EmbreeWorld world(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.glb: error:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  s.parts[0].triangles.pop_back();
  s.parts[0].positions[2].x() = std::nanf("");
  EXPECT_THROW(EmbreeWorld{s}, InputError);
}

TEST(EmbreeWorld, EmptySceneMissesEverything) {
  EmbreeWorld world(scenes::Scene{});
  EXPECT_FALSE(world.Intersect(V(0, 0, 0), V(1, 0, 0)).hit());
}

}  // namespace
}  // namespace mopad::sim
