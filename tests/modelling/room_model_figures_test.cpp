// Figures of the room model on generated scenes (scenes/*.yaml): per-point label agreement with
// the truth and the per-scan processing time at the scanner's full 0.2 deg resolution. Times
// are printed, never asserted.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>

#include "modelling/room_model.h"
#include "scenes/element_class.h"
#include "tests/modelling/sim_scans.h"

namespace mopad::modelling {
namespace {

using testing::SimScan;
using testing::TakeScan;

std::string SpecPath(const std::string& name) {
  return std::string(MOPAD_SOURCE_DIR) + "/scenes/" + name + ".yaml";
}

struct RoomRun {
  std::string room;
  std::vector<Vec2> positions;
};

// Scans each room from the given positions; returns label agreement with the truth.
// `pose_error`: the second and later scans get this registration error (translation along x and
// y, metres; yaw, radians), the acceptance bound of the registration.
void RunRooms(const std::string& spec, const std::vector<RoomRun>& runs, double step_deg,
              double min_agreement, double pose_error_m = 0.0, double pose_error_rad = 0.0) {
  const scenes::GeneratedScene g = scenes::Generate(scenes::LoadSceneSpec(SpecPath(spec)));
  const sim::EmbreeWorld world(g.scene, &g.truth);
  for (const RoomRun& run : runs) {
    const scenes::Room* room = nullptr;
    for (const auto& r : g.truth.rooms) {
      if (r.id == run.room) room = &r;
    }
    ASSERT_NE(room, nullptr) << run.room;
    RoomModel model;
    std::size_t agree = 0, total = 0;
    std::vector<SimScan> scans;
    for (std::size_t k = 0; k < run.positions.size(); ++k) {
      scans.push_back(TakeScan(world, testing::TestTls(step_deg), run.positions[k].x(),
                               run.positions[k].y(), k, 11));
      const auto t0 = std::chrono::steady_clock::now();
      Pose3 X_MS = scans.back().X_MS;
      if (k > 0) {
        X_MS.translation() += Vec3(pose_error_m, pose_error_m, 0.0) / std::sqrt(2.0);
        X_MS.linear() =
            Eigen::AngleAxisd(pose_error_rad, Vec3::UnitZ()).toRotationMatrix() * X_MS.linear();
      }
      model.AddScan(scans.back().scan, X_MS);
      const double dt =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf(
          "[figures] %s %s scan %zu: %zu points (total %zu), AddScan %.2f s, coverage %.3f\n",
          spec.c_str(), run.room.c_str(), k, scans.back().scan.points.size(), model.PointCount(),
          dt, model.Coverage().ratio);
    }
    int confusion[4][4] = {};
    std::map<std::string, int> wrong;  // "class truth->model" of disagreements
    for (const auto& s : scans) {
      const auto truth = testing::TruthLabels(s, g.scene, run.room, room->polygon);
      std::size_t k = 0;
      for (std::uint32_t c = 0; c < s.scan.columns; ++c) {
        for (std::uint32_t r = 0; r < s.scan.rows; ++r) {
          if (!s.scan.at(r, c).valid()) continue;
          const int m = static_cast<int>(model.Labels()[total + k]);
          agree += m == truth[k];
          ++confusion[truth[k]][m];
          if (m != truth[k]) {
            const auto& t = s.truth.at(r, c);
            const std::string cls =
                t.part >= 0 ? std::string(scenes::ToString(g.scene.parts[t.part].element_class))
                            : "none";
            ++wrong[cls + (t.flags & sim::kTruthTransmitted ? "(glass)" : "") + " " +
                    std::to_string(truth[k]) + "->" + std::to_string(m)];
          }
          ++k;
        }
      }
      total += truth.size();
    }
    for (const auto& [key, count] : wrong) {
      if (count * 1000 > static_cast<int>(total))
        std::printf("[figures]   disagreement %s: %d\n", key.c_str(), count);
    }
    const double acc = static_cast<double>(agree) / total;
    std::printf(
        "[figures] %s %s: label agreement %.4f over %zu points; truth rows (in/out/clutter) x "
        "model cols "
        "(none/in/out/clutter):\n",
        spec.c_str(), run.room.c_str(), acc, total);
    for (int t = 1; t <= 3; ++t) {
      std::printf("[figures]   %d: %d %d %d %d\n", t, confusion[t][0], confusion[t][1],
                  confusion[t][2], confusion[t][3]);
    }
    std::printf("[figures] %s %s: %s\n", spec.c_str(), run.room.c_str(),
                model.FiguresJson().substr(0, 400).c_str());
    EXPECT_GE(acc, min_agreement) << run.room;
  }
}

TEST(RoomModelFigures, TwoRoomsDoorLabelsAgreeWithTruth) {
  RunRooms("two_rooms_door", {{"R1", {{1.5, 2.2}, {3.8, 1.5}}}, {"R2", {{7.0, 2.0}, {9.0, 1.2}}}},
           0.3, 0.98);
}

TEST(RoomModelFigures, LabelsWithTheLargestAcceptedRegistrationError) {
  // 1 cm and 0.1 deg on every scan after the first (the registration acceptance bound).
  RunRooms("two_rooms_door", {{"R1", {{1.5, 2.2}, {3.8, 1.5}}}}, 0.3, 0.98, 0.01, DegToRad(0.1));
}

}  // namespace
}  // namespace mopad::modelling
