// The suites the project ships (suites/*.yaml) parse, and each of their config overlays loads as
// the main job's params, as `mopad run --config` will load it in every case.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/params.h"
#include "mission/floor_job.h"
#include "suite/manifest.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;

TEST(CommittedSuites, ParseAndTheirConfigsLoad) {
  int manifests = 0, configs = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(MOPAD_SOURCE_DIR) / "suites")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const suite::Manifest m = suite::LoadManifest(entry.path().string());
    ++manifests;
    for (const suite::ConfigEntry& c : m.configs) {
      SCOPED_TRACE(c.name);
      if (c.yaml.empty()) continue;
      const auto params = LoadParams<FloorMissionParams>(
          LoadYamlString(c.yaml, entry.path().string()), entry.path().string());
      EXPECT_NO_THROW(ValidateParams(params, "room."));
      ++configs;
    }
  }
  EXPECT_GE(manifests, 4);
  EXPECT_GE(configs, 3);  // suites/realism.yaml's three
}

}  // namespace
}  // namespace mopad::mission
