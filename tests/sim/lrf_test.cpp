#include "sim/lrf.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>

#include "tests/sim/test_scenes.h"

namespace mopad::sim {
namespace {

using testing::AddMaterial;
using testing::AddRoomBox;
using testing::BoxExitDistance;
using V = Eigen::Vector3f;

TEST(Lrf, ProfilesMatchTheDataSheets) {
  scenes::Scene s;
  EmbreeWorld world(std::move(s));
  LrfSimulator hokuyo(world, LrfProfile("hokuyo_utm30lx"));
  EXPECT_EQ(hokuyo.beams(), 1081);
  LrfSimulator sick(world, LrfProfile("sick_lms111"));
  EXPECT_EQ(sick.beams(), 541);
  EXPECT_EQ(LrfSimulator(world, LrfProfile("sick_lms111_fine")).beams(), 1081);
  EXPECT_DOUBLE_EQ(LrfProfile("sick_lms111").beam_divergence_mrad, 15.0);
  EXPECT_EQ(PaperLrfRig().size(), 2u);
}

TEST(Lrf, NoiseFreeRangesAreAnalyticInABoxRoom) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  AddRoomBox(s, V(-4, -3, 0), V(5, 6, 3), 0);
  EmbreeWorld world(std::move(s));
  LrfParams p = LrfProfile("hokuyo_utm30lx").NoiseFree();
  p.mount_xyz = {0.1, 0.0, 0.3};
  LrfSimulator lrf(world, p);
  Pose3 X_WB = Pose3::Identity();
  X_WB.translation() = Eigen::Vector3d(0.5, 1.0, 0.0);
  X_WB.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto scan = lrf.Scan(X_WB, 1, 0, 0.0);
  ASSERT_EQ(scan.ranges.size(), 1081u);
  const Pose3 X_WL = X_WB * p.X_BL();
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = scan.angle_min + i * scan.angle_increment;
    const Eigen::Vector3d d = X_WL.linear() * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    const double t = BoxExitDistance(X_WL.translation(), d, Eigen::Vector3d(-4, -3, 0),
                                     Eigen::Vector3d(5, 6, 3));
    EXPECT_NEAR(scan.ranges[i], t, 1e-4) << i;
  }
}

TEST(Lrf, OpenSpaceGivesMaxRangeReadings) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  // Only a wall 50 m away (beyond range_max) and a floor below the scan plane.
  testing::AddQuad(s, V(50, -100, -5), V(50, 100, -5), V(50, 100, 5), V(50, -100, 5),
                   scenes::ElementClass::kWall, "far", 0);
  EmbreeWorld world(std::move(s));
  LrfSimulator lrf(world, LrfProfile("hokuyo_utm30lx"));
  const auto scan = lrf.Scan(Pose3::Identity(), 1, 0, 0.0);
  for (float r : scan.ranges) EXPECT_EQ(r, 30.0f);
}

TEST(Lrf, NoiseMatchesTheProfile) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  AddRoomBox(s, V(-4, -4, 0), V(4, 4, 3), 0);
  EmbreeWorld world(std::move(s));
  LrfParams p = LrfProfile("hokuyo_utm30lx");
  p.dropouts = false;
  const LrfSimulator noisy(world, p), clean(world, p.NoiseFree());
  double sum2 = 0;
  std::size_t n = 0;
  const auto truth = clean.Scan(Pose3::Identity(), 1, 0, 0.0);
  for (int k = 0; k < 200; ++k) {
    const auto scan = noisy.Scan(Pose3::Identity(), 1, static_cast<std::uint64_t>(k), 0.025 * k);
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      const double e = scan.ranges[i] - truth.ranges[i];
      sum2 += e * e;
      ++n;
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.03, 0.003);  // all ranges < 10 m: sigma_near
  // Same seed and seq: identical sweep; another seq: different noise.
  EXPECT_EQ(noisy.Scan(Pose3::Identity(), 1, 3, 0).ranges,
            noisy.Scan(Pose3::Identity(), 1, 3, 0).ranges);
  EXPECT_NE(noisy.Scan(Pose3::Identity(), 1, 3, 0).ranges,
            noisy.Scan(Pose3::Identity(), 1, 4, 0).ranges);
}

TEST(Lrf, SickFootprintStillMeasuresAFlatWall) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  AddRoomBox(s, V(-4, -4, 0), V(4, 4, 3), 0);
  EmbreeWorld world(std::move(s));
  LrfParams p = LrfProfile("sick_lms111").NoiseFree();
  const auto scan = LrfSimulator(world, p).Scan(Pose3::Identity(), 1, 0, 0.0);
  const std::size_t ahead = scan.ranges.size() / 2;  // angle 0: the east wall at 4 m
  EXPECT_NEAR(scan.ranges[ahead], 4.0, 2e-3);
}

// A sweep is traced and measured in parallel (packets and beams split between threads): the
// same bytes on one thread and on two, with a footprint of 7 sub-rays and with one ray, in a
// room with an opening (misses) and a pillar (mixed footprints).
TEST(Lrf, TheSameBytesOnOneThreadAndOnTwo) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  testing::AddRoomWithOpening(s, 6, 5, 3, 1.5f, 3.0f, 0.0f, 2.0f, 0);
  AddRoomBox(s, V(2.0f, 3.0f, 0), V(2.3f, 3.3f, 3), 0);  // a pillar
  EmbreeWorld world(std::move(s));
  for (const char* profile : {"sick_lms111", "hokuyo_utm30lx"}) {
    const LrfSimulator lrf(world, LrfProfile(profile));
    const Pose3 X_WB = Pose3(Eigen::Translation3d(1.5, 2.0, 0.0));
    interfaces::LrfScan one, two;
    tbb::task_arena(1).execute([&] { one = lrf.Scan(X_WB, 7, 11, 0.0); });
    tbb::task_arena(2).execute([&] { two = lrf.Scan(X_WB, 7, 11, 0.0); });
    EXPECT_EQ(one.ranges, two.ranges) << profile;
    EXPECT_EQ(one.intensities, two.intensities) << profile;
    int returns = 0;
    for (float r : one.ranges) returns += r < one.range_max;
    EXPECT_GT(returns, 100) << profile;
    EXPECT_LT(returns, static_cast<int>(one.ranges.size())) << profile;  // the opening
  }
}

}  // namespace
}  // namespace mopad::sim
