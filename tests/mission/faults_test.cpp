// The world's injected faults (mission/faults.h) on the simulated robot: each against the same
// robot without it, on scenes/two_rooms_door.yaml (R1 [0,5]x[0,4], R2 [5.2,10]x[0,4], door D1
// at (5.1, 2)); the `faults:` config section; an all-off section changes nothing.
#include "mission/faults.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "common/error.h"
#include "common/params.h"
#include "mission/floor_job.h"
#include "mission/sim_robot.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "tests/input_error_of.h"

namespace mopad::mission {
namespace {

using test_support::InputErrorOf;

sim::EmbreeWorld MakeWorld() {
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  scenes::GeneratedScene g = scenes::Generate(spec);
  const scenes::GroundTruth truth = g.truth;
  return sim::EmbreeWorld(std::move(g.scene), &truth);
}

const sim::EmbreeWorld& World() {
  static const sim::EmbreeWorld world = MakeWorld();
  return world;
}

constexpr double kScanStepDeg = 2.0;  // coarse: the tests need the grid, not the detail
const Pose2 kStart{1.5, 2.0, 0.0};

std::size_t ValidReturns(const interfaces::TlsScan& s) {
  std::size_t n = 0;
  for (const auto& p : s.points) n += p.valid();
  return n;
}

// The base driven straight ahead at 0.3 m/s for `seconds`; the steps' "new top sweep" flags.
std::vector<bool> Drive(SimRobot& robot, double seconds) {
  std::vector<bool> top_new;
  const int steps = static_cast<int>(std::lround(seconds / robot.ControlPeriod()));
  for (int k = 0; k < steps; ++k) top_new.push_back(robot.Step({0.3, 0.0}));
  return top_new;
}

TEST(Faults, AreOffByDefaultAndAnAllOffSectionLoadsToTheDefaults) {
  const FaultParams none;
  EXPECT_FALSE(none.Any());
  EXPECT_FALSE(none.LrfSilentAt(0.0));
  EXPECT_FALSE(none.SlipAt(0.0));
  EXPECT_EQ(ScanFaultOf(none, 0), ScanFault::kNone);
  const FloorMissionParams p = LoadParams<FloorMissionParams>(
      LoadYamlString("faults: {tls_empty_scans: [], lrf_silent_at: -1}\n", "c.yaml"), "c.yaml");
  EXPECT_FALSE(p.room.faults.Any());
  EXPECT_EQ(YAML::Dump(SaveParams(p)), YAML::Dump(SaveParams(FloorMissionParams{})));
}

TEST(Faults, TheConfigSectionParsesAndRefusesAFaultThatCannotAct) {
  const std::string yaml =
      "faults:\n"
      "  tls_empty_scans: [3]\n"
      "  tls_partial_scans: [5, 7]\n"
      "  tls_partial_fraction: 0.25\n"
      "  lrf_silent_at: 40\n"
      "  lrf_silent_for: 5\n"
      "  slip_at: 60\n"
      "  slip_for: 4\n"
      "  slip_factor: 1.5\n"
      "  kidnap_at: 90\n";
  const FloorMissionParams p =
      LoadParams<FloorMissionParams>(LoadYamlString(yaml, "f.yaml"), "f.yaml");
  EXPECT_NO_THROW(ValidateParams(p, "room."));
  const FaultParams& f = p.room.faults;
  EXPECT_TRUE(f.Any());
  EXPECT_EQ(ScanFaultOf(f, 3), ScanFault::kEmpty);
  EXPECT_EQ(ScanFaultOf(f, 7), ScanFault::kPartial);
  EXPECT_EQ(ScanFaultOf(f, 4), ScanFault::kNone);
  EXPECT_TRUE(f.LrfSilentAt(40.0) && f.LrfSilentAt(44.9) && !f.LrfSilentAt(45.0));
  EXPECT_TRUE(f.SlipAt(62.0) && !f.SlipAt(59.9));
  EXPECT_DOUBLE_EQ(f.kidnap_distance, 0.5);

  // Unknown keys and out-of-range values are input errors with the file and line.
  EXPECT_NE(InputErrorOf([] {
              LoadParams<FloorMissionParams>(LoadYamlString("faults: {kidnap_in: 3}\n", "f.yaml"),
                                             "f.yaml");
            }).find("f.yaml:1: error: unknown key 'faults.kidnap_in'"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([] {
              LoadParams<FloorMissionParams>(
                  LoadYamlString("faults:\n  tls_empty_scans: [-2]\n", "f.yaml"), "f.yaml");
            }).find("parameter 'faults.tls_empty_scans' out of range"),
            std::string::npos);
  // A fault switched on that could not act is refused before any work, naming the field.
  FloorMissionParams q;
  q.room.faults.lrf_silent_at = 10.0;
  EXPECT_EQ(InputErrorOf([&] { ValidateParams(q, "room."); }),
            "room.faults: error: parameter 'lrf_silent_for' must be positive when lrf_silent_at "
            "is set; got 0, expected (0, 1e6] s");
  q = {};
  q.room.faults.door_close_id = "D3";
  EXPECT_NE(InputErrorOf([&] {
              ValidateParams(q, "room.");
            }).find("'door_close_id' and 'door_close_at' go together"),
            std::string::npos);
  q = {};
  q.room.faults.slip_at = 1.0;
  q.room.faults.slip_for = 2.0;
  EXPECT_NE(InputErrorOf([&] { ValidateParams(q, "room."); }).find("'slip_factor' of 1 is no slip"),
            std::string::npos);
}

// Every ```yaml block of docs/reliability.md is a mission config that loads and validates.
TEST(Faults, TheReliabilityPagesExampleLoads) {
  std::ifstream in(std::string(MOPAD_SOURCE_DIR) + "/docs/reliability.md");
  ASSERT_TRUE(in);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  int blocks = 0;
  for (std::size_t at = text.find("```yaml\n"); at != std::string::npos;
       at = text.find("```yaml\n", at + 1)) {
    const std::size_t begin = at + 8, end = text.find("```", begin);
    ASSERT_NE(end, std::string::npos);
    const std::string name = "docs/reliability.md#" + std::to_string(++blocks);
    const FloorMissionParams p =
        LoadParams<FloorMissionParams>(LoadYamlString(text.substr(begin, end - begin), name), name);
    EXPECT_NO_THROW(ValidateParams(p, "room.")) << name;
    EXPECT_TRUE(p.room.faults.Any()) << name;
  }
  EXPECT_GE(blocks, 1);
}

// With every fault off the simulated robot is the one it was: the same scans and odometry.
TEST(Faults, AnAllOffSectionChangesNothing) {
  SimRobot plain(World(), DriveParams{}, kStart, 3);
  FaultParams off;
  off.tls_partial_fraction = 0.5;  // a parameter of a fault that is off
  off.kidnap_distance = 2.0;
  SimRobot with_off(World(), DriveParams{}, kStart, 3, off);
  const interfaces::TlsScan a = plain.Scan(kScanStepDeg, nullptr);
  const interfaces::TlsScan b = with_off.Scan(kScanStepDeg, nullptr);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i)
    ASSERT_EQ(a.points[i].range, b.points[i].range) << i;
  EXPECT_EQ(Drive(plain, 2.0), Drive(with_off, 2.0));
  EXPECT_EQ(plain.WheelOdometry().X_OB.x, with_off.WheelOdometry().X_OB.x);
  EXPECT_EQ(plain.TruePoseInWorld().x, with_off.TruePoseInWorld().x);
  EXPECT_EQ(plain.TopSweep().ranges, with_off.TopSweep().ranges);
  EXPECT_TRUE(with_off.FaultEvents().empty());
}

TEST(Faults, AnEmptyScanReturnsNothingAndAPartialScanOnlyItsFirstColumns) {
  FaultParams f;
  f.tls_empty_scans = {1};
  f.tls_partial_scans = {2};
  f.tls_partial_fraction = 1.0 / 3.0;
  SimRobot plain(World(), DriveParams{}, kStart, 3);
  SimRobot faulty(World(), DriveParams{}, kStart, 3, f);
  for (int k = 0; k < 3; ++k) {
    const interfaces::TlsScan a = plain.Scan(kScanStepDeg, nullptr);
    const interfaces::TlsScan b = faulty.Scan(kScanStepDeg, nullptr);
    ASSERT_EQ(a.points.size(), b.points.size());
    ASSERT_GT(ValidReturns(a), a.points.size() / 2) << "a closed room returns most pulses";
    if (k == 0) {
      EXPECT_EQ(ValidReturns(b), ValidReturns(a));
    } else if (k == 1) {
      EXPECT_EQ(ValidReturns(b), 0u);
    }
    if (k == 2) {
      const std::uint32_t kept = b.columns / 3;
      std::size_t first_third = 0;
      for (std::size_t i = 0; i < a.points.size(); ++i) {
        const auto& pa = a.points[i];
        const auto& pb = b.points[i];
        EXPECT_EQ(pb.row, pa.row);
        EXPECT_EQ(pb.column, pa.column);
        if (pa.column < kept) {
          EXPECT_EQ(pb.range, pa.range);
          first_third += pa.valid();
        } else {
          EXPECT_FALSE(pb.valid());
          EXPECT_EQ(pb.x, 0.0f);
        }
      }
      EXPECT_EQ(ValidReturns(b), first_third);
      EXPECT_GT(first_third, 0u);
    }
  }
  // The truth sidecar says a surface was there and nothing was reported.
  const sim::TlsTruth& t = faulty.ScanTruths().at(1);
  std::size_t dropped = 0;
  for (const auto& p : t.points) dropped += (p.flags & sim::kTruthDropped) != 0;
  EXPECT_GT(dropped, t.points.size() / 2);
  ASSERT_EQ(faulty.FaultEvents().size(), 2u);
  EXPECT_NE(faulty.FaultEvents()[0].find("TLS scan 1 returned nothing"), std::string::npos);
  EXPECT_NE(faulty.FaultEvents()[1].find("TLS scan 2 returned only the first 0.333"),
            std::string::npos);
}

TEST(Faults, SilentLrfsDeliverNoNewSweepForTheirDuration) {
  FaultParams f;
  f.lrf_silent_at = 0.5;
  f.lrf_silent_for = 1.0;
  SimRobot plain(World(), DriveParams{}, kStart, 3);
  SimRobot faulty(World(), DriveParams{}, kStart, 3, f);
  plain.Scan(kScanStepDeg, nullptr);
  faulty.Scan(kScanStepDeg, nullptr);
  const std::vector<bool> a = Drive(plain, 2.0), b = Drive(faulty, 2.0);
  int silent_new = 0, plain_new = 0, after_new = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double t = (k + 1) * plain.ControlPeriod();
    if (t < 0.5 - 1e-9) continue;
    if (t < 1.5 - 1e-9) {
      silent_new += b[k];
      plain_new += a[k];
    } else {
      after_new += b[k];
    }
  }
  EXPECT_GT(plain_new, 20);  // 40 Hz for 1 s
  EXPECT_EQ(silent_new, 0);
  EXPECT_GT(after_new, 10);
  // The last sweep the robot holds is the newest: after the silence it is fresh again.
  EXPECT_NEAR(faulty.TopSweep().timestamp, faulty.Time(), 0.05);
  // The body moved the same: silence is of the sensors, not of the wheels.
  EXPECT_EQ(plain.TruePoseInWorld().x, faulty.TruePoseInWorld().x);
  ASSERT_EQ(faulty.FaultEvents().size(), 2u);
  EXPECT_NE(faulty.FaultEvents()[0].find("LRFs silent"), std::string::npos);
}

TEST(Faults, SlippingWheelsReportTheirFactorTimesTheMotionOnlyWhileTheySlip) {
  FaultParams f;
  f.slip_at = 0.51;  // between two control steps (20 ms)
  f.slip_for = 1.0;
  f.slip_factor = 2.0;
  DriveParams p;
  p.body.odometry = {};  // exact odometry: the slip alone makes the difference
  SimRobot plain(World(), p, kStart, 3);
  SimRobot faulty(World(), p, kStart, 3, f);
  Drive(plain, 0.5);
  Drive(faulty, 0.5);
  const double x_before = faulty.WheelOdometry().X_OB.x;
  EXPECT_EQ(x_before, plain.WheelOdometry().X_OB.x);
  Drive(plain, 1.0);
  Drive(faulty, 1.0);
  const double true_motion = plain.WheelOdometry().X_OB.x - x_before;
  EXPECT_GT(true_motion, 0.2);
  EXPECT_NEAR(faulty.WheelOdometry().X_OB.x - x_before, 2.0 * true_motion, 1e-9);
  const double x_after = faulty.WheelOdometry().X_OB.x;
  Drive(plain, 1.0);
  Drive(faulty, 1.0);
  // After the slip the wheels report the motion again (the error made stays).
  EXPECT_NEAR(faulty.WheelOdometry().X_OB.x - x_after,
              plain.WheelOdometry().X_OB.x - (x_before + true_motion), 1e-9);
  EXPECT_EQ(plain.TruePoseInWorld().x, faulty.TruePoseInWorld().x);
  EXPECT_EQ(faulty.FaultEvents().size(), 2u);
}

TEST(Faults, AKidnapPushesTheBaseWhileTheOdometrySaysNothing) {
  FaultParams f;
  f.kidnap_at = 0.2;
  SimRobot plain(World(), DriveParams{}, kStart, 3);
  SimRobot faulty(World(), DriveParams{}, kStart, 3, f);
  for (int k = 0; k < 20; ++k) {
    plain.Step({0.0, 0.0});
    faulty.Step({0.0, 0.0});
  }
  const Pose2 a = plain.TruePoseInWorld(), b = faulty.TruePoseInWorld();
  EXPECT_NEAR(std::hypot(b.x - a.x, b.y - a.y), 0.5, 0.05);  // the room has space around kStart
  EXPECT_EQ(b.yaw, a.yaw);
  EXPECT_EQ(faulty.WheelOdometry().X_OB.x, plain.WheelOdometry().X_OB.x);
  EXPECT_EQ(faulty.WheelOdometry().X_OB.y, plain.WheelOdometry().X_OB.y);
  ASSERT_EQ(faulty.FaultEvents().size(), 1u);
  EXPECT_NE(faulty.FaultEvents()[0].find("0.20 s: fault: kidnap: the base pushed"),
            std::string::npos)
      << faulty.FaultEvents()[0];
  // The direction comes from the seed: the same seed, the same push.
  SimRobot again(World(), DriveParams{}, kStart, 3, f);
  for (int k = 0; k < 20; ++k) again.Step({0.0, 0.0});
  EXPECT_EQ(again.TruePoseInWorld().x, b.x);
  EXPECT_EQ(again.TruePoseInWorld().y, b.y);
}

// The door fault swings the leaf shut in the world: the rays meet it and the base stops at it.
// A robot standing in the doorway keeps it open; each new robot finds it as the scene has it.
TEST(Faults, ADoorThatClosesIsSeenAndFeltAndWaitsForTheBaseToLeaveItsSwing) {
  scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml"));
  const scenes::GroundTruth truth = g.truth;
  sim::EmbreeWorld world(std::move(g.scene), &truth);
  const DoorFaultWorld door{&world, *truth.FindOpening("D1")};
  FaultParams f;
  f.door_close_id = "D1";
  f.door_close_at = 0.2;
  DriveParams p;
  p.body.odometry = {};
  auto ahead = [&](double x) {  // m to the first surface along +x at 1 m height, y = 2
    return world.Intersect(Eigen::Vector3f(float(x), 2.0f, 1.0f), Eigen::Vector3f::UnitX()).t;
  };
  EXPECT_GT(ahead(4.0), 5.0f);                          // through the open door to R2's far wall
  const double leaf_plane = door.door.hinge_point.x();  // the leaf shuts on R2's wall face
  {
    SimRobot control(world, p, {4.4, 2.0, 0.0}, 3);  // without the fault it drives through
    for (int k = 0; k < 250; ++k) control.Step({0.3, 0.0});
    EXPECT_GT(control.TruePoseInWorld().x, leaf_plane + 0.5);
  }
  {
    SimRobot robot(world, p, {4.4, 2.0, 0.0}, 3, f, door);
    for (int k = 0; k < 10; ++k) robot.Step({0.0, 0.0});
    EXPECT_NEAR(world.DoorAngle("D1"), 0.0, 1e-12);
    EXPECT_LT(ahead(4.0), 1.3f);  // the leaf in the door's wall (x 5 .. 5.2)
    // Driving on, the base stops at the closed leaf instead of passing.
    for (int k = 0; k < 250; ++k) robot.Step({0.3, 0.0});
    EXPECT_LT(robot.TruePoseInWorld().x + 0.3, leaf_plane);  // the front of the base, stopped
    DriveResult r;
    robot.FillResult(r);
    EXPECT_GE(r.contacts, 1);
    ASSERT_EQ(robot.FaultEvents().size(), 1u);
    EXPECT_NE(robot.FaultEvents()[0].find("fault: door D1 closed"), std::string::npos);
  }
  {
    // A new robot finds the door as the scene has it; standing in the doorway, it keeps it open.
    SimRobot robot(world, p, {5.1, 2.0, 0.0}, 3, f, door);
    EXPECT_NEAR(world.DoorAngle("D1"), DegToRad(90.0), 1e-12);
    for (int k = 0; k < 20; ++k) robot.Step({0.0, 0.0});
    EXPECT_NEAR(world.DoorAngle("D1"), DegToRad(90.0), 1e-12);
    ASSERT_EQ(robot.FaultEvents().size(), 1u);
    EXPECT_NE(robot.FaultEvents()[0].find("cannot close yet"), std::string::npos);
    for (int k = 0; k < 100; ++k) robot.Step({-0.3, 0.0});  // backs out of the doorway
    EXPECT_NEAR(world.DoorAngle("D1"), 0.0, 1e-12);
  }
  FaultParams unknown = f;
  unknown.door_close_id = "D7";
  sim::SceneWorld mw;
  mw.truth = truth;
  mw.world = std::make_unique<sim::EmbreeWorld>(
      scenes::Generate(
          scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml"))
          .scene,
      &truth);
  EXPECT_EQ(InputErrorOf([&] { DoorFaultOf(mw, unknown); }),
            "faults: error: parameter 'door_close_id' names no door with a leaf; got 'D7', "
            "expected one of D1");
  EXPECT_FALSE(DoorFaultOf(mw, FaultParams{}).has_value());
}

// Near a wall the push ends at the nearest free pose it can slide to, never through the wall.
TEST(Faults, AKidnapTargetInAWallEndsAtTheNearestFreePoseOnThisSide) {
  // A wall along x = 5: free where x + 0.3 < 5 (half the footprint's length beyond the axle).
  auto free = [](const Pose2& p) { return p.x + 0.3 < 5.0; };
  Pose2 to;
  ASSERT_TRUE(KidnapTarget({4.5, 2.0, 0.0}, 0.0, 0.5, free, &to));
  EXPECT_LT(to.x + 0.3, 5.0);
  EXPECT_GT(to.x, 4.6);  // pushed towards the wall as far as it goes, within a ring step
  EXPECT_TRUE(KidnapTarget({1.0, 2.0, 0.0}, 0.0, 0.5, free, &to));
  EXPECT_DOUBLE_EQ(to.x, 1.5);
  // Nothing free within the search radius: no push.
  EXPECT_FALSE(KidnapTarget(
      {1.0, 2.0, 0.0}, 0.0, 0.5, [](const Pose2&) { return false; }, &to));
  // A target beyond a thin wall is not reached through it.
  auto wall = [](const Pose2& p) { return std::abs(p.x - 1.25) > 0.35; };
  ASSERT_TRUE(KidnapTarget({0.5, 2.0, 0.0}, 0.0, 0.5, wall, &to));
  EXPECT_LT(to.x, 0.9);
}

}  // namespace
}  // namespace mopad::mission
