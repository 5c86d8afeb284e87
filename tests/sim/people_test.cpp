// People walking (sim/people.h) and the world's movers (EmbreeWorld::AddMovers): people stay on
// the free floor of their room, give way to the robot, walk the same way from the same seed,
// and their scan track is what their steps do; a ray meets a mover where the track puts it at
// the ray's time; a scan sees a person as points of class kPerson with their element id.

#include "sim/people.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/polygon.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/tls_scanner.h"

namespace mopad::sim {
namespace {

scenes::GeneratedScene Office() {
  return scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
}

// The office as a world, with its truth.
struct OfficeWorld {
  scenes::GeneratedScene g = Office();
  EmbreeWorld world{scenes::Scene(g.scene), &g.truth};
};

PeopleParams Walkers(int count, double pause_mean) {
  PeopleParams p;
  p.count = count;
  p.pause_mean = pause_mean;
  return p;
}

const scenes::Room& RoomById(const scenes::GroundTruth& truth, const std::string& id) {
  for (const auto& r : truth.rooms)
    if (r.id == id) return r;
  throw std::runtime_error("no room " + id);
}

TEST(People, WalkOnTheFreeFloorOfTheirOwnRoomAndReallyWalk) {
  const OfficeWorld o;
  const auto& [g, world] = o;
  const PeopleParams p = Walkers(5, 2.0);
  const Vec2 robot(-100.0, -100.0);  // far away: nobody gives way
  People people(world, g.truth, p, 7, robot);
  ASSERT_EQ(people.size(), 5u);
  std::vector<MoverPose> last = people.Poses();
  std::vector<double> walked(people.size(), 0.0);
  int checked = 0;
  for (int step = 0; step < 6000; ++step) {  // 5 minutes at 0.05 s
    people.Step(0.05, robot);
    const std::vector<MoverPose> now = people.Poses();
    for (std::size_t i = 0; i < now.size(); ++i) {
      walked[i] += std::hypot(now[i].x - last[i].x, now[i].y - last[i].y);
      EXPECT_LE(std::hypot(now[i].x - last[i].x, now[i].y - last[i].y), 2.5 * 1.2 * 0.05 + 1e-9);
      if (step % 50) continue;
      const scenes::Room& room = RoomById(g.truth, people.RoomOf(i));
      ASSERT_TRUE(PointInPolygon(Vec2(now[i].x, now[i].y), room.polygon))
          << "person " << i << " left " << room.id << " at step " << step;
      // Nothing solid within the person's radius at knee and hip height.
      for (int k = 0; k < 8; ++k) {
        const float a = static_cast<float>(k * kPi / 4.0);
        for (float z : {0.4f, 0.9f}) {
          const RayHit h = world.Intersect(
              Eigen::Vector3f(static_cast<float>(now[i].x), static_cast<float>(now[i].y),
                              static_cast<float>(room.floor_z) + z),
              Eigen::Vector3f(std::cos(a), std::sin(a), 0.0f));
          EXPECT_GE(h.t, 0.2f) << "person " << i << " at step " << step << " direction " << k << " "
                               << world.Part(h.part).element_id << " z " << z << " at " << now[i].x
                               << "," << now[i].y;
          ++checked;
        }
      }
    }
    last = now;
  }
  EXPECT_GT(checked, 1000);
  for (std::size_t i = 0; i < walked.size(); ++i)
    EXPECT_GT(walked[i], 20.0) << "person " << i << " hardly walked";
}

TEST(People, GiveWayToTheRobotAndWalkAlikeFromTheSameSeed) {
  const OfficeWorld o;
  const auto& [g, world] = o;
  PeopleParams p = Walkers(3, 1.0);
  p.clearance = 1.2;
  People people(world, g.truth, p, 11, Vec2(-100.0, -100.0));
  People twin(world, g.truth, p, 11, Vec2(-100.0, -100.0));
  // The robot stands in the middle of the first person's room.
  const scenes::Room& room = RoomById(g.truth, people.RoomOf(0));
  Vec2 robot = Vec2::Zero();
  for (const Vec2& q : room.polygon) robot += q;
  robot /= static_cast<double>(room.polygon.size());
  double closest = 1e9;
  for (int step = 0; step < 4000; ++step) {
    const std::vector<MoverPose> before = people.Poses();
    people.Step(0.05, robot);
    twin.Step(0.05, robot);
    const std::vector<MoverPose> after = people.Poses();
    for (std::size_t i = 0; i < after.size(); ++i) {
      const double d0 = std::hypot(before[i].x - robot.x(), before[i].y - robot.y());
      const double d1 = std::hypot(after[i].x - robot.x(), after[i].y - robot.y());
      // Inside the clearance nobody steps closer.
      if (d1 < p.clearance) EXPECT_GE(d1, d0 - 1e-12) << "person " << i << " at step " << step;
      closest = std::min(closest, d1);
    }
  }
  EXPECT_GT(closest, 0.5);
  const std::vector<MoverPose> a = people.Poses(), b = twin.Poses();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].yaw, b[i].yaw);
  }
  People other(world, g.truth, p, 12, Vec2(-100.0, -100.0));
  EXPECT_NE(other.Poses()[0].x, People(world, g.truth, p, 11, Vec2(-100, -100)).Poses()[0].x);
}

TEST(People, TheirScanTrackIsWhatTheirStepsDo) {
  const OfficeWorld o;
  const auto& [g, world] = o;
  const PeopleParams p = Walkers(4, 0.5);
  const Vec2 robot(-100.0, -100.0);
  People people(world, g.truth, p, 3, robot);
  const double dt = 0.05;
  const int knots = 9;
  const auto track = people.Track(4.0, dt, knots, robot);  // a knot every 10 steps
  ASSERT_EQ(track.size(), 4u);
  for (int step = 0; step <= 80; ++step) {
    if (step % 10 == 0) {
      const std::vector<MoverPose> now = people.Poses();
      for (std::size_t i = 0; i < now.size(); ++i) {
        const MoverPose& k = track[i][static_cast<std::size_t>(step / 10)];
        EXPECT_NEAR(k.x, now[i].x, 1e-9);
        EXPECT_NEAR(k.y, now[i].y, 1e-9);
        EXPECT_NEAR(std::remainder(k.yaw - now[i].yaw, 2 * kPi), 0.0, 1e-9);
      }
    }
    people.Step(dt, robot);
  }
}

TEST(Movers, ARayMeetsAMoverWhereItsTrackPutsItAtTheRaysTime) {
  scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml"));
  EmbreeWorld world(std::move(g.scene), &g.truth);
  const std::int32_t scene_parts = world.PartCount();
  const PeopleParams p = Walkers(1, 4.0);
  People people(world, g.truth, p, 1, Vec2(-100, -100));
  world.AddMovers(people.Models());
  EXPECT_EQ(world.MoverCount(), 1u);
  EXPECT_EQ(world.PartCount(), scene_parts + 3);
  EXPECT_EQ(world.ElementIds().back(), "person_1");
  // In R1 ([0, 5] x [0, 4]) from x = 1 to x = 4 over 10 s, facing +x.
  world.SetMoverTrack(0.0, 10.0, {{{1.0, 2.0, 0.0}, {4.0, 2.0, 0.0}}});
  const Eigen::Vector3f from(2.5f, 0.5f, 1.2f), up(0.0f, 1.0f, 0.0f);  // at the torso's height
  const RayHit at_start = world.Intersect(from, up, 0.0f, 10.0f, 0.0);
  const RayHit midway = world.Intersect(from, up, 0.0f, 10.0f, 5.0);
  ASSERT_TRUE(at_start.hit());
  ASSERT_TRUE(midway.hit());
  EXPECT_LT(world.Part(at_start.part).element_class, scenes::ElementClass::kPerson);
  EXPECT_EQ(world.Part(midway.part).element_class, scenes::ElementClass::kPerson);
  EXPECT_EQ(world.ElementIds()[static_cast<std::size_t>(world.ElementIndex(midway.part))],
            "person_1");
  // The arm's outer side, 0.30 m from the centre across the shoulders; it faces the ray.
  EXPECT_NEAR(from.y() + midway.t, 1.70, 0.02);
  EXPECT_LT(midway.normal.dot(up), -0.9f);
  // Packets see it alike, and at the end of the track the person is at x = 4.
  std::vector<Eigen::Vector3f> o(3, from), d(3, up);
  o[2] = Eigen::Vector3f(4.0f, 0.5f, 1.2f);
  std::vector<RayHit> hits(3);
  world.IntersectMany(o, d, 0.0f, 10.0f, hits, 5.0);
  EXPECT_EQ(hits[0].part, midway.part);
  EXPECT_FLOAT_EQ(hits[0].t, midway.t);
  EXPECT_NE(world.Part(hits[2].part).element_class, scenes::ElementClass::kPerson);
  world.IntersectMany(o, d, 0.0f, 10.0f, hits, 20.0);
  EXPECT_EQ(world.Part(hits[2].part).element_class, scenes::ElementClass::kPerson);
  // Turned by 90 deg to face away, the person shows the ray their back, 0.13 m off centre.
  world.SetMoverTrack(0.0, 0.0, {{{2.5, 2.0, kPi / 2}}});
  const RayHit side = world.Intersect(from, up, 0.0f, 10.0f, 0.0);
  ASSERT_EQ(world.Part(side.part).element_class, scenes::ElementClass::kPerson);
  EXPECT_NEAR(from.y() + side.t, 2.0 - 0.13, 0.02);
  EXPECT_LT(side.normal.dot(up), -0.9f);
}

TEST(Movers, AScanSeesAWalkingPersonAsPointsOfTheirOwnClass) {
  scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml"));
  EmbreeWorld world(std::move(g.scene), &g.truth);
  TlsParams tp = TlsParams{}.NoiseFree();
  tp.step_deg = 0.5;
  ScanRequest req;
  req.X_WB.translation() = Eigen::Vector3d(1.0, 1.0, 0.0);
  TlsTruth empty_truth;
  const interfaces::TlsScan empty = TlsScanner(world, tp).Scan(req, &empty_truth);
  const PeopleParams p = Walkers(1, 4.0);
  People people(world, g.truth, p, 1, Vec2(-100, -100));
  world.AddMovers(people.Models());
  const TlsScanner scanner(world, tp);
  const double duration = static_cast<double>(scanner.pulses()) / tp.pulse_rate_hz;
  // Walking across R1 at 3 m from the scanner while the head turns towards them (from azimuth
  // 0 up): from azimuth 39 deg down to -8 deg, met near 34 deg.
  world.SetMoverTrack(0.0, duration, {{{4.0, 3.4, -kPi / 2}, {4.0, 0.6, -kPi / 2}}});
  TlsTruth truth;
  const interfaces::TlsScan scan = scanner.Scan(req, &truth);
  ASSERT_EQ(scan.points.size(), empty.points.size());
  int person = 0, other_changed = 0;
  for (std::size_t i = 0; i < truth.points.size(); ++i) {
    const TlsPointTruth& t = truth.points[i];
    if (t.element_class == static_cast<std::uint8_t>(scenes::ElementClass::kPerson)) {
      ++person;
      EXPECT_EQ(truth.element_ids[static_cast<std::size_t>(t.element)], "person_1");
      EXPECT_LT(scan.points[i].range, empty.points[i].range);
    } else if (scan.points[i].range != empty.points[i].range) {
      ++other_changed;
    }
  }
  EXPECT_TRUE(truth.movers);
  EXPECT_FALSE(empty_truth.movers);
  // A person is about 0.45 m wide by 1.75 m at about 3 m: some 8 x 33 deg of the sphere at the
  // scan's 0.5 deg step, a few hundred points; where they are depends on when the head looked.
  EXPECT_GT(person, 100);
  EXPECT_LT(person, 2000);
  EXPECT_EQ(other_changed, 0);
}

}  // namespace
}  // namespace mopad::sim
