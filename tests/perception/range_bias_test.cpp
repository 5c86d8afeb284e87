// A TLS scan's range offset from its floor and ceiling (perception/range_bias.h), on simulated
// 0.2 deg VZ-400 scans of scenes/one_room.yaml whose truth holds the drawn offset.
#include "perception/range_bias.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/tls_params.h"
#include "sim/tls_scanner.h"
#include "sim/tls_truth.h"

namespace mopad::perception {
namespace {

class OneRoom {
 public:
  OneRoom() {
    scenes::GeneratedScene g = scenes::Generate(
        scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/one_room.yaml"));
    truth_ = std::move(g.truth);
    world_ = std::make_unique<sim::EmbreeWorld>(std::move(g.scene), &truth_);
  }
  interfaces::TlsScan Scan(const sim::TlsParams& tls, std::uint64_t id, const Pose2& base,
                           sim::TlsTruth& truth) const {
    sim::TlsScanner scanner(*world_, tls);
    sim::ScanRequest req;
    req.seed = 5;
    req.scan_id = id;
    req.X_WB = base.To3d();
    return scanner.Scan(req, &truth);
  }

 private:
  scenes::GroundTruth truth_;
  std::unique_ptr<sim::EmbreeWorld> world_;
};

// Mean of measured minus true range over the valid returns (the scan's offset plus the mean
// of its noise).
double MeanRangeError(const interfaces::TlsScan& scan, const sim::TlsTruth& truth) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& p = scan.points[i];
    if (!p.valid() || truth.points[i].true_range <= 0.0f ||
        (truth.points[i].flags & (sim::kTruthTransmitted | sim::kTruthMixed)))
      continue;
    sum += double(p.range) - truth.points[i].true_range;
    ++n;
  }
  return sum / static_cast<double>(n);
}

TEST(RangeBias, EachScansDrawnOffsetIsFoundWithinAFifthOfAMillimetre) {
  const OneRoom room;
  sim::TlsParams tls = sim::TlsProfile("riegl_vz400");
  tls.tilt_sigma_deg = 0.05;  // six times the profile's levelling error: the slopes take it
  const Pose2 bases[3] = {{1.5, 1.2, 0.3}, {3.2, 2.9, -1.2}, {5.2, 0.9, 0.8}};
  int far_from_zero = 0;
  for (std::uint64_t id = 0; id < 3; ++id) {
    sim::TlsTruth truth;
    interfaces::TlsScan scan = room.Scan(tls, id, bases[id], truth);
    const RangeBiasEstimate e = EstimateRangeBias(scan, RangeBiasParams{});
    std::printf("  scan %d: truth %.2f mm, tilt %.3f/%.3f deg; %s\n", int(id),
                1e3 * truth.range_bias, RadToDeg(truth.tilt_roll), RadToDeg(truth.tilt_pitch),
                e.message.c_str());
    ASSERT_TRUE(e.ok) << e.message;
    EXPECT_NEAR(e.bias, truth.range_bias, 2e-4);
    EXPECT_LT(e.sigma, 1e-4);
    EXPECT_GT(e.floor_points, 10000u);
    EXPECT_GT(e.ceiling_points, 10000u);
    far_from_zero += std::abs(truth.range_bias) > 1e-3;
    // Removing it leaves the ranges unbiased.
    const double before = MeanRangeError(scan, truth);
    RemoveRangeBias(scan, e.bias);
    const double after = MeanRangeError(scan, truth);
    EXPECT_NEAR(before, truth.range_bias, 2e-4);
    EXPECT_LT(std::abs(after), 2e-4) << "before " << before;
    for (const auto& p : scan.points) {
      if (!p.valid()) continue;
      ASSERT_NEAR(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), p.range, 1e-4);
    }
  }
  EXPECT_GT(far_from_zero, 0);  // the check above is not one of zero offsets
}

TEST(RangeBias, ACalibrationOffsetIsPartOfTheEstimate) {
  const OneRoom room;
  sim::TlsParams tls = sim::TlsProfile("riegl_vz400");
  tls.range_offset = 0.02;
  sim::TlsTruth truth;
  const interfaces::TlsScan scan = room.Scan(tls, 7, {2.0, 2.0, 0.0}, truth);
  const RangeBiasEstimate e = EstimateRangeBias(scan, RangeBiasParams{});
  ASSERT_TRUE(e.ok) << e.message;
  EXPECT_NEAR(truth.range_bias, 0.02, 0.015);  // the truth carries the offset
  EXPECT_NEAR(e.bias, truth.range_bias, 2e-4);
  // Beyond max_bias it is reported, not applied.
  RangeBiasParams tight;
  tight.max_bias = 0.01;
  const RangeBiasEstimate t = EstimateRangeBias(scan, tight);
  EXPECT_FALSE(t.ok);
  EXPECT_NEAR(t.bias, e.bias, 1e-9);
  EXPECT_NE(t.message.find("implausible"), std::string::npos) << t.message;
}

TEST(RangeBias, AScanWithoutFloorOrCeilingIsNotEstimated) {
  interfaces::TlsScan scan;
  scan.rows = 1;
  scan.columns = 360;
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    interfaces::TlsPoint p;
    const double a = DegToRad(c);
    p.x = static_cast<float>(3.0 * std::cos(a));
    p.y = static_cast<float>(3.0 * std::sin(a));
    p.z = 0.1f;
    p.range = static_cast<float>(std::sqrt(9.0 + 0.01));
    p.column = c;
    scan.points.push_back(p);
  }
  const RangeBiasEstimate e = EstimateRangeBias(scan, RangeBiasParams{});
  EXPECT_FALSE(e.ok);
  EXPECT_EQ(e.bias, 0.0);
  EXPECT_NE(e.message.find("not estimated"), std::string::npos) << e.message;
  interfaces::TlsScan torn = scan;
  torn.rows = 2;  // fewer points than the grid holds
  const RangeBiasEstimate t = EstimateRangeBias(torn, RangeBiasParams{});
  EXPECT_FALSE(t.ok);
  EXPECT_NE(t.message.find("inconsistent"), std::string::npos) << t.message;
  RangeBiasParams bad;
  bad.band = -1.0;
  EXPECT_THROW(EstimateRangeBias(scan, bad), InputError);
}

}  // namespace
}  // namespace mopad::perception
