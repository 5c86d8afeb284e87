// Sloped ceilings in plan (common/ceiling_planes.h): hand-worked regions and wall outlines.
#include "common/ceiling_planes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/polygon.h"

namespace mopad {
namespace {

using V2 = Eigen::Vector2d;

// A plane through the line y = y0 at height z0, rising by `rise` per metre of y.
CeilingPlane Slope(double y0, double z0, double rise) {
  CeilingPlane p;
  p.n = Eigen::Vector3d(0.0, rise, -1.0).normalized();
  p.c = p.n.dot(Eigen::Vector3d(0.0, y0, z0));
  return p;
}

CeilingPlane Level(double z) {
  CeilingPlane p;
  p.c = -z;
  return p;
}

// A 4 x 6 m room (y 0..6) under a gable roof rising 1 m per metre from 1 m at both eaves to the
// ridge at y = 3 (4 m), with a level collar ceiling at 3 m: the slopes up to y = 2 and from
// y = 4, the collar between.
TEST(CeilingPlanes, AGableWithACollarCeilingSplitsThePlanWhereEachIsLowest) {
  const std::vector<V2> plan{{0, 0}, {4, 0}, {4, 6}, {0, 6}};
  const std::vector<CeilingPlane> planes{Slope(0.0, 1.0, 1.0), Slope(6.0, 1.0, -1.0), Level(3.0)};
  EXPECT_NEAR(planes[0].ZAt(V2(1, 1.5)), 2.5, 1e-12);
  const auto regions = LowestCeilingRegions(plan, planes, nullptr, 1e-6);
  ASSERT_EQ(regions.size(), 3u);
  EXPECT_NEAR(SignedArea(regions[0]), 4.0 * 2.0, 1e-9);
  EXPECT_NEAR(SignedArea(regions[1]), 4.0 * 2.0, 1e-9);
  EXPECT_NEAR(SignedArea(regions[2]), 4.0 * 2.0, 1e-9);
  // Within its hull only: the collar's faces end at x = 2 (a stairwell beside it); the strip
  // beside them is no plane's (the slopes are higher there), the slopes keep their parts.
  const std::vector<std::vector<V2>> hulls{{}, {}, {{0, 2}, {2, 2}, {2, 4}, {0, 4}}};
  const auto cut = LowestCeilingRegions(plan, planes, &hulls, 1e-6);
  EXPECT_NEAR(SignedArea(cut[2]), 2.0 * 2.0, 1e-9);
  EXPECT_NEAR(SignedArea(cut[0]), 8.0, 1e-9);
  // A plane nowhere the lowest has no region.
  const auto high = LowestCeilingRegions(plan, {Slope(0.0, 1.0, 1.0), Level(0.5)}, nullptr, 1e-6);
  EXPECT_TRUE(high[0].empty());
  EXPECT_NEAR(SignedArea(high[1]), 24.0, 1e-9);
}

TEST(CeilingPlanes, AGableWallEndsUnderTheRoofAndAWallUnderTheCollarIsLeftAlone) {
  const std::vector<V2> plan{{0, 0}, {4, 0}, {4, 6}, {0, 6}};
  const std::vector<CeilingPlane> planes{Slope(0.0, 1.0, 1.0), Slope(6.0, 1.0, -1.0), Level(3.0)};
  const auto regions = LowestCeilingRegions(plan, planes, nullptr, 1e-6);
  // The gable at x = 4, its foot from (4, 0) towards +y, inward -x, 3 m high from z = 0.
  const auto gable =
      WallUnderCeilings(V2(4, 0), V2(0, 1), V2(-1, 0), 6.0, 0.0, 3.0, planes, regions);
  const std::vector<V2> want{{0, 0}, {0, 1}, {2, 3}, {4, 3}, {6, 1}, {6, 0}};
  ASSERT_EQ(gable.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k)
    EXPECT_NEAR((gable[k] - want[k]).norm(), 0.0, 1e-9) << k;
  // The knee wall at y = 0 (foot from (0, 0) along +x, inward +y): 1 m high all along.
  const auto knee = WallUnderCeilings(V2(0, 0), V2(1, 0), V2(0, 1), 4.0, 0.0, 3.0, planes, regions);
  ASSERT_EQ(knee.size(), 4u);
  EXPECT_NEAR(knee[1].y(), 1.0, 1e-9);
  EXPECT_NEAR(knee[2].x(), 4.0, 1e-9);
  // A wall no plane comes under (a 2.5 m partition under the 3 m collar) stays as it is.
  EXPECT_TRUE(
      WallUnderCeilings(V2(0, 3), V2(1, 0), V2(0, 1), 4.0, 0.0, 2.5, planes, regions).empty());
}

}  // namespace
}  // namespace mopad
