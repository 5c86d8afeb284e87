// SM5's placement on the samples (modelling/sample_fit.h): box queries of SeSamples, and the
// fit of a model's depth or colour to samples drawn in code on a wall, with known truth.

#include "modelling/sample_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "common/error.h"
#include "common/rng.h"

namespace mopad::modelling {
namespace {

constexpr double kPixel = 0.005;  // SE image pixel, m

// A 2 m x 1 m wall's image (no points: SeSamples only reads its geometry).
Orthoimage WallImage() { return Orthoimage(PatchFrame{}, kPixel, 400, 200); }

// Samples one per cell of a grid of `spacing` over the wall, anywhere in it (as scans from
// several places interleave: no edge falls between two rows of samples), with range noise
// `noise` (m) and colour noise of 3 levels; depth and colour of the surface at (u, v) from
// `surface`; `seen(u, v)` false: no sample there (a shadow).
struct Drawn {
  std::vector<Eigen::Vector3f> uvd;
  std::vector<std::array<std::uint8_t, 3>> rgb;
};
Drawn Draw(double spacing, double noise,
           const std::function<void(double, double, double*, cv::Vec3b*)>& surface,
           const std::function<bool(double, double)>& seen = nullptr) {
  CounterRng rng(7, "sample_fit_test");
  Drawn d;
  for (double v = 0.2; v < 0.8; v += spacing)
    for (double u = 0.6; u < 1.4; u += spacing) {
      const double uu = u + rng.Uniform(-0.5, 0.5) * spacing;
      const double vv = v + rng.Uniform(-0.5, 0.5) * spacing;
      if (seen && !seen(uu, vv)) continue;
      double depth = 0.0;
      cv::Vec3b c;
      surface(uu, vv, &depth, &c);
      d.uvd.emplace_back(static_cast<float>(uu), static_cast<float>(vv),
                         static_cast<float>(depth + rng.Uniform(-1.7, 1.7) * noise));
      std::array<std::uint8_t, 3> q;
      for (int k = 0; k < 3; ++k)
        q[k] = static_cast<std::uint8_t>(std::clamp(c[k] + rng.Uniform(-3.0, 3.0), 0.0, 255.0));
      d.rgb.push_back(q);
    }
  return d;
}

const cv::Vec3b kWallRgb(220, 218, 205);
const cv::Vec3b kRed(200, 30, 32);

// A socket-like box, 8 x 8 cm, 4 cm proud, with a 7.2 cm cover 7 mm prouder than its base, at
// (u0, v0); its model at 2 mm pixels.
void Socket(double u0, double v0, double u, double v, double* depth, cv::Vec3b* c) {
  *depth = 0.0, *c = kWallRgb;
  if (std::abs(u - u0) < 0.04 && std::abs(v - v0) < 0.04)
    *depth = 0.033, *c = cv::Vec3b(245, 245, 242);
  if (std::abs(u - u0) < 0.036 && std::abs(v - v0) < 0.036) *depth = 0.04;
}
SampleModel SocketModel() {
  SampleModel m;
  m.pixel = 0.002;
  m.width = m.height = 0.08;
  m.protrusion = 0.04;
  m.depth = cv::Mat(40, 40, CV_32F, cv::Scalar(0.033));
  m.depth(cv::Rect(2, 2, 36, 36)).setTo(0.04);
  return m;
}

// The image pixel of (u, v) and back (edge convention, as SeSamples places a sample).
double ColOf(double u) { return u / kPixel; }
double RowOf(double v) { return 200 - v / kPixel; }

// The place a fit gives, (u, v) in metres, from its start (col, row).
double UOf(const SampleFit& f, double col) { return (col + f.dcol) * kPixel; }
double VOf(const SampleFit& f, double row) { return 200 * kPixel - (row + f.drow) * kPixel; }

TEST(SeSamples, InReturnsExactlyTheSamplesInTheBox) {
  const Orthoimage im = WallImage();
  const Drawn d = Draw(
      0.01, 0.0, [](double u, double v, double* z, cv::Vec3b* c) { Socket(1.0, 0.5, u, v, z, c); });
  const SeSamples s(im, d.uvd, d.rgb);
  const double c0 = 150.3, r0 = 41.7, c1 = 233.9, r1 = 120.2;
  std::vector<int> brute;
  int n = 0;
  for (std::size_t k = 0; k < d.uvd.size(); ++k) {
    const double c = ColOf(d.uvd[k].x()), r = RowOf(d.uvd[k].y());
    if (c >= c0 && c < c1 && r >= r0 && r < r1) brute.push_back(n);
    ++n;  // every drawn sample lies on the image
  }
  const std::vector<int> got = s.In(c0, r0, c1, r1);
  EXPECT_EQ(got, brute);
  EXPECT_GT(got.size(), 50u);
  EXPECT_TRUE(s.In(500, 0, 600, 10).empty());  // beyond the image
  EXPECT_THROW(SeSamples(im, d.uvd, {}), InputError);
}

// Samples 8 mm apart with 2 mm range noise: the fit finds the socket's place from 7 mm and
// 4 mm off to within a millimetre, in both axes.
TEST(FitOnSamples, FindsTheBoxOfASocketFromItsSamples) {
  const double u0 = 1.0031, v0 = 0.4987;
  const Drawn d = Draw(0.008, 0.002, [&](double u, double v, double* z, cv::Vec3b* c) {
    Socket(u0, v0, u, v, z, c);
  });
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  const double col = ColOf(u0 + 0.007), row = RowOf(v0 - 0.004);
  const SampleFit f = FitOnSamples(s, SocketModel(), col, row, kPixel, 0.008, {});
  ASSERT_TRUE(f.fitted);
  EXPECT_NEAR(UOf(f, col), u0, 0.001);
  EXPECT_NEAR(VOf(f, row), v0, 0.001);
  EXPECT_GT(f.samples, 100);
}

// Depth and colour together (the sum of both losses) place it as well.
TEST(FitOnSamples, DepthAndColourTogetherPlaceTheSocket) {
  const double u0 = 1.0024, v0 = 0.5031;
  const Drawn d = Draw(0.008, 0.002, [&](double u, double v, double* z, cv::Vec3b* c) {
    Socket(u0, v0, u, v, z, c);
  });
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  SampleModel m = SocketModel();
  m.wall_rgb = kWallRgb;
  m.colour_rgb = cv::Mat(40, 40, CV_8UC3, cv::Scalar(245, 245, 242));
  const double col = ColOf(u0 - 0.006), row = RowOf(v0 + 0.005);
  const SampleFit f = FitOnSamples(s, m, col, row, kPixel, 0.008, {});
  ASSERT_TRUE(f.fitted);
  EXPECT_NEAR(UOf(f, col), u0, 0.001);
  EXPECT_NEAR(VOf(f, row), v0, 0.001);
}

// Seen from the left at a slant, the socket hides 3 cm of the wall to its right: no sample
// there. The shadow pulls nothing: the place is still within a millimetre.
TEST(FitOnSamples, AShadowBesideTheObjectPullsNothing) {
  const double u0 = 0.9972, v0 = 0.5013;
  auto surface = [&](double u, double v, double* z, cv::Vec3b* c) { Socket(u0, v0, u, v, z, c); };
  auto seen = [&](double u, double v) {
    return !(u >= u0 + 0.04 && u < u0 + 0.07 && std::abs(v - v0) < 0.04);
  };
  const Drawn d = Draw(0.008, 0.002, surface, seen);
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  const double col = ColOf(u0 + 0.012), row = RowOf(v0);  // where a filled image puts it
  const SampleFit f = FitOnSamples(s, SocketModel(), col, row, kPixel, 0.008, {});
  ASSERT_TRUE(f.fitted);
  EXPECT_NEAR(UOf(f, col), u0, 0.001);
}

// A flush sign (a red plate with a white square on it) is placed by its colour alone.
TEST(FitOnSamples, AFlushSignIsPlacedByItsColour) {
  const double u0 = 1.0043, v0 = 0.5021;
  auto surface = [&](double u, double v, double* z, cv::Vec3b* c) {
    *z = 0.0, *c = kWallRgb;
    if (std::abs(u - u0) < 0.1 && std::abs(v - v0) < 0.1) *c = kRed;
    if (std::abs(u - u0 + 0.02) < 0.03 && std::abs(v - v0) < 0.03) *c = cv::Vec3b(250, 250, 250);
  };
  const Drawn d = Draw(0.01, 0.002, surface);
  SampleModel m;
  m.pixel = 0.002;
  m.width = m.height = 0.2;
  m.wall_rgb = kWallRgb;
  m.colour_rgb = cv::Mat(100, 100, CV_8UC3, cv::Scalar(kRed[0], kRed[1], kRed[2]));
  m.colour_rgb(cv::Rect(25, 35, 30, 30)).setTo(cv::Scalar(250, 250, 250));
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  const double col = ColOf(u0 - 0.009), row = RowOf(v0 + 0.006);
  const SampleFit f = FitOnSamples(s, m, col, row, kPixel, 0.01, {});
  ASSERT_TRUE(f.fitted);
  EXPECT_NEAR(UOf(f, col), u0, 0.001);
  EXPECT_NEAR(VOf(f, row), v0, 0.001);
}

// A model that does not describe the samples slides as far as the search lets it (here a
// socket's model started at the end of a 12 cm long bar of its depth: every place wholly on
// the bar fits, and the nearest is beyond the search): a best place at the edge of the search
// is no place, and the fit reports none; with a search that holds those places, it moves.
TEST(FitOnSamples, ABestPlaceAtTheEdgeOfTheSearchIsNone) {
  auto surface = [](double u, double v, double* z, cv::Vec3b* c) {
    *z = 0.0, *c = kWallRgb;
    if (u > 0.9 && u < 1.02 && std::abs(v - 0.5) < 0.04) *z = 0.04;
  };
  const Drawn d = Draw(0.008, 0.002, surface);
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  ComponentParams p;
  p.place_radius = 0.03;
  EXPECT_FALSE(FitOnSamples(s, SocketModel(), ColOf(0.9), RowOf(0.5), kPixel, 0.008, p).fitted);
  p.place_radius = 0.2;
  const SampleFit g = FitOnSamples(s, SocketModel(), ColOf(0.9), RowOf(0.5), kPixel, 0.008, p);
  ASSERT_TRUE(g.fitted);
  EXPECT_GT(UOf(g, ColOf(0.9)), 0.935);
  EXPECT_LT(UOf(g, ColOf(0.9)), 0.985);
}

TEST(FitOnSamples, TooFewSamplesGiveNoFit) {
  const Drawn d = Draw(0.2, 0.002, [](double u, double v, double* z, cv::Vec3b* c) {
    Socket(1.0, 0.5, u, v, z, c);
  });
  const SeSamples s(WallImage(), d.uvd, d.rgb);
  EXPECT_FALSE(FitOnSamples(s, SocketModel(), ColOf(1.0), RowOf(0.5), kPixel, 0.1, {}).fitted);
  EXPECT_FALSE(FitOnSamples(SeSamples(), SocketModel(), 10, 10, kPixel, 0.01, {}).fitted);
}

}  // namespace
}  // namespace mopad::modelling
