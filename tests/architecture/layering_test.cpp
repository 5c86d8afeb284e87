// Arrows point one way (STYLE.md §1, docs/architecture.md): every library has a layer, and a
// library links and includes only libraries of lower layers. The link graph is CMake's own
// (build/link_graph.txt, cmake/LinkGraph.cmake); the includes are read from the sources. The
// compiler enforces the includes too (cmake/IncludeRoots.cmake: each library sees only the
// headers of what it links); this test names the offending line and also covers headers no
// source of the library compiles.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/architecture/link_graph.h"

namespace {

namespace fs = std::filesystem;
using mopad::architecture::Closure;
using mopad::architecture::Graph;
using mopad::architecture::ReadGraph;

// The layers, lowest first; a library may link only libraries of a strictly lower layer. Two
// libraries of one layer never see each other (the robot's and the world's halves, side by side).
const std::map<std::string, int> kLayer = {
    {"common", 0},     {"interfaces", 1}, {"io", 2},       {"scenes", 2},    {"perception", 3},
    {"sim", 3},        {"modelling", 4},  {"autonomy", 5}, {"runfolder", 6}, {"exports", 7},
    {"evaluation", 8}, {"report", 9},     {"mission", 10}, {"suite", 11},
    {"tools", 12}};

std::string FolderOf(const std::string& target) {
  if (target == "mopad") return "tools";
  return target.rfind("mopad_", 0) == 0 ? target.substr(6) : "";
}

// The back-edges of `g`: "a -> b" for every edge between project libraries whose layer does not
// go down (and every project library without a layer).
std::vector<std::string> BackEdges(const Graph& g) {
  std::vector<std::string> out;
  for (const auto& [from, deps] : g) {
    const std::string a = FolderOf(from);
    if (!kLayer.count(a)) {
      out.push_back(from + ": no layer");
      continue;
    }
    for (const auto& to : deps) {
      const std::string b = FolderOf(to);
      if (b.empty()) continue;  // a third-party library
      if (!kLayer.count(b) || kLayer.at(b) >= kLayer.at(a)) out.push_back(from + " -> " + to);
    }
  }
  return out;
}

TEST(Layering, TheCheckFindsABackEdgeAndASkippedLayer) {
  Graph g;
  g["mopad_modelling"] = {"mopad_perception", "Eigen3::Eigen"};
  g["mopad_perception"] = {"mopad_interfaces"};
  EXPECT_TRUE(BackEdges(g).empty());
  g["mopad_perception"].push_back("mopad_modelling");  // up
  g["mopad_io"] = {"mopad_scenes"};                    // sideways
  g["mopad_newlib"] = {};                              // unplaced
  const std::vector<std::string> bad = BackEdges(g);
  EXPECT_EQ(bad, (std::vector<std::string>{"mopad_io -> mopad_scenes", "mopad_newlib: no layer",
                                           "mopad_perception -> mopad_modelling"}));
}

TEST(Layering, EveryLinkGoesDown) {
  const Graph g = ReadGraph();
  ASSERT_GE(g.size(), 12u) << "the link graph lists too few libraries";
  for (const std::string& e : BackEdges(g)) ADD_FAILURE() << "back-edge: " << e;
}

TEST(Layering, EveryLibraryIncludesOnlyWhatItLinks) {
  const Graph g = ReadGraph();
  const fs::path root(MOPAD_SOURCE_DIR);
  const std::regex include(R"(^\s*#\s*include\s*[<"]([a-z_]+)/)");
  int files = 0;
  for (const auto& [target, deps] : g) {
    const std::string folder = FolderOf(target);
    if (folder.empty() || !fs::is_directory(root / folder)) continue;
    std::set<std::string> visible{folder};
    for (const auto& d : Closure(g, target)) visible.insert(FolderOf(d));
    for (const auto& e : fs::recursive_directory_iterator(root / folder)) {
      const auto ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
      ++files;
      std::ifstream in(e.path());
      std::string line;
      std::smatch m;
      for (int n = 1; std::getline(in, line); ++n)
        if (std::regex_search(line, m, include) && kLayer.count(m[1]) && !visible.count(m[1]))
          ADD_FAILURE() << e.path().string() << ":" << n << ": " << target << " includes " << m[1]
                        << "/ without linking it";
    }
  }
  EXPECT_GE(files, 100);
}

}  // namespace
