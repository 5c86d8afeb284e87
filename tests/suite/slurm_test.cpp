// submit.sh of `mopad suite slurm` (suite/slurm.h) without a cluster: a stand-in `sbatch` on the
// PATH records its options and the job scripts it is fed, and the recorded job scripts are run
// with a stand-in `mopad` that records its arguments. The real Slurm run is
// tests/suite/slurm_local_test.sh (label `slurm`).
#include "suite/slurm.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/params.h"
#include "tests/process_temp_dir.h"

namespace {

namespace fs = std::filesystem;
using mopad::suite::SlurmJob;
using mopad::suite::SubmitScript;

std::string Read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

void WriteExecutable(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
  fs::permissions(p, fs::perms::owner_all);
}

int Shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A folder with stand-ins for sbatch and mopad, first on the PATH.
struct FakeCluster {
  fs::path dir;
  SlurmJob job;
  FakeCluster() {
    // A space and a quote in every path: the script must quote them.
    dir = mopad::test_support::ProcessTempDir("mopad_slurm_", " it's");
    fs::create_directories(dir / "bin");
    WriteExecutable(dir / "bin" / "sbatch",
                    "#!/usr/bin/env bash\n"
                    "n=$(cat \"$FAKE/count\" 2>/dev/null || echo 0); n=$((n + 1))\n"
                    "echo $n > \"$FAKE/count\"\n"
                    "printf '%s\\n' \"$@\" > \"$FAKE/args.$n\"\n"
                    "cat > \"$FAKE/script.$n\"\n"
                    "echo \"$((100 + n));cluster\"\n");
    WriteExecutable(dir / "mopad",
                    "#!/usr/bin/env bash\n"
                    "printf '%s\\n' \"$@\" > \"$FAKE/mopad.args\"\n"
                    "exit \"${FAKE_MOPAD_RC:-0}\"\n");
    setenv("FAKE", dir.c_str(), 1);
    setenv("PATH", ((dir / "bin").string() + ":" + std::getenv("PATH")).c_str(), 1);
    job.mopad = (dir / "mopad").string();
    job.suite = (dir / "smoke suite.yaml").string();
    job.out_dir = (dir / "out").string();
    job.params.shards = 3;
    job.params.throttle = 2;
    job.params.partition = "debug";
  }
  // Runs recorded job script `n` as Slurm would, with `env` set; its exit code.
  int RunJob(int n, const std::string& env) {
    return Shell(env + " bash " +
                 mopad::suite::ShellQuote((dir / ("script." + std::to_string(n))).string()));
  }
};

TEST(SlurmSubmit, ArrayOfShardsThenAMergeThatWaitsForIt) {
  FakeCluster f;
  const std::string script = SubmitScript(f.job);
  EXPECT_EQ(script, SubmitScript(f.job));  // deterministic
  const fs::path path = f.dir / "out" / "submit.sh";
  fs::create_directories(path.parent_path());
  std::ofstream(path) << script;
  const mopad::suite::SubmittedJobs ids = mopad::suite::RunSubmitScript(path.string());
  EXPECT_EQ(ids.array_id, "101");  // the cluster name after ';' is dropped
  EXPECT_EQ(ids.merge_id, "102");
  EXPECT_TRUE(fs::is_directory(f.dir / "out" / "logs"));

  const std::vector<std::string> array_args = Lines(Read(f.dir / "args.1"));
  const auto has = [](const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  };
  EXPECT_TRUE(has(array_args, "--parsable"));
  EXPECT_TRUE(has(array_args, "--array=0-2%2"));
  EXPECT_TRUE(has(array_args, "--partition=debug"));
  EXPECT_TRUE(has(array_args, "--output=" + (f.dir / "out" / "logs" / "%A_%a.out").string()));
  const std::vector<std::string> merge_args = Lines(Read(f.dir / "args.2"));
  EXPECT_TRUE(has(merge_args, "--dependency=afterok:101"));
  EXPECT_TRUE(has(merge_args, "--kill-on-invalid-dep=yes"));

  // Task 1 of the array is shard 2/3, into shards/1.
  EXPECT_EQ(f.RunJob(1, "SLURM_ARRAY_TASK_ID=1"), 0);
  EXPECT_EQ(
      Lines(Read(f.dir / "mopad.args")),
      (std::vector<std::string>{"suite", "run", f.job.suite, "-o", f.job.out_dir + "/shards/1",
                                "--shard", "2/3", "--jobs", "1"}));
  // A shard with a failed case (exit 1) is a finished task; bad input (2) is not.
  EXPECT_EQ(f.RunJob(1, "SLURM_ARRAY_TASK_ID=0 FAKE_MOPAD_RC=1"), 0);
  EXPECT_EQ(f.RunJob(1, "SLURM_ARRAY_TASK_ID=0 FAKE_MOPAD_RC=2"), 2);
  EXPECT_NE(f.RunJob(1, "env -u SLURM_ARRAY_TASK_ID"), 0);  // not in an array: refuses

  // The merge joins every shard, in order, into the suite folder.
  EXPECT_EQ(f.RunJob(2, ""), 0);
  EXPECT_EQ(Lines(Read(f.dir / "mopad.args")),
            (std::vector<std::string>{"suite", "merge", f.job.out_dir + "/shards/0",
                                      f.job.out_dir + "/shards/1", f.job.out_dir + "/shards/2",
                                      "-o", f.job.out_dir}));
}

TEST(SlurmSubmit, NoThrottleMeansAllShardsAndNoPartitionTheDefault) {
  FakeCluster f;
  f.job.params.throttle = 0;
  f.job.params.partition.clear();
  f.job.params.cpus_per_task = 4;
  const std::string s = SubmitScript(f.job);
  EXPECT_NE(s.find("--array=0-2%3 --cpus-per-task=4"), std::string::npos) << s;
  EXPECT_EQ(s.find("--partition"), std::string::npos);
  EXPECT_NE(s.find("--jobs 4"), std::string::npos);
}

TEST(SlurmSubmit, BadJobsAreRejectedBeforeAnythingIsWritten) {
  FakeCluster f;
  auto expect_error = [](SlurmJob j, const std::string& what) {
    try {
      SubmitScript(j);
      ADD_FAILURE() << "no error for " << what;
    } catch (const mopad::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  SlurmJob j = f.job;
  j.suite = "suites/smoke.yaml";
  expect_error(j, "not an absolute path");
  j = f.job;
  j.params.shards = 0;
  expect_error(j, "shards");
  j = f.job;
  j.params.throttle = 4;
  expect_error(j, "--throttle above --shards");
  j = f.job;
  j.params.partition = "a b;rm";
  expect_error(j, "not a partition name");
  EXPECT_TRUE(mopad::FieldsMissingFromVisit(mopad::suite::SlurmParams{}).empty());
}

TEST(SlurmSubmit, ShellQuoteSurvivesTheShell) {
  const fs::path dir = mopad::test_support::ProcessTempDir("mopad_quote_");
  for (const std::string s : {"plain", "it's", "a b", "$HOME `x` \"q\" \\ *", ""}) {
    EXPECT_EQ(Shell("printf %s " + mopad::suite::ShellQuote(s) + " > " +
                    mopad::suite::ShellQuote((dir / "q").string())),
              0);
    EXPECT_EQ(Read(dir / "q"), s);
  }
}

TEST(SlurmSubmit, WithoutSbatchSubmittingIsAClearError) {
  const std::string old = std::getenv("PATH");
  setenv("PATH", "/nonexistent", 1);
  EXPECT_THROW(mopad::suite::RunSubmitScript("/dev/null"), mopad::InputError);
  setenv("PATH", old.c_str(), 1);
}

}  // namespace
