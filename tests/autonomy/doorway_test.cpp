// A doorway's clear width in the obstacle map: what the floor mission compares between when a
// door was found and when the robot comes to pass it.

#include "autonomy/doorway.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace mopad::autonomy {
namespace {

using perception::CellState;
using perception::OccupancyGrid;

// Room [0, 4] x [0, 3] (free), its east wall x in [4, 4.1] occupied but for the doorway
// y in (1.0, 1.9), free space beyond; `leaf(p)`: the cells a door leaf occupies.
OccupancyGrid Doorway(const std::function<bool(const Vec2&)>& leaf,
                      CellState hole = CellState::kFree) {
  OccupancyGrid g(perception::OccupancyGridParams{}, Vec2(-1.0, -1.0), 160, 100);
  for (int j = 0; j < g.Height(); ++j)
    for (int i = 0; i < g.Width(); ++i) {
      const perception::Cell c{i, j};
      const Vec2 p = g.CentreOf(c);
      CellState s = CellState::kFree;
      const bool wall = p.x() >= 4.0 && p.x() <= 4.1 && p.y() >= -0.1 && p.y() <= 3.1;
      if (wall) s = p.y() > 1.0 && p.y() < 1.9 ? hole : CellState::kOccupied;
      if (leaf(p)) s = CellState::kOccupied;
      g.SetState(c, s);
    }
  return g;
}

const Vec2 kA(4.0, 1.0), kB(4.0, 1.9), kInward(-1.0, 0.0);

// The cells within 2.5 cm of the leaf: a segment from the hinge (4.05, 1.0), `deg` from shut,
// swung past the wall plane (+x).
std::function<bool(const Vec2&)> Leaf(double deg) {
  const double a = deg * M_PI / 180.0;
  const Vec2 h(4.05, 1.0), e = h + 0.9 * Vec2(std::sin(a), std::cos(a));
  return [=](const Vec2& p) {
    const Vec2 d = e - h;
    const double s = std::clamp((p - h).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - (h + s * d)).norm() < 0.025;
  };
}

TEST(Doorway, AnOpenDoorwayIsClearOverItsWidth) {
  const double w = DoorwayClearWidth(Doorway([](const Vec2&) { return false; }), kA, kB, kInward,
                                     DoorwayParams{});
  EXPECT_NEAR(w, 0.9, 0.05);
}

TEST(Doorway, ALeafShutInItsFrameLeavesNoClearWidth) {
  EXPECT_LT(DoorwayClearWidth(Doorway(Leaf(0.0)), kA, kB, kInward, DoorwayParams{}), 0.1);
}

TEST(Doorway, ALeafOpenedBeyondTheWallTakesOnlyItsThickness) {
  EXPECT_NEAR(DoorwayClearWidth(Doorway(Leaf(90.0)), kA, kB, kInward, DoorwayParams{}), 0.85, 0.06);
}

// At 45 deg the leaf crosses the slab (0.3 m past the plane) within 0.3 m of the hinge.
TEST(Doorway, AHalfShutLeafBlocksWhatItCrossesInTheSlab) {
  const double w = DoorwayClearWidth(Doorway(Leaf(45.0)), kA, kB, kInward, DoorwayParams{});
  EXPECT_NEAR(w, 0.9 - (0.3 - 0.05), 0.07);
  DoorwayParams shallow;  // a slab that stops short of the leaf's far reach sees less of it
  shallow.depth_beyond = 0.1;
  EXPECT_GT(DoorwayClearWidth(Doorway(Leaf(45.0)), kA, kB, kInward, shallow), w + 0.1);
}

TEST(Doorway, UnknownCellsDoNotBlock) {
  const double w =
      DoorwayClearWidth(Doorway([](const Vec2&) { return false; }, CellState::kUnknown), kA, kB,
                        kInward, DoorwayParams{});
  EXPECT_NEAR(w, 0.9, 0.05);
}

TEST(Doorway, EitherEndFirstGivesTheSameWidthAndNoWidthIsZero) {
  const OccupancyGrid g = Doorway(Leaf(45.0));
  EXPECT_NEAR(DoorwayClearWidth(g, kA, kB, kInward, DoorwayParams{}),
              DoorwayClearWidth(g, kB, kA, kInward, DoorwayParams{}), 1e-9);
  EXPECT_EQ(DoorwayClearWidth(g, kA, kA, kInward, DoorwayParams{}), 0.0);
}

}  // namespace
}  // namespace mopad::autonomy
