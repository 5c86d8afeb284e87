#include "autonomy/traversal_tree.h"

#include "common/error.h"

namespace mopad::autonomy {

const char* ToString(NodeState s) {
  switch (s) {
    case NodeState::kUnvisited:
      return "unvisited";
    case NodeState::kVisited:
      return "visited";
    case NodeState::kSeenNotEntered:
      return "seen_not_entered";
    case NodeState::kUnreachable:
      return "unreachable";
  }
  return "?";
}

int TraversalTree::AddRoot(const std::string& room) {
  if (!nodes_.empty()) throw std::logic_error("traversal tree: the root exists already");
  TraversalNode n;
  n.id = 0;
  nodes_.push_back(n);
  MarkVisited(0, room);
  return 0;
}

int TraversalTree::AddChild(int parent, const DoorRecord& door, NodeState state,
                            const std::string& reason) {
  if (parent < 0 || parent >= static_cast<int>(nodes_.size()))
    throw std::logic_error("traversal tree: no node " + std::to_string(parent));
  if (state != NodeState::kUnvisited && state != NodeState::kSeenNotEntered)
    throw std::logic_error("traversal tree: a new child is unvisited or seen, not entered");
  TraversalNode n;
  n.id = static_cast<int>(nodes_.size());
  n.parent = parent;
  n.state = state;
  n.reason = reason;
  n.has_entry_door = true;
  n.entry_door = door;
  nodes_.push_back(n);
  nodes_[static_cast<std::size_t>(parent)].children.push_back(n.id);
  return n.id;
}

void TraversalTree::MarkVisited(int node, const std::string& room) {
  TraversalNode& n = Node(node);
  if (n.state == NodeState::kVisited && n.visit_order >= 0) return;
  n.state = NodeState::kVisited;
  n.room = room;
  n.visit_order = visited_++;
}

void TraversalTree::MarkUnreachable(int node, const std::string& reason) {
  TraversalNode& n = Node(node);
  n.state = NodeState::kUnreachable;
  n.reason = reason;
}

void TraversalTree::MarkSeenNotEntered(int node, const std::string& reason) {
  TraversalNode& n = Node(node);
  n.state = NodeState::kSeenNotEntered;
  n.reason = reason;
}

std::string TraversalTree::Summary() const {
  return std::to_string(visited_) + " rooms visited of " + std::to_string(nodes_.size()) + " known";
}

std::vector<int> TraversalTree::UnvisitedChildren(int node) const {
  std::vector<int> out;
  for (int c : Node(node).children)
    if (Node(c).state == NodeState::kUnvisited) out.push_back(c);
  return out;
}

}  // namespace mopad::autonomy
