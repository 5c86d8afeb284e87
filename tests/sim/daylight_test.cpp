// Daylight (TlsParams::window_light): surfaces near a room's windows are brighter and the light
// falls off into the room; a room without windows keeps its colours; what stands between a
// window and a surface shadows it; ranges do not change; the single-ray kernel and the general
// path colour a point alike. And a camera turned from its calibration (TlsParams::camera_rpy_deg).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/realism.h"
#include "sim/tls_scanner.h"

namespace mopad::sim {
namespace {

struct Scan {
  interfaces::TlsScan scan;
  TlsTruth truth;
};

Scan ScanR1(const EmbreeWorld& world, const TlsParams& p) {
  ScanRequest req;
  req.X_WB.translation() = Eigen::Vector3d(2.5, 2.5, 0.0);
  Scan s;
  s.scan = TlsScanner(world, p).Scan(req, &s.truth);
  return s;
}

// two_rooms_door without R2's window: R1 [0, 5] x [0, 4] has W1 in its south wall (y = 0).
EmbreeWorld OneWindowWorld() {
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  spec.windows.erase(std::remove_if(spec.windows.begin(), spec.windows.end(),
                                    [](const scenes::WindowSpec& w) { return w.id == "W2"; }),
                     spec.windows.end());
  for (auto& b : spec.bscs)
    if (b.class_name == "radiator") b.count = 1;  // one window, one radiator under it
  scenes::GeneratedScene g = scenes::Generate(spec);
  return EmbreeWorld(std::move(g.scene), &g.truth);
}

// A noise-free scanner at 0.25 deg, and the same in daylight of 8.
TlsParams Plain() {
  TlsParams p = TlsParams{}.NoiseFree();
  p.step_deg = 0.25;
  return p;
}
TlsParams InDaylight() {
  TlsParams p = Plain();
  p.window_light = 8.0;
  return p;
}

TEST(Daylight, NearARoomsWindowsSurfacesAreBrighterAndARoomWithoutWindowsIsNot) {
  const EmbreeWorld world = OneWindowWorld();
  const TlsParams p = Plain(), day = InDaylight();
  // The general path: a footprint of identical sub-rays.
  TlsParams general = day;
  general.footprint_rays = 3;
  general.beam_divergence_mrad = 0.0;
  general.beam_exit_diameter = 0.0;
  const Scan base = ScanR1(world, p), lit = ScanR1(world, day), gen = ScanR1(world, general);
  const auto& ids = base.truth.element_ids;
  const Eigen::Vector3d o(2.5, 2.5, p.mount_xyz[2]);
  double near_sum = 0.0, far_sum = 0.0;
  int near = 0, far = 0, r2 = 0, same_path = 0, compared = 0;
  for (std::size_t i = 0; i < base.scan.points.size(); ++i) {
    const auto& a = base.scan.points[i];
    const auto& b = lit.scan.points[i];
    const auto& c = gen.scan.points[i];
    const TlsPointTruth& t = base.truth.points[i];
    if (!a.valid() || !b.valid() || t.element < 0) continue;
    EXPECT_EQ(a.range, b.range);  // light is colour only
    const std::string& id = ids[static_cast<std::size_t>(t.element)];
    const Eigen::Vector3d q = o + Eigen::Vector3d(a.x, a.y, a.z);
    if (id == "floor_R1") {
      const double gain = static_cast<double>(b.g) - static_cast<double>(a.g);
      EXPECT_GE(gain, 0.0);
      if (q.y() < 1.0) near_sum += gain, ++near;
      if (q.y() > 3.0) far_sum += gain, ++far;
    }
    if (id.find("R2") != std::string::npos) {  // seen through the door: no window there
      EXPECT_EQ(a.g, b.g) << id;
      ++r2;
    }
    if (c.valid() && gen.truth.points[i].part == lit.truth.points[i].part) {
      ++compared;
      same_path += std::abs(static_cast<int>(b.g) - static_cast<int>(c.g)) <= 1;
    }
  }
  ASSERT_GT(near, 200);
  ASSERT_GT(far, 200);
  ASSERT_GT(r2, 200);
  EXPECT_GT(near_sum / near, 10.0);                 // sRGB levels brighter by the window
  EXPECT_GT(near_sum / near, 2.0 * far_sum / far);  // and falling off into the room
  EXPECT_GT(compared, 10000);
  EXPECT_EQ(same_path, compared);
}

TEST(Daylight, WhatStandsBetweenTheWindowAndASurfaceShadowsIt) {
  const EmbreeWorld world = OneWindowWorld();
  const TlsParams p = Plain();
  const Scan base = ScanR1(world, p), lit = ScanR1(world, InDaylight());
  // The pane, found here by its class, as the centres of a 9 x 9 grid of equal cells: the
  // share of them a floor point sees is the share of the pane that lights it.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
  for (const scenes::MeshPart& part : world.scene().parts)
    if (part.element_class == scenes::ElementClass::kWindowGlass)
      for (const Eigen::Vector3f& v : part.positions) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  ASSERT_LT(hi.y() - lo.y(), 1e-3f);  // a pane in the plane y = const
  std::vector<Eigen::Vector3f> pane;
  for (int i = 0; i < 9; ++i)
    for (int k = 0; k < 9; ++k)
      pane.emplace_back(lo.x() + (hi.x() - lo.x()) * (i + 0.5f) / 9.0f, lo.y(),
                        lo.z() + (hi.z() - lo.z()) * (k + 0.5f) / 9.0f);
  // Floor points of R1 within 2 m of the window (where its light is well above a level), by
  // the share of the pane they see: none (in the shadow of the desk, the radiator, the
  // reveal), some, all. The scanner's one ray per pulse to a random point of the pane lights a
  // point as often as it sees the pane: never in the umbra, about half the time in the middle
  // of a penumbra.
  const auto& ids = base.truth.element_ids;
  const Eigen::Vector3f o(2.5f, 2.5f, static_cast<float>(p.mount_xyz[2]));
  int umbra = 0, umbra_dark = 0, open = 0, open_lit = 0, half = 0, half_lit = 0;
  for (std::size_t i = 0; i < base.scan.points.size(); ++i) {
    const auto& a = base.scan.points[i];
    const auto& b = lit.scan.points[i];
    const TlsPointTruth& t = base.truth.points[i];
    if (!a.valid() || !b.valid() || t.element < 0) continue;
    if (ids[static_cast<std::size_t>(t.element)] != "floor_R1") continue;
    const Eigen::Vector3f q = o + Eigen::Vector3f(a.x, a.y, a.z) + Eigen::Vector3f(0, 0, 1e-3f);
    if (q.y() > 2.0f) continue;
    int seen = 0;
    for (const Eigen::Vector3f& s : pane) {
      const Eigen::Vector3f d = s - q;
      const float dist = d.norm();
      seen += !world.Intersect(q, d / dist, 0.0f, dist - 0.03f).hit();
    }
    const double share = static_cast<double>(seen) / static_cast<double>(pane.size());
    const bool brighter = b.g > a.g, same = a.r == b.r && a.g == b.g && a.b == b.b;
    if (seen == 0) ++umbra, umbra_dark += same;
    if (share >= 0.95) ++open, open_lit += brighter;
    if (share >= 0.3 && share <= 0.7) ++half, half_lit += brighter;
  }
  ASSERT_GT(umbra, 200);
  ASSERT_GT(open, 2000);
  ASSERT_GT(half, 100);
  EXPECT_GT(umbra_dark, 0.98 * umbra);
  EXPECT_GT(open_lit, 0.95 * open);
  EXPECT_GT(half_lit, 0.2 * half);
  EXPECT_LT(half_lit, 0.8 * half);
  std::printf("umbra %d (%d dark), penumbra %d (%d lit), open %d (%d lit)\n", umbra, umbra_dark,
              half, half_lit, open, open_lit);
}

TEST(Daylight, ARealismSetsIt) {
  ScannerRealism r;
  r.window_light = 5.0;
  r.window_light_sigma_stops = 0.5;
  const TlsParams p = RealisticTls(TlsProfile("riegl_vz400"), r, 7);
  EXPECT_EQ(p.window_light, 5.0);
  EXPECT_EQ(p.window_light_sigma_stops, 0.5);
}

// A camera turned by 1 deg about the scanner's z axis from its calibration: each point takes the
// colour of what lies 1 deg further round, i.e. four 0.25 deg columns on.
TEST(CameraRig, ATurnedCameraColoursAPointWithWhatItsTurnedRaySees) {
  const EmbreeWorld world = OneWindowWorld();
  const TlsParams p = Plain();
  TlsParams turned = p;
  turned.camera_rpy_deg = {0.0, 0.0, 1.0};
  const Scan a = ScanR1(world, p), b = ScanR1(world, turned);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> cell;
  for (std::size_t i = 0; i < a.scan.points.size(); ++i)
    cell[{a.scan.points[i].row, a.scan.points[i].column}] = i;
  const auto rgb = [](const interfaces::TlsPoint& q) { return std::array<int, 3>{q.r, q.g, q.b}; };
  int edges = 0, as_turned = 0, as_own = 0;
  for (std::size_t i = 0; i < a.scan.points.size(); ++i) {
    const auto& own = a.scan.points[i];
    EXPECT_EQ(own.range, b.scan.points[i].range);  // the camera moves no point
    const auto it = cell.find({own.row, own.column + 4});
    if (!own.valid() || it == cell.end() || !a.scan.points[it->second].valid()) continue;
    const auto& next = a.scan.points[it->second];
    if (rgb(own) == rgb(next)) continue;  // no colour edge within the turn
    ++edges;
    as_turned += rgb(b.scan.points[i]) == rgb(next);
    as_own += rgb(b.scan.points[i]) == rgb(own);
  }
  std::printf("colour edges %d: turned %d, own %d\n", edges, as_turned, as_own);
  ASSERT_GT(edges, 2000);
  EXPECT_GT(as_turned, 0.95 * edges);
  EXPECT_LT(as_own, 0.05 * edges);
}

TEST(CameraRig, ARealismDrawsTheRotationOncePerRun) {
  ScannerRealism r;
  const TlsParams none = RealisticTls(TlsProfile("riegl_vz400"), r, 7);
  EXPECT_EQ(none.camera_rpy_deg, (std::vector<double>{0.0, 0.0, 0.0}));
  r.camera_misalignment_sigma_deg = 0.1;
  const TlsParams a = RealisticTls(TlsProfile("riegl_vz400"), r, 7),
                  a2 = RealisticTls(TlsProfile("riegl_vz400"), r, 7),
                  b = RealisticTls(TlsProfile("riegl_vz400"), r, 8);
  EXPECT_EQ(a.camera_rpy_deg, a2.camera_rpy_deg);
  EXPECT_NE(a.camera_rpy_deg, b.camera_rpy_deg);
  for (double e : a.camera_rpy_deg) {
    EXPECT_GT(std::abs(e), 0.0);
    EXPECT_LT(std::abs(e), 0.5);
  }
  // The instrument's other draws do not move with it.
  ScannerRealism axes;
  axes.axis_error_sigma_deg = 0.01;
  ScannerRealism both = axes;
  both.camera_misalignment_sigma_deg = 0.1;
  EXPECT_EQ(RealisticTls(TlsParams{}, axes, 7).collimation_error_deg,
            RealisticTls(TlsParams{}, both, 7).collimation_error_deg);
}

}  // namespace
}  // namespace mopad::sim
