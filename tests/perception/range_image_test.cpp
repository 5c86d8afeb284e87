// What a later scan saw through (perception/range_image.h): a point in front of what the scan
// saw is seen through, one on or behind it is not; an edge of a nearer object, a missing return
// or a point outside the field of view gives no proof; the scan's map pose applies; the circle
// closes at azimuth 0. And a map cell whose band points were seen through is no obstacle.

#include "perception/range_image.h"

#include <gtest/gtest.h>

#include <cmath>

#include "perception/occupancy_grid.h"

namespace mopad::perception {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A 1-deg scan from elevation +60 to -60 deg whose every return is at `range`, but for a nearer
// block (a person) of ranges `near` over azimuths [a0, a1) deg.
interfaces::TlsScan SphereScan(float range, float near = 0.f, int a0 = 0, int a1 = 0) {
  interfaces::TlsScan s;
  s.rows = 121;
  s.columns = 360;
  s.azimuth_min = 0.0;
  s.azimuth_step = kPi / 180.0;
  s.elevation_max = kPi / 3.0;
  s.elevation_step = kPi / 180.0;
  s.points.resize(std::size_t{s.rows} * s.columns);
  for (std::uint32_t r = 0; r < s.rows; ++r)
    for (std::uint32_t c = 0; c < s.columns; ++c) {
      interfaces::TlsPoint& p = s.points[std::size_t{r} * s.columns + c];
      p.row = r;
      p.column = c;
      p.range = static_cast<int>(c) >= a0 && static_cast<int>(c) < a1 ? near : range;
    }
  return s;
}

Eigen::Vector3d At(double az_deg, double el_deg, double r) {
  const double a = az_deg * kPi / 180.0, e = el_deg * kPi / 180.0;
  return r * Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

TEST(RangeImage, APointInFrontOfWhatTheScanSawIsSeenThroughAndOneOnItIsNot) {
  const RangeImage image(SphereScan(5.0f), Eigen::Isometry3d::Identity(), 0.0175);  // 1 deg
  EXPECT_TRUE(image.SeesThrough(At(30, 10, 3.0), 0.2));
  EXPECT_TRUE(image.SeesThrough(At(200, -30, 4.7), 0.2));
  EXPECT_FALSE(image.SeesThrough(At(30, 10, 4.9), 0.2));  // within the margin
  EXPECT_FALSE(image.SeesThrough(At(30, 10, 6.0), 0.2));  // behind
  EXPECT_FALSE(image.SeesThrough(At(30, 75, 3.0), 0.2));  // above the field of view
  EXPECT_FALSE(image.SeesThrough(At(30, 10, 0.3), 0.2));  // nearer than the minimum range
  // The circle closes: just below azimuth 0 is the last column, just above the first.
  EXPECT_TRUE(image.SeesThrough(At(-0.3, 0, 3.0), 0.2));
  EXPECT_TRUE(image.SeesThrough(At(359.7, 0, 3.0), 0.2));
}

TEST(RangeImage, ANearerObjectItsEdgesAndMissingReturnsGiveNoProof) {
  // A person 2 m away over azimuths 40-49 deg in front of walls at 5 m.
  interfaces::TlsScan scan = SphereScan(5.0f, 2.0f, 40, 50);
  const RangeImage image(scan, Eigen::Isometry3d::Identity(), 0.0175);
  EXPECT_TRUE(image.SeesThrough(At(45, 0, 1.5), 0.2));   // in front of the person
  EXPECT_FALSE(image.SeesThrough(At(45, 0, 3.0), 0.2));  // behind them
  EXPECT_FALSE(image.SeesThrough(At(39, 0, 3.0), 0.2));  // beside, but the edge is near
  EXPECT_TRUE(image.SeesThrough(At(37, 0, 3.0), 0.2));   // clear of it
  // No return near a direction (a window to the sky): no proof.
  for (std::uint32_t r = 55; r < 65; ++r)
    scan.points[std::size_t{r} * scan.columns + 100].range = 0;
  const RangeImage holes(scan, Eigen::Isometry3d::Identity(), 0.0175);
  EXPECT_FALSE(holes.SeesThrough(At(100, 0, 3.0), 0.2));
  EXPECT_TRUE(holes.SeesThrough(At(104, 0, 3.0), 0.2));
  // Pooled cells keep the nearest return of their block: at 4 deg cells the person's block
  // reaches farther.
  const RangeImage coarse(SphereScan(5.0f, 2.0f, 40, 50), Eigen::Isometry3d::Identity(), 0.07);
  EXPECT_FALSE(coarse.SeesThrough(At(37, 0, 3.0), 0.2));
  EXPECT_TRUE(coarse.SeesThrough(At(25, 0, 3.0), 0.2));
}

TEST(RangeImage, TheScansMapPoseApplies) {
  Eigen::Isometry3d X_MS = Eigen::Isometry3d::Identity();
  X_MS.translation() = Eigen::Vector3d(10.0, -2.0, 1.4);
  X_MS.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const RangeImage image(SphereScan(5.0f, 2.0f, 40, 50), X_MS, 0.0175);
  // Scanner azimuth 45 deg is map azimuth 135 deg.
  const Eigen::Vector3d o = X_MS.translation();
  EXPECT_FALSE(image.SeesThrough(o + At(135, 0, 3.0), 0.2));
  EXPECT_TRUE(image.SeesThrough(o + At(135, 0, 1.5), 0.2));
  EXPECT_TRUE(image.SeesThrough(o + At(45, 0, 3.0), 0.2));
}

TEST(OccupancyGrid, ACellWhoseBandPointsWereSeenThroughIsNoObstacle) {
  OccupancyGridParams p;
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 20; ++k) pts.emplace_back(1.02, 1.02, 0.1 + 0.08 * k);  // a person's cell
  pts.emplace_back(2.02, 1.02, 0.0);                                          // floor
  CloudEvidence e = OccupancyGrid::Evidence(p, pts);
  OccupancyGrid grid(p, Eigen::Vector2d::Zero(), 60, 60);
  grid.InsertPoints(e);
  EXPECT_TRUE(grid.IsOccupied(Eigen::Vector2d(1.02, 1.02)));
  for (auto& c : e.cells) {
    if (c.band == 0) continue;
    EXPECT_FLOAT_EQ(c.lo[2], 0.1f);
    EXPECT_NEAR(c.hi[2], 0.1 + 0.08 * 19, 1e-6);
    c.transient = true;
  }
  OccupancyGrid later(p, Eigen::Vector2d::Zero(), 60, 60);
  later.InsertPoints(e);
  EXPECT_FALSE(later.IsOccupied(Eigen::Vector2d(1.02, 1.02)));
  EXPECT_TRUE(later.IsFree(Eigen::Vector2d(2.02, 1.02)));
}

}  // namespace
}  // namespace mopad::perception
