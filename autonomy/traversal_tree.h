#pragma once
// The Dynamic Traversal Tree of the floor mission (paper §2, Figures 3-4): rooms are nodes,
// created as the robot discovers them; the root is the room the robot starts in. After a room
// is modelled, each door of its SM4 that leads to space no visited room covers becomes a child:
// a passable (open or semi-open, wide enough) door an unvisited child, a closed or too narrow
// one a leaf "seen, not entered" with the reason. Gaps in the room's walls that its obstacle map
// saw through and SM4 did not model (autonomy/wall_gaps.h) count as doors. The robot visits the nearest unvisited child
// of the node it is in, returns to the parent when none is left, and ends at the root.
//
// Pure bookkeeping (no driving, no geometry beyond the door records): robot side,
// deterministic (nodes numbered in creation order, children in the order they were added).

#include <array>
#include <string>
#include <vector>

#include "common/frames.h"

namespace mopad::autonomy {

enum class NodeState { kUnvisited, kVisited, kSeenNotEntered, kUnreachable };
const char* ToString(NodeState s);

/// A door as the robot modelled it (SM4, map frame), seen from the room that found it.
struct DoorRecord {
  std::string room;     ///< the room whose SM4 found it (robot's name)
  std::string opening;  ///< SM4 opening id in that room, e.g. "opening_2", or "gap_k"
  std::string state;    ///< SM4 state: "open", "semi_open", "closed"; "gap" for a map gap
  double opening_angle_deg = 0.0;
  double clear_width_m = 0.0;     ///< m, SM4's passable width
  Vec2 centre = Vec2::Zero();     ///< m, bottom-edge midpoint on the wall plane (plan)
  Vec2 inward = Vec2::UnitX();    ///< unit, plan normal into the room that found it
  double width = 0.0;             ///< m, the hole's width
  std::array<Vec3, 4> corners{};  ///< map frame, SM4's rectangle
  /// m, the doorway's clear width in the robot's obstacle map when the door was found
  /// (autonomy/doorway.h); -1: not measured
  double map_clear_width_m = -1.0;
};

struct TraversalNode {
  int id = 0;
  std::string room;  ///< the robot's name for the room ("room_1", ...); empty for a leaf
  int parent = -1;
  NodeState state = NodeState::kUnvisited;
  std::string reason;    ///< why not visited / unreachable, or how the visit ended
  int visit_order = -1;  ///< 0 for the root, 1 for the next room entered, ...; -1 never
  bool has_entry_door = false;
  DoorRecord entry_door;  ///< the door from the parent (none for the root)
  std::vector<int> children;
  /// The mission's scan indices (the navigator's order) of the two door scans: the one in
  /// front of the door frame (parent's side) and the one just beyond it (the room's first).
  int door_scan_before = -1, door_scan_after = -1;
};

class TraversalTree {
 public:
  /// The root: the room the robot starts in, visited first.
  int AddRoot(const std::string& room);
  /// A child of `parent` behind `door`, in `state` (kUnvisited or kSeenNotEntered + reason).
  int AddChild(int parent, const DoorRecord& door, NodeState state, const std::string& reason);
  /// Marks `node` visited as `room`, with the next visit order.
  void MarkVisited(int node, const std::string& room);
  void MarkUnreachable(int node, const std::string& reason);
  void MarkSeenNotEntered(int node, const std::string& reason);

  const std::vector<TraversalNode>& Nodes() const { return nodes_; }
  TraversalNode& Node(int id) { return nodes_.at(static_cast<std::size_t>(id)); }
  const TraversalNode& Node(int id) const { return nodes_.at(static_cast<std::size_t>(id)); }
  /// The unvisited children of `node`, in the order they were added.
  std::vector<int> UnvisitedChildren(int node) const;
  int VisitedCount() const { return visited_; }
  /// "K rooms visited of N known" (known: every node, leaves included).
  std::string Summary() const;

 private:
  std::vector<TraversalNode> nodes_;
  int visited_ = 0;
};

}  // namespace mopad::autonomy
