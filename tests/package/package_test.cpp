// The installed package as a user meets it: this build installed into a scratch prefix,
// examples/frontier_explorer configured and built against it with find_package(OpenMoPAD), and
// run on the office scene: its own brain explores through the robot boundary and the evaluator
// scores the models it made.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "tests/process_temp_dir.h"
#include "tests/run_command.h"

namespace mopad {
namespace {

namespace fs = std::filesystem;
using test_support::RunCommand;

std::string Quoted(const fs::path& p) {
  std::string q = p.string();
  q.insert(q.begin(), '\'');
  q.push_back('\'');
  return q;
}

// Runs `command` with its stderr, failing the test with its output when it exits non-zero.
std::string MustRun(const std::string& command) {
  const test_support::CommandResult r = RunCommand(command + " 2>&1");
  EXPECT_EQ(r.code, 0) << command << "\n" << r.out;
  return r.out;
}

// The command configuring the project in `source` into `build` against the package in
// `prefix`, with this build's generator, compiler and compiler launcher.
std::string ConfigureAgainst(const fs::path& prefix, const fs::path& source,
                             const fs::path& build) {
  std::string c = std::string(MOPAD_CMAKE) + " -S " + Quoted(source) + " -B " + Quoted(build) +
                  " -G '" + MOPAD_GENERATOR +
                  "' -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + Quoted(prefix) +
                  " -DCMAKE_CXX_COMPILER=" + Quoted(MOPAD_CXX_COMPILER);
  if (!std::string(MOPAD_MAKE_PROGRAM).empty())
    c += " -DCMAKE_MAKE_PROGRAM=" + Quoted(MOPAD_MAKE_PROGRAM);
  if (!std::string(MOPAD_CXX_LAUNCHER).empty())
    c += " -DCMAKE_CXX_COMPILER_LAUNCHER=" + Quoted(MOPAD_CXX_LAUNCHER);
  return c;
}

TEST(Package, ExampleBuiltAgainstTheInstalledPackageExploresTheOfficeAndIsScored) {
  const fs::path work = test_support::ProcessTempDir("mopad_package_");
  const fs::path prefix = work / "prefix", build = work / "build", out = work / "run";

  // 1. The install: libraries, headers under their include roots, the package config.
  MustRun(std::string(MOPAD_CMAKE) + " --install " + Quoted(MOPAD_BINARY_DIR) + " --prefix " +
          Quoted(prefix));
  for (const char* f :
       {"lib/cmake/OpenMoPAD/OpenMoPADConfig.cmake",
        "lib/cmake/OpenMoPAD/OpenMoPADConfigVersion.cmake",
        "lib/cmake/OpenMoPAD/OpenMoPADTargets.cmake", "lib/libmopad_sim.a",
        "lib/libmopad_autonomy.a", "include/mopad/interfaces/interfaces/robot_platform.h",
        "include/mopad/evaluation/evaluation/run_evaluation.h",
        "share/OpenMoPAD/scenes/office_5rooms.yaml", "bin/mopad"})
    EXPECT_TRUE(fs::exists(prefix / f)) << f;
  EXPECT_FALSE(fs::exists(prefix / "include/mopad/modelling/modelling/room_model_internal.h"));

  // 2. The example, a project of its own, against the installed package only.
  MustRun(
      ConfigureAgainst(prefix, fs::path(MOPAD_SOURCE_DIR) / "examples/frontier_explorer", build));
  // The package found is the one just installed (not a checkout or another prefix).
  std::ifstream cache(build / "CMakeCache.txt");
  const std::string cache_text((std::istreambuf_iterator<char>(cache)),
                               std::istreambuf_iterator<char>());
  EXPECT_NE(cache_text.find("OpenMoPAD_DIR:PATH=" + (prefix / "lib/cmake/OpenMoPAD").string()),
            std::string::npos);
  MustRun(std::string(MOPAD_CMAKE) + " --build " + Quoted(build) + " -j2");
  ASSERT_TRUE(fs::exists(build / "frontier_explorer"));

  // The installed include roots hold the arrows: a target linking OpenMoPAD::modelling compiles
  // an include of modelling/ (positive control) and not one of sim/.
  const fs::path probe = work / "probe";
  MustRun(
      ConfigureAgainst(prefix, fs::path(MOPAD_SOURCE_DIR) / "tests/package/include_probe", probe));
  MustRun(std::string(MOPAD_CMAKE) + " --build " + Quoted(probe) +
          " --target robot_header_from_robot_side");
  const test_support::CommandResult truth =
      RunCommand(std::string(MOPAD_CMAKE) + " --build " + Quoted(probe) +
                 " --target truth_header_from_robot_side 2>&1");
  EXPECT_NE(truth.code, 0) << truth.out;
  EXPECT_NE(truth.out.find("sim/scene_world.h: No such file"), std::string::npos) << truth.out;

  // 3. A short run: three scans at a coarse step in the office's first room.
  const std::string printed =
      MustRun(Quoted(build / "frontier_explorer") + " --out " + Quoted(out) +
              " --max-scans 3 --step-deg 0.5 --time-budget 400");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      printed, m, std::regex(R"(explored: (\d+) scans \((\d+) registered\), ([0-9.]+) m)")))
      << printed;
  EXPECT_GE(std::stoi(m[1]), 2) << printed;  // it moved on from the first scan
  EXPECT_GE(std::stoi(m[2]), 2) << printed;  // and registered a later one
  EXPECT_GT(std::stod(m[3]), 0.5) << printed;
  EXPECT_NE(printed.find("scored: walls"), std::string::npos) << printed;

  // 4. The evaluator's figures: one room, its walls found, the model on the truth.
  std::ifstream f(out / "eval/evaluation.json");
  ASSERT_TRUE(f.good());
  const nlohmann::json summary = nlohmann::json::parse(f).at("summary");
  EXPECT_EQ(summary.at("rooms").get<int>(), 1);
  const auto& walls = summary.at("detection").at("wall");
  EXPECT_GE(walls.at("n_truth").get<int>(), 4);
  EXPECT_GE(walls.at("tp").get<int>(), 3) << summary.dump();
  EXPECT_GT(summary.at("isprs_completeness").get<double>(), 0.5) << summary.dump();
  EXPECT_GT(summary.at("isprs_correctness").get<double>(), 0.5) << summary.dump();
  EXPECT_GT(summary.at("floorplan_mean_iou").get<double>(), 0.7) << summary.dump();
  for (const char* file : {"run.json", "sm1.ply", "sm2.json", "sm3.json", "dsm3.ply"})
    EXPECT_TRUE(fs::exists(out / "room" / file)) << file;
}

}  // namespace
}  // namespace mopad
