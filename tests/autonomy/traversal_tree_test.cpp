// The Dynamic Traversal Tree's bookkeeping (autonomy/traversal_tree.h).
#include "autonomy/traversal_tree.h"

#include <gtest/gtest.h>

namespace mopad::autonomy {
namespace {

DoorRecord Door(const std::string& room, const std::string& opening) {
  DoorRecord d;
  d.room = room;
  d.opening = opening;
  return d;
}

TEST(TraversalTree, RoomsAreNumberedInVisitOrderAndChildrenKeepTheirOrder) {
  TraversalTree t;
  EXPECT_EQ(t.AddRoot("room_1"), 0);
  EXPECT_EQ(t.Node(0).visit_order, 0);
  const int a = t.AddChild(0, Door("room_1", "opening_1"), NodeState::kUnvisited, "");
  const int b = t.AddChild(0, Door("room_1", "opening_2"), NodeState::kSeenNotEntered, "closed");
  const int c = t.AddChild(0, Door("room_1", "opening_3"), NodeState::kUnvisited, "");
  EXPECT_EQ(t.UnvisitedChildren(0), (std::vector<int>{a, c}));
  t.MarkVisited(c, "room_2");
  EXPECT_EQ(t.Node(c).visit_order, 1);
  EXPECT_EQ(t.UnvisitedChildren(0), (std::vector<int>{a}));
  t.MarkUnreachable(a, "no route");
  EXPECT_TRUE(t.UnvisitedChildren(0).empty());
  EXPECT_EQ(t.Node(b).reason, "closed");
  EXPECT_EQ(t.Node(a).entry_door.opening, "opening_1");
  EXPECT_EQ(t.VisitedCount(), 2);
  EXPECT_STREQ(ToString(t.Node(a).state), "unreachable");
}

TEST(TraversalTree, MisuseIsALogicError) {
  TraversalTree t;
  EXPECT_THROW(t.AddChild(0, Door("x", "y"), NodeState::kUnvisited, ""), std::logic_error);
  t.AddRoot("room_1");
  EXPECT_THROW(t.AddRoot("room_1"), std::logic_error);
  EXPECT_THROW(t.AddChild(0, Door("x", "y"), NodeState::kVisited, ""), std::logic_error);
}

}  // namespace
}  // namespace mopad::autonomy
