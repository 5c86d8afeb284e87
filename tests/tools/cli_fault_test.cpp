// `mopad run` meeting the faults of its process rather than of its robot (docs/reliability.md,
// "Fault injection"): SIGTERM and SIGINT in the middle of a room, and an output folder that
// cannot take a file. Each ends in an explained status with every file already written whole,
// and `--resume` finishes the run. Whole runs of small scenes: ctest label `long`.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/tools/mopad_cli.h"

namespace {

namespace fs = std::filesystem;
using mopad::test_support::Mopad;
using mopad::test_support::RunFiles;
using mopad::test_support::Src;
using mopad::test_support::TempDir;

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// `mopad ARGS` in a child process (stdout and stderr into `log`), after `setup` ran in it.
pid_t StartMopad(const std::vector<std::string>& args, const std::string& log,
                 const std::function<void()>& setup = {}) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  if (!freopen(log.c_str(), "w", stdout)) _exit(127);
  dup2(fileno(stdout), fileno(stderr));
  if (setup) setup();
  std::vector<char*> argv{const_cast<char*>("mopad")};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  execv(MOPAD_BINARY, argv.data());
  _exit(127);
}

// Waits until the run has loaded its scene and printed it (`scene: ...` in its log): the job
// then begins its first room.
bool WaitForTheMission(const std::string& log, pid_t pid) {
  for (int k = 0; k < 2400; ++k) {
    usleep(50000);
    if (waitpid(pid, nullptr, WNOHANG) == pid) return false;
    std::ifstream f(log, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    if (text.find("scene: ") != std::string::npos) return true;
  }
  return false;
}

int ExitCodeOf(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

std::string ReadText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

// Every file of the folder is whole: each JSON parses, no temporary file is left.
void ExpectEveryFileWhole(const std::string& dir) {
  int json = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
    if (e.path().extension() != ".json") continue;
    ++json;
    EXPECT_FALSE(nlohmann::json::parse(ReadText(e.path().string()), nullptr, false).is_discarded())
        << e.path() << " does not parse";
  }
  EXPECT_GT(json, 0) << dir;
}

TEST(CliFaults, SigtermInTheFirstRoomStopsAfterItAndResumeFinishesTheRun) {
  const std::string d = TempDir("sigterm");
  const std::string spec = Src("scenes/two_rooms_door.yaml");
  const std::vector<std::string> args = {"run", "--spec", spec,      "--step-deg",
                                         "0.5", "-o",     d + "/run"};
  // The uninterrupted run writes to the same path (eval/ names its run folder), then moves aside.
  const pid_t whole = StartMopad(args, d + "/whole.log");
  ASSERT_EQ(ExitCodeOf(whole), 0) << ReadText(d + "/whole.log");
  fs::rename(d + "/run", d + "/whole");

  const pid_t pid = StartMopad(args, d + "/stopped.log");
  ASSERT_TRUE(WaitForTheMission(d + "/stopped.log", pid)) << ReadText(d + "/stopped.log");
  kill(pid, SIGTERM);
  EXPECT_EQ(ExitCodeOf(pid), 128 + SIGTERM);
  const std::string log = ReadText(d + "/stopped.log");
  EXPECT_NE(log.find("mopad: stopped by SIGTERM before all rooms were done"), std::string::npos)
      << log;
  EXPECT_NE(log.find("mopad run --resume " + d + "/run"), std::string::npos) << log;
  // The room in progress was finished and reported; the mission says why it ended there.
  const auto summary = ReadJson(d + "/run/summary.json");
  EXPECT_EQ(summary.at("rooms").size(), 1u);
  EXPECT_EQ(summary.at("rooms")[0].at("status"), "scanned");
  EXPECT_EQ(summary.at("mission").at("end_reason"),
            "stop: requested by the operator after 1 rooms");
  EXPECT_EQ(ReadJson(d + "/run/checkpoint/manifest.json").at("state"), "stopped");
  ExpectEveryFileWhole(d + "/run");

  const auto resumed = Mopad("run -q --resume " + d + "/run");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  EXPECT_EQ(ReadJson(d + "/run/checkpoint/manifest.json").at("state"), "complete");
  const auto a = RunFiles(d + "/whole"), b = RunFiles(d + "/run");
  ASSERT_GT(a.size(), 20u);
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name << " missing after the resume";
    EXPECT_TRUE(b.at(name) == bytes) << name << " differs after the resume";
  }
  EXPECT_EQ(a.size(), b.size());
}

TEST(CliFaults, SigintInPerRoomModeLeavesTheLaterRoomsNotRunAndResumeRunsThem) {
  const std::string d = TempDir("sigint");
  const std::vector<std::string> args = {"run",        "--spec",  Src("scenes/two_rooms_door.yaml"),
                                         "--step-deg", "0.5",     "--room",
                                         "R1",         "--room",  "R2",
                                         "-o",         d + "/run"};
  const pid_t pid = StartMopad(args, d + "/stopped.log");
  ASSERT_TRUE(WaitForTheMission(d + "/stopped.log", pid)) << ReadText(d + "/stopped.log");
  kill(pid, SIGINT);
  EXPECT_EQ(ExitCodeOf(pid), 128 + SIGINT);
  EXPECT_NE(ReadText(d + "/stopped.log").find("stopped by SIGINT"), std::string::npos);
  const auto summary = ReadJson(d + "/run/summary.json");
  ASSERT_EQ(summary.at("rooms").size(), 2u);
  EXPECT_EQ(summary.at("rooms")[0].at("status"), "scanned");
  EXPECT_EQ(summary.at("rooms")[1].at("status"), "not run");
  EXPECT_EQ(summary.at("rooms")[1].at("reason"),
            "not run: the operator stopped the job before this room");
  ExpectEveryFileWhole(d + "/run");

  const auto resumed = Mopad("run -q --resume " + d + "/run");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  const auto done = ReadJson(d + "/run/summary.json");
  ASSERT_EQ(done.at("rooms").size(), 2u);
  for (const auto& r : done.at("rooms")) EXPECT_EQ(r.at("status"), "scanned") << r.at("room");
}

// A file system that refuses a write (here: a file larger than RLIMIT_FSIZE allows, SIGXFSZ
// ignored, so write() fails with EFBIG as it fails with ENOSPC on a full disk) ends the run
// with one line naming the file; what was written before stays whole and `--resume` finishes.
TEST(CliFaults, AnOutputFolderThatRefusesAFileEndsNamingItAndResumeFinishesTheRun) {
  const std::string d = TempDir("full");
  const std::vector<std::string> args = {"run",        "-q", "--spec", Src("scenes/one_room.yaml"),
                                         "--step-deg", "2",  "-o",     d + "/run"};
  const pid_t pid = StartMopad(args, d + "/full.log", [] {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{1 << 20, 1 << 20};  // 1 MiB per file: the scene fits, a room's cloud not
    setrlimit(RLIMIT_FSIZE, &limit);
  });
  const int code = ExitCodeOf(pid);
  const std::string log = ReadText(d + "/full.log");
  EXPECT_GT(code, 0) << log;  // an exit code, not a signal
  EXPECT_NE(log.find("error: write failed; got File too large"), std::string::npos) << log;
  const auto line = log.find("mopad: " + d + "/run/");
  ASSERT_NE(line, std::string::npos) << "the error names the file: " << log;
  EXPECT_FALSE(fs::exists(d + "/run/summary.json"));
  EXPECT_EQ(ReadJson(d + "/run/checkpoint/manifest.json").at("state"), "running");
  ExpectEveryFileWhole(d + "/run");

  const auto resumed = Mopad("run -q --resume " + d + "/run");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  EXPECT_EQ(ReadJson(d + "/run/summary.json").at("rooms")[0].at("status"), "scanned");
}

}  // namespace
