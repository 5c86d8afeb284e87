#pragma once
// The CLI tests' helpers: the `mopad` binary under test (MOPAD_BINARY) run with arguments, the
// source tree's files, per-process scratch folders, and a run folder's files as a resume
// compares them.

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/process_temp_dir.h"
#include "tests/run_command.h"

namespace mopad::test_support {

/// `mopad ARGS`, stdout and stderr together in `out`.
inline CommandResult Mopad(const std::string& args) {
  return RunCommand(std::string(MOPAD_BINARY) + " " + args + " 2>&1");
}

/// A file of the source tree.
inline std::string Src(const std::string& rel) { return std::string(MOPAD_SOURCE_DIR) + "/" + rel; }

/// Per process: ctest runs each test case in its own process, possibly in parallel.
inline std::string TempDir(const std::string& name) {
  return ProcessTempDir("mopad_cli_", "_" + name).string();
}

/// The wall-clock timings a resumed run may write differently (docs/floor-mission.md, Resume).
inline nlohmann::json WithoutTimings(nlohmann::json j) {
  if (j.is_array())
    for (auto& x : j) x = WithoutTimings(x);
  if (!j.is_object()) return j;
  for (const char* key :
       {"seconds", "wall_time", "wall_time_s", "tls_wall_time_s", "sm4_seconds", "sm5_seconds"})
    j.erase(key);
  for (auto& [k, v] : j.items()) v = WithoutTimings(v);
  return j;
}

/// Every file of a run folder (checkpoint/ aside), JSON without its timings, the reports
/// without their Timing table.
inline std::map<std::string, std::string> RunFiles(const std::string& dir) {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).generic_string();
    if (rel.rfind("checkpoint/", 0) == 0) continue;
    std::ifstream f(e.path(), std::ios::binary);
    std::string s((std::istreambuf_iterator<char>(f)), {});
    if (e.path().extension() == ".json") s = WithoutTimings(nlohmann::json::parse(s)).dump(1);
    for (const char* timing : {"## Timing", "<h2>Timing</h2>"})
      if (const auto at = s.find(timing); at != std::string::npos) {
        const auto end = s.find(timing[0] == '#' ? "\n#" : "</table>", at + 1);
        s.erase(at, end == std::string::npos ? std::string::npos : end - at);
      }
    out[rel] = std::move(s);
  }
  return out;
}

}  // namespace mopad::test_support
