// A SCENE argument: a spec generated in memory (with door angles set first), a generated
// folder, a scene file with its sidecar beside it, and the refusals, each in one line.

#include "scenes/scene_paths.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "tests/input_error_of.h"

namespace mopad::scenes {
namespace {

namespace fs = std::filesystem;

const std::string kSpec = std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml";

using test_support::InputErrorOf;

const Opening& Door(const GroundTruth& truth, const std::string& id) {
  for (const Opening& o : truth.openings)
    if (o.id == id) return o;
  throw std::runtime_error("no door " + id);
}

TEST(SceneArg, ASpecIsGeneratedWithItsDoorAnglesSetFirst) {
  const LoadedScene as_is = LoadSceneArg(kSpec);
  ASSERT_TRUE(as_is.truth);
  EXPECT_EQ(as_is.description, kSpec + " (generated)");
  EXPECT_NEAR(RadToDeg(Door(*as_is.truth, "D1").opening_angle), 90.0, 1e-9);
  const LoadedScene closed = LoadSceneArg(kSpec, {{"D1", 0.0}}, "--door");
  EXPECT_EQ(Door(*closed.truth, "D1").opening_angle, 0.0);
  EXPECT_EQ(Door(*closed.truth, "D1").state, DoorState::kClosed);
  EXPECT_EQ(InputErrorOf([] {
              LoadSceneArg(kSpec, {{"D9", 30.0}}, "--door");
            }),
            "--door: error: unknown door; got 'D9', expected a door of the spec");
}

TEST(SceneArg, AFolderAndAFileReadTheTruthBesideThem) {
  const fs::path dir = fs::temp_directory_path() / ("mopad_scene_arg_" + std::to_string(getpid()));
  fs::remove_all(dir);
  WriteGeneratedScene(Generate(LoadSceneSpec(kSpec)), dir.string());
  const std::string glb = (dir / "scene.glb").string();
  const std::string truth = (dir / "scene.truth.json").string();
  for (const std::string& arg : {dir.string(), glb}) {
    const LoadedScene s = LoadSceneArg(arg);
    ASSERT_TRUE(s.truth) << arg;
    EXPECT_EQ(s.description, glb + " + " + truth);
    EXPECT_GT(s.scene.TriangleCount(), 0u);
  }
  EXPECT_EQ(InputErrorOf([&] {
              LoadSceneArg(dir.string(), {{"D1", 0.0}}, "--door");
            }),
            "--door: error: only with a scene spec (.yaml)");
  fs::remove(dir / "scene.glb");
  EXPECT_EQ(InputErrorOf([&] { LoadSceneArg(dir.string()); }),
            dir.string() +
                ": error: scene folder has no scene.glb; expected a folder written by `mopad "
                "scene generate`, or a scene file");
  fs::remove_all(dir);
  EXPECT_EQ(InputErrorOf([&] { LoadSceneArg(dir.string()); }),
            dir.string() + ": error: no such scene file or folder");
}

}  // namespace
}  // namespace mopad::scenes
