// Daylight (TlsParams::window_light): surfaces near a room's windows are brighter and the light
// falls off into the room; a room without windows keeps its colours; ranges do not change; the
// single-ray kernel and the general path colour a point alike.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

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

TEST(Daylight, NearARoomsWindowsSurfacesAreBrighterAndARoomWithoutWindowsIsNot) {
  // two_rooms_door without R2's window: R1 [0, 5] x [0, 4] has W1 in its south wall (y = 0).
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  spec.windows.erase(std::remove_if(spec.windows.begin(), spec.windows.end(),
                                    [](const scenes::WindowSpec& w) { return w.id == "W2"; }),
                     spec.windows.end());
  for (auto& b : spec.bscs)
    if (b.class_name == "radiator") b.count = 1;  // one window, one radiator under it
  scenes::GeneratedScene g = scenes::Generate(spec);
  const EmbreeWorld world(std::move(g.scene), &g.truth);
  TlsParams p = TlsParams{}.NoiseFree();
  p.step_deg = 0.25;
  TlsParams day = p;
  day.window_light = 8.0;
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

TEST(Daylight, ARealismSetsIt) {
  ScannerRealism r;
  r.window_light = 5.0;
  r.window_light_sigma_stops = 0.5;
  const TlsParams p = RealisticTls(TlsProfile("riegl_vz400"), r, 7);
  EXPECT_EQ(p.window_light, 5.0);
  EXPECT_EQ(p.window_light_sigma_stops, 0.5);
}

}  // namespace
}  // namespace mopad::sim
