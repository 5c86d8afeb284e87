// Radiometric alignment of a room's scans (modelling/colour_alignment.h): on synthetic colours
// with known gains, and on simulated scans whose camera changes exposure and white balance.
#include "modelling/colour_alignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/rng.h"
#include "common/srgb.h"
#include "modelling/room_model.h"
#include "tests/modelling/sim_scans.h"

namespace mopad::modelling {
namespace {

double Linear(std::uint8_t v) { return SrgbToLinear(v / 255.0); }

// A 3 m x 2 m wall at 1 cm spacing with a pattern of colours, seen by two "scans": the second
// with per-channel gains and the points 3 mm off.
struct TwoScans {
  std::vector<Eigen::Vector3f> points;
  std::vector<Rgb8> colours;
  std::size_t split = 0;
};
TwoScans MakeTwoScans(const std::array<double, 3>& gains) {
  TwoScans t;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) t.split = t.points.size();
    for (int i = 0; i < 300; ++i) {
      for (int j = 0; j < 200; ++j) {
        const float off = pass == 1 ? 0.003f : 0.0f;
        t.points.emplace_back(0.01f * i + off, 2.0f, 0.01f * j + off);
        // Patches of three colours, 0.5 m wide.
        const int patch = (i / 50 + j / 50) % 3;
        const std::array<double, 3> albedo = patch == 0   ? std::array<double, 3>{0.5, 0.45, 0.4}
                                             : patch == 1 ? std::array<double, 3>{0.2, 0.3, 0.35}
                                                          : std::array<double, 3>{0.7, 0.7, 0.7};
        // The scanner's colour noise, added before the 8-bit rounding as the scanner does:
        // triangular, +-4 levels (1 sigma 1.6).
        Rgb8 c{};
        for (std::size_t ch = 0; ch < 3; ++ch) {
          const std::uint64_t h = Mix64((t.points.size() << 3) + (ch << 1) + pass);
          const double noise =
              4.0 * ((h & 0xFFFF) / 65536.0 + ((h >> 16) & 0xFFFF) / 65536.0 - 1.0);
          const double lin = (pass == 1 ? gains[ch] : 1.0) * albedo[ch];
          c[ch] = static_cast<std::uint8_t>(
              std::clamp(std::lround(255.0 * LinearToSrgb(lin) + noise), 0L, 255L));
        }
        t.colours.push_back(c);
      }
    }
  }
  return t;
}

TEST(ColourAlignment, AScansGainsAreFoundAndUndone) {
  const std::array<double, 3> gains{1.3, 0.9, 1.12};
  TwoScans t = MakeTwoScans(gains);
  ColourReference ref;
  EXPECT_EQ(ref.Gains(t.points, t.colours, 0, t.split), (std::array<double, 3>{1, 1, 1}));
  ref.Align(t.points, t.colours, 0, t.split);
  int shared = 0;
  const auto g = ref.Gains(t.points, t.colours, t.split, t.points.size(), &shared);
  EXPECT_GT(shared, 2000);
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(g[ch], 1.0 / gains[ch], 0.01) << ch;
  // Before: the second scan's colours differ from the first's by the gains; after, by noise
  // only (mean signed difference per channel, sRGB levels).
  const auto mean_difference = [&t](std::size_t ch) {
    double sum = 0.0;
    for (std::size_t i = 0; i < t.split; ++i)
      sum += int(t.colours[t.split + i][ch]) - int(t.colours[i][ch]);
    return sum / static_cast<double>(t.split);
  };
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_GT(std::abs(mean_difference(ch)), 5.0) << ch;
  ApplyColourGains(g, t.colours, t.split, t.points.size());
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_LT(std::abs(mean_difference(ch)), 0.5) << ch;
}

// The room model's step: the gains Gains finds, applied as ApplyColourGains applies them, and
// the aligned colours added (a third scan like the second is found off by the same gains).
TEST(ColourAlignment, AlignIsTheGainsAppliedAndTheAlignedScanAdded) {
  const std::array<double, 3> gains{1.3, 0.9, 1.12};
  TwoScans t = MakeTwoScans(gains);
  const std::vector<Rgb8> scanned = t.colours;
  ColourReference ref;
  EXPECT_EQ(ref.Align(t.points, t.colours, 0, t.split), (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(t.colours, scanned);  // the first scan is the reference, as scanned
  const auto query = ref.Gains(t.points, t.colours, t.split, t.points.size());
  int shared = 0;
  const auto g = ref.Align(t.points, t.colours, t.split, t.points.size(), &shared);
  EXPECT_EQ(g, query);
  EXPECT_GT(shared, 2000);
  std::vector<Rgb8> expected = scanned;
  ApplyColourGains(query, expected, t.split, t.points.size());
  EXPECT_EQ(t.colours, expected);
  // The room now holds both scans at the first one's colours.
  std::vector<Rgb8> again = scanned;
  const auto third = ref.Gains(t.points, again, t.split, t.points.size());
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(third[ch], 1.0 / gains[ch], 0.01) << ch;
}

TEST(ColourAlignment, NoGainWithoutOverlapOrWithinTheDeadband) {
  // The same camera: nothing to undo, and colours stay bit for bit.
  TwoScans same = MakeTwoScans({1.0, 1.0, 1.0});
  ColourReference ref;
  ref.Align(same.points, same.colours, 0, same.split);
  EXPECT_EQ(ref.Gains(same.points, same.colours, same.split, same.points.size()),
            (std::array<double, 3>{1, 1, 1}));
  // A gain within the deadband (1 %) is left alone.
  TwoScans slight = MakeTwoScans({1.005, 1.0, 0.996});
  EXPECT_EQ(ref.Gains(slight.points, slight.colours, slight.split, slight.points.size()),
            (std::array<double, 3>{1, 1, 1}));
  // Too few shared cells: a scan of another wall.
  TwoScans t = MakeTwoScans({1.5, 1.5, 1.5});
  for (std::size_t i = t.split; i < t.points.size(); ++i) t.points[i].y() += 1.0f;
  ColourReference ref2;
  ref2.Align(t.points, t.colours, 0, t.split);
  EXPECT_EQ(ref2.Gains(t.points, t.colours, t.split, t.points.size()),
            (std::array<double, 3>{1, 1, 1}));
  // Disabled.
  ColourAlignmentParams off;
  off.enabled = false;
  ColourReference ref3(off);
  TwoScans u = MakeTwoScans({1.5, 1.5, 1.5});
  ref3.Align(u.points, u.colours, 0, u.split);
  EXPECT_EQ(ref3.Gains(u.points, u.colours, u.split, u.points.size()),
            (std::array<double, 3>{1, 1, 1}));
}

// Median per channel over 5 cm cells seen by both scans of the ratio scan 1 / scan 0 of their
// mean linear colours in the model.
std::array<double, 3> ModelRatio(const RoomModel& m) {
  struct Acc {
    std::array<double, 3> sum[2]{};
    int n[2]{0, 0};
  };
  std::unordered_map<std::int64_t, Acc> cells;
  const auto& pts = m.Points();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto key = (static_cast<std::int64_t>(std::floor(pts[i].x() / 0.05)) << 40) ^
                     (static_cast<std::int64_t>(std::floor(pts[i].y() / 0.05)) << 20) ^
                     static_cast<std::int64_t>(std::floor(pts[i].z() / 0.05));
    Acc& a = cells[key];
    const int s = m.ScanIndices()[i];
    for (std::size_t ch = 0; ch < 3; ++ch) a.sum[s][ch] += Linear(m.Colours()[i][ch]);
    ++a.n[s];
  }
  std::array<std::vector<double>, 3> r;
  for (const auto& [key, a] : cells) {
    if (a.n[0] < 3 || a.n[1] < 3) continue;
    for (std::size_t ch = 0; ch < 3; ++ch)
      r[ch].push_back((a.sum[1][ch] / a.n[1]) / (a.sum[0][ch] / a.n[0]));
  }
  std::array<double, 3> out{};
  for (std::size_t ch = 0; ch < 3; ++ch) {
    EXPECT_GT(r[ch].size(), 500u);
    std::nth_element(r[ch].begin(), r[ch].begin() + r[ch].size() / 2, r[ch].end());
    out[ch] = r[ch][r[ch].size() / 2];
  }
  return out;
}

// A room scanned twice by a scanner with `tls`'s camera, modelled without and with the alignment.
struct RawAndAligned {
  RoomModel raw{Off()}, aligned;
  static RoomModelParams Off() {
    RoomModelParams p;
    p.colour_alignment.enabled = false;
    return p;
  }
};
RawAndAligned TwoScansOfARoom(const sim::TlsParams& tls) {
  const sim::EmbreeWorld world(testing::RoomWithDoorScene());
  const testing::SimScan a = testing::TakeScan(world, tls, 2.0, 1.8, 0);
  const testing::SimScan b = testing::TakeScan(world, tls, 4.0, 2.2, 1);
  RawAndAligned m;
  for (RoomModel* model : {&m.raw, &m.aligned}) {
    model->AddScan(a.scan, a.X_MS);
    model->AddScan(b.scan, b.X_MS);
  }
  return m;
}

TEST(ColourAlignment, ARoomsScansShareOneExposureAndWhiteBalance) {
  sim::TlsParams tls = testing::TestTls();
  tls.exposure_sigma_stops = 1.0;
  tls.white_balance_sigma = 0.3;
  const RawAndAligned m = TwoScansOfARoom(tls);
  // The camera changed between the scans: the raw model's colours disagree...
  const auto before = ModelRatio(m.raw);
  double worst = 0.0;
  for (double r : before) worst = std::max(worst, std::abs(std::log(r)));
  EXPECT_GT(worst, 0.1);
  // ... the aligned model's agree, the first scan untouched.
  const auto after = ModelRatio(m.aligned);
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(after[ch], 1.0, 0.02) << ch;
  EXPECT_EQ(m.aligned.ColourGains()[0], (std::array<double, 3>{1, 1, 1}));
  for (std::size_t ch = 0; ch < 3; ++ch)
    EXPECT_NEAR(m.aligned.ColourGains()[1][ch], 1.0 / before[ch], 0.02) << ch;
  // Geometry is not touched.
  EXPECT_EQ(m.raw.Points(), m.aligned.Points());
}

TEST(ColourAlignment, OneCameraLeavesTheColoursAsScanned) {
  // Colour noise, no change of exposure or white balance.
  const RawAndAligned m = TwoScansOfARoom(testing::TestTls());
  EXPECT_EQ(m.aligned.ColourGains()[1], (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(m.raw.Colours(), m.aligned.Colours());
}

}  // namespace
}  // namespace mopad::modelling
