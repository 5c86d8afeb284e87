// Every YAML example in docs/navigation.md loads into the params structs it names (STYLE.md §8).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "autonomy/global_planner.h"
#include "autonomy/local_controller.h"
#include "common/params.h"
#include "perception/amcl.h"
#include "perception/occupancy_grid.h"

namespace mopad::autonomy {
namespace {

std::vector<std::string> YamlBlocks(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::string> blocks;
  std::string line, block;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line.rfind("```yaml", 0) == 0) {
      inside = true;
      block.clear();
    } else if (inside && line.rfind("```", 0) == 0) {
      inside = false;
      blocks.push_back(block);
    } else if (inside) {
      block += line + "\n";
    }
  }
  return blocks;
}

TEST(NavigationDocs, YamlExamplesLoadIntoTheParamsStructs) {
  const std::string path = std::string(MOPAD_SOURCE_DIR) + "/docs/navigation.md";
  const auto blocks = YamlBlocks(path);
  ASSERT_FALSE(blocks.empty());
  for (const auto& text : blocks) {
    const YAML::Node root = LoadYamlString(text, path);
    RejectUnknownKeys(root, {"occupancy_grid", "amcl", "global_planner", "local_controller"}, path,
                      "");
    const auto grid = LoadParams<perception::OccupancyGridParams>(root["occupancy_grid"], path);
    const auto amcl = LoadParams<perception::AmclParams>(root["amcl"], path);
    const auto planner = LoadParams<GlobalPlannerParams>(root["global_planner"], path);
    const auto ctl = LoadParams<LocalControllerParams>(root["local_controller"], path);
    EXPECT_NO_THROW(grid.Validate());
    EXPECT_NO_THROW(amcl.Validate());
    EXPECT_NO_THROW(planner.Validate());
    EXPECT_NO_THROW(ctl.Validate());
  }
}

}  // namespace
}  // namespace mopad::autonomy
