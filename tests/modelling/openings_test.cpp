// SM4 (paper §3.3): the orthoimage J_CD, opening detection from colour and depth, the
// door leaf's angle and state, and the sm4.json file. Scenes are coloured boxes scanned by the
// analytic ray caster of openings_scenes.h; the truth of each is the scene's own numbers.
#include "modelling/openings.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "common/error.h"
#include "modelling/model_io.h"
#include "modelling/orthoimage.h"
#include "modelling/voxel_space.h"
#include "tests/modelling/openings_scenes.h"

namespace mopad::modelling {
namespace {

using testing::Cloud;
using testing::HoleSpec;

// ---- The orthoimage ----

TEST(Orthoimage, WallFrameHasUHorizontalLeftToRightSeenFromTheRoomAndVUp) {
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);  // south wall, n = +y
  EXPECT_NEAR(f.n.dot(Vec3::UnitY()), 1.0, 1e-12);
  EXPECT_NEAR(f.v.dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(f.u.dot(-Vec3::UnitX()), 1.0, 1e-12);  // facing -y, right hand is -x
  EXPECT_NEAR(f.u.cross(f.v).dot(f.n), 1.0, 1e-12);
  EXPECT_NEAR(f.width, 5.0, 1e-12);
  EXPECT_NEAR(f.height, 2.7, 1e-12);
  EXPECT_NEAR((f.ToMap(0, 0) - Vec3(5, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(Orthoimage, CeilingFrameIsRightHandedWithUAlongX) {
  const PatchFrame f = PatchFrame::Of(-Vec3::UnitZ(), {{0, 0, 3}, {0, 2, 3}, {4, 2, 3}, {4, 0, 3}});
  EXPECT_NEAR(f.u.dot(Vec3::UnitX()), 1.0, 1e-12);
  EXPECT_NEAR(f.u.cross(f.v).dot(f.n), 1.0, 1e-12);
  EXPECT_NEAR(f.width, 4.0, 1e-12);
}

// A ray that stops just in front of the wall at a grazing angle meets the plane kilometres off
// the image: its pixel is one past the edge, never an int overflow (UBSan float-cast-overflow).
TEST(Orthoimage, APointFarOffTheImageIsOnePixelPastTheEdge) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{5, 0, 0}, {0, 0, 0}, {0, 0, 2}, {5, 0, 2}});
  const Orthoimage img(f, 0.01, 500, 200);
  const auto far = img.PixelOf(4.4e7, -4.4e7);
  EXPECT_EQ(far[0], 500);
  EXPECT_EQ(far[1], 200);
  const auto near = img.PixelOf(-4.4e7, 4.4e7);
  EXPECT_EQ(near[0], -1);
  EXPECT_EQ(near[1], -1);
  const auto nan = img.PixelOf(std::nan(""), std::nan(""));
  EXPECT_FALSE(img.Inside(nan[0], nan[1]));
  EXPECT_EQ(img.PixelOf(0.995, 1.005)[0], 99);  // inside: unchanged
}

TEST(Orthoimage, PointsLandInTheirPixelWithMeanColourAndSignedDepth) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{5, 0, 0}, {0, 0, 0}, {0, 0, 2}, {5, 0, 2}});
  std::vector<Eigen::Vector3f> pts = {
      {4.005f, 0.03f, 1.005f}, {4.005f, 0.01f, 1.005f}, {1.0f, 0.5f, 1.0f}};
  std::vector<std::array<std::uint8_t, 3>> rgb = {{100, 0, 0}, {200, 0, 50}, {1, 2, 3}};
  std::vector<std::uint16_t> scan = {0, 0, 0};
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb, in.scan_index = &scan, in.scan_origins = {{2.5, 2.0, 1.0}};
  const Orthoimage img = BuildOrthoimage(in, f, {}, 0.01);
  EXPECT_EQ(img.Cols(), 500);
  EXPECT_EQ(img.Rows(), 200);
  const auto px = img.PixelOf(0.995, 1.005);  // u = 5 - x
  ASSERT_TRUE(img.Inside(px[0], px[1]));
  const std::size_t i = img.Index(px[0], px[1]);
  EXPECT_EQ(img.Count(i), 2u);
  EXPECT_EQ(img.Rgb(i)[0], 150);
  EXPECT_EQ(img.Rgb(i)[2], 25);
  EXPECT_NEAR(img.Depth(i), 0.02, 1e-6);
  // The front depth is the surface nearest the room: an oblique scan that saw the wall behind
  // an object standing off it puts both in one pixel, and their mean is neither.
  EXPECT_NEAR(img.FrontDepth(i), 0.03, 1e-6);
  EXPECT_EQ(px[1], 200 - 1 - 100);  // row 0 at the top
  // The third point is 0.5 m in front (beyond the band): its ray, extended, meets the wall.
  std::uint32_t blocked = 0;
  for (std::size_t k = 0; k < 500u * 200u; ++k) blocked += img.Blocked(k);
  EXPECT_EQ(blocked, 1u);
}

TEST(Orthoimage, RaysEndingBehindTheWallMarkWherePassedThrough) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{5, 0, 0}, {0, 0, 0}, {0, 0, 2}, {5, 0, 2}});
  // Scanner at y = 2, point at y = -2 straight behind (x = 2, z = 1): crossing at (2, 0, 1).
  std::vector<Eigen::Vector3f> pts = {{2.0f, -2.0f, 1.0f}};
  std::vector<std::array<std::uint8_t, 3>> rgb = {{0, 0, 0}};
  std::vector<std::uint16_t> scan = {0};
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb, in.scan_index = &scan, in.scan_origins = {{2.0, 2.0, 1.0}};
  const Orthoimage img = BuildOrthoimage(in, f, {}, 0.01);
  const auto px = img.PixelOf(3.0, 1.0);
  EXPECT_EQ(img.Passed(img.Index(px[0], px[1])), 1u);
  EXPECT_EQ(img.Count(img.Index(px[0], px[1])), 0u);
}

TEST(Orthoimage, RaysWithoutAReturnPassTheWallWhereTheyCrossIt) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{5, 0, 0}, {0, 0, 0}, {0, 0, 2}, {5, 0, 2}});
  // A 3 x 3 grid scan from (2, 2, 1): only the centre ray (straight along -y) returned nothing;
  // its neighbours returned from 5 m (a window's frame, beyond the minimum range).
  interfaces::TlsScan scan;
  scan.rows = 3, scan.columns = 3;
  scan.azimuth_min = -testing::kPi / 2 - 0.1, scan.azimuth_step = 0.1;
  scan.elevation_max = 0.1, scan.elevation_step = 0.1;
  scan.points.resize(9);
  for (auto& p : scan.points) p.range = 5.0f;
  scan.points[4].range = 0.0f;
  Pose3 X_MS = Pose3::Identity();
  X_MS.translation() = Vec3(2, 2, 1);
  std::vector<Eigen::Vector3f> pts;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  std::vector<std::uint16_t> idx;
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb, in.scan_index = &idx, in.scan_origins = {X_MS.translation()};
  AddNoReturnRays(scan, X_MS, 0, in);
  ASSERT_EQ(in.no_return_dirs.size(), 1u);
  EXPECT_NEAR((in.no_return_dirs[0].cast<double>() - Vec3(0, -1, 0)).norm(), 0.0, 1e-6);
  const Orthoimage img = BuildOrthoimage(in, f, {}, 0.01);
  const auto px = img.PixelOf(3.0, 1.0);  // (x, z) = (2, 1)
  EXPECT_EQ(img.Passed(img.Index(px[0], px[1])), 1u);
  // The same ray from 1.7 m (beyond the 1.5 m minimum range: the wall would have returned) and
  // from 1.4 m (inside it: the wall may be there).
  for (const auto& [dist, passed] : {std::pair{1.7, 1u}, {1.4, 0u}}) {
    OrthoPoints near = in;
    near.scan_origins = {Vec3(2, dist, 1)};
    const Orthoimage at = BuildOrthoimage(near, f, {}, 0.01);
    EXPECT_EQ(at.Passed(at.Index(px[0], px[1])), passed) << "scanner " << dist << " m away";
  }
  in.no_return_scan[0] = 3;
  EXPECT_THROW(BuildOrthoimage(in, f, {}, 0.01), InputError);
}

// A scanner standing beside an opened leaf (or a desk) gets no return from it where it lies
// inside the minimum range, over a wide angle; those rays, extended, cross the walls behind it
// and would read as a window there. A region without returns bordered mostly by returns nearer
// than no_return_min_range met such a surface: its rays are left out. A region bordered by far
// returns (a window's frame) keeps its rays.
TEST(Orthoimage, RaysWithoutAReturnBorderedByNearReturnsMetASurfaceInsideTheMinimumRange) {
  // A 20 x 40 grid: a 6 x 8 block without returns bordered by returns at `border` m.
  auto scan_with_hole = [](float border) {
    interfaces::TlsScan scan;
    scan.rows = 20, scan.columns = 40;
    scan.azimuth_min = -1.0, scan.azimuth_step = 0.02;
    scan.elevation_max = 0.2, scan.elevation_step = 0.02;
    scan.points.resize(20 * 40);
    for (std::uint32_t r = 0; r < 20; ++r)
      for (std::uint32_t c = 0; c < 40; ++c) {
        auto& p = scan.points[r * 40 + c];
        p.row = r, p.column = c;
        const bool hole = r >= 7 && r < 13 && c >= 16 && c < 24;
        const bool ring = r >= 6 && r < 14 && c >= 15 && c < 25;
        p.range = hole ? 0.0f : ring ? border : 6.0f;
      }
    return scan;
  };
  // A window's frame 1.7 m away (a scan standing near the window's wall) is beyond the 1.5 m
  // minimum range: its rays are kept.
  for (const auto& [border, rays] : {std::pair{1.2f, 0u}, {1.7f, 48u}, {4.0f, 48u}}) {
    OrthoPoints in;
    AddNoReturnRays(scan_with_hole(border), Pose3::Identity(), 0, in);
    EXPECT_EQ(in.no_return_dirs.size(), rays) << "border at " << border << " m";
  }
  OrthoimageParams keep_all;
  keep_all.no_return_near_border_share = 1.0;
  OrthoPoints in;
  AddNoReturnRays(scan_with_hole(1.2f), Pose3::Identity(), 0, in, keep_all);
  EXPECT_EQ(in.no_return_dirs.size(), 48u);
}

// A scanner 1.4 m above the floor, 1.7 m from a wall, a desk top (z 0.74) between them that
// other scans saw: a ray heading for the wall's foot passes through the desk 1.1 m away, inside
// the 1.5 m minimum range, and returned nothing for that reason (extended, it would read as a
// low window). It is left out; a level ray to the wall and one over the desk are kept.
TEST(Orthoimage, RaysWithoutAReturnThroughASurfaceSeenInsideTheMinimumRangeAreLeftOut) {
  std::vector<Eigen::Vector3f> pts;
  for (double x = 0.6; x <= 1.2; x += 0.01)
    for (double y = -0.4; y <= 0.4; y += 0.01)
      pts.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.74f);
  for (double y = -1.0; y <= 1.0; y += 0.01)
    for (double z = 0.0; z <= 2.8; z += 0.01)
      pts.emplace_back(1.7f, static_cast<float>(y), static_cast<float>(z));
  OrthoPoints in;
  in.points = &pts;
  in.scan_origins = {Vec3(0, 0, 1.4)};
  const Eigen::Vector3f through_desk = Eigen::Vector3f(1.7f, 0.0f, -1.2f).normalized();
  const Eigen::Vector3f level = Eigen::Vector3f(1.0f, 0.0f, 0.0f);
  const Eigen::Vector3f over_desk = Eigen::Vector3f(1.7f, 0.0f, -0.3f).normalized();
  in.no_return_dirs = {through_desk, level, over_desk};
  in.no_return_scan = {0, 0, 0};
  EXPECT_EQ(DropNoReturnRaysThroughSeenSurfaces(in, {}), 1u);
  ASSERT_EQ(in.no_return_dirs.size(), 2u);
  EXPECT_EQ(in.no_return_dirs[0], level);
  EXPECT_EQ(in.no_return_dirs[1], over_desk);
  in.no_return_scan = {0, 1};
  EXPECT_THROW(DropNoReturnRaysThroughSeenSurfaces(in, {}), InputError);
  in.no_return_scan = {0, 0};
  OrthoimageParams no_cell;
  no_cell.no_return_blocker_cell = 0.0;
  EXPECT_THROW(DropNoReturnRaysThroughSeenSurfaces(in, no_cell), InputError);
}

TEST(Orthoimage, RaysWithoutAReturnMeetingTheWallAtAGrazingAngleSayNothing) {
  // The wall y = 0 seen from (0, 2, 1): a ray without a return heading for (4, 0, 1) meets it
  // at 63 deg from its normal, one heading for (23, 0, 1) at 85 deg (a weak echo, no hole).
  const PatchFrame f =
      PatchFrame::Of(Vec3::UnitY(), {{30, 0, 0}, {0, 0, 0}, {0, 0, 2}, {30, 0, 2}});
  std::vector<Eigen::Vector3f> pts;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  std::vector<std::uint16_t> idx;
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb, in.scan_index = &idx, in.scan_origins = {Vec3(0, 2, 1)};
  in.no_return_dirs = {Eigen::Vector3f(4, -2, 0).normalized(),
                       Eigen::Vector3f(23, -2, 0).normalized()};
  in.no_return_scan = {0, 0};
  OrthoimageParams p;  // 80 deg
  const Orthoimage img = BuildOrthoimage(in, f, p, 0.01);
  const auto a = img.PixelOf(30.0 - 4.0, 1.0), b = img.PixelOf(30.0 - 23.0, 1.0);
  EXPECT_EQ(img.Passed(img.Index(a[0], a[1])), 1u);
  EXPECT_EQ(img.PassedNoReturn(img.Index(a[0], a[1])), 1u);
  EXPECT_EQ(img.Passed(img.Index(b[0], b[1])), 0u);
  p.no_return_max_incidence_deg = 60.0;
  const Orthoimage at60 = BuildOrthoimage(in, f, p, 0.01);
  EXPECT_EQ(at60.Passed(at60.Index(a[0], a[1])), 0u);
}

TEST(Orthoimage, PixelSizeFollowsDensityAndIsOneCentimetreWhenDenseEnough) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{1, 0, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}});
  auto grid = [](double spacing) {
    std::vector<Eigen::Vector3f> p;
    for (double x = 0.0005; x < 1; x += spacing)
      for (double z = 0.0005; z < 1; z += spacing) p.push_back({float(x), 0.0f, float(z)});
    return p;
  };
  for (const auto& [spacing, expected] : {std::pair{0.005, 0.01}, {0.02, 0.028}, {0.05, 0.05}}) {
    const auto pts = grid(spacing);
    const std::vector<std::array<std::uint8_t, 3>> rgb(pts.size(), {9, 9, 9});
    OrthoPoints in;
    in.points = &pts, in.colours = &rgb;
    EXPECT_NEAR(ChoosePixelSize(in, f, {}), expected, 0.0011) << spacing;
  }
}

TEST(Orthoimage, PixelSizeOfAPatchTooLargeForADenseCountGridIsTheSame) {
  // Same points, same cell origin (the polygons share their min corner): a 2 m patch counts
  // its density cells in a dense grid, a 400 m one (16e6 cells) from sorted cell keys.
  std::vector<Eigen::Vector3f> pts;
  for (double x = 0.0005; x < 2; x += 0.013)
    for (double z = 0.0005; z < 2; z += 0.004 + 0.01 * x) pts.push_back({float(x), 0.0f, float(z)});
  const std::vector<std::array<std::uint8_t, 3>> rgb(pts.size(), {9, 9, 9});
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb;
  auto square = [](double s) {
    return PatchFrame::Of(Vec3::UnitY(), {{s, 0, 0}, {0, 0, 0}, {0, 0, s}, {s, 0, s}});
  };
  const double small = ChoosePixelSize(in, square(2.0), {});
  EXPECT_GT(small, 0.01);
  EXPECT_EQ(ChoosePixelSize(in, square(400.0), {}), small);
}

TEST(Orthoimage, BuiltImageHasTheMeansOfAddingItsPointsOneByOne) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{1, 0, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}});
  std::vector<Eigen::Vector3f> pts;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  for (int k = 0; k < 2000; ++k) {
    pts.push_back(
        {float((k % 97) / 97.0), float(0.0001 * (k % 13) - 0.0006), float((k % 89) / 89.0)});
    rgb.push_back({std::uint8_t(k % 256), std::uint8_t(k * 7 % 256), std::uint8_t(k * 13 % 256)});
  }
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb;
  const Orthoimage built = BuildOrthoimage(in, f, {}, 0.05);
  Orthoimage added(f, 0.05, built.Cols(), built.Rows());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Vec3 q = pts[k].cast<double>();
    added.AddPoint(f.ToUv(q).x(), f.ToUv(q).y(), f.Depth(q), rgb[k]);
  }
  int seen = 0, multi = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(built.Cols() * built.Rows()); ++i) {
    ASSERT_EQ(built.Count(i), added.Count(i));
    if (added.Count(i) == 0) continue;
    ++seen;
    EXPECT_EQ(built.Rgb(i), added.Rgb(i));
    EXPECT_EQ(built.Depth(i), added.Depth(i));
    EXPECT_EQ(built.FrontDepth(i), added.FrontDepth(i));
    multi += added.Count(i) > 1;
  }
  EXPECT_GT(seen, 300);
  EXPECT_GT(multi, 300);
}

// A scan 4 m from a wall with a 1 x 0.8 m hole (x 2-3 m, z 0.8-1.6 m), its beams 0.01 rad
// apart: they meet the wall 4-4.5 cm apart, four pixels of 1 cm. With the scan's step
// known every pixel of the wall and of the hole takes the nearest sample whose footprint
// covers it; without it most read unseen. Beyond the scan's field a pixel stays unseen.
TEST(Orthoimage, ASampleStandsForItsBeamsFootprint) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{5, 0, 0}, {0, 0, 0}, {0, 0, 2}, {5, 0, 2}});
  const Vec3 scanner(2.5, 4.0, 1.0);
  const double step = 0.01;
  std::vector<Eigen::Vector3f> pts;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  std::vector<std::uint16_t> scan;
  for (double az = -0.35; az <= 0.35; az += step)      // x 1.04-3.96 m on the wall
    for (double el = -0.24; el <= 0.24; el += step) {  // z 0.02-1.98 m
      const Vec3 dir(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
      const Vec3 on_wall = scanner + (scanner.y() / -dir.y()) * dir;
      const bool hole =
          on_wall.x() > 2.0 && on_wall.x() < 3.0 && on_wall.z() > 0.8 && on_wall.z() < 1.6;
      const Vec3 p = hole ? Vec3(scanner + ((scanner.y() + 3.0) / -dir.y()) * dir) : on_wall;
      pts.push_back(p.cast<float>());
      rgb.push_back({200, 200, 200});
      scan.push_back(0);
    }
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb, in.scan_index = &scan, in.scan_origins = {scanner};
  const Orthoimage sparse = BuildOrthoimage(in, f, {}, 0.01);
  in.scan_steps = {step};
  const Orthoimage filled = BuildOrthoimage(in, f, {}, 0.01);
  auto at = [](const Orthoimage& img, double x, double z) {
    const auto px = img.PixelOf(5.0 - x, z);  // u = 5 - x
    return img.Index(px[0], px[1]);
  };
  int unseen_before = 0, unseen_after = 0, wrong = 0, total = 0;
  for (double x = 1.2; x < 3.8; x += 0.01)
    for (double z = 0.1; z < 1.9; z += 0.01) {
      const bool hole = x > 2.07 && x < 2.93 && z > 0.87 && z < 1.53;
      const bool wall = x < 1.93 || x > 3.07 || z < 0.73 || z > 1.67;
      if (!hole && !wall) continue;  // within a beam spacing of the hole's edge
      ++total;
      const std::size_t i = at(sparse, x, z);
      unseen_before += sparse.Count(i) == 0 && sparse.Passed(i) == 0;
      unseen_after += filled.Count(i) == 0 && filled.Passed(i) == 0;
      wrong += hole ? filled.Count(i) > 0 || filled.Passed(i) == 0
                    : filled.Count(i) == 0 || filled.Passed(i) > 0;
    }
  EXPECT_GT(unseen_before, total / 2);
  EXPECT_EQ(unseen_after, 0);
  EXPECT_EQ(wrong, 0);
  // A sample still lands in its own pixel: the pixels that had samples are unchanged.
  for (std::size_t i = 0; i < static_cast<std::size_t>(sparse.Cols() * sparse.Rows()); ++i)
    if (sparse.Count(i) > 0 || sparse.Passed(i) > 0) {
      ASSERT_EQ(sparse.Count(i), filled.Count(i));
      ASSERT_EQ(sparse.Passed(i), filled.Passed(i));
    }
  // Outside the scan's field (x < 1 m) and beyond footprint_max / 2 of its last beams: unseen.
  const std::size_t out = at(filled, 0.9, 1.0);
  EXPECT_EQ(filled.Count(out) + filled.Passed(out) + filled.Blocked(out), 0u);
  // footprint_max 0, or below the beams' spacing (too sparse to say what lies between two
  // samples: at a grazing angle a casing's shadow falls between them): the samples alone.
  for (const double max : {0.0, 0.03}) {
    OrthoimageParams off;
    off.footprint_max = max;
    const Orthoimage plain = BuildOrthoimage(in, f, off, 0.01);
    for (std::size_t i = 0; i < static_cast<std::size_t>(sparse.Cols() * sparse.Rows()); ++i)
      ASSERT_EQ(plain.Count(i) + plain.Passed(i), sparse.Count(i) + sparse.Passed(i)) << max;
  }
  in.scan_steps = {step, step};
  EXPECT_THROW(BuildOrthoimage(in, f, {}, 0.01), InputError);
}

TEST(Orthoimage, MismatchedInputIsAnInputError) {
  const PatchFrame f = PatchFrame::Of(Vec3::UnitY(), {{1, 0, 0}, {0, 0, 0}, {0, 0, 1}});
  std::vector<Eigen::Vector3f> pts = {{0.5f, 0.0f, 0.5f}};
  std::vector<std::array<std::uint8_t, 3>> rgb;
  OrthoPoints in;
  in.points = &pts, in.colours = &rgb;
  EXPECT_THROW(BuildOrthoimage(in, f, {}), InputError);
  EXPECT_THROW(PatchFrame::Of(Vec3::Zero(), {{1, 0, 0}, {0, 0, 0}, {0, 0, 1}}), InputError);
  OrthoimageParams bad;
  bad.finest_pixel = 0.1, bad.coarsest_pixel = 0.05;
  rgb.push_back({0, 0, 0});
  try {
    BuildOrthoimage(in, f, bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("finest_pixel"), std::string::npos) << e.what();
  }
}

TEST(Orthoimage, WritesColourAndSixteenBitDepthPngs) {
  const HoleSpec h;
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);
  const Orthoimage img = BuildOrthoimage(c.View(), f, {});
  EXPECT_LE(img.Pixel(), 0.012);  // dense enough for about 1 cm
  const std::string stem = ::testing::TempDir() + "sm4_wall";
  WriteOrthoimagePngs(img, stem);
  EXPECT_GT(std::filesystem::file_size(stem + "_colour.png"), 1000u);
  EXPECT_GT(std::filesystem::file_size(stem + "_depth.png"), 1000u);
  EXPECT_THROW(WriteOrthoimagePngs(img, "/nonexistent_dir/x"), InputError);
}

// ---- Openings in scanned scenes ----

struct Found {
  Sm4Model sm4;
  std::vector<DetectedOpening> on_wall1;
};

Found Detect(const testing::Scene& s, const OpeningParams& p = {}) {
  const Cloud c = testing::ScanRoom(s);
  Found f;
  f.sm4 = DetectOpenings(testing::RoomSm3(), c.View(), p);
  for (const auto& o : f.sm4.openings)
    if (o.host == "wall_1") f.on_wall1.push_back(o);
  return f;
}

std::string Describe(const Sm4Model& m) {
  std::string s;
  for (const auto& o : m.openings) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%s %s on %s u[%.3f %.3f] v[%.3f %.3f] %s lambda=%.2f conf=%.2f known=%.2f "
                  "ev=%.2f sup=%.2f leaf=%d\n",
                  o.id.c_str(), ToString(o.type), o.host.c_str(), o.u0, o.u1, o.v0, o.v1,
                  ToString(o.state), o.opening_angle_deg, o.confidence, o.known_share,
                  o.evidence_share, o.side_support, o.leaf_points);
    s += buf;
  }
  return s;
}

// The hole x in [x0, x1] of the south wall is u in [5 - x1, 5 - x0].
void ExpectHole(const DetectedOpening& o, const HoleSpec& h, double tol = 0.03) {
  EXPECT_NEAR(o.u0, 5.0 - h.x1, tol);
  EXPECT_NEAR(o.u1, 5.0 - h.x0, tol);
  EXPECT_NEAR(o.v0, h.z0, tol);
  EXPECT_NEAR(o.v1, h.z1, tol);
}

TEST(Openings, ClosedDoorWhoseCasingAndLeafHaveTheWallColourIsFoundByDepthAlone) {
  HoleSpec h;
  h.casing_rgb = testing::kWallRgb;
  h.leaf_rgb = testing::kWallRgb;
  h.swing_into_room = false;  // the leaf sits at the far face: 18 cm deep seen from here
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kDoor);
  ExpectHole(o, h);
  EXPECT_EQ(o.state, DoorState::kClosed) << Describe(f.sm4);
  EXPECT_NEAR(o.clear_width_m, 0.0, 1e-12);
}

TEST(Openings, FlushDoorOfAnotherColourIsFoundByColourAlone) {
  HoleSpec h;
  h.casing = false;
  h.flush_leaf = true;
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kDoor);
  ExpectHole(o, h);
  EXPECT_EQ(o.state, DoorState::kClosed) << Describe(f.sm4);
}

TEST(Openings, ClosedDoorWithCasingGivesTheHoleNotTheCasing) {
  const HoleSpec h;  // dark casing 8 cm wide, brown leaf flush with the casing's face
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  ExpectHole(f.on_wall1.at(0), h);
  EXPECT_EQ(f.on_wall1.at(0).state, DoorState::kClosed) << Describe(f.sm4);
}

// The hole's top is the lintel's underside seen through the hole, not an edge in the images
// (a casing's outer edge, an opened leaf's top): within 1 cm.
struct LintelCase {
  double lambda_deg;
  bool swing_into_room;
  bool casing_of_wall_colour;
};
void PrintTo(const LintelCase& c, std::ostream* os) {
  *os << "lambda " << c.lambda_deg << (c.swing_into_room ? " into the room" : " away")
      << (c.casing_of_wall_colour ? ", casing of the wall's colour" : "");
}
class DoorTop : public ::testing::TestWithParam<LintelCase> {};
TEST_P(DoorTop, IsTheLintelWithinOneCentimetre) {
  HoleSpec h;
  h.lambda_deg = GetParam().lambda_deg;
  h.swing_into_room = GetParam().swing_into_room;
  if (GetParam().casing_of_wall_colour) h.casing_rgb = testing::kWallRgb;
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.on_wall1.size(), 1u) << Describe(f.sm4);
  EXPECT_NEAR(f.on_wall1[0].v1, h.z1, 0.01) << Describe(f.sm4);
}
INSTANTIATE_TEST_SUITE_P(Doors, DoorTop,
                         ::testing::Values(LintelCase{0, true, false}, LintelCase{45, true, false},
                                           LintelCase{90, false, false}, LintelCase{45, true, true},
                                           LintelCase{0, false, true}));

TEST(Openings, DoorFortyPercentOccludedByACabinetIsStillFound) {
  HoleSpec h;
  testing::Scene s = testing::RoomScene(h);
  // 1.0 m wide, 0.85 m tall, 0.5 m deep in front of the 0.9 x 2.1 door: ~40% of it hidden.
  s.boxes.push_back(testing::AxisBox({1.95, 0.05, 0.0}, {2.95, 0.55, 0.85}, testing::kCabinetRgb));
  const Found f = Detect(s);
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kDoor);
  ExpectHole(o, h);
}

class SemiOpenDoor : public ::testing::TestWithParam<double> {};

TEST_P(SemiOpenDoor, AngleWithinThreeDegreesAndStateSemiOpen) {
  HoleSpec h;
  h.lambda_deg = GetParam();
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kDoor);
  SCOPED_TRACE(Describe(f.sm4));
  ExpectHole(o, h, 0.05);
  EXPECT_NEAR(o.opening_angle_deg, h.lambda_deg, 3.0) << Describe(f.sm4);
  EXPECT_EQ(o.state, DoorState::kSemiOpen);
  EXPECT_GT(o.clear_width_m, 0.0);
  EXPECT_LT(o.clear_width_m, 0.9);
}
INSTANTIATE_TEST_SUITE_P(Lambda, SemiOpenDoor, ::testing::Values(20.0, 45.0, 70.0));

TEST(Openings, DoorOpenedIntoTheRoomBehindIsMeasuredThroughTheHole) {
  HoleSpec h;
  h.swing_into_room = false;
  h.lambda_deg = 45.0;
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  EXPECT_NEAR(f.on_wall1.at(0).opening_angle_deg, 45.0, 3.0) << Describe(f.sm4);
}

TEST(Openings, WideOpenDoorIsOpen) {
  HoleSpec h;
  h.lambda_deg = 95.0;
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  EXPECT_EQ(f.on_wall1.at(0).state, DoorState::kOpen) << Describe(f.sm4);
}

// A leaf opened to 90 deg lies beside the jamb's reveal (the hole's side through the wall):
// the reveal is not the leaf, on either side of the wall.
class NinetyDegreeDoor : public ::testing::TestWithParam<bool> {};

TEST_P(NinetyDegreeDoor, AngleWithinThreeDegreesAndStateOpen) {
  HoleSpec h;
  h.lambda_deg = 90.0;
  h.swing_into_room = GetParam();
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  SCOPED_TRACE(Describe(f.sm4));
  // The sides: the hinge jamb stands behind the opened leaf (its reveal gives it).
  EXPECT_NEAR(o.u0, 5.0 - h.x1, 0.02);
  EXPECT_NEAR(o.u1, 5.0 - h.x0, 0.02);
  EXPECT_NEAR(o.opening_angle_deg, 90.0, 3.0);
  EXPECT_EQ(o.state, DoorState::kOpen);
  // The room behind returns the rays that rose through the door (its walls and ceiling).
  EXPECT_LT(o.sky_share, 0.05);
}
INSTANTIATE_TEST_SUITE_P(SwingIntoRoom, NinetyDegreeDoor, ::testing::Bool());

// A door of a storey standing in nothing (an imported storey has no ground or building around
// it): every ray through the hole returns nothing, as a dark cabinet's would. Its leaf, opened
// into the room at the hole's jamb, makes it a door; the rays that rose through it all returned
// nothing (sky_share 1: the floor mission does not take it into a room).
TEST(Openings, ADoorOpenOntoNothingIsFoundByItsLeafAndSeesNoCeilingBeyond) {
  HoleSpec h;
  h.lambda_deg = 90.0;
  h.nothing_behind = true;
  const Found f = Detect(testing::RoomScene(h));
  SCOPED_TRACE(Describe(f.sm4));
  ASSERT_EQ(f.sm4.openings.size(), 1u);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kDoor);
  ExpectHole(o, h, 0.02);
  EXPECT_NEAR(o.opening_angle_deg, 90.0, 3.0);
  EXPECT_EQ(o.state, DoorState::kOpen);
  EXPECT_GT(o.sky_share, 0.95);
}

// The same hole without a leaf: rays that return nothing alone are no door (a black cabinet's
// front returns nothing either).
TEST(Openings, AHoleOntoNothingWithoutALeafIsNoDoor) {
  HoleSpec h;
  h.leaf = false;
  h.nothing_behind = true;
  const Found f = Detect(testing::RoomScene(h));
  for (const auto& o : f.sm4.openings) EXPECT_NE(o.type, OpeningType::kDoor) << Describe(f.sm4);
}

// Seen through the hole only part of the leaf shows; past 90 deg is told by the line's
// direction from the hinge, which stands on the wall's far face (the reveals' depth).
TEST(Openings, DoorSwungPastNinetyBehindTheWallReadsOverNinety) {
  HoleSpec h;
  h.swing_into_room = false;
  h.lambda_deg = 100.0;
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  EXPECT_NEAR(f.on_wall1.at(0).opening_angle_deg, 100.0, 3.0) << Describe(f.sm4);
  EXPECT_EQ(f.on_wall1.at(0).state, DoorState::kOpen) << Describe(f.sm4);
}

// Seen from where the opened leaf hides the hinge side of the doorway, the images show a hole
// seen through beside the leaf, framed on the leaf's side by an occlusion boundary: that side
// is no jamb, and the door reaches the jamb its leaf hinges at.
struct SplitCase {
  double lambda_deg, x, y;
};
void PrintTo(const SplitCase& c, std::ostream* os) {
  *os << "lambda " << c.lambda_deg << " deg, scan at (" << c.x << ", " << c.y << ")";
}
class DoorwaySplitByItsLeaf : public ::testing::TestWithParam<SplitCase> {};

TEST_P(DoorwaySplitByItsLeaf, DoorReachesTheJambItsLeafHingesAt) {
  HoleSpec h;
  h.lambda_deg = GetParam().lambda_deg;
  const testing::Scene s = testing::RoomScene(h);
  Cloud c;
  testing::Scan(s, {GetParam().x, GetParam().y, 1.3}, -testing::kPi, testing::kPi, 0.003, c);
  testing::Scan(s, {2.5, 3.2, 1.3}, -testing::kPi, testing::kPi, 0.003, c);
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), {});
  ASSERT_EQ(m.openings.size(), 1u) << Describe(m);
  const auto& o = m.openings[0];
  SCOPED_TRACE(Describe(m));
  EXPECT_NEAR(o.u0, 5.0 - h.x1, 0.03);
  EXPECT_NEAR(o.u1, 5.0 - h.x0, 0.06);
  EXPECT_NEAR(o.opening_angle_deg, h.lambda_deg, 3.0);
  EXPECT_EQ(o.state, DoorState::kSemiOpen);
}
INSTANTIATE_TEST_SUITE_P(Views, DoorwaySplitByItsLeaf,
                         ::testing::Values(SplitCase{30, 4.2, 2.0}, SplitCase{35, 3.3, 2.0},
                                           SplitCase{40, 3.3, 2.0}),
                         [](const ::testing::TestParamInfo<SplitCase>& info) {
                           return "Lambda" +
                                  std::to_string(static_cast<int>(info.param.lambda_deg));
                         });

// A closed 1.2 m door 35 cm from the end of its wall (an exterior door in a corridor's end
// wall): the side wall stands inside the leaf's search window beyond the jamb, perpendicular to
// the wall like a leaf at 90 deg. A RANSAC hypothesis through the jamb may converge onto it by
// least squares; a leaf hinges at a jamb, so a line that ends up 35 cm from both is no leaf,
// whatever the RANSAC stream.
TEST(Openings, SideWallBesideAClosedDoorIsNoLeafWhateverTheRansacStream) {
  HoleSpec h;
  h.x0 = 0.39, h.x1 = 1.59;
  testing::Scene s = testing::RoomScene(h);
  // An extinguisher-like box on the side wall, 0.9 m out from the door's wall.
  s.boxes.push_back(testing::AxisBox({0.0, 0.8, 0.9}, {0.12, 1.0, 1.5}, {200, 30, 30}));
  const Cloud c = testing::ScanRoom(s);
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);
  const OpeningParams p;
  for (std::uint64_t k = 0; k < 40; ++k) {
    const LeafFit leaf = FitDoorLeaf(c.View(), f, 5.0 - h.x1, 5.0 - h.x0, 0.0, h.z1, p, k);
    EXPECT_LT(leaf.lambda_deg, p.closed_below_deg) << "stream " << k;
  }
  const Found found = Detect(s);
  ASSERT_EQ(found.on_wall1.size(), 1u) << Describe(found.sm4);
  EXPECT_EQ(found.on_wall1[0].state, DoorState::kClosed) << Describe(found.sm4);
}

// Only part of a leaf may be seen: the part near its hinge hidden (behind the leaf's own edge,
// or past an occluder), or only its free end seen through the hole at a slant. The leaf's line
// passes its hinge: the hinge is where the line meets the jamb, not the seen run's nearer end,
// and lambda follows from the line's direction away from it.
struct PartLeafCase {
  double lambda_deg;
  bool into_room;   // hinged on the room's face, else on the far face (20 cm deep)
  bool hinge_left;  // at u0, else at u1
  double s0, s1;    // the seen part, m from the hinge along the 0.9 m leaf
};
void PrintTo(const PartLeafCase& c, std::ostream* os) {
  *os << c.lambda_deg << " deg " << (c.into_room ? "into the room" : "away") << ", hinge "
      << (c.hinge_left ? "u0" : "u1") << ", seen " << c.s0 << "-" << c.s1 << " m";
}
class PartlySeenLeaf : public ::testing::TestWithParam<PartLeafCase> {};

TEST_P(PartlySeenLeaf, HingeIsWhereItsLineMeetsTheJamb) {
  const PartLeafCase& k = GetParam();
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);
  const double u0 = 2.1, u1 = 3.0, hinge_depth = k.into_room ? 0.021 : -0.221;
  const double lam = k.lambda_deg * testing::kPi / 180.0;
  const Vec2 hinge(k.hinge_left ? u0 : u1, hinge_depth);
  const Vec2 leaf_dir((k.hinge_left ? 1.0 : -1.0) * std::cos(lam),
                      (k.into_room ? 1.0 : -1.0) * std::sin(lam));
  std::vector<Eigen::Vector3f> pts;
  for (double s = k.s0; s <= k.s1; s += 0.004)
    for (double v = 0.6; v <= 1.7; v += 0.02) {
      const Vec2 q = hinge + s * leaf_dir;
      pts.push_back(f.ToMap(q.x(), v, q.y()).cast<float>());
    }
  OrthoPoints in;
  in.points = &pts;
  const LeafFit leaf = FitDoorLeaf(in, f, u0, u1, 0.0, 2.1, OpeningParams{}, 0);
  ASSERT_GT(leaf.inliers, 0);
  EXPECT_NEAR(leaf.hinge_u, hinge.x(), 0.05);
  EXPECT_NEAR(leaf.lambda_deg, k.lambda_deg, 1.0);
}
INSTANTIATE_TEST_SUITE_P(Views, PartlySeenLeaf,
                         ::testing::Values(PartLeafCase{35, true, true, 0.3, 0.9},
                                           PartLeafCase{35, true, false, 0.3, 0.9},
                                           PartLeafCase{60, false, true, 0.5, 0.9},
                                           PartLeafCase{60, false, false, 0.5, 0.9},
                                           PartLeafCase{100, false, true, 0.3, 0.9}));

// A tall cabinet standing over a closed door's casing hides the wall beside the door: that side
// is an occlusion boundary, but no leaf is hinged at the cabinet's far edge, so the door keeps
// its side and its state.
TEST(Openings, TallCabinetOverAClosedDoorsCasingDoesNotWidenTheDoor) {
  HoleSpec h;
  testing::Scene s = testing::RoomScene(h);
  s.boxes.push_back(testing::AxisBox({2.86, 0.02, 0.0}, {3.5, 0.52, 2.2}, testing::kCabinetRgb));
  const Found f = Detect(s);
  SCOPED_TRACE(Describe(f.sm4));
  for (const auto& o : f.on_wall1) {
    EXPECT_GT(o.u0, 5.0 - 2.98 - 0.05);
    EXPECT_NE(o.state, DoorState::kOpen);
  }
}

// One scan from near the wall's end: the wall near the scanner is dense, so its pixel is fine,
// and the door 2-3 m along the wall is hit at a slant, more sparsely than a point per pixel.
// The gaps between its points take their neighbours' values (gap_fill), not the wall's, so its
// edges follow the door rather than the edge of the sparse area.
struct SparseCase {
  double x, step;
};
class SparselySampledDoor : public ::testing::TestWithParam<SparseCase> {};

TEST_P(SparselySampledDoor, IsStillFound) {
  HoleSpec h;
  const testing::Scene s = testing::RoomScene(h);
  Cloud c;
  testing::Scan(s, {GetParam().x, 0.25, 1.3}, -testing::kPi, testing::kPi, GetParam().step, c);
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), {});
  ASSERT_EQ(m.openings.size(), 1u) << Describe(m);
  SCOPED_TRACE(Describe(m));
  ExpectHole(m.openings[0], h, 0.1);
  EXPECT_EQ(m.openings[0].state, DoorState::kClosed);
}
INSTANTIATE_TEST_SUITE_P(Scans, SparselySampledDoor,
                         ::testing::Values(SparseCase{4.8, 0.003}, SparseCase{0.2, 0.005}));

// A scanner 0.6-0.9 m from a wall with a door beside it, under a real scanner's 1.5 m minimum
// range (returns nearer are dropped, their rays kept as returning nothing): a disc of the wall
// around the scanner's foot reads unseen, from the floor to the ceiling, beside the door's
// jamb. The wall's top edge (the ceiling) is a line along the whole wall; a rectangle from the
// jamb across the disc up to that edge was a door (random corridor floors: false doors up to
// the ceiling on the corridor's walls, SM4 precision 0.63-0.69). A door's head lies under a
// lintel, door_head_clearance below the wall's top: the only door is the real one.
TEST(Openings, TheCeilingsEdgeIsNoDoorsHead) {
  HoleSpec h;  // the hole u 2.1-3.0 m (x 2.0-2.9 m), its leaf opened 90 deg into the room
  h.lambda_deg = 90.0;
  const testing::Scene s = testing::RoomScene(h);
  for (const double dist : {0.6, 0.9}) {
    Cloud raw, c;
    const Eigen::Vector3d origin(3.3, dist, 1.4);
    testing::Scan(s, origin, -testing::kPi, testing::kPi, 0.004, raw);
    c.origins = raw.origins, c.steps = raw.steps;
    c.no_return_dirs = raw.no_return_dirs, c.no_return_scan = raw.no_return_scan;
    for (std::size_t i = 0; i < raw.points.size(); ++i) {
      const Eigen::Vector3d d = raw.points[i].cast<double>() - origin;
      if (d.norm() < 1.5) {  // inside the minimum range: no return
        c.no_return_dirs.push_back(d.normalized().cast<float>());
        c.no_return_scan.push_back(raw.scan_index[i]);
        continue;
      }
      c.points.push_back(raw.points[i]);
      c.colours.push_back(raw.colours[i]);
      c.scan_index.push_back(raw.scan_index[i]);
    }
    const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), {});
    SCOPED_TRACE(Describe(m));
    std::vector<DetectedOpening> on_wall1;
    for (const auto& o : m.openings)
      if (o.host == "wall_1") on_wall1.push_back(o);
    ASSERT_EQ(on_wall1.size(), 1u) << dist << " m from the wall";
    EXPECT_LT(on_wall1[0].v1, 2.2) << dist << " m from the wall";
    EXPECT_GT(on_wall1[0].u0, 2.0) << dist << " m from the wall";
    EXPECT_LT(on_wall1[0].u1, 3.1) << dist << " m from the wall";
  }
}

// A hole up to the ceiling has no lintel: with a leaf hinged in it (opened 30 or 90 deg) it is
// no door, and a 2.5 m door keeps its head at its lintel, not at the ceiling 0.2 m above where
// the leaf fit's reveal search may carry it (the stair hall of the Jasmin-Sun house: a 1 m
// "door" to the ceiling across the stairwell's unfitted edge). door_head_clearance 0 finds
// both.
TEST(Openings, NoDoorsHeadAtTheCeilingWhereverItWasFound) {
  const OpeningParams p;
  OpeningParams none = p;
  none.door_head_clearance = 0.0;
  HoleSpec to_ceiling;
  to_ceiling.z1 = 2.7, to_ceiling.casing = false, to_ceiling.lambda_deg = 30.0;
  const Cloud a = testing::ScanRoom(testing::RoomScene(to_ceiling));
  EXPECT_TRUE(DetectOpenings(testing::RoomSm3(), a.View(), p).openings.empty());
  const Sm4Model without = DetectOpenings(testing::RoomSm3(), a.View(), none);
  ASSERT_EQ(without.openings.size(), 1u) << Describe(without);
  EXPECT_GT(without.openings[0].v1, 2.65);
  HoleSpec tall = to_ceiling;
  tall.z1 = 2.5;
  const Cloud b = testing::ScanRoom(testing::RoomScene(tall));
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), b.View(), p);
  ASSERT_EQ(m.openings.size(), 1u) << Describe(m);
  EXPECT_NEAR(m.openings[0].v1, 2.5, 0.05) << Describe(m);
  const Sm4Model lifted = DetectOpenings(testing::RoomSm3(), b.View(), none);
  ASSERT_EQ(lifted.openings.size(), 1u) << Describe(lifted);
  EXPECT_GT(lifted.openings[0].v1, 2.65) << Describe(lifted);
}

// Two door rectangles on one hole (a part seen through and a part behind the leaf, or a
// casing's rectangle moved by the reveal step) are one door: the hole, not the casing, with
// its leaf measured again.
TEST(Openings, TwoDoorRectanglesOnOneHoleBecomeOneDoorWithoutItsCasing) {
  HoleSpec h;
  h.lambda_deg = 35.0;
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  const OpeningParams p;
  const Orthoimage img =
      BuildOrthoimage(c.View(), PatchFrame::Of(testing::RoomSm3().patches[0]), p.orthoimage);
  auto rect = [](double u0, double u1, double conf) {
    DetectedOpening o;
    o.host = "wall_1", o.u0 = u0, o.u1 = u1, o.v0 = 0.0, o.v1 = 2.1, o.confidence = conf;
    o.known_share = 0.5, o.through_share = 0.3, o.evidence_share = 1.0;
    return o;
  };
  // Each from a casing's outer edge (the casing is 8 cm wide) to somewhere inside the hole.
  const auto one =
      OneOpeningPerHole({rect(2.02, 2.62, 0.9), rect(2.55, 3.08, 0.6)}, img, c.View(), p);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].u0, 5.0 - h.x1, 0.03);
  EXPECT_NEAR(one[0].u1, 5.0 - h.x0, 0.03);
  EXPECT_NEAR(one[0].opening_angle_deg, 35.0, 3.0);
  EXPECT_EQ(one[0].state, DoorState::kSemiOpen);
  EXPECT_DOUBLE_EQ(one[0].confidence, 0.9);
  // Apart by more than door_merge_gap (a strip of wall between their casings): two doors.
  const auto two = OneOpeningPerHole({rect(0.6, 1.5, 0.9), rect(2.1, 3.0, 0.6)}, img, c.View(), p);
  EXPECT_EQ(two.size(), 2u);
}

// A window of two casements either side of a mullion, seen as two window rectangles that share
// the mullion's columns or leave a strip of the hole between them (the imported FZK-Haus: one
// 2.0 m window found as 1.03 m and 1.01 m overlapping 0.13 m, and on another drive as 0.82 m
// and 0.72 m 0.15 m apart), is one window: their union, its corners on the wall. Windows with
// the wall's surface between them, or sharing a corner but not their rows, stay two.
TEST(Openings, TwoCasementsOfOneWindowAreOneWindow) {
  HoleSpec h;
  h.x0 = 1.5, h.x1 = 3.5, h.z0 = 0.9, h.z1 = 2.1;
  h.leaf = false;
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  const OpeningParams p;
  const Orthoimage img =
      BuildOrthoimage(c.View(), PatchFrame::Of(testing::RoomSm3().patches[0]), p.orthoimage);
  auto rect = [&](double u0, double u1, double v0, double v1, double conf) {
    DetectedOpening o;
    o.type = OpeningType::kWindow;
    o.host = "wall_1", o.u0 = u0, o.u1 = u1, o.v0 = v0, o.v1 = v1, o.confidence = conf;
    o.known_share = 0.5, o.through_share = 0.8, o.evidence_share = 1.0;
    const PatchFrame& f = img.Frame();
    o.corners = {f.ToMap(u0, v0), f.ToMap(u1, v0), f.ToMap(u1, v1), f.ToMap(u0, v1)};
    return o;
  };
  const double u0 = 5.0 - h.x1, u1 = 5.0 - h.x0;
  const auto one = OneOpeningPerHole(
      {rect(u0, u0 + 1.03, 0.9, 2.1, 0.7), rect(u1 - 1.01, u1, 0.9, 2.107, 0.9)}, img, c.View(), p);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].type, OpeningType::kWindow);
  EXPECT_DOUBLE_EQ(one[0].u0, u0);
  EXPECT_DOUBLE_EQ(one[0].u1, u1);
  EXPECT_DOUBLE_EQ(one[0].v0, 0.9);
  EXPECT_DOUBLE_EQ(one[0].v1, 2.107);
  EXPECT_DOUBLE_EQ(one[0].confidence, 0.9);
  const PatchFrame& f = img.Frame();
  EXPECT_LT((one[0].corners[0] - f.ToMap(u0, 0.9)).norm(), 1e-9);
  EXPECT_LT((one[0].corners[2] - f.ToMap(u1, 2.107)).norm(), 1e-9);
  EXPECT_NEAR((one[0].corners[1] - one[0].corners[0]).norm(), h.x1 - h.x0, 1e-9);
  const auto mullion = OneOpeningPerHole(
      {rect(u0, u0 + 0.9, 0.9, 2.1, 0.7), rect(u1 - 0.9, u1, 0.9, 2.1, 0.9)}, img, c.View(), p);
  ASSERT_EQ(mullion.size(), 1u);
  EXPECT_DOUBLE_EQ(mullion[0].u0, u0);
  EXPECT_DOUBLE_EQ(mullion[0].u1, u1);
  const auto apart = OneOpeningPerHole(
      {rect(0.2, 0.8, 0.9, 2.1, 0.9), rect(1.0, 1.45, 0.9, 2.1, 0.6)}, img, c.View(), p);
  EXPECT_EQ(apart.size(), 2u);
  const auto other_rows = OneOpeningPerHole(
      {rect(0.6, 1.5, 0.9, 2.1, 0.9), rect(1.45, 2.6, 1.9, 2.5, 0.6)}, img, c.View(), p);
  EXPECT_EQ(other_rows.size(), 2u);
}

// With a room behind, and onto nothing (a storey standing in nothing: its rays return nothing,
// and no leaf makes the hole a door).
class WindowWithGlass : public ::testing::TestWithParam<bool> {};

TEST_P(WindowWithGlass, IsFoundFromTheRaysThatPassedIt) {
  HoleSpec h;
  h.x0 = 1.5, h.x1 = 2.7, h.z0 = 0.9, h.z1 = 2.1;
  h.leaf = false;
  h.glass = true;
  h.casing_rgb = {235, 235, 235};
  h.nothing_behind = GetParam();
  const Found f = Detect(testing::RoomScene(h));
  ASSERT_EQ(f.sm4.openings.size(), 1u) << Describe(f.sm4);
  const auto& o = f.on_wall1.at(0);
  EXPECT_EQ(o.type, OpeningType::kWindow);
  ExpectHole(o, h);
}
INSTANTIATE_TEST_SUITE_P(NothingBehind, WindowWithGlass, ::testing::Bool());

TEST(Openings, TallCabinetAgainstTheWallIsNotAnOpening) {
  testing::Scene s = testing::RoomScene({}, /*with_hole=*/false);
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 0.0}, {2.9, 0.5, 2.0}, testing::kCabinetRgb));
  const Found f = Detect(s);
  EXPECT_TRUE(f.sm4.openings.empty()) << Describe(f.sm4);
}

TEST(Openings, PictureLikeSignIsNotAnOpening) {
  testing::Scene s = testing::RoomScene({}, /*with_hole=*/false);
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 1.2}, {2.6, 0.01, 1.65}, {200, 40, 30}));
  s.boxes.push_back(testing::AxisBox({3.2, 0.0, 0.9}, {4.4, 0.015, 1.8}, {30, 60, 160}));
  const Found f = Detect(s);
  EXPECT_TRUE(f.sm4.openings.empty()) << Describe(f.sm4);
}

// A bookshelf of a door's size (0.9 x 1.8 m, 0.35 m deep) against the wall can pass as a door
// (office seeds 2, 3, 5: R1's shelf, its side panel read as a leaf at 89-90 deg): its outline
// gives the sides, its off-colour back lies on the wall's surface layer like a flush leaf. But
// it stands in front of its whole "doorway", out to both sides; an opened leaf swept its
// doorway's front clear, and a door seen behind an object has its frame beside the object.
testing::Scene BookshelfScene() {
  testing::Scene s = testing::RoomScene({}, /*with_hole=*/false);
  const testing::Rgb wood{120, 40, 35}, back{178, 158, 122};
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 0.0}, {2.9, 0.01, 1.8}, back));
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 0.0}, {2.02, 0.35, 1.8}, wood));
  s.boxes.push_back(testing::AxisBox({2.88, 0.0, 0.0}, {2.9, 0.35, 1.8}, wood));
  for (double z : {0.0, 0.6, 1.2, 1.78})
    s.boxes.push_back(testing::AxisBox({2.0, 0.0, z}, {2.9, 0.35, z + 0.02}, wood));
  return s;
}

DetectedOpening DoorRect(double u0, double u1, double v1) {
  DetectedOpening o;
  o.type = OpeningType::kDoor, o.host = "wall_1";
  o.u0 = u0, o.u1 = u1, o.v0 = 0.0, o.v1 = v1;
  return o;
}

TEST(Openings, BookshelfOfADoorsSizeStandsInFrontOfTheWall) {
  const Cloud c = testing::ScanRoom(BookshelfScene());
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);
  const OpeningParams p;
  // The shelf's outline (x 2.0-2.9 is u 2.1-3.0), with its side panel as the 'leaf'.
  DetectedOpening shelf = DoorRect(2.1, 3.0, 1.8);
  shelf.leaf_points = 1000;
  shelf.leaf_line_point = Vec2(2.99, 0.2), shelf.leaf_line_dir = Vec2(0.0, 1.0);
  EXPECT_TRUE(StandsInFrontOfTheWall(shelf, f, c.View(), p));
  // A door frame twice as wide around it: the object ends away from the sides.
  EXPECT_FALSE(StandsInFrontOfTheWall(DoorRect(1.65, 3.45, 2.1), f, c.View(), p));
  // Nothing is detected on the wall.
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), p);
  EXPECT_TRUE(m.openings.empty()) << Describe(m);
}

// The leaf of a door opened into the room stands in front of the wall, but it is the leaf: a
// door at 20 and at 90 deg is no object in front of its doorway.
class OpenedIntoTheRoom : public ::testing::TestWithParam<double> {};
TEST_P(OpenedIntoTheRoom, DoorIsNoObjectInFrontOfTheWall) {
  HoleSpec h;
  h.lambda_deg = GetParam();
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  const PatchFrame f = PatchFrame::Of(testing::RoomSm3().patches[0]);
  const OpeningParams p;
  OpeningParams keep_all = p;
  keep_all.front_min_share = 1.0;
  keep_all.front_depth = 0.1;  // nothing counts as in front
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), keep_all);
  ASSERT_EQ(m.openings.size(), 1u) << Describe(m);
  ASSERT_GT(m.openings[0].leaf_points, 0) << Describe(m);
  EXPECT_FALSE(StandsInFrontOfTheWall(m.openings[0], f, c.View(), p)) << Describe(m);
}
INSTANTIATE_TEST_SUITE_P(Lambda, OpenedIntoTheRoom, ::testing::Values(20.0, 90.0));

TEST(Openings, OpenShelfWithAnOffColourBackIsNotADoor) {
  // 0.9 m wide, 2.0 m tall, 0.35 m deep: a back panel 1 cm in front of the wall (another
  // colour, on the wall's surface layer like a flush door), sides, and six boards.
  testing::Scene s = testing::RoomScene({}, /*with_hole=*/false);
  const testing::Rgb wood{178, 158, 122};
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 0.0}, {2.9, 0.01, 2.0}, wood));
  s.boxes.push_back(testing::AxisBox({2.0, 0.0, 0.0}, {2.02, 0.35, 2.0}, wood));
  s.boxes.push_back(testing::AxisBox({2.88, 0.0, 0.0}, {2.9, 0.35, 2.0}, wood));
  for (double z : {0.0, 0.4, 0.8, 1.2, 1.6, 1.98})
    s.boxes.push_back(testing::AxisBox({2.0, 0.0, z}, {2.9, 0.35, z + 0.02}, wood));
  const Found f = Detect(s);
  EXPECT_TRUE(f.sm4.openings.empty()) << Describe(f.sm4);
}

TEST(Openings, SameInputGivesTheSameBytes) {
  HoleSpec h;
  h.lambda_deg = 30.0;
  const Found a = Detect(testing::RoomScene(h)), b = Detect(testing::RoomScene(h));
  EXPECT_EQ(Sm4Json(a.sm4), Sm4Json(b.sm4));
}

TEST(Openings, ClosedDoorPointsAreMaskedForTheWallRefit) {
  StructuralModel m = testing::RoomSm3();
  DetectedOpening o;
  o.type = OpeningType::kDoor, o.state = DoorState::kClosed, o.host = "wall_1";
  o.corners = {Vec3(2.9, 0, 0), Vec3(2.0, 0, 0), Vec3(2.0, 0, 2.1), Vec3(2.9, 0, 2.1)};
  const std::vector<Eigen::Vector3f> pts = {{2.5f, 0.02f, 1.0f},   // on the leaf
                                            {1.95f, 0.02f, 1.0f},  // on the casing
                                            {1.0f, 0.0f, 1.0f},    // on the wall
                                            {2.5f, 1.0f, 1.0f}};   // in the room
  const auto mask = ClosedDoorPointMask(pts, m.patches, {o});
  EXPECT_EQ(mask, (std::vector<std::uint8_t>{1, 1, 0, 0}));
  o.state = DoorState::kSemiOpen;
  EXPECT_EQ(ClosedDoorPointMask(pts, m.patches, {o}), (std::vector<std::uint8_t>(4, 0)));
}

TEST(Openings, VoxelsInsideAnOpeningReadAsOpeningWhateverTheyHold) {
  // A 10 cm grid over x, z in [0, 3], y in [-0.1, 0.1]; the wall y = 0 is the structural layer
  // j = 1 (y in [0, 0.1)); a closed door x in [1, 2], z in [0, 2.1] on it.
  VoxelSpace vs(Vec3(0, -0.1, 0), 0.1, 30, 2, 30);
  for (int k = 0; k < 30; ++k)
    for (int i = 0; i < 30; ++i)
      vs.MutableFlags(vs.Index(i, 1, k)) = VoxelSpace::kStructural | VoxelSpace::kOccupied;
  DetectedOpening o;
  o.corners = {Vec3(2, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 2.1), Vec3(2, 0, 2.1)};
  const auto before = vs.LabelCounts();
  EXPECT_EQ(before[int(VoxelLabel::kStructure)], 900);
  // Columns i = 10..19 (x centres 1.05..1.95) and rows k = 0..20 (centres up to 2.05; 2.05 is
  // within 2.1 - 0.0375 of the top): 10 x 21 voxels, the ones straddling the head stay wall.
  EXPECT_EQ(MarkOpeningVoxels({o}, vs), 10 * 21);
  const auto after = vs.LabelCounts();
  EXPECT_EQ(after[int(VoxelLabel::kOpening)], 210);
  EXPECT_EQ(after[int(VoxelLabel::kStructure)], 900 - 210);
  EXPECT_EQ(vs.Label(vs.Index(15, 1, 5)), VoxelLabel::kOpening);
  EXPECT_EQ(vs.Label(vs.Index(9, 1, 5)), VoxelLabel::kStructure);
  EXPECT_EQ(vs.Label(vs.Index(15, 0, 5)), VoxelLabel::kUnseen);  // not structural: untouched
}

TEST(Openings, StateThresholdsAreThePapers) {
  EXPECT_EQ(DoorStateFromAngleDeg(0.0), DoorState::kClosed);
  EXPECT_EQ(DoorStateFromAngleDeg(4.99), DoorState::kClosed);
  EXPECT_EQ(DoorStateFromAngleDeg(5.0), DoorState::kSemiOpen);
  EXPECT_EQ(DoorStateFromAngleDeg(89.9), DoorState::kSemiOpen);
  EXPECT_EQ(DoorStateFromAngleDeg(90.0), DoorState::kOpen);
}

TEST(Openings, ParamsRoundTripThroughYamlAndRejectBadValues) {
  OpeningParams p;
  p.flush_depth = 0.04, p.orthoimage.band = 0.3, p.seed = 9, p.max_lines = 33;
  p.door_merge_gap = 0.07, p.gap_fill = 0.05;
  p.front_depth = 0.9, p.front_min_share = 0.7, p.orthoimage.no_return_near_border_share = 0.6;
  const OpeningParams q = LoadParams<OpeningParams>(SaveParams(p), "mem");
  EXPECT_EQ(q.front_depth, 0.9);
  EXPECT_EQ(q.front_min_share, 0.7);
  EXPECT_EQ(q.orthoimage.no_return_near_border_share, 0.6);
  EXPECT_EQ(q.flush_depth, 0.04);
  EXPECT_EQ(q.door_merge_gap, 0.07);
  EXPECT_EQ(q.gap_fill, 0.05);
  EXPECT_EQ(q.orthoimage.band, 0.3);
  EXPECT_EQ(q.seed, 9u);
  EXPECT_EQ(q.max_lines, 33);
  OpeningParams bad;
  bad.door_min_width = 3.0;
  EXPECT_THROW(bad.Validate(), InputError);
  EXPECT_THROW(LoadParams<OpeningParams>(LoadYamlString("flush_dept: 0.1", "t.yaml"), "t.yaml"),
               InputError);
}

// ---- sm4.json ----

TEST(Sm4File, RoundTripKeepsEveryField) {
  Sm4Model m;
  m.room = "R1";
  DetectedOpening d;
  d.id = "opening_1", d.type = OpeningType::kDoor, d.host = "wall_3";
  d.corners = {Vec3(1, 2, 0), Vec3(2, 2, 0), Vec3(2, 2, 2.1), Vec3(1, 2, 2.1)};
  d.state = DoorState::kSemiOpen, d.opening_angle_deg = 37.5, d.clear_width_m = 0.86;
  d.confidence = 0.93;
  d.hole_from = "room_2";
  DetectedOpening w;
  w.id = "opening_2", w.type = OpeningType::kWindow, w.host = "wall_1";
  w.corners = {Vec3(0, 0, 0.9), Vec3(1.2, 0, 0.9), Vec3(1.2, 0, 2.1), Vec3(0, 0, 2.1)};
  w.confidence = 0.5;
  DetectedOpening u = d;
  u.id = "opening_3", u.state = DoorState::kOpen, u.opening_angle_deg = std::nan("");
  u.hole_from.clear();
  m.openings = {d, w, u};
  const std::string text = Sm4Json(m);
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["format"], "mopad-sm4");
  EXPECT_EQ(j["version"], 1);
  EXPECT_FALSE(j["openings"][1].contains("state"));  // doors only
  EXPECT_TRUE(j["openings"][2]["opening_angle_deg"].is_null());
  const Sm4Model b = ParseSm4(text, "sm4.json");
  ASSERT_EQ(b.openings.size(), 3u);
  EXPECT_EQ(b.room, "R1");
  EXPECT_EQ(b.openings[0].id, "opening_1");
  EXPECT_EQ(b.openings[0].host, "wall_3");
  EXPECT_EQ(b.openings[0].state, DoorState::kSemiOpen);
  EXPECT_DOUBLE_EQ(b.openings[0].opening_angle_deg, 37.5);
  EXPECT_DOUBLE_EQ(b.openings[0].clear_width_m, 0.86);
  EXPECT_DOUBLE_EQ(b.openings[0].confidence, 0.93);
  EXPECT_EQ(b.openings[0].hole_from, "room_2");
  EXPECT_TRUE(b.openings[0].state_from.empty());  // its state is this room's own
  EXPECT_FALSE(j["openings"][2].contains("hole_from"));
  EXPECT_EQ(b.openings[1].type, OpeningType::kWindow);
  EXPECT_DOUBLE_EQ(b.openings[1].corners[2].z(), 2.1);
  EXPECT_TRUE(std::isnan(b.openings[2].opening_angle_deg));
  EXPECT_EQ(b.openings[2].state, DoorState::kOpen);
  EXPECT_EQ(Sm4Json(b), text);
}

TEST(Sm4File, TheSameBytesOnOneThreadAndOnTwo) {
  HoleSpec h;
  h.lambda_deg = 35.0;
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  std::string one, two;
  std::vector<std::pair<std::string, Orthoimage>> images_one, images_two;
  tbb::task_arena(1).execute(
      [&] { one = Sm4Json(DetectOpenings(testing::RoomSm3(), c.View(), {}, &images_one)); });
  tbb::task_arena(2).execute(
      [&] { two = Sm4Json(DetectOpenings(testing::RoomSm3(), c.View(), {}, &images_two)); });
  EXPECT_NE(one.find("\"door\""), std::string::npos);
  EXPECT_EQ(one, two);
  ASSERT_EQ(images_one.size(), images_two.size());
  for (std::size_t i = 0; i < images_one.size(); ++i)
    EXPECT_EQ(images_one[i].first, images_two[i].first);
}

TEST(Sm4File, RoomFilesAreTheJsonAndOneColourAndDepthImagePerWall) {
  const Cloud c = testing::ScanRoom(testing::RoomScene(HoleSpec{}));
  std::vector<std::pair<std::string, Orthoimage>> images;
  const Sm4Model m = DetectOpenings(testing::RoomSm3(), c.View(), {}, &images);
  ASSERT_EQ(images.size(), 4u);
  EXPECT_EQ(images[0].first, "wall_1");
  const std::string dir = ::testing::TempDir() + "sm4_room";
  std::filesystem::create_directories(dir);
  WriteSm4Files(dir, m, images);
  EXPECT_EQ(ReadSm4(dir + "/sm4.json").openings.size(), m.openings.size());
  for (const char* w : {"wall_1", "wall_2", "wall_3", "wall_4"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/orthoimages/" + w + "_colour.png")) << w;
    EXPECT_TRUE(std::filesystem::exists(dir + "/orthoimages/" + w + "_depth.png")) << w;
  }
  EXPECT_THROW(WriteSm4Files("/nonexistent_dir/room", m, images), InputError);
}

TEST(Sm4File, MalformedFilesAreInputErrorsNamingTheField) {
  auto msg = [](const std::string& text) {
    try {
      ParseSm4(text, "sm4.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(msg(R"({"format":"mopad-sm3","version":1,"room":"A","openings":[]})").find("format"),
            std::string::npos);
  EXPECT_NE(msg(R"({"format":"mopad-sm4","version":2,"room":"A","openings":[]})").find("version"),
            std::string::npos);
  EXPECT_NE(
      msg(R"({"format":"mopad-sm4","version":1,"room":"A","openings":[{"id":"o","type":"door","host":"w","corners":[[0,0,0],[1,0,0],[1,0,1]],"confidence":1,"state":"closed","opening_angle_deg":0,"clear_width_m":0}]})")
          .find("openings[0].corners"),
      std::string::npos);
  EXPECT_NE(
      msg(R"({"format":"mopad-sm4","version":1,"room":"A","openings":[{"id":"o","type":"door","host":"w","corners":[[0,0,0],[1,0,0],[1,0,1],[0,0,1]],"confidence":1,"state":"ajar","opening_angle_deg":0,"clear_width_m":0}]})")
          .find("state"),
      std::string::npos);
  EXPECT_NE(msg("{").find("JSON"), std::string::npos);
  EXPECT_THROW(ReadSm4("/nonexistent/sm4.json"), InputError);
}

// A side's line is where its step lies, to a fraction of a pixel: Canny marks the first pixel
// of a step between two pixels, and taking that pixel's centre put every side of a window half
// a pixel the same way along u and along v. Over eight phases of a glazed window against a
// 2.5 cm pixel grid the window's centre stays on the hole's within 0.15 pixel on average and
// within one pixel at every phase.
TEST(Openings, WindowCentreIsUnbiasedAtAnyPhaseOfThePixelGrid) {
  constexpr double kPixel = 0.025;
  OpeningParams p;
  p.orthoimage.finest_pixel = p.orthoimage.coarsest_pixel = kPixel;
  double mean_u = 0.0, mean_v = 0.0;
  for (int k = 0; k < 8; ++k) {
    HoleSpec h;
    const double d = k * kPixel / 8.0;
    h.x0 = 1.5 + d, h.x1 = 2.7 + d, h.z0 = 0.9 + d, h.z1 = 2.1 + d;
    h.leaf = false;
    h.glass = true;
    h.casing_rgb = {235, 235, 235};
    const Found f = Detect(testing::RoomScene(h), p);
    ASSERT_EQ(f.on_wall1.size(), 1u) << "phase " << k << "\n" << Describe(f.sm4);
    const auto& o = f.on_wall1[0];
    const double eu = 0.5 * (o.u0 + o.u1) - (5.0 - 0.5 * (h.x0 + h.x1));
    const double ev = 0.5 * (o.v0 + o.v1) - 0.5 * (h.z0 + h.z1);
    EXPECT_LE(std::abs(eu), kPixel) << "phase " << k;
    EXPECT_LE(std::abs(ev), kPixel) << "phase " << k;
    mean_u += eu / 8.0, mean_v += ev / 8.0;
  }
  EXPECT_LE(std::abs(mean_u), 0.15 * kPixel);
  EXPECT_LE(std::abs(mean_v), 0.15 * kPixel);
}

// ---- Doors another room found (HoleHints, AddDoorsFromNeighbours, DetectOpenings) ----

// The room behind the south wall found the door: its hole on the wall's other face (y = -0.2),
// counter-clockwise seen from there.
Sm4Model RoomBehindWithDoor(const HoleSpec& h) {
  Sm4Model behind;
  behind.room = "B";
  DetectedOpening d;
  d.id = "opening_1", d.type = OpeningType::kDoor, d.host = "wall_9";
  d.corners = {Vec3(h.x0, -0.2, 0.0), Vec3(h.x1, -0.2, 0.0), Vec3(h.x1, -0.2, h.z1),
               Vec3(h.x0, -0.2, h.z1)};
  d.state = DoorState::kOpen, d.confidence = 0.9;
  behind.openings.push_back(d);
  return behind;
}

TEST(Openings, ADoorTheRoomBehindFoundIsAHintOnTheWallsOtherFaceOnly) {
  HoleSpec h;
  const Sm4Model behind = RoomBehindWithDoor(h);
  const StructuralModel sm3 = testing::RoomSm3();
  const OpeningParams p;
  int on_south = 0, elsewhere = 0;
  for (const StructuralPatch& w : sm3.patches) {
    if (w.patch_class != PatchClass::kWall) continue;
    const auto hints = HoleHints(PatchFrame::Of(w), sm3.room, {behind}, p);
    (w.id == "wall_1" ? on_south : elsewhere) += static_cast<int>(hints.size());
    for (const HoleHint& k : hints) {
      EXPECT_EQ(k.room, "B");
      EXPECT_NEAR(k.u1 - k.u0, h.x1 - h.x0, 1e-9);
      EXPECT_NEAR(k.v1, h.z1, 1e-9);
    }
  }
  EXPECT_EQ(on_south, 1);
  EXPECT_EQ(elsewhere, 0);
  // Its own doors are no hints.
  Sm4Model self = behind;
  self.room = sm3.room;
  EXPECT_TRUE(HoleHints(PatchFrame::Of(sm3.patches.front()), sm3.room, {self}, p).empty());
}

// A room modelled before the room behind, its own images missing the door: the hint's hole
// with the leaf measured in this room's points (45 deg into this room), hole_from the finder.
TEST(Openings, ALeafOpenedIntoTheRoomIsMeasuredOnTheHoleTheRoomBehindFound) {
  HoleSpec h;
  h.lambda_deg = 45.0;
  const Cloud c = testing::ScanRoom(testing::RoomScene(h));
  Sm4Model sm4;
  sm4.room = "R";
  const OpeningParams p;
  ASSERT_EQ(AddDoorsFromNeighbours(testing::RoomSm3(), sm4, c.View(), {RoomBehindWithDoor(h)}, p),
            1);
  const DetectedOpening& o = sm4.openings.at(0);
  EXPECT_EQ(o.host, "wall_1");
  EXPECT_EQ(o.hole_from, "B");
  EXPECT_EQ(o.id, "opening_1");
  EXPECT_EQ(o.state, DoorState::kSemiOpen);
  EXPECT_NEAR(o.opening_angle_deg, 45.0, 3.0);
  // Nothing is added twice, and no door where this room's wall is solid.
  EXPECT_EQ(AddDoorsFromNeighbours(testing::RoomSm3(), sm4, c.View(), {RoomBehindWithDoor(h)}, p),
            0);
  Sm4Model solid;
  solid.room = "R";
  const Cloud no_hole = testing::ScanRoom(testing::RoomScene(h, false));
  EXPECT_EQ(
      AddDoorsFromNeighbours(testing::RoomSm3(), solid, no_hole.View(), {RoomBehindWithDoor(h)}, p),
      0);
  EXPECT_TRUE(solid.openings.empty());
}

}  // namespace
}  // namespace mopad::modelling
