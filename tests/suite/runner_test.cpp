// The runner with fake commands in place of missions: a case's "run" is a /bin/sh line that
// writes a summary.json, exits 2 with a message, sleeps past its limit or kills itself.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "common/error.h"
#include "io/text_file.h"
#include "suite/merge.h"
#include "suite/process.h"
#include "suite/runner.h"
#include "tests/process_temp_dir.h"

namespace mopad::suite {
namespace {

namespace fs = std::filesystem;

const char* kManifest = R"(suite: fake
scenes:
  - spec: good.yaml
  - spec: bad.yaml
  - spec: slow.yaml
    limits: {wall_s: 1}
  - spec: crash.yaml
  - spec: low.yaml
seeds: 1-2
checks:
  - scans >= 3
  - mean(scans) >= 3
)";

// good: scans 3 + seed (passes); low: scans 1 (fails); bad: exit 2 with a message; slow:
// sleeps 30 s (1 s limit); crash: SIGKILL to itself. Each run appends its id to DIR/cases/runs.log.
std::vector<std::string> FakeCommand(const Case& c, const std::string& dir) {
  const std::string scene = c.id.substr(0, c.id.find('/'));
  std::string sh = "echo " + c.id + " >> \"$0/../../runs.log\"; ";
  if (scene == "good" || scene == "low") {
    const int scans = scene == "good" ? 3 + static_cast<int>(c.seed) : 1;
    sh += "printf '{\"mission\": {\"scans\": " + std::to_string(scans) +
          ", \"contacts\": 0}}' > \"$0/summary.json\"";
  } else if (scene == "bad") {
    sh += "echo 'scene: loading' >&2; echo 'mopad: bad.yaml:3: error: unknown key' >&2; exit 2";
  } else if (scene == "slow") {
    sh += "exec sleep 30";
  } else {
    sh += "kill -9 $$";
  }
  return {"/bin/sh", "-c", sh, dir};
}

RunOptions Options(const fs::path& out, int jobs = 1) {
  RunOptions o;
  o.out_dir = out.string();
  o.jobs = jobs;
  o.quiet = true;
  o.command = FakeCommand;
  return o;
}

// A file with the measured fields (and junit's times) blanked.
std::string Stripped(const fs::path& p) {
  std::string t = io::ReadTextFile(p.string());
  t = std::regex_replace(t, std::regex(R"re("(wall_s|peak_rss_mb|bytes_written)": [0-9.e+\-]+)re"),
                         "\"$1\": 0");
  return std::regex_replace(t, std::regex(R"( time="[0-9.]+")"), "");
}

int RunCount(const fs::path& out, const std::string& id) {
  std::ifstream in(out / "cases" / "runs.log");
  std::string line;
  int n = 0;
  while (std::getline(in, line)) n += line == id;
  return n;
}

TEST(SuiteRunner, EveryVerdictKindAndTheOtherCasesFinish) {
  const fs::path out = test_support::ProcessTempDir("mopad_suite_verdicts_");
  const Manifest m = ParseManifest(kManifest, "fake.yaml");
  EXPECT_EQ(RunSuite(m, Options(out, 3)), 1);
  const nlohmann::json j = nlohmann::json::parse(io::ReadTextFile((out / "suite.json").string()));
  std::map<std::string, nlohmann::json> byid;
  for (const auto& c : j["cases"]) byid[c["id"]] = c;
  ASSERT_EQ(byid.size(), 10u);
  EXPECT_EQ(byid["good/seed-1"]["verdict"], "passed");
  EXPECT_EQ(byid["good/seed-2"]["figures"]["scans"], 5);
  EXPECT_EQ(byid["low/seed-1"]["verdict"], "failed");
  EXPECT_EQ(byid["low/seed-1"]["message"], "check 'scans >= 3': 1 not >= 3");
  EXPECT_EQ(byid["low/seed-1"]["checks"][0]["value"], 1);
  EXPECT_EQ(byid["low/seed-1"]["checks"][0]["bound"], 3);
  EXPECT_EQ(byid["bad/seed-1"]["verdict"], "error");
  EXPECT_EQ(byid["bad/seed-1"]["message"],
            "input error (exit 2): mopad: bad.yaml:3: error: unknown key");
  EXPECT_EQ(byid["slow/seed-2"]["verdict"], "timeout");
  EXPECT_LT(byid["slow/seed-2"]["wall_s"].get<double>(), 10.0);
  EXPECT_EQ(byid["crash/seed-1"]["verdict"], "crashed");
  EXPECT_NE(byid["crash/seed-1"]["message"].get<std::string>().find("signal 9"), std::string::npos);
  EXPECT_EQ(j["totals"]["passed"], 2);
  EXPECT_EQ(j["totals"]["failed"], 2);
  EXPECT_EQ(j["totals"]["error"], 2);
  EXPECT_EQ(j["totals"]["timeout"], 2);
  EXPECT_EQ(j["totals"]["crashed"], 2);
  // Pooled, per group in manifest order: good's mean scans 4.5 passes, low's 1 fails, and the
  // groups without the figure fail with value null.
  ASSERT_EQ(j["pooled_checks"].size(), 5u);
  EXPECT_EQ(j["pooled_checks"][0]["group"], "good");
  EXPECT_TRUE(j["pooled_checks"][0]["passed"].get<bool>());
  EXPECT_EQ(j["pooled_checks"][0]["value"], 4.5);
  EXPECT_EQ(j["pooled_checks"][1]["group"], "bad");
  EXPECT_TRUE(j["pooled_checks"][1]["value"].is_null());
  EXPECT_EQ(j["pooled_checks"][4]["group"], "low");
  EXPECT_FALSE(j["pooled_checks"][4]["passed"].get<bool>());
  EXPECT_TRUE(fs::is_regular_file(out / "cases/good/seed-1/case.json"));
  EXPECT_TRUE(fs::is_regular_file(out / "scoreboard.md"));
  EXPECT_NE(io::ReadTextFile((out / "scoreboard.html").string()).find("<svg"), std::string::npos);
}

TEST(SuiteRunner, JunitIsWellFormedWithAFailureOrErrorPerCase) {
  const fs::path out = test_support::ProcessTempDir("mopad_suite_junit_");
  EXPECT_EQ(RunSuite(ParseManifest(kManifest, "fake.yaml"), Options(out, 2)), 1);
  const std::string x = io::ReadTextFile((out / "junit.xml").string());
  EXPECT_NE(x.find("tests=\"10\" failures=\"2\" errors=\"6\""), std::string::npos);
  int failures = 0, errors = 0;
  for (std::size_t p = 0; (p = x.find("<failure ", p)) != std::string::npos; ++p) ++failures;
  for (std::size_t p = 0; (p = x.find("<error ", p)) != std::string::npos; ++p) ++errors;
  EXPECT_EQ(failures, 2);
  EXPECT_EQ(errors, 6);
  if (!fs::exists("/usr/bin/xmllint")) GTEST_SKIP() << "xmllint not installed (libxml2-utils)";
  const std::string cmd = "/usr/bin/xmllint --noout '" + (out / "junit.xml").string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 0) << "xmllint rejects junit.xml";
}

TEST(SuiteRunner, OutputsDoNotDependOnJobs) {
  const fs::path a = test_support::ProcessTempDir("mopad_suite_jobs1_");
  const fs::path b = test_support::ProcessTempDir("mopad_suite_jobs4_");
  const Manifest m = ParseManifest(kManifest, "fake.yaml");
  RunSuite(m, Options(a, 1));
  RunSuite(m, Options(b, 4));
  for (const char* f : {"suite.json", "junit.xml", "scoreboard.md"})
    EXPECT_EQ(Stripped(a / f), Stripped(b / f)) << f;
}

TEST(SuiteRunner, MergedShardsEqualTheSingleRun) {
  const fs::path root = test_support::ProcessTempDir("mopad_suite_shards_");
  const Manifest m = ParseManifest(kManifest, "fake.yaml");
  RunSuite(m, Options(root / "single", 2));
  std::vector<std::string> shards;
  for (int i = 1; i <= 3; ++i) {
    RunOptions o = Options(root / ("shard" + std::to_string(i)), 2);
    o.shard = Shard{i, 3};
    RunSuite(m, o);
    shards.push_back(o.out_dir);
  }
  EXPECT_THROW(MergeSuites({shards[0], shards[1]}, (root / "partial").string(), true), InputError);
  EXPECT_EQ(MergeSuites(shards, (root / "merged").string(), true), 1);
  for (const char* f : {"suite.json", "junit.xml", "scoreboard.md", "scoreboard.html"})
    EXPECT_EQ(Stripped(root / "single" / f), Stripped(root / "merged" / f)) << f;
  EXPECT_TRUE(fs::is_regular_file(root / "merged/cases/crash/seed-2/suite.stderr.log"));
  EXPECT_THROW(MergeSuites({shards[0], shards[0], shards[1], shards[2]}, (root / "twice").string(), true),
               InputError);
}

TEST(SuiteRunner, ResumeRerunsOnlyUnfinishedCases) {
  const fs::path out = test_support::ProcessTempDir("mopad_suite_resume_");
  const Manifest m = ParseManifest(kManifest, "fake.yaml");
  RunSuite(m, Options(out, 2));
  const std::string before = Stripped(out / "suite.json");
  // An unfinished case: its folder without case.json (the runner was killed while it ran).
  fs::remove(out / "cases/good/seed-2/case.json");
  fs::remove(out / "suite.json");
  EXPECT_THROW(RunSuite(m, Options(out, 2)), InputError);  // results there, no --resume
  RunOptions o = Options(out, 2);
  o.resume = true;
  EXPECT_EQ(RunSuite(m, o), 1);
  EXPECT_EQ(RunCount(out, "good/seed-2"), 2);
  for (const char* id : {"good/seed-1", "bad/seed-1", "slow/seed-1", "crash/seed-2", "low/seed-2"})
    EXPECT_EQ(RunCount(out, id), 1) << id;
  EXPECT_EQ(Stripped(out / "suite.json"), before);
  // Another manifest in the same folder: refused.
  const Manifest other = ParseManifest(std::string(kManifest) + "\n", "fake.yaml");
  EXPECT_THROW(RunSuite(other, o), InputError);
}

TEST(SuiteProcess, AMemoryHogIsKilledAtItsLimit) {
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const fs::path d = test_support::ProcessTempDir("mopad_suite_mem_");
  ProcessPool pool;
  ProcessSpec p;
  p.argv = {"/usr/bin/python3", "-c",
            "import time\nb = bytearray(400 * 1000 * 1000)\nfor i in range(0, len(b), 4096): "
            "b[i] = 1\ntime.sleep(20)"};
  p.stdout_path = (d / "out").string();
  p.stderr_path = (d / "err").string();
  p.memory_limit_mb = 100;
  p.wall_limit_s = 15;
  pool.Start(7, p);
  std::vector<std::pair<int, ProcessOutcome>> done;
  while (done.empty()) done = pool.Wait(1.0);
  EXPECT_EQ(done[0].first, 7);
  EXPECT_EQ(done[0].second.end, ProcessOutcome::End::kOverMemory);
  EXPECT_GT(done[0].second.peak_rss_mb, 100.0);
}

TEST(SuiteProcess, AMissingProgramIsExitCode127WithTheReason) {
  const fs::path d = test_support::ProcessTempDir("mopad_suite_noexec_");
  ProcessPool pool;
  ProcessSpec p;
  p.argv = {"/nonexistent/mopad", "run"};
  p.stdout_path = (d / "out").string();
  p.stderr_path = (d / "err").string();
  pool.Start(1, p);
  std::vector<std::pair<int, ProcessOutcome>> done;
  while (done.empty()) done = pool.Wait(1.0);
  EXPECT_EQ(done[0].second.exit_code, 127);
  EXPECT_NE(LastLine(p.stderr_path).find("No such file"), std::string::npos);
}

}  // namespace
}  // namespace mopad::suite
