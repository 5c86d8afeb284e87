// `mopad dataset` end to end (evaluation/dataset.h, docs/dataset.md): a short run of one room,
// its dataset written twice (the same bytes), its files and figures checked here, and read back
// by the Python loader (python/mopad/dataset.py, python/tests/test_dataset.py) with Debian's
// python3, numpy and pytest (skipped without them).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/run_command.h"

namespace {

namespace fs = std::filesystem;
using mopad::test_support::RunCommand;

std::string TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("mopad_dataset_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Dataset, ARunsScansComeOutLabelledTheSameTwiceAndThePythonLoaderReadsThemBack) {
  const std::string d = TempDir("run");
  const std::string mopad = MOPAD_BINARY;
  const auto run = RunCommand(mopad + " run -q --spec " MOPAD_SOURCE_DIR
                              "/scenes/one_room.yaml --step-deg 0.5 -o " + d + "/run 2>&1");
  ASSERT_EQ(run.code, 0) << run.out;
  for (const char* out : {"/a", "/b"}) {
    const auto r = RunCommand(mopad + " dataset " + d + "/run -o " + d + out + " 2>&1");
    ASSERT_EQ(r.code, 0) << r.out;
  }
  std::ifstream in(d + "/a/dataset.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("format"), "mopad-dataset");
  ASSERT_FALSE(j.at("scans").empty());
  long long points = 0, unlabelled = 0;
  for (const auto& s : j.at("scans")) {
    const std::string file = s.at("file");
    EXPECT_EQ(Bytes(fs::path(d) / "a" / file), Bytes(fs::path(d) / "b" / file)) << file;
    points += s.at("points").get<long long>();
    if (s.at("semantic_histogram").contains("0"))
      unlabelled += s.at("semantic_histogram").at("0").get<long long>();
  }
  EXPECT_EQ(Bytes(fs::path(d) / "a" / "dataset.json"), Bytes(fs::path(d) / "b" / "dataset.json"));
  EXPECT_GT(points, 100000);
  EXPECT_LT(unlabelled, points / 100);
  EXPECT_TRUE(fs::exists(fs::path(d) / "a" / "truth.json"));

  // Bad input: one line, exit 2, nothing written.
  const auto bad = RunCommand(mopad + " dataset " + d + "/nothing -o " + d + "/c 2>&1");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_FALSE(fs::exists(fs::path(d) / "c"));

  const std::string py = "/usr/bin/python3";
  if (RunCommand(py + " -c 'import numpy, pytest' 2>&1").code != 0)
    GTEST_SKIP() << "Debian python3 with numpy and pytest absent (scripts/install-deps.sh --test)";
  const auto t = RunCommand("cd " MOPAD_SOURCE_DIR " && PYTHONPATH=" MOPAD_SOURCE_DIR
                            "/python MOPAD_RUN_DIR=" + d + "/run MOPAD_DATASET_DIR=" + d +
                            "/a " + py + " -m pytest -q -p no:cacheprovider python/tests 2>&1");
  EXPECT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("2 passed"), std::string::npos) << t.out;
}

}  // namespace
