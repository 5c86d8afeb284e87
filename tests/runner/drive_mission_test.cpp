// `mopad drive`'s closed loop on scenes/two_rooms_door.yaml: R1 [0,5]x[0,4] and R2
// [5.2,10]x[0,4] joined by door D1 at (5.1, 2). The robot starts in R1 and must reach R2.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "runner/drive_mission.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"

namespace mopad::runner {
namespace {

namespace fs = std::filesystem;

sim::EmbreeWorld MakeWorld(double door_angle_deg) {
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  for (auto& d : spec.doors) d.angle_deg = door_angle_deg;
  scenes::GeneratedScene g = scenes::Generate(spec);
  const scenes::GroundTruth truth = g.truth;
  return sim::EmbreeWorld(std::move(g.scene), &truth);
}

DriveRequest Request(std::uint64_t seed) {
  DriveRequest r;
  r.X_WB_start = Pose2{1.5, 2.0, 0.0};
  r.X_WB_goal = Pose2{8.0, 2.0, 0.0};
  r.seed = seed;
  return r;
}

DriveParams Params() {
  DriveParams p;
  p.max_time = 150.0;
  return p;
}

void Print(const char* what, const DriveResult& r) {
  std::printf("[%s] %s: %s\n  final error %.3f m / %.2f deg, localisation RMS %.4f m max %.4f m, "
              "contacts %d, path %.2f m, %d TLS scans, sim %.1f s, wall %.2f s (%.1fx real time)\n",
              what, ToString(r.status), r.message.c_str(), r.goal_error_xy, r.goal_error_yaw_deg,
              r.loc_rms, r.loc_max, r.contacts, r.path_length, r.tls_scans, r.sim_time, r.wall_time,
              r.RealTimeFactor());
}

TEST(DriveMission, ArrivesThroughOpenDoorAndIsDeterministic) {
  const sim::EmbreeWorld world = MakeWorld(90.0);
  const DriveResult a = RunDrive(world, Params(), Request(5));
  Print("open door, seed 5", a);
  EXPECT_EQ(a.status, DriveStatus::kArrived) << a.message;
  EXPECT_LE(a.goal_error_xy, 0.10);
  EXPECT_LE(a.goal_error_yaw_deg, 5.0);
  EXPECT_EQ(a.contacts, 0);
  EXPECT_LE(a.loc_rms, 0.03);
  EXPECT_LE(a.loc_max, 0.10);
  // The robot crossed into R2 (map frame: start at the origin, R2 beyond x = 3.7).
  ASSERT_FALSE(a.truth.empty());
  EXPECT_GT(a.truth.back().pose.x, 4.5);

  const DriveResult b = RunDrive(world, Params(), Request(5));
  EXPECT_EQ(ToTum(a.estimated), ToTum(b.estimated));
  EXPECT_EQ(ToTum(a.truth), ToTum(b.truth));
}

TEST(DriveMission, ClosedDoorEndsExplainedWithPartialTrajectory) {
  const sim::EmbreeWorld world = MakeWorld(0.0);
  const DriveResult r = RunDrive(world, Params(), Request(5));
  Print("closed door, seed 5", r);
  EXPECT_TRUE(r.status == DriveStatus::kUnreachable || r.status == DriveStatus::kBlocked)
      << ToString(r.status) << ": " << r.message;
  EXPECT_FALSE(r.message.empty());
  EXPECT_LT(r.sim_time, 150.0);  // bounded: decided well before the timeout
  EXPECT_EQ(r.contacts, 0);
  const fs::path dir = fs::temp_directory_path() / "mopad_drive_test_closed";
  fs::remove_all(dir);
  WriteDriveOutputs(r, Params(), Request(5), dir.string());
  for (const char* f : {"trajectory_estimated.tum", "trajectory_true.tum", "map.png", "map.yaml",
                        "map_path.png", "summary.json"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_GT(fs::file_size(dir / "trajectory_true.tum"), 100u);  // partial trajectory saved
}

}  // namespace
}  // namespace mopad::runner
