// The robot never sees ground truth (brief; STYLE.md §2). perception/, modelling/ and autonomy/
// consume only sensor data and object models, and exports/ only the robot's model files: they
// must neither link nor include the scene model, the simulator or the evaluator, nor the
// libraries that read scene files.
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

const std::vector<std::string> kRobotTargets = {"mopad_io",        "mopad_perception",
                                                "mopad_modelling", "mopad_autonomy",
                                                "mopad_runfolder", "mopad_exports"};
const std::vector<std::string> kRobotDirs = {"io",       "perception", "modelling",
                                             "autonomy", "runfolder",  "exports"};
// Targets and third-party libraries that carry or read the truth, the mission library (the
// simulated robot and its truth log) and the suites (missions' scores against the truth): the
// robot's brain reaches none of them.
const std::set<std::string> kTruthTargets = {"mopad_scenes",  "mopad_sim",   "mopad_evaluation",
                                             "mopad_mission", "mopad_suite", "tinygltf",
                                             "assimp::assimp", "embree"};

TEST(TruthIsolation, LinkGraphIsReadAndTheWalkerFindsKnownEdges) {
  // Positive controls: if these fail, the checks below could not fail either.
  const Graph g = ReadGraph();
  ASSERT_TRUE(g.count("mopad_sim"));
  EXPECT_TRUE(Closure(g, "mopad_sim").count("mopad_scenes"));
  EXPECT_TRUE(Closure(g, "mopad_evaluation").count("mopad_scenes"));
  EXPECT_TRUE(Closure(g, "mopad_autonomy").count("mopad_interfaces"));
  EXPECT_TRUE(Closure(g, "mopad_mission").count("mopad_sim"));
  EXPECT_TRUE(Closure(g, "mopad_mission").count("mopad_autonomy"));
  EXPECT_TRUE(Closure(g, "mopad_exports").count("mopad_modelling"));
}

TEST(TruthIsolation, RobotLibrariesDoNotLinkTruth) {
  const Graph g = ReadGraph();
  for (const auto& t : kRobotTargets) {
    ASSERT_TRUE(g.count(t)) << t << " missing from the link graph";
    for (const auto& dep : Closure(g, t)) {
      EXPECT_FALSE(kTruthTargets.count(dep)) << t << " links " << dep;
    }
  }
}

const std::regex& ForbiddenInclude() {
  static const std::regex re(
      R"(#\s*include\s*[<"]\s*)"
      R"((scenes/|sim/|evaluation/|mission/|suite/|tiny_gltf\.h|assimp/|embree3/))");
  return re;
}

TEST(TruthIsolation, ForbiddenIncludePatternMatchesWhatItShould) {
  EXPECT_TRUE(std::regex_search("#include \"scenes/scene.h\"", ForbiddenInclude()));
  EXPECT_TRUE(std::regex_search("#  include <sim/embree_world.h>", ForbiddenInclude()));
  EXPECT_TRUE(std::regex_search("#include <assimp/scene.h>", ForbiddenInclude()));
  EXPECT_TRUE(std::regex_search("#include \"mission/sim_robot.h\"", ForbiddenInclude()));
  EXPECT_TRUE(std::regex_search("#include \"suite/compare.h\"", ForbiddenInclude()));
  EXPECT_FALSE(std::regex_search("#include \"interfaces/tls_scan.h\"", ForbiddenInclude()));
  EXPECT_FALSE(std::regex_search("#include \"perception/scenes_like.h\"", ForbiddenInclude()));
}

TEST(TruthIsolation, RobotSourcesDoNotIncludeTruth) {
  const fs::path root(MOPAD_SOURCE_DIR);
  int files = 0;
  for (const auto& dir : kRobotDirs) {
    ASSERT_TRUE(fs::is_directory(root / dir)) << dir;
    for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
      if (!e.is_regular_file()) continue;
      const auto ext = e.path().extension().string();
      if (ext != ".h" && ext != ".hpp" && ext != ".cpp" && ext != ".cc" && ext != ".txt") continue;
      ++files;
      std::ifstream in(e.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        EXPECT_FALSE(std::regex_search(line, ForbiddenInclude()))
            << e.path().string() << ":" << n << ": " << line;
        const bool cmake_comment = ext == ".txt" &&
                                   line.find_first_not_of(" \t") != std::string::npos &&
                                   line[line.find_first_not_of(" \t")] == '#';
        if (ext == ".txt" && !cmake_comment) {  // CMakeLists: no truth targets by name either
          EXPECT_EQ(line.find("mopad::scenes"), std::string::npos) << e.path() << ":" << n;
          EXPECT_EQ(line.find("mopad::sim"), std::string::npos) << e.path() << ":" << n;
          EXPECT_EQ(line.find("mopad::mission"), std::string::npos) << e.path() << ":" << n;
        }
      }
    }
  }
  EXPECT_GE(files, 3);  // at least the three CMakeLists were read
}

}  // namespace
