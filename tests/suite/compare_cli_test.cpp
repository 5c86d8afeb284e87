// `mopad suite compare` and `mopad suite slurm` end to end: exit codes (0 no regression, 1 a
// regression beyond noise, 2 bad input), the files written and the messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/process_temp_dir.h"
#include "tests/run_command.h"
#include "tests/suite/synthetic_suite.h"

namespace {

namespace fs = std::filesystem;
using mopad::test_support::Group;
using mopad::test_support::Suite;
using nlohmann::json;

using Result = mopad::test_support::CommandResult;  // out: stdout and stderr together

Result Mopad(const std::string& args) {
  return mopad::test_support::RunCommand(std::string(MOPAD_BINARY) + " " + args + " 2>&1");
}

std::string Read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// 's' (the test's paths hold no quote).
std::string Quoted(const std::string& s) { return std::string(1, '\'') + s + '\''; }

fs::path Dir(const std::string& name) {
  return mopad::test_support::ProcessTempDir("mopad_suite_cli_", "_" + name);
}

std::string WriteSuite(const std::string& name, const json& suite) {
  const fs::path d = Dir(name);
  std::ofstream(d / "suite.json") << suite.dump(1);
  return d.string();
}

TEST(SuiteCompareCli, SameCodeOtherSeedsExitsZeroAndWritesBothReports) {
  const std::string base = WriteSuite("base", Suite({Group("office", 1, 10, 0.9, 0.01)}));
  const std::string next = WriteSuite("new", Suite({Group("office", 11, 10, 0.9, 0.01)}));
  const fs::path out = Dir("out") / "cmp";
  const Result r = Mopad("suite compare " + base + " " + next + " -o " + out.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("No regression beyond noise"), std::string::npos) << r.out;
  EXPECT_EQ(Read(out / "compare.md"), r.out + "\n");
  const json j = json::parse(Read(out / "compare.json"));
  EXPECT_EQ(j["summary"]["regressed"], false);
  EXPECT_EQ(j["figures"].size(), 3u);
}

TEST(SuiteCompareCli, ARegressionBeyondNoiseExitsOne) {
  const std::string base = WriteSuite("base", Suite({Group("office", 1, 10, 0.9, 0.01)}));
  const std::string next = WriteSuite("new", Suite({Group("office", 11, 10, 0.8, 0.01)}));
  const Result r = Mopad("suite compare " + base + " " + next);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("**Regression beyond noise**: 1 figure(s)"), std::string::npos) << r.out;
  const std::size_t table = r.out.find("## Regressions"), end = r.out.find("## Improvements");
  const std::size_t row = r.out.find("| office | sm5_tp |", table);
  EXPECT_LT(row, end) << r.out;  // the TP's row in the regressions' table
  EXPECT_NE(r.out.find("| regression |", row), std::string::npos) << r.out;
  // A looser minimum effect (20 % of the mean) lets the 0.1 drop pass.
  EXPECT_EQ(Mopad("suite compare " + base + " " + next + " --min-effect 0.2").code, 0);
}

TEST(SuiteCompareCli, BadInputExitsTwoWithTheFileNamed) {
  const std::string base = WriteSuite("base", Suite({Group("office", 1, 3, 0.9, 0.01)}));
  const fs::path empty = Dir("empty");
  Result r = Mopad("suite compare " + base + " " + empty.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find((empty / "suite.json").string()), std::string::npos) << r.out;
  std::ofstream(empty / "suite.json") << "[1, 2";
  r = Mopad("suite compare " + base + " " + empty.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("not valid JSON"), std::string::npos) << r.out;
  r = Mopad("suite compare " + base + " " + base + " --alpha 0.7");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("alpha"), std::string::npos) << r.out;
}

TEST(SuiteSlurmCli, WritesSubmitShWithAbsolutePathsWithoutSubmitting) {
  const fs::path d = Dir("slurm");
  std::ofstream(d / "tiny.yaml") << "name: tiny\n";
  const Result r = Mopad("suite slurm " + (d / "tiny.yaml").string() + " -o " + (d / "B").string() +
                         " --shards 2 --throttle 1");
  EXPECT_EQ(r.code, 0) << r.out;
  const std::string s = Read(d / "B" / "submit.sh");
  const std::string run = Quoted(fs::canonical(MOPAD_BINARY).string()) + " suite run " +
                          Quoted((d / "tiny.yaml").string());
  EXPECT_NE(s.find(run), std::string::npos) << s;
  EXPECT_NE(s.find("--array=0-1%1"), std::string::npos) << s;
  EXPECT_FALSE(fs::exists(d / "B" / "shards"));  // nothing ran
  EXPECT_EQ((fs::status(d / "B" / "submit.sh").permissions() & fs::perms::owner_exec),
            fs::perms::owner_exec);
}

TEST(SuiteSlurmCli, BadOptionsExitTwoBeforeWriting) {
  const fs::path d = Dir("slurm_bad");
  Result r = Mopad("suite slurm " + (d / "absent.yaml").string() + " -o " + (d / "B").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("no such suite manifest"), std::string::npos) << r.out;
  std::ofstream(d / "tiny.yaml") << "name: tiny\n";
  r = Mopad("suite slurm " + (d / "tiny.yaml").string() + " -o " + (d / "B").string() +
            " --shards 2 --throttle 3");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_FALSE(fs::exists(d / "B"));
}

}  // namespace
