// Doorways from the obstacle map: gaps in a room's walls that the scans saw through.

#include "autonomy/wall_gaps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace mopad::autonomy {
namespace {

using perception::CellState;
using perception::OccupancyGrid;

// A map drawn from a function of the cell centre (map frame).
OccupancyGrid Draw(const std::function<CellState(const Vec2&)>& f) {
  OccupancyGrid g(perception::OccupancyGridParams{}, Vec2(-2.0, -2.0), 200, 160);
  for (int j = 0; j < g.Height(); ++j)
    for (int i = 0; i < g.Width(); ++i) {
      const perception::Cell c{i, j};
      g.SetState(c, f(g.CentreOf(c)));
    }
  return g;
}

// Room [0, 4] x [0, 3] with 0.1 m walls outside it and a neighbour beyond the east wall; the
// east wall has a hole for y in [y0, y1] (nothing in the wall band there). `hole` is the state
// of the hole's cells and of the neighbour room.
OccupancyGrid TwoRooms(double y0, double y1, CellState hole) {
  return Draw([=](const Vec2& p) {
    const double x = p.x(), y = p.y();
    if (x > 0 && x < 4 && y > 0 && y < 3) return CellState::kFree;
    const bool in_east_wall = x >= 4 && x <= 4.1 && y >= -0.1 && y <= 3.1;
    if (in_east_wall && y > y0 && y < y1) return hole;
    if (x >= -0.1 && x <= 4.1 && y >= -0.1 && y <= 3.1) return CellState::kOccupied;
    if (x > 4.1 && x < 7 && y > 0 && y < 3) return hole;
    return CellState::kUnknown;
  });
}

const std::vector<Vec2> kRoom = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};

TEST(WallGaps, AnOpenDoorwayTheScansSawThroughIsOneGap) {
  const auto gaps = WallGaps(TwoRooms(1.0, 1.9, CellState::kFree), kRoom, WallGapParams{});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].edge, 1);
  EXPECT_NEAR(gaps[0].width(), 0.9, 0.1);
  EXPECT_NEAR(gaps[0].centre().x(), 4.0, 1e-9);
  EXPECT_NEAR(gaps[0].centre().y(), 1.45, 0.05);
  EXPECT_NEAR(gaps[0].inward.x(), -1.0, 1e-9);  // into the room
}

// Outlines make small steps in doorways (a shadow step, a sealed reveal): a gap across such a
// vertex is still one gap, not two halves too narrow and unframed.
TEST(WallGaps, AGapAcrossAKinkOfTheOutlineIsOneGap) {
  const std::vector<Vec2> kinked = {{0, 0}, {4, 0}, {4.03, 1.4}, {4.0, 2.0}, {4, 3}, {0, 3}};
  const auto gaps = WallGaps(TwoRooms(1.0, 1.9, CellState::kFree), kinked, WallGapParams{});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_NEAR(gaps[0].width(), 0.9, 0.1);
  EXPECT_NEAR(gaps[0].centre().y(), 1.45, 0.05);
  EXPECT_NEAR(gaps[0].inward.x(), -1.0, 0.02);
  WallGapParams per_edge;  // edges taken one by one: the gap is lost
  per_edge.collinear_deg = 0.0;
  EXPECT_TRUE(WallGaps(TwoRooms(1.0, 1.9, CellState::kFree), kinked, per_edge).empty());
}

TEST(WallGaps, EitherPolygonOrientationGivesTheSameGap) {
  const std::vector<Vec2> cw(kRoom.rbegin(), kRoom.rend());
  const auto gaps = WallGaps(TwoRooms(1.0, 1.9, CellState::kFree), cw, WallGapParams{});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_NEAR(gaps[0].inward.x(), -1.0, 1e-9);
  EXPECT_NEAR(gaps[0].width(), 0.9, 0.1);
}

TEST(WallGaps, AWallNothingSawIsNoGap) {
  EXPECT_TRUE(WallGaps(TwoRooms(1.0, 1.9, CellState::kUnknown), kRoom, WallGapParams{}).empty());
}

TEST(WallGaps, GapsOutsideTheWidthRangeAreNotDoorways) {
  EXPECT_TRUE(WallGaps(TwoRooms(1.0, 1.3, CellState::kFree), kRoom, WallGapParams{}).empty());
  WallGapParams narrow_max;
  narrow_max.max_width = 0.6;
  EXPECT_TRUE(WallGaps(TwoRooms(1.0, 1.9, CellState::kFree), kRoom, narrow_max).empty());
}

TEST(WallGaps, AClosedWallIsNoGap) {
  EXPECT_TRUE(WallGaps(TwoRooms(1.0, 1.9, CellState::kOccupied), kRoom, WallGapParams{}).empty());
}

TEST(WallGaps, AWallAt45DegreesWithAGap) {
  // A square room turned by 45 degrees about (2, 1.5), its north-east wall open near its middle.
  const double c = std::sqrt(0.5);
  const Vec2 o(2.0, 1.5);
  const auto local = [&](const Vec2& p) {  // room frame: the square [-1.2, 1.2]^2
    const Vec2 d = p - o;
    return Vec2(c * d.x() + c * d.y(), -c * d.x() + c * d.y());
  };
  const OccupancyGrid g = Draw([&](const Vec2& p) {
    const Vec2 q = local(p);
    if (std::abs(q.x()) < 1.2 && std::abs(q.y()) < 1.2) return CellState::kFree;
    const bool wall = std::abs(q.x()) <= 1.35 && std::abs(q.y()) <= 1.35;
    if (wall && q.x() > 1.2 && std::abs(q.y()) < 0.45) return CellState::kFree;  // the doorway
    if (wall) return CellState::kOccupied;
    if (q.x() > 1.35 && q.x() < 3 && std::abs(q.y()) < 1.2) return CellState::kFree;
    return CellState::kUnknown;
  });
  std::vector<Vec2> room;
  for (const Vec2& q : {Vec2(-1.2, -1.2), Vec2(1.2, -1.2), Vec2(1.2, 1.2), Vec2(-1.2, 1.2)})
    room.push_back(o + Vec2(c * q.x() - c * q.y(), c * q.x() + c * q.y()));
  const auto gaps = WallGaps(g, room, WallGapParams{});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_NEAR(gaps[0].width(), 0.9, 0.15);
  const Vec2 centre = local(gaps[0].centre());
  EXPECT_NEAR(centre.x(), 1.2, 1e-6);
  EXPECT_NEAR(centre.y(), 0.0, 0.08);
  EXPECT_NEAR(gaps[0].inward.dot(Vec2(-c, -c)), 1.0, 1e-9);
}

}  // namespace
}  // namespace mopad::autonomy
