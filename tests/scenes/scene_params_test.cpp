// The params of `mopad scene import` and `mopad scene plan` (their --config files).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/params.h"
#include "scenes/bim_import.h"
#include "scenes/plan_view.h"

namespace mopad::scenes {
namespace {

TEST(SceneParams, EveryFieldIsInTheFieldList) {
  for (const auto& m : FieldsMissingFromVisit(BimImportParams{}, "import.")) ADD_FAILURE() << m;
  for (const auto& m : FieldsMissingFromVisit(PlanViewParams{}, "plan.")) ADD_FAILURE() << m;
}

TEST(SceneParams, AnImportConfigSetsPerDoorAnglesAndFurtherModels) {
  const auto p = LoadParams<BimImportParams>(
      LoadYamlString("storey: '1. Obergeschoss'\ndoor_angles_deg: {D1: 30, 2aB: 0}\n"
                     "merge: [pipes.ifc]\nceiling_from_spaces: true\n",
                     "import.yaml"),
      "import.yaml");
  EXPECT_EQ(p.storey, "1. Obergeschoss");
  EXPECT_EQ(p.door_angles_deg, (std::map<std::string, double>{{"2aB", 0.0}, {"D1", 30.0}}));
  EXPECT_EQ(p.merge, std::vector<std::string>{"pipes.ifc"});
  EXPECT_TRUE(p.ceiling_from_spaces);
  EXPECT_EQ(p.door_angle_deg, 90.0);  // absent: the default
  EXPECT_NO_THROW(p.Validate());
  EXPECT_THROW(LoadParams<BimImportParams>(
                   LoadYamlString("door_angles_deg: {D1: 190}\n", "import.yaml"), "import.yaml"),
               InputError);
}

// Every ```yaml block of docs/scene-import.md is a `scene import --config` file (STYLE.md §8).
TEST(SceneParams, TheDocsYamlExamplesLoadAsImportConfigs) {
  std::ifstream in(std::string(MOPAD_SOURCE_DIR) + "/docs/scene-import.md");
  ASSERT_TRUE(in) << "docs/scene-import.md";
  std::string line, block;
  bool inside = false;
  int blocks = 0;
  while (std::getline(in, line)) {
    if (!inside && line == "```yaml") {
      inside = true, block.clear();
    } else if (inside && line == "```") {
      inside = false, ++blocks;
      const auto p =
          LoadParams<BimImportParams>(LoadYamlString(block, "scene-import.md"), "scene-import.md");
      EXPECT_NO_THROW(p.Validate());
    } else if (inside) {
      block += line + "\n";
    }
  }
  EXPECT_GE(blocks, 1);
}

}  // namespace
}  // namespace mopad::scenes
