#include "sim/realism.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "sim/surface_model.h"
#include "sim/tls_scanner.h"
#include "tests/sim/test_scenes.h"

namespace mopad::sim {
namespace {

using testing::AddMaterial;
using testing::AddRoomBox;
using V = Eigen::Vector3f;

std::string Yaml(const TlsParams& p) { return YAML::Dump(SaveParams(p)); }

TEST(Realism, IdealLeavesTheScannerAsItsProfileDescribesIt) {
  for (const std::string& name : TlsProfileNames()) {
    const TlsParams base = TlsProfile(name);
    for (std::uint64_t seed : {1ull, 2ull, 987654321ull})
      EXPECT_EQ(Yaml(RealisticTls(base, RealismProfile("ideal").scanner, seed)), Yaml(base));
  }
}

TEST(Realism, OneSeedOneInstrument) {
  const ScannerRealism typical = RealismProfile("typical").scanner;
  const TlsParams a = RealisticTls(TlsParams{}, typical, 1),
                  a2 = RealisticTls(TlsParams{}, typical, 1),
                  b = RealisticTls(TlsParams{}, typical, 2);
  EXPECT_EQ(Yaml(a), Yaml(a2));
  EXPECT_NE(a.collimation_error_deg, b.collimation_error_deg);
  for (const TlsParams& p : {a, b}) {
    for (double e :
         {p.collimation_error_deg, p.trunnion_axis_error_deg, p.vertical_index_error_deg}) {
      EXPECT_NE(e, 0.0);
      EXPECT_LT(std::abs(e), 5 * typical.axis_error_sigma_deg);
    }
    EXPECT_NE(p.range_scale_ppm, 0.0);
    EXPECT_LT(std::abs(p.range_scale_ppm), 5 * typical.range_scale_sigma_ppm);
    EXPECT_EQ(p.low_signal_range_bias, typical.low_signal_range_bias);
    EXPECT_EQ(p.exposure_sigma_stops, typical.exposure_sigma_stops);
    EXPECT_NO_THROW(p.Validate());
  }
  // Over many seeds the axis errors have the profile's spread.
  double sum2 = 0.0;
  const int n = 2000;
  for (int s = 0; s < n; ++s) {
    const double c = RealisticTls(TlsParams{}, typical, 1000 + s).collimation_error_deg;
    sum2 += c * c;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), typical.axis_error_sigma_deg,
              0.1 * typical.axis_error_sigma_deg);
}

TEST(Realism, AConfigNamingAProfileStartsFromItsValues) {
  const auto p = LoadParams<RealismParams>(
      LoadYamlString("profile: typical\nscanner:\n  exposure_sigma_stops: 0.1\n", "r.yaml"),
      "r.yaml");
  EXPECT_EQ(p.profile, "typical");
  EXPECT_EQ(p.scanner.axis_error_sigma_deg, RealismProfile("typical").scanner.axis_error_sigma_deg);
  EXPECT_EQ(p.scanner.exposure_sigma_stops, 0.1);
  // The effective config (every field) loads back to the same values.
  const std::string text = YAML::Dump(SaveParams(p));
  const auto back = LoadParams<RealismParams>(LoadYamlString(text, "back.yaml"), "back.yaml");
  EXPECT_EQ(YAML::Dump(SaveParams(back)), text);
  // No profile named: ideal, with the keys given.
  const auto q = LoadParams<RealismParams>(
      LoadYamlString("scanner:\n  white_balance_sigma: 0.2\n", "q.yaml"), "q.yaml");
  EXPECT_EQ(q.profile, "ideal");
  EXPECT_EQ(q.scanner.white_balance_sigma, 0.2);
  EXPECT_EQ(q.scanner.axis_error_sigma_deg, 0.0);
  try {
    (void)LoadParams<RealismParams>(LoadYamlString("profile: realistic\n", "u.yaml"), "u.yaml");
    FAIL() << "an unknown profile was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'realism.profile' unknown; got 'realistic', expected "
                                         "one of ideal, typical, hard"),
              std::string::npos)
        << e.what();
  }
}

TEST(Realism, TheProfilesBuildOffTheDesignAsTheirTolerancesSay) {
  // ideal is the design; typical and hard depart from it (their values' DIN 18202 check is
  // AsBuilt.*, tests/scenes/as_built_test.cpp); a zero geometry seed means the run's.
  EXPECT_FALSE(RealismProfile("ideal").geometry.Enabled());
  const RealismParams typical = RealismProfile("typical"), hard = RealismProfile("hard");
  EXPECT_TRUE(typical.geometry.Enabled());
  EXPECT_LT(typical.geometry.flatness_mm, hard.geometry.flatness_mm);
  EXPECT_LT(typical.geometry.lean_sigma_deg, hard.geometry.lean_sigma_deg);
  EXPECT_EQ(RunGeometry(typical, 42).seed, 42u);
  RealismParams own = typical;
  own.geometry.seed = 5;
  EXPECT_EQ(RunGeometry(own, 42).seed, 5u);
  // A config may switch the geometry off and keep the scanner's errors.
  const auto p = LoadParams<RealismParams>(
      LoadYamlString("profile: typical\ngeometry: {flatness_mm: 0, lean_sigma_deg: 0}\n", "g.yaml"),
      "g.yaml");
  EXPECT_FALSE(p.geometry.Enabled());
  EXPECT_EQ(p.scanner.exposure_sigma_stops, typical.scanner.exposure_sigma_stops);
}

TEST(Realism, TheProfilesFurnishTheBuildingWithDetailsIdealDoesNot) {
  // Their placement is Details.* (tests/scenes/details_test.cpp); here what each profile holds.
  EXPECT_FALSE(RealismProfile("ideal").details.Enabled());
  EXPECT_FALSE(RealismProfile("ideal").ChangesTheBuilding());
  const RealismParams typical = RealismProfile("typical"), hard = RealismProfile("hard");
  EXPECT_TRUE(typical.details.Enabled());
  EXPECT_GT(typical.details.skirting_height, 0.0);
  EXPECT_LT(typical.details.posters_per_room, hard.details.posters_per_room);
  EXPECT_LT(typical.details.glazed_doors, hard.details.glazed_doors);
  EXPECT_LT(typical.details.frames_in_wall_colour, hard.details.frames_in_wall_colour);
  EXPECT_EQ(RunDetails(typical, 42).seed, 42u);
  // A config may take the details out and keep the rest of the profile.
  const auto p = LoadParams<RealismParams>(
      LoadYamlString("profile: typical\ndetails: {skirting_height: 0, ducts_per_room: 0, "
                     "pipes_per_room: 0, posters_per_room: 0, frames_in_wall_colour: 0, "
                     "glazed_doors: 0}\n",
                     "d.yaml"),
      "d.yaml");
  EXPECT_FALSE(p.details.Enabled());
  EXPECT_TRUE(p.ChangesTheBuilding());  // its as-built geometry stays
}

// A box room, the scanner at its centre, its errors alone (noise off).
struct BoxScan {
  TlsParams params;
  interfaces::TlsScan scan;
  TlsTruth truth;
};
BoxScan ScanBox(TlsParams p, std::uint64_t scan_id = 0) {
  scenes::Scene s;
  s.source = "box";
  const int white = AddMaterial(s, "white", 0.8f, 0.6f, 0.4f);
  AddRoomBox(s, V(-4, -3, -1.4f), V(5, 3, 1.4f), white);
  EmbreeWorld world(std::move(s));
  p.mount_xyz = {0, 0, 0};
  p.step_deg = 0.25;
  BoxScan b{p, {}, {}};
  ScanRequest req;
  req.seed = 3;
  req.scan_id = scan_id;
  b.scan = TlsScanner(world, p).Scan(req, &b.truth);
  return b;
}

// Range to the east wall x = 5 along the true beam of the standard axis-error model.
double PredictedEastRange(const TlsParams& p, double az, double el) {
  const double c = DegToRad(p.collimation_error_deg), i = DegToRad(p.trunnion_axis_error_deg),
               v = DegToRad(p.vertical_index_error_deg);
  const double az_true = az + c / std::cos(el) + i * std::tan(el), el_true = el + v;
  return 5.0 / (std::cos(el_true) * std::cos(az_true));
}

TEST(Realism, AxisErrorsBendTheBeamAsTheStandardModelSays) {
  TlsParams p = TlsParams{}.NoiseFree();
  p.collimation_error_deg = 0.3;
  p.trunnion_axis_error_deg = -0.2;
  p.vertical_index_error_deg = 0.25;
  // The vectorised single-ray path and the general one (a footprint of identical sub-rays).
  TlsParams general = p;
  general.footprint_rays = 3;
  general.beam_divergence_mrad = 0.0;
  general.beam_exit_diameter = 0.0;
  for (const TlsParams& params : {p, general}) {
    const BoxScan b = ScanBox(params);
    const auto& ids = b.truth.element_ids;
    const int east = static_cast<int>(std::find(ids.begin(), ids.end(), "wall_e") - ids.begin());
    TlsParams ideal = b.params;
    ideal.collimation_error_deg = ideal.trunnion_axis_error_deg = ideal.vertical_index_error_deg =
        0;
    std::size_t n = 0;
    double worst = 0.0, ideal_mean = 0.0;
    for (std::uint32_t r = 0; r < b.scan.rows; ++r) {
      for (std::uint32_t c = 0; c < b.scan.columns; ++c) {
        const auto& pt = b.scan.points[static_cast<std::size_t>(r) * b.scan.columns + c];
        const auto& tr = b.truth.at(r, c);
        const double az = b.scan.azimuth_min + c * b.scan.azimuth_step,
                     el = b.scan.elevation_max - r * b.scan.elevation_step;
        // Well inside the wall: away from its edges, where the two models hit different parts.
        if (!pt.valid() || tr.element != east || std::abs(az) > 0.45 || std::abs(el) > 0.2)
          continue;
        const double predicted = PredictedEastRange(b.params, az, el);
        worst = std::max(worst, std::abs(pt.range - predicted) / predicted);
        ideal_mean += std::abs(pt.range - PredictedEastRange(ideal, az, el)) / predicted;
        ++n;
        // Reported along the encoder angles.
        const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                std::sin(el));
        EXPECT_LT((Eigen::Vector3d(pt.x, pt.y, pt.z) - pt.range * d).norm(), 1e-5);
      }
    }
    ASSERT_GT(n, 5000u);
    EXPECT_LT(worst, 1e-5) << "footprint_rays " << params.footprint_rays;
    // The errors are large against the check's tolerance: without them the ranges differ.
    EXPECT_GT(ideal_mean / static_cast<double>(n), 5e-4);
  }
}

TEST(Realism, RangeScaleAndTheLowSignalWalkFollowTheReturn) {
  TlsParams p = TlsParams{}.NoiseFree();
  p.range_scale_ppm = 800.0;
  p.low_signal_range_bias = 0.05;
  p.low_signal_intensity = 0.9;
  const BoxScan b = ScanBox(p);
  std::size_t n = 0, walked = 0;
  for (std::size_t i = 0; i < b.scan.points.size(); ++i) {
    const auto& pt = b.scan.points[i];
    if (!pt.valid()) continue;
    const double t = b.truth.points[i].true_range;
    const double weak = std::max(0.0, 1.0 - pt.intensity / 0.9);
    EXPECT_NEAR(pt.range, t * (1 + 800e-6) + 0.05 * weak, 2e-6 * t + 1e-6) << i;
    EXPECT_NEAR(Eigen::Vector3d(pt.x, pt.y, pt.z).norm(), pt.range, 2e-6 * pt.range);
    walked += weak > 0.1;
    ++n;
  }
  ASSERT_GT(n, 100000u);
  EXPECT_GT(walked, n / 10);  // grazing returns are weak: the walk is exercised
}

TEST(Realism, ExposureAndWhiteBalanceAreOneGainPerChannelAndScan) {
  TlsParams p = TlsParams{}.NoiseFree();
  const BoxScan ideal = ScanBox(p, 0);
  p.exposure_sigma_stops = 1.0;
  p.white_balance_sigma = 0.3;
  const BoxScan a = ScanBox(p, 0), b = ScanBox(p, 1);
  const SrgbTables& srgb = SrgbTables::Get();
  // The linear gain of each channel: the same for every point of a scan (within the 8-bit
  // quantisation), different between scans.
  std::array<double, 3> gain_a{}, gain_b{};
  for (const BoxScan* s : {&a, &b}) {
    for (int ch = 0; ch < 3; ++ch) {
      double lo = 1e9, hi = 0.0, sum = 0.0;
      std::size_t n = 0;
      for (std::size_t i = 0; i < s->scan.points.size(); ++i) {
        const auto& q = ideal.scan.points[i];
        const auto& pt = s->scan.points[i];
        const std::uint8_t vi = ch == 0 ? q.r : (ch == 1 ? q.g : q.b);
        const std::uint8_t vs = ch == 0 ? pt.r : (ch == 1 ? pt.g : pt.b);
        if (!pt.valid() || vi < 100 || vs < 100 || vs > 250) continue;
        const double g = srgb.Decode(vs) / srgb.Decode(vi);
        lo = std::min(lo, g);
        hi = std::max(hi, g);
        sum += g;
        ++n;
      }
      ASSERT_GT(n, 1000u) << ch;
      EXPECT_LT((hi - lo) / (sum / n), 0.04) << "channel " << ch;
      (s == &a ? gain_a : gain_b)[static_cast<std::size_t>(ch)] = sum / n;
    }
  }
  EXPECT_GT(std::abs(std::log2(gain_a[1] / gain_b[1])), 0.05);
  // White balance: red and blue move against green.
  EXPECT_GT(std::abs(std::log(gain_a[0] / gain_a[1])), 0.01);
  // Geometry untouched.
  for (std::size_t i = 0; i < a.scan.points.size(); i += 97)
    EXPECT_EQ(a.scan.points[i].range, ideal.scan.points[i].range);
}

}  // namespace
}  // namespace mopad::sim
