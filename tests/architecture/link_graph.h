#pragma once
// The link graph CMake writes (build/link_graph.txt, cmake/LinkGraph.cmake), read for the
// architecture tests: one line per target, "target: dep dep ...".
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace mopad::architecture {

using Graph = std::map<std::string, std::vector<std::string>>;

inline Graph ReadGraph() {
  Graph g;
  std::ifstream in(MOPAD_LINK_GRAPH);
  EXPECT_TRUE(in.good()) << "missing " << MOPAD_LINK_GRAPH;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream deps(line.substr(colon + 1));
    auto& list = g[line.substr(0, colon)];
    for (std::string d; deps >> d;) list.push_back(d);
  }
  return g;
}

/// Every target `root` reaches through its links (itself not included unless on a cycle).
inline std::set<std::string> Closure(const Graph& g, const std::string& root) {
  std::set<std::string> seen;
  std::vector<std::string> stack{root};
  while (!stack.empty()) {
    const std::string t = stack.back();
    stack.pop_back();
    const auto it = g.find(t);
    if (it == g.end()) continue;
    for (const auto& d : it->second)
      if (seen.insert(d).second) stack.push_back(d);
  }
  return seen;
}

}  // namespace mopad::architecture
