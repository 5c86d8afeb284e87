// The Python module (python/mopad_module.cpp, docs/python.md) against the CLI and the C++
// libraries: python/tests/test_module.py runs under Debian's python3 with numpy and pytest (a
// scan as arrays equals `mopad scan`'s PLY, the evaluator's summary equals `mopad eval`'s, a
// 60 s closed-loop drive decided in Python writes its commands, the main job runs from Python
// and stops in order on KeyboardInterrupt); here the same commands drive the same robot through
// C++ and the true trajectory must be the same bytes, and the run folder mopad.run() wrote must
// hold the files of `mopad run`'s, byte for byte (timings aside). Skipped when the
// module was not built (no pybind11) or python3 lacks numpy or pytest.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/tum.h"
#include "mission/drive_mission.h"
#include "mission/sim_robot.h"
#include "scenes/start_spot.h"
#include "sim/scene_world.h"
#include "tests/run_command.h"
#include "tests/tools/mopad_cli.h"

namespace {

namespace fs = std::filesystem;
using mopad::test_support::RunCommand;

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Python, TheModuleMatchesTheCliAndADriveInPythonIsTheSameDriveInCpp) {
  const fs::path module_dir = fs::path(MOPAD_BINARY_DIR) / "python" / "mopad";
  bool built = false;
  for (const auto& e : fs::directory_iterator(module_dir))
    built = built || e.path().filename().string().rfind("_mopad", 0) == 0;
  if (!built)
    GTEST_SKIP() << "mopad._mopad not built (no Debian pybind11-dev, -DMOPAD_PYTHON=OFF or a "
                    "sanitizer build)";
  if (RunCommand("/usr/bin/python3 -c 'import numpy, pytest' 2>&1").code != 0)
    GTEST_SKIP() << "Debian python3 with numpy and pytest absent (scripts/install-deps.sh --test)";
  const fs::path work = fs::temp_directory_path() / ("mopad_python_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const auto t = RunCommand("cd " MOPAD_SOURCE_DIR " && PYTHONPATH=" MOPAD_BINARY_DIR
                            "/python MOPAD_BINARY=" MOPAD_BINARY " MOPAD_SOURCE_DIR=" MOPAD_SOURCE_DIR
                            " MOPAD_WORK=" + work.string() +
                            " /usr/bin/python3 -m pytest -q -p no:cacheprovider "
                            "python/tests/test_module.py 2>&1");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("5 passed"), std::string::npos) << t.out;

  // The main job: mopad.run() and `mopad run` on one spec (both wrote to work/run).
  const auto cli = mopad::test_support::RunFiles((work / "run_cli").string());
  const auto py = mopad::test_support::RunFiles((work / "run").string());
  ASSERT_GT(cli.size(), 20u);
  EXPECT_EQ(cli.size(), py.size());
  for (const auto& [name, bytes] : cli) {
    ASSERT_TRUE(py.count(name)) << name << " missing from the run folder of mopad.run()";
    EXPECT_TRUE(py.at(name) == bytes) << name << " differs between mopad.run() and `mopad run`";
  }

  // The commands the Python brain sent, through the C++ robot.
  const mopad::sim::SceneWorld w = mopad::sim::LoadSceneWorld((work / "office").string());
  mopad::mission::DriveParams params;
  params.seed = 1;
  const mopad::Pose2 start =
      mopad::scenes::ChooseStart(w.world->scene(), *w.truth, mopad::sim::FootprintOf(params.body))
          .X_WB;
  mopad::mission::SimRobot robot(*w.world, params, start, 1);
  std::ifstream commands(work / "commands.txt");
  int steps = 0;
  for (double v, om; commands >> v >> om; ++steps) robot.Step({v, om});
  EXPECT_GE(steps, 2900);
  std::string tum;
  for (const auto& s : robot.TrueTrajectory())
    tum += mopad::io::TumLinePlanar(s.t, s.pose.x, s.pose.y, s.pose.yaw);
  const std::string py_tum = Bytes(work / "python_trajectory.tum");
  EXPECT_GT(py_tum.size(), 1000u);
  EXPECT_TRUE(tum == py_tum) << "C++ and Python trajectories differ";
  fs::remove_all(work);
}

}  // namespace
