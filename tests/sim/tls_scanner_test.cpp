#include "sim/tls_scanner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "io/scan_io.h"
#include "sim/realism.h"
#include "sim/scan_writer.h"
#include "sim/threads.h"
#include "tests/sim/test_scenes.h"

namespace mopad::sim {
namespace {

using testing::AddMaterial;
using testing::AddQuad;
using testing::AddRoomBox;
using testing::AddRoomWithOpening;
using testing::BoxExitDistance;
using V = Eigen::Vector3f;

TlsParams AtOrigin(TlsParams p) {
  p.mount_xyz = {0, 0, 0};
  return p;
}

ScanRequest At(double x, double y, double z, std::uint64_t seed = 1, std::uint64_t scan_id = 0) {
  ScanRequest r;
  r.seed = seed;
  r.scan_id = scan_id;
  r.X_WB.translation() = Eigen::Vector3d(x, y, z);
  return r;
}

Eigen::Vector3d Direction(const interfaces::TlsScan& s, std::uint32_t r, std::uint32_t c) {
  const double az = s.azimuth_min + c * s.azimuth_step, el = s.elevation_max - r * s.elevation_step;
  return Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("mopad_sim_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

scenes::Scene BoxScene(const V& lo, const V& hi) {
  scenes::Scene s;
  s.source = "box";
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  AddRoomBox(s, lo, hi, 0);
  return s;
}

TEST(TlsScanner, GridMatchesProfile) {
  EmbreeWorld world(BoxScene(V(-5, -4, -2), V(5, 4, 2)));
  TlsParams p;
  p.step_deg = 0.04;
  TlsScanner scanner(world, p);
  EXPECT_EQ(scanner.rows(), 2501u);
  EXPECT_EQ(scanner.columns(), 9000u);
  EXPECT_EQ(scanner.pulses(), 22509000u);
}

TEST(TlsScanner, EveryRayFromInsideAClosedRoomReturns) {
  // Scanner exactly at the centre: many rays aim at edges and corners of the box.
  const V lo(-4, -4, -1.5), hi(4, 4, 1.5);
  EmbreeWorld world(BoxScene(lo, hi));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.range_min = 0.0;
  p.step_deg = 0.1;
  p.elevation_max_deg = 90;
  p.elevation_min_deg = -90;
  TlsScanner scanner(world, p);
  const auto scan = scanner.Scan(At(0, 0, 0));
  std::size_t missing = 0;
  for (const auto& pt : scan.points) missing += !pt.valid();
  EXPECT_EQ(missing, 0u) << "of " << scan.points.size();
  // With the full noise model (dropouts off for a deterministic count) too.
  TlsParams noisy = AtOrigin(TlsParams{});
  noisy.dropouts = false;
  noisy.range_min = 0.0;
  const auto scan2 = TlsScanner(world, noisy).Scan(At(0.3, -0.2, 0.1));
  missing = 0;
  for (const auto& pt : scan2.points) missing += !pt.valid();
  EXPECT_EQ(missing, 0u);
}

TEST(TlsScanner, NoiseFreeRangesMatchTheAnalyticDistance) {
  const V lo(-3, -5, -1.2), hi(6, 4, 1.8);
  EmbreeWorld world(BoxScene(lo, hi));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.step_deg = 0.25;
  TlsScanner scanner(world, p);
  const Eigen::Vector3d o(0.37, -0.21, 0.05);
  const auto scan = scanner.Scan(At(o.x(), o.y(), o.z()));
  double worst = 0.0;
  std::size_t n = 0;
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const auto& pt = scan.at(r, c);
      const Eigen::Vector3d d = Direction(scan, r, c);
      const double t = BoxExitDistance(o, d, lo.cast<double>(), hi.cast<double>());
      if (t < p.range_min) {
        EXPECT_FALSE(pt.valid());
        continue;
      }
      ASSERT_TRUE(pt.valid()) << r << "," << c;
      worst = std::max(worst, std::abs(pt.range - t));
      worst = std::max(worst, (Eigen::Vector3d(pt.x, pt.y, pt.z) - t * d).norm());
      ++n;
    }
  EXPECT_GT(n, 100000u);
  EXPECT_LT(worst, 1e-4) << "m";
}

// Accuracy is the total 1-sigma range error, precision the per-point repeatability (RIEGL's
// definitions): residual = per-scan bias ~ N(0, sqrt(acc^2 - prec^2)) + N(0, prec).
TEST(TlsScanner, ResidualsMatchConfiguredAccuracyAndPrecision) {
  const V lo(-6, -6, -2), hi(6, 6, 2);
  EmbreeWorld world(BoxScene(lo, hi));
  TlsParams p = AtOrigin(TlsParams{});
  p.incidence_noise_exponent = 0.0;  // isolate the range noise
  p.dropouts = false;
  p.tilt_sigma_deg = 0.0;
  p.angle_noise_deg = 0.0;
  p.range_precision = 0.003;
  p.range_accuracy = 0.005;

  // (1) Within one scan: sigma = precision, mean = the scan's drawn bias (in the truth).
  {
    p.step_deg = 0.5;
    TlsScanner scanner(world, p);
    TlsTruth truth;
    const auto scan = scanner.Scan(At(0.5, 0.5, 0, 7, 3), &truth);
    double sum = 0, sum2 = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      if (!scan.points[i].valid()) continue;
      const double e = scan.points[i].range - truth.points[i].true_range - truth.range_bias;
      sum += e;
      sum2 += e * e;
      ++n;
    }
    ASSERT_GE(n, 100000u);
    const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(sigma, p.range_precision, 0.1 * p.range_precision);
    EXPECT_NEAR(mean, 0.0, 0.1 * p.range_precision);
  }
  // (2) Over many scans: total residual sigma = accuracy, per-scan biases ~ N(0, 4 mm), mean ~ 0.
  {
    p.step_deg = 5.0;
    TlsScanner scanner(world, p);
    double sum = 0, sum2 = 0, bias2 = 0;
    std::size_t n = 0;
    const int scans = 1000;
    for (int k = 0; k < scans; ++k) {
      TlsTruth truth;
      const auto scan = scanner.Scan(At(0.5, 0.5, 0, 11, static_cast<std::uint64_t>(k)), &truth);
      bias2 += truth.range_bias * truth.range_bias;
      for (std::size_t i = 0; i < scan.points.size(); ++i) {
        if (!scan.points[i].valid()) continue;
        const double e = scan.points[i].range - truth.points[i].true_range;
        sum += e;
        sum2 += e * e;
        ++n;
      }
    }
    ASSERT_GE(n, 100000u);
    const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(sigma, p.range_accuracy, 0.1 * p.range_accuracy);
    EXPECT_NEAR(std::sqrt(bias2 / scans), 0.004, 0.1 * 0.004);
    EXPECT_NEAR(mean, 0.0, 0.1 * p.range_accuracy);
  }
  // (3) A fixed calibration offset shows up as the residual mean.
  {
    p.step_deg = 0.5;
    p.range_accuracy = p.range_precision;  // no random per-scan part
    p.range_offset = 0.005;
    TlsScanner scanner(world, p);
    TlsTruth truth;
    const auto scan = scanner.Scan(At(0, 0, 0), &truth);
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      if (!scan.points[i].valid()) continue;
      sum += scan.points[i].range - truth.points[i].true_range;
      ++n;
    }
    ASSERT_GE(n, 100000u);
    EXPECT_NEAR(sum / n, p.range_offset, 0.1 * p.range_offset);
  }
}

TEST(TlsScanner, NoiseGrowsWithIncidenceAsConfigured) {
  // A large floor seen from 1.5 m: incidence from 0 to ~80 deg.
  scenes::Scene s;
  AddMaterial(s, "white", 0.9f, 0.9f, 0.9f);
  AddQuad(s, V(-30, -30, 0), V(30, -30, 0), V(30, 30, 0), V(-30, 30, 0),
          scenes::ElementClass::kFloor, "floor", 0);
  EmbreeWorld world(std::move(s));
  TlsParams p = AtOrigin(TlsParams{});
  p.elevation_max_deg = -10;
  p.elevation_min_deg = -90;
  p.step_deg = 0.1;
  p.dropouts = false;
  p.tilt_sigma_deg = p.angle_noise_deg = 0.0;
  p.range_accuracy = p.range_precision = 0.003;
  p.incidence_noise_exponent = 1.0;
  p.range_min = 0.0;
  TlsScanner scanner(world, p);
  TlsTruth truth;
  const auto scan = scanner.Scan(At(0, 0, 1.5), &truth);
  // Bins of incidence angle: measured RMS residual vs the configured precision / cos(alpha).
  struct Bin {
    double lo, hi, sum2 = 0, expected2 = 0;
    std::size_t n = 0;
  };
  std::vector<Bin> bins = {{0, 20}, {30, 40}, {50, 60}, {65, 75}};
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const auto& pt = scan.at(r, c);
      if (!pt.valid()) continue;
      const double cos_a = -Direction(scan, r, c).z();
      const double alpha = RadToDeg(std::acos(cos_a));
      const double e = pt.range - truth.at(r, c).true_range;
      for (auto& b : bins) {
        if (alpha < b.lo || alpha >= b.hi) continue;
        b.sum2 += e * e;
        b.expected2 += std::pow(p.range_precision / cos_a, 2);
        ++b.n;
      }
    }
  double previous = 0;
  for (const auto& b : bins) {
    ASSERT_GT(b.n, 10000u) << b.lo;
    const double rms = std::sqrt(b.sum2 / b.n), expected = std::sqrt(b.expected2 / b.n);
    EXPECT_NEAR(rms, expected, 0.1 * expected) << "incidence " << b.lo << "-" << b.hi << " deg";
    EXPECT_GT(rms, previous);
    previous = rms;
  }
}

TEST(TlsScanner, RaysThroughAnOpenDoorLeaveTheRoom) {
  scenes::Scene s;
  AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  AddRoomWithOpening(s, 8, 6, 3, 2.5f, 3.5f, 0.0f, 2.1f, 0);  // door 1 m x 2.1 m in x = 8
  EmbreeWorld world(std::move(s));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.step_deg = 0.2;
  TlsScanner scanner(world, p);
  const Eigen::Vector3d o(3, 3, 1.4);
  TlsTruth truth;
  const auto scan = scanner.Scan(At(o.x(), o.y(), o.z()), &truth);
  std::size_t through = 0, wrong = 0;
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const Eigen::Vector3d d = Direction(scan, r, c);
      bool in_gap = false;
      if (d.x() > 1e-9) {
        const double t = (8 - o.x()) / d.x();
        const Eigen::Vector3d q = o + t * d;
        const bool strictly =
            q.y() > 2.5 + 1e-3 && q.y() < 3.5 - 1e-3 && q.z() > 1e-3 && q.z() < 2.1 - 1e-3;
        const bool near_edge =
            !strictly && q.y() > 2.5 - 1e-3 && q.y() < 3.5 + 1e-3 && q.z() < 2.1 + 1e-3;
        if (near_edge) continue;
        in_gap = strictly;
      }
      const bool valid = scan.at(r, c).valid();
      if (in_gap) {
        ++through;
        wrong += valid;
        if (valid)
          ADD_FAILURE() << "return through the gap at " << r << "," << c << " range "
                        << scan.at(r, c).range;
        EXPECT_EQ(truth.at(r, c).part, -1);
      } else {
        wrong += !valid;
        if (!valid)
          ADD_FAILURE() << "no return at " << r << "," << c << " flags "
                        << int(truth.at(r, c).flags) << " part " << truth.at(r, c).part << " d "
                        << d.transpose();
      }
    }
  EXPECT_GT(through, 500u);
  EXPECT_EQ(wrong, 0u);
}

TEST(TlsScanner, RaysThroughAWindowLeaveAndComeBackAsOutliers) {
  scenes::Scene s;
  const int white = AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  const int glass = AddMaterial(s, "glass", 0.9f, 0.95f, 0.95f, 0.f, 0.05f, 1.0f);
  AddRoomWithOpening(s, 8, 6, 3, 2.0f, 4.0f, 1.0f, 2.2f, white);
  AddQuad(s, V(8, 2, 1), V(8, 4, 1), V(8, 4, 2.2f), V(8, 2, 2.2f),
          scenes::ElementClass::kWindowGlass, "window_1", glass);
  const std::size_t n_room_parts = s.parts.size();
  EmbreeWorld world(s);
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.step_deg = 0.2;
  const Eigen::Vector3d o(3, 3, 1.6);
  auto count = [&](const EmbreeWorld& w, std::size_t* through, std::size_t* outliers,
                   double* far_range) {
    TlsTruth truth;
    const auto scan = TlsScanner(w, p).Scan(At(o.x(), o.y(), o.z()), &truth);
    *through = *outliers = 0;
    *far_range = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const auto& t = truth.points[i];
      if (!scan.points[i].valid() && t.part < 0) ++*through;
      if (scan.points[i].valid() && (t.flags & kTruthTransmitted)) {
        ++*outliers;
        *far_range = std::max(*far_range, static_cast<double>(scan.points[i].range));
        EXPECT_GT(scan.points[i].range, 8 - o.x());  // beyond the window: an outlier of the room
      }
    }
  };
  std::size_t through, outliers;
  double far_range;
  count(world, &through, &outliers, &far_range);
  EXPECT_GT(through, 1000u);  // nothing outside: the rays are lost
  EXPECT_EQ(outliers, 0u);
  // A building across the street: the same rays now come back from 20 m away, flagged.
  AddQuad(s, V(28, -20, -5), V(28, 20, -5), V(28, 20, 10), V(28, -20, 10),
          scenes::ElementClass::kWall, "facade", white);
  ASSERT_EQ(s.parts.size(), n_room_parts + 1);
  EmbreeWorld world2(std::move(s));
  std::size_t through2, outliers2;
  count(world2, &through2, &outliers2, &far_range);
  EXPECT_GT(outliers2, 1000u);
  EXPECT_GT(far_range, 25.0 - o.x());
}

TEST(TlsScanner, ColoursOnATexturedQuadMatchTheTexture) {
  scenes::Scene s;
  // 12 x 12 texels in 4 x 4 blocks of 3 x 3 equal texels, every block a different colour (so
  // bilinear filtering near a block's middle texel sees only that block's colour).
  scenes::Texture tex;
  tex.name = "checker";
  tex.width = tex.height = 12;
  for (int ty = 0; ty < 12; ++ty)
    for (int tx = 0; tx < 12; ++tx) {
      const int x = tx / 3, y = ty / 3;
      tex.rgba.push_back(static_cast<std::uint8_t>(20 + 60 * x));
      tex.rgba.push_back(static_cast<std::uint8_t>(10 + 70 * y));
      tex.rgba.push_back(static_cast<std::uint8_t>(200 - 13 * (x + 4 * y)));
      tex.rgba.push_back(255);
    }
  s.textures.push_back(tex);
  scenes::Material m;
  m.name = "textured";
  m.base_color = Eigen::Vector4f(1, 1, 1, 1);
  m.base_color_texture = 0;
  s.materials.push_back(m);
  // Quad in the plane x = 4, facing -x: u along +y, v down (glTF: v = 0 at the top).
  scenes::MeshPart q;
  q.name = q.element_id = "poster";
  q.element_class = scenes::ElementClass::kWall;
  q.material = 0;
  q.positions = {V(4, -1, 2), V(4, 1, 2), V(4, 1, 0), V(4, -1, 0)};
  q.uvs = {Eigen::Vector2f(0, 0), Eigen::Vector2f(1, 0), Eigen::Vector2f(1, 1),
           Eigen::Vector2f(0, 1)};
  q.triangles = {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(0, 2, 3)};
  s.parts.push_back(q);
  EmbreeWorld world(std::move(s));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.ambient_light = 1.0;
  p.top_light = 0.0;
  p.step_deg = 0.1;
  const Eigen::Vector3d o(0, 0, 1);
  const auto scan = TlsScanner(world, p).Scan(At(o.x(), o.y(), o.z()));
  std::size_t checked = 0;
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const auto& pt = scan.at(r, c);
      if (!pt.valid()) continue;
      const Eigen::Vector3d w = o + Eigen::Vector3d(pt.x, pt.y, pt.z);
      const double u = (w.y() + 1) / 2, v = (2 - w.z()) / 2;
      const double fx = u * 4, fy = v * 4;
      // Only near a block's middle texel, where bilinear filtering stays inside the block.
      if (std::abs(fx - std::floor(fx) - 0.5) > 0.15 || std::abs(fy - std::floor(fy) - 0.5) > 0.15)
        continue;
      const int x = std::clamp(static_cast<int>(fx), 0, 3),
                y = std::clamp(static_cast<int>(fy), 0, 3);
      const std::uint8_t* t = &tex.rgba[4 * ((3 * y + 1) * 12 + 3 * x + 1)];
      EXPECT_NEAR(pt.r, t[0], 1) << x << "," << y;
      EXPECT_NEAR(pt.g, t[1], 1);
      EXPECT_NEAR(pt.b, t[2], 1);
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
}

TEST(TlsScanner, MixedPixelsAppearOnlyAtDepthEdges) {
  scenes::Scene s;
  const int white = AddMaterial(s, "white", 0.7f, 0.7f, 0.7f);
  AddRoomBox(s, V(-6, -6, -1.5f), V(6, 6, 1.5f), white);
  // A panel 0.3 m in front of the east wall (closer than echo_separation): depth edges.
  AddQuad(s, V(5.7f, -1, -0.5f), V(5.7f, 1, -0.5f), V(5.7f, 1, 0.5f), V(5.7f, -1, 0.5f),
          scenes::ElementClass::kFurniture, "panel", white);
  EmbreeWorld world(std::move(s));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.step_deg = 0.1;
  p.beam_divergence_mrad = 3.0;  // wide beam so the footprint straddles edges often
  TlsParams one = p;
  p.footprint_rays = 7;
  const auto req = At(0, 0, 0);
  TlsTruth truth1, truth7;
  const auto s1 = TlsScanner(world, one).Scan(req, &truth1);
  const auto s7 = TlsScanner(world, p).Scan(req, &truth7);
  auto is_edge = [&](std::uint32_t r, std::uint32_t c) {
    const auto& t0 = truth1.at(r, c);
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const long rr = static_cast<long>(r) + dr;
        const long cc = (static_cast<long>(c) + dc + s1.columns) % s1.columns;
        if (rr < 0 || rr >= static_cast<long>(s1.rows)) continue;
        const auto& t = truth1.at(static_cast<std::uint32_t>(rr), static_cast<std::uint32_t>(cc));
        if (t.part != t0.part || std::abs(t.true_range - t0.true_range) > 0.05) return true;
      }
    return false;
  };
  std::size_t mixed = 0, edges = 0;
  for (std::uint32_t r = 0; r < s1.rows; ++r)
    for (std::uint32_t c = 0; c < s1.columns; ++c) {
      const auto &a = s1.at(r, c), &b = s7.at(r, c);
      ASSERT_TRUE(a.valid() && b.valid());
      const bool edge = is_edge(r, c);
      edges += edge;
      const bool deviates = std::abs(a.range - b.range) > 0.002;
      const bool flagged = truth7.at(r, c).flags & kTruthMixed;
      if (deviates || flagged) {
        EXPECT_TRUE(edge) << "mixed pixel away from any depth edge at " << r << "," << c << ": "
                          << a.range << " vs " << b.range;
        ++mixed;
      }
    }
  EXPECT_GT(mixed, 100u);
  EXPECT_GT(edges, mixed);
}

TEST(TlsScanner, MinimumRangeIsHonoured) {
  EmbreeWorld world(BoxScene(V(-1, -5, -1.5f), V(8, 5, 1.5f)));
  TlsParams p = AtOrigin(TlsParams{}.NoiseFree());
  p.step_deg = 0.5;
  TlsTruth truth;
  const auto scan = TlsScanner(world, p).Scan(At(0, 0, 0), &truth);
  std::size_t close = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const auto& pt = scan.points[i];
    if (truth.points[i].true_range < p.range_min) {
      ++close;
      EXPECT_FALSE(pt.valid());
      EXPECT_TRUE(truth.points[i].flags & kTruthTooClose);
    } else {
      EXPECT_TRUE(pt.valid());
      EXPECT_GE(pt.range, p.range_min);
    }
  }
  EXPECT_GT(close, 1000u);
}

TEST(TlsScanner, DarkAndSpecularSurfacesDropOut) {
  scenes::Scene s;
  const int white = AddMaterial(s, "white", 0.8f, 0.8f, 0.8f);
  const int black = AddMaterial(s, "black", 0.01f, 0.01f, 0.01f, 0.f, 1.f, 0.f, 0.002f);
  const int mirror = AddMaterial(s, "chrome", 0.9f, 0.9f, 0.9f, 1.f, 0.05f);
  AddRoomBox(s, V(-6, -6, -1.5f), V(6, 6, 1.5f), white);
  AddQuad(s, V(5.9f, -3, -1), V(5.9f, -1, -1), V(5.9f, -1, 1), V(5.9f, -3, 1),
          scenes::ElementClass::kFurniture, "black", black);
  AddQuad(s, V(5.9f, 1, -1), V(5.9f, 3, -1), V(5.9f, 3, 1), V(5.9f, 1, 1),
          scenes::ElementClass::kFurniture, "chrome", mirror);
  EmbreeWorld world(std::move(s));
  TlsParams p = AtOrigin(TlsParams{});
  p.step_deg = 0.2;
  TlsTruth truth;
  const auto scan = TlsScanner(world, p).Scan(At(0, 0, 0), &truth);
  const auto& ids = truth.element_ids;
  auto id_of = [&](const std::string& name) {
    return static_cast<int>(std::find(ids.begin(), ids.end(), name) - ids.begin());
  };
  std::size_t hits[3] = {0, 0, 0}, returns[3] = {0, 0, 0};
  const int elems[3] = {id_of("wall_e"), id_of("black"), id_of("chrome")};
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (truth.points[i].element == elems[k]) {
        ++hits[k];
        returns[k] += scan.points[i].valid();
      }
  for (int k = 0; k < 3; ++k) ASSERT_GT(hits[k], 500u) << k;
  EXPECT_GT(returns[0], 0.99 * hits[0]);  // white wall: everything returns
  EXPECT_LT(returns[1], 0.6 * hits[1]);   // 0.2 % reflectance (+ 4 % Fresnel lobe): thinned out
  EXPECT_LT(returns[2], 0.1 * hits[2]);   // polished metal at 10-30 deg incidence: lost
}

TEST(TlsScanner, OutputIsByteIdenticalWithOneAndTwoThreads) {
  scenes::Scene s;
  const int white = AddMaterial(s, "white", 0.8f, 0.6f, 0.4f);
  const int glass = AddMaterial(s, "glass", 0.9f, 0.95f, 0.95f, 0.f, 0.05f, 0.7f);
  AddRoomWithOpening(s, 8, 6, 3, 2.0f, 4.0f, 1.0f, 2.2f, white);
  AddQuad(s, V(8, 2, 1), V(8, 4, 1), V(8, 4, 2.2f), V(8, 2, 2.2f),
          scenes::ElementClass::kWindowGlass, "window_1", glass);
  AddQuad(s, V(20, -20, -5), V(20, 20, -5), V(20, 20, 10), V(20, -20, 10),
          scenes::ElementClass::kWall, "facade", white);
  EmbreeWorld world(std::move(s));
  // The vectorised single-ray path and the general path (footprint, camera parallax).
  TlsParams single;
  single.step_deg = 0.2;
  single.angle_noise_deg = 0.001;
  TlsParams p;
  p.step_deg = 0.3;
  p.footprint_rays = 7;
  p.camera_offset = {0.0, 0.05, 0.1};
  // And the instrument's errors of the hard realism profile (axes, range walk, colour gains).
  TlsParams realistic = RealisticTls(TlsParams{}, RealismProfile("hard").scanner, 1234);
  realistic.step_deg = 0.2;
  ScanRequest req = At(3, 3, 0, 1234, 5);
  for (const TlsParams& params : {single, p, realistic}) {
    TlsScanner scanner(world, params);
    auto run = [&](int threads, const std::string& tag) {
      const ScanOutputPaths paths{TempPath(tag + ".ply"), TempPath(tag + ".ptx"),
                                  TempPath(tag + ".truth.ply")};
      RunWithThreads(threads, [&] {
        ScanFileSink sink(paths, scanner.MakeHeader(req), scanner.MakeTruthHeader(req),
                          scanner.pulses());
        scanner.ScanStreamed(req, sink);
        sink.Close();
      });
      std::array<std::string, 3> files = {ReadBytes(paths.ply), ReadBytes(paths.ptx),
                                          ReadBytes(paths.truth)};
      for (const auto& f : {paths.ply, paths.ptx, paths.truth}) std::remove(f.c_str());
      return files;
    };
    const auto one = run(1, "t1"), two = run(2, "t2");
    EXPECT_GT(one[0].size(), 1000000u);
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE(one[i] == two[i]) << "file " << i << " differs between 1 and 2 threads";
    // And the streamed files equal the in-memory scan written afterwards.
    TlsTruth truth;
    const auto scan = scanner.Scan(req, &truth);
    const std::string ply = TempPath("mem.ply"), ptx = TempPath("mem.ptx"),
                      tply = TempPath("mem.truth.ply");
    io::WriteTlsScanPly(ply, scan);
    io::WriteTlsScanPtx(ptx, scan);
    WriteTlsTruthPly(tply, scan, truth);
    EXPECT_TRUE(ReadBytes(ply) == one[0]);
    EXPECT_TRUE(ReadBytes(ptx) == one[1]);
    EXPECT_TRUE(ReadBytes(tply) == one[2]);
    for (const auto& f : {ply, ptx, tply}) std::remove(f.c_str());
  }
  TlsScanner scanner(world, p);
  TlsTruth truth;
  const auto scan = scanner.Scan(req, &truth);
  // A different seed changes the noise.
  ScanRequest other = req;
  other.seed = 99;
  const auto scan_other = scanner.Scan(other);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    differ += scan.points[i].range != scan_other.points[i].range;
  EXPECT_GT(differ, scan.points.size() / 2);
}

TEST(TlsScanner, ScanCarriesNoTruth) {
  // The robot's scan type has exactly the fields a real scanner reports.
  static_assert(sizeof(interfaces::TlsPoint) == 40,
                "TlsPoint changed: keep truth out of it (sim/tls_truth.h)");
  static_assert(!std::is_same_v<interfaces::TlsScan, TlsTruth>);
  EmbreeWorld world(BoxScene(V(-3, -3, -1.5f), V(3, 3, 1.5f)));
  TlsParams p = AtOrigin(TlsParams{});
  p.step_deg = 2;
  const auto scan = TlsScanner(world, p).Scan(At(0, 0, 0));
  const std::string path = TempPath("notruth.ply");
  io::WriteTlsScanPly(path, scan);
  const std::string bytes = ReadBytes(path);
  const std::string header = bytes.substr(0, bytes.find("end_header"));
  for (const char* bad :
       {"label", "element", "part", "class", "door", "true", "flags", "X_WS", "bias"}) {
    // "element vertex" is the PLY keyword; anything else naming truth is a leak.
    std::string h = header;
    for (std::size_t pos; (pos = h.find("element vertex")) != std::string::npos;) h.erase(pos, 14);
    EXPECT_EQ(h.find(bad), std::string::npos) << bad;
  }
  std::remove(path.c_str());
}

TEST(TlsScanner, PoseStampAndTimestamps) {
  EmbreeWorld world(BoxScene(V(-3, -3, -1.5f), V(3, 3, 3)));
  TlsParams p;  // default mount 1.4 m above base_link
  p.step_deg = 1;
  TlsScanner scanner(world, p);
  ScanRequest req = At(0.5, 0.2, 0);
  req.X_WB.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  req.start_time = 10.0;
  TlsTruth truth;
  const auto scan = scanner.Scan(req, &truth);
  EXPECT_NEAR(scan.X_MS_estimate.translation().z(), 1.4, 1e-12);
  EXPECT_TRUE(scan.X_MS_estimate.isApprox(req.X_WB * scanner.X_BS()));
  EXPECT_NEAR(scan.points[0].timestamp, 10.0, 1e-12);
  EXPECT_NEAR(scan.at(1, 0).timestamp - scan.at(0, 0).timestamp, 1.0 / p.pulse_rate_hz, 1e-12);
  EXPECT_NEAR(scan.at(0, 1).timestamp - scan.at(0, 0).timestamp, scan.rows / p.pulse_rate_hz, 1e-9);
  // The drawn tilt is in the truth only.
  EXPECT_GT(std::abs(truth.tilt_roll) + std::abs(truth.tilt_pitch), 0.0);
  EXPECT_FALSE(truth.X_WS.isApprox(scan.X_MS_estimate, 1e-9));
}

}  // namespace
}  // namespace mopad::sim
