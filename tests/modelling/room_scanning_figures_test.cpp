// Figures of autonomous room scanning without navigation: in each room of office_5rooms the
// robot starts at a free spot, scans (0.2 deg, the real resolution), and then repeatedly asks
// the next best scan for a position, is placed there (no driving in this test) and scans again
// until the stopping rule says stop or 5 scans. Poses are the true ones (registration is tested
// elsewhere). Printed: per-scan processing time (AddScan + NBS), coverage, the stop reason and
// the per-point label agreement with the truth. Only the label agreement is asserted.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include "autonomy/next_best_scan.h"
#include "common/polygon.h"
#include "modelling/room_model.h"
#include "modelling/stopping.h"
#include "scenes/element_class.h"
#include "tests/modelling/sim_scans.h"

namespace mopad::modelling {
namespace {

using testing::SimScan;
using testing::TakeScan;

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A start spot: the interior grid point farthest from walls and furniture (test harness only).
Vec2 StartSpot(const scenes::GroundTruth& truth, const scenes::Room& room) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : room.polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Vec2 best = lo;
  double best_d = -1;
  for (double y = lo.y() + 0.25; y < hi.y(); y += 0.25) {
    for (double x = lo.x() + 0.25; x < hi.x(); x += 0.25) {
      const Vec2 p(x, y);
      if (!PointInPolygon(p, room.polygon)) continue;
      double d = 1e300;
      for (std::size_t i = 0; i < room.polygon.size(); ++i) {
        const Vec2 a = room.polygon[i], b = room.polygon[(i + 1) % room.polygon.size()];
        const double u = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        d = std::min(d, (p - (a + u * (b - a))).norm());
      }
      for (const auto& f : truth.furniture) {
        d = std::min(d, (p - f.centre.head<2>()).norm() - 0.5 * f.size.head<2>().norm());
      }
      // Prefer spots off-centre along the longer axis a little (like a robot entering).
      if (d > best_d + 1e-9) {
        best_d = d;
        best = p;
      }
    }
  }
  return best;
}

// Runs the loop in `rooms` (all if empty); `force_scans` > 0 ignores the stopping rule and
// takes that many scans (timing with a full accumulated cloud).
void RunLoop(const std::vector<std::string>& rooms, int force_scans) {
  const scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
  const sim::EmbreeWorld world(g.scene, &g.truth);
  const sim::TlsParams tls = testing::TestTls(0.2);
  for (const scenes::Room& room : g.truth.rooms) {
    if (!rooms.empty() && std::find(rooms.begin(), rooms.end(), room.id) == rooms.end()) continue;
    RoomModel model;
    std::vector<SimScan> scans;
    Vec2 pos = StartSpot(g.truth, room);
    std::string stop_message;
    for (int k = 0; k < std::max(5, force_scans); ++k) {
      scans.push_back(TakeScan(world, tls, pos.x(), pos.y(), static_cast<std::uint64_t>(k), 21));
      const auto t0 = std::chrono::steady_clock::now();
      model.AddScan(scans.back().scan, scans.back().X_MS);
      const double t_model = Seconds(t0);
      const auto t1 = std::chrono::steady_clock::now();
      std::vector<Eigen::Vector3d> pts;
      pts.reserve(model.PointCount());
      for (const auto& p : model.Points()) pts.push_back(p.cast<double>());
      perception::OccupancyGrid map = perception::OccupancyGrid::Covering({}, pts, 1.0);
      map.InsertPoints(pts);
      const Pose2 here{pos.x(), pos.y(), 0.0};
      CoverageFigures coverage = model.Coverage();
      coverage.SetHiddenArea(autonomy::EstimateHiddenArea(model, map, here).area);
      StopDecision stop = CheckStopping(coverage, {});
      if (force_scans > 0) stop.stop = k + 1 >= force_scans;
      double t_nbs = Seconds(t1);
      autonomy::NbsResult nbs;
      if (!stop.stop) {
        nbs = autonomy::NextBestScan(model, map, here, 0.2);
        t_nbs = Seconds(t1);
      }
      std::printf(
          "[figures] %s scan %d at (%.2f, %.2f): %zu pts, model %.2f s + NBS %.2f s = %.2f s; "
          "coverage %.3f of the observable (+%.3f) of %.1f m2; %s\n",
          room.id.c_str(), k, pos.x(), pos.y(), scans.back().scan.points.size(), t_model, t_nbs,
          t_model + t_nbs, coverage.observable_ratio, coverage.increment, coverage.total_area,
          stop.stop ? stop.message.c_str() : nbs.message.c_str());
      if (stop.stop) {
        stop_message = stop.message;
        break;
      }
      if (!nbs.found) break;
      pos = nbs.candidates[nbs.chosen].position;
    }
    std::size_t agree = 0, total = 0;
    std::map<std::string, int> wrong;  // "class truth->model" of disagreements
    for (const auto& s : scans) {
      const auto truth = testing::TruthLabels(s, g.scene, room.id, room.polygon);
      std::size_t k = 0;
      for (std::uint32_t c = 0; c < s.scan.columns; ++c) {
        for (std::uint32_t r = 0; r < s.scan.rows; ++r) {
          if (!s.scan.at(r, c).valid()) continue;
          const int m = static_cast<int>(model.Labels()[total + k]);
          agree += m == truth[k];
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
      if (count * 500 > static_cast<int>(total))
        std::printf("[figures]   %s disagreement %s: %d\n", room.id.c_str(), key.c_str(), count);
    }
    const double acc = static_cast<double>(agree) / static_cast<double>(total);
    std::printf("[figures] %s: %d scans, label agreement %.4f over %zu points, %zu columns\n",
                room.id.c_str(), model.ScanCount(), acc, total, model.Columns().size());
    EXPECT_GE(acc, 0.98) << room.id;
  }
}

TEST(RoomScanningFigures, Office5RoomsNextBestScanLoop) { RunLoop({}, 0); }

TEST(RoomScanningFigures, FiveScansInTheLargestRooms) { RunLoop({"R1", "H"}, 5); }

}  // namespace
}  // namespace mopad::modelling
