#include "common/polygon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mopad {
namespace {

using V2 = Eigen::Vector2d;
using Poly = std::vector<V2>;

Poly Rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// The outline as a set of corners, whatever vertex it starts at.
bool HasCorner(const Poly& p, const V2& c) {
  for (const V2& v : p)
    if ((v - c).norm() < 1e-6) return true;
  return false;
}

TEST(SignedArea, PositiveCounterClockwiseNegativeClockwise) {
  Poly r = Rect(0, 0, 2, 3);
  EXPECT_DOUBLE_EQ(SignedArea(r), 6.0);
  std::reverse(r.begin(), r.end());
  EXPECT_DOUBLE_EQ(SignedArea(r), -6.0);
}

TEST(UnionOfTiledPolygons, ThreeRoomsSplitByBoundariesWithoutAWallBecomeOneOutline) {
  // An L of a hall (a notch where a wall stub stands) and two rooms sharing parts of its edges,
  // as the FZK-Haus ground floor: the shared pieces are split at each other's vertices.
  const Poly hall = {{3.8, 4.01}, {7.41, 4.01}, {7.41, 5.75},
                     {0.3, 5.75}, {0.3, 4.25},  {3.8, 4.25}};
  const Poly living = Rect(3.8, 0.3, 11.7, 4.01);
  Poly kitchen = Rect(0.3, 0.3, 3.8, 4.01);
  std::reverse(kitchen.begin(), kitchen.end());  // any winding
  const auto u = UnionOfTiledPolygons({hall, living, kitchen});
  ASSERT_TRUE(u.has_value());
  EXPECT_GT(SignedArea(*u), 0.0);
  EXPECT_NEAR(SignedArea(*u),
              std::abs(SignedArea(hall)) + SignedArea(living) + std::abs(SignedArea(kitchen)),
              1e-9);
  EXPECT_EQ(u->size(), 10u);  // 12 corners less the two on the straight south wall
  for (const V2& c : {V2(0.3, 0.3), V2(11.7, 0.3), V2(11.7, 4.01), V2(7.41, 4.01), V2(7.41, 5.75),
                      V2(0.3, 5.75), V2(0.3, 4.25), V2(3.8, 4.25), V2(3.8, 4.01), V2(0.3, 4.01)})
    EXPECT_TRUE(HasCorner(*u, c)) << c.transpose();
  EXPECT_FALSE(HasCorner(*u, V2(3.8, 0.3)));
}

TEST(UnionOfTiledPolygons, VerticesWithinTheToleranceAreOnePoint) {
  const auto u = UnionOfTiledPolygons({Rect(0, 0, 1, 1), Rect(1.0005, 0, 2, 1.0004)}, 1e-3);
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->size(), 4u);
  EXPECT_NEAR(SignedArea(*u), 2.0, 2e-3);
}

TEST(UnionOfTiledPolygons, RefusesWhatIsNotOneSimpleOutline) {
  // Apart.
  EXPECT_FALSE(UnionOfTiledPolygons({Rect(0, 0, 1, 1), Rect(2, 0, 3, 1)}).has_value());
  // Touching at a corner only.
  EXPECT_FALSE(UnionOfTiledPolygons({Rect(0, 0, 1, 1), Rect(1, 1, 2, 2)}).has_value());
  // Overlapping.
  EXPECT_FALSE(UnionOfTiledPolygons({Rect(0, 0, 2, 1), Rect(1, 0, 3, 1)}).has_value());
  EXPECT_FALSE(UnionOfTiledPolygons({Rect(0, 0, 1, 1), Rect(0, 0, 1, 1)}).has_value());
  // A ring of four rooms around a courtyard: the union has a hole.
  EXPECT_FALSE(
      UnionOfTiledPolygons({Rect(0, 0, 3, 1), Rect(2, 1, 3, 3), Rect(0, 2, 2, 3), Rect(0, 1, 1, 2)})
          .has_value());
  // Degenerate.
  EXPECT_FALSE(UnionOfTiledPolygons({}).has_value());
  EXPECT_FALSE(UnionOfTiledPolygons({{{0, 0}, {1, 0}, {2, 0}}}).has_value());
}

TEST(UnionOfTiledPolygons, OnePolygonComesBackCounterClockwiseWithoutCollinearVertices) {
  const Poly p = {{0, 0}, {0, 1}, {1, 1}, {1, 0.5}, {1, 0}, {0.5, 0}};  // clockwise
  const auto u = UnionOfTiledPolygons({p});
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->size(), 4u);
  EXPECT_NEAR(SignedArea(*u), 1.0, 1e-12);
}

// A room's outline after its walls were refitted (office_5rooms R1, map frame): the short
// edge fitted across an open doorway left two jogs of 3.4-3.5 cm in the wall x = 11.05, which
// SM3 split into three walls. With a 4 cm tolerance the wall is one edge again; a 5 cm shadow
// step and the room's corners stay.
TEST(RemoveShallowVertices, RemovesJogsInAStraightWallAndKeepsCornersStepsAndSpikes) {
  Poly outline = {{19.5523, 2.1519},  {-2.9557, 2.1522},  {-2.9468, -5.036},  {11.0303, -5.0549},
                  {11.0604, -2.7966}, {11.0258, -2.1958}, {11.0621, -0.6511}, {19.5531, -0.649}};
  RemoveShallowVertices(outline, 0.04);
  ASSERT_EQ(outline.size(), 6u);
  EXPECT_FALSE(HasCorner(outline, {11.0604, -2.7966}));
  EXPECT_FALSE(HasCorner(outline, {11.0258, -2.1958}));
  for (const V2& c : {V2(11.0303, -5.0549), V2(11.0621, -0.6511), V2(-2.9468, -5.036)})
    EXPECT_TRUE(HasCorner(outline, c));
  // A 5 cm step (two vertices) is a feature at 4 cm, and at 6 cm it goes.
  const Poly step = {{0, 0}, {4, 0}, {4, 1.5}, {4.05, 1.5}, {4.05, 3}, {0, 3}};
  Poly kept = step;
  RemoveShallowVertices(kept, 0.04);
  EXPECT_EQ(kept.size(), step.size());
  Poly gone = step;
  RemoveShallowVertices(gone, 0.06);
  EXPECT_LT(gone.size(), step.size());
  // A spike beyond its neighbours' span is not a jog, however thin.
  Poly spike = {{0, 0}, {4, 0}, {4, 3}, {2, 3}, {2.01, 6}, {1.99, 3}, {0, 3}};
  RemoveShallowVertices(spike, 0.04);
  EXPECT_TRUE(HasCorner(spike, {2.01, 6}));
  Poly triangle = {{0, 0}, {1, 0}, {0.5, 0.01}};
  RemoveShallowVertices(triangle, 0.04);
  EXPECT_EQ(triangle.size(), 3u);
}

TEST(DistanceToSegment, ProjectsOntoTheSegmentAndClampsToItsEnds) {
  const V2 a(0, 0), b(4, 0);
  EXPECT_DOUBLE_EQ(DistanceToSegment(V2(1, 2), a, b), 2.0);
  EXPECT_DOUBLE_EQ(DistanceToSegment(V2(7, 4), a, b), 5.0);   // beyond b: to b
  EXPECT_DOUBLE_EQ(DistanceToSegment(V2(-3, 4), a, b), 5.0);  // before a: to a
  EXPECT_DOUBLE_EQ(SquaredDistanceToSegment(V2(1, 2), a, b), 4.0);
  EXPECT_DOUBLE_EQ(DistanceToSegment(V2(3, 4), a, a), 5.0);  // a point
  // A segment far shorter than a micrometre is still a segment, not its first end.
  const V2 c(1e-7, 0);
  EXPECT_DOUBLE_EQ(SquaredDistanceToSegment(V2(2e-7, 0), a, c), 1e-14);
}

TEST(DistanceToBoundary, IsTheNearestEdgeInsideAndOutside) {
  const Poly r = Rect(0, 0, 4, 2);
  EXPECT_DOUBLE_EQ(DistanceToBoundary(V2(1, 1.5), r), 0.5);  // inside, nearest the top edge
  EXPECT_DOUBLE_EQ(DistanceToBoundary(V2(7, 6), r), 5.0);    // outside, nearest corner (4, 2)
  EXPECT_DOUBLE_EQ(DistanceToBoundary(V2(0.5, 0), r), 0.0);  // on an edge
  EXPECT_EQ(DistanceToBoundary(V2(0, 0), {}), std::numeric_limits<double>::infinity());
}

TEST(PolygonArea3d, IsTheAreaOfAPlanarPolygonInAnyPlaneAndWinding) {
  // A 2 x 3 rectangle in the plane x = 1, and an L (area 3) tilted out of the x-y plane.
  std::vector<Eigen::Vector3d> wall = {{1, 0, 0}, {1, 2, 0}, {1, 2, 3}, {1, 0, 3}};
  EXPECT_DOUBLE_EQ(PolygonArea3d(wall), 6.0);
  EXPECT_TRUE(NewellVector(wall).isApprox(Eigen::Vector3d(12, 0, 0)));  // twice the area, +x
  std::reverse(wall.begin(), wall.end());
  EXPECT_DOUBLE_EQ(PolygonArea3d(wall), 6.0);
  EXPECT_TRUE(NewellVector(wall).isApprox(Eigen::Vector3d(-12, 0, 0)));
  const double s = std::sqrt(0.5);
  std::vector<Eigen::Vector3d> ell;
  for (const V2& q : Poly{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}})
    ell.emplace_back(q.x(), s * q.y(), s * q.y());
  EXPECT_NEAR(PolygonArea3d(ell), 3.0, 1e-12);
  EXPECT_EQ(PolygonArea3d({{0, 0, 0}, {1, 1, 1}}), 0.0);
  EXPECT_EQ(PolygonArea3d({}), 0.0);
}

TEST(ConvexHull, IsCounterClockwiseFromTheLowestXWithoutInnerCollinearOrRepeatedPoints) {
  const Poly points = {{1, 1}, {2, 0}, {0, 0}, {2, 2}, {1, 0}, {0, 2}, {2, 0}, {0.5, 1.5}};
  const Poly hull = ConvexHull(points);
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_EQ(hull[0], V2(0, 0));
  EXPECT_EQ(hull[1], V2(2, 0));
  EXPECT_EQ(hull[2], V2(2, 2));
  EXPECT_EQ(hull[3], V2(0, 2));
  EXPECT_GT(SignedArea(hull), 0.0);
  // Fewer than 3 distinct points come back sorted and distinct.
  EXPECT_EQ(ConvexHull({{1, 1}, {0, 0}, {1, 1}}), (Poly{{0, 0}, {1, 1}}));
  EXPECT_TRUE(ConvexHull({}).empty());
}

TEST(ConvexHull, ToleranceDropsNearlyStraightTurns) {
  const Poly points = {{0, 0}, {1, -1e-9}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_EQ(ConvexHull(points).size(), 5u);
  EXPECT_EQ(ConvexHull(points, 1e-6).size(), 4u);
}

}  // namespace
}  // namespace mopad
