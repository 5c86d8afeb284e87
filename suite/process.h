#pragma once
// Child processes of the suite runner (POSIX, Linux): each case's command runs in its own
// process and process group, stdout and stderr to files, with a wall-time limit (the group
// is killed with SIGKILL when it runs over) and a resident-memory limit (polled from
// /proc/<pid>/status every poll; over it, the group is killed). The child dies with the
// runner (PR_SET_PDEATHSIG), so a killed runner leaves no orphan writing into a case folder.
// Not thread-safe: one ProcessPool per thread.

#include <sys/types.h>

#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace mopad::suite {

struct ProcessSpec {
  std::vector<std::string> argv;  ///< argv[0] is the program (a path; no PATH search)
  std::string stdout_path;        ///< file for stdout (truncated)
  std::string stderr_path;        ///< file for stderr (truncated)
  double wall_limit_s = 0.0;      ///< s, 0 = none
  double memory_limit_mb = 0.0;   ///< MB (10^6 bytes) resident, 0 = none
};

struct ProcessOutcome {
  enum class End { kExited, kSignalled, kTimedOut, kOverMemory };
  End end = End::kExited;
  int exit_code = 0;         ///< kExited
  int signal = 0;            ///< kSignalled
  double wall_s = 0.0;       ///< s, start to end
  double peak_rss_mb = 0.0;  ///< MB, the largest of the kernel's maximum RSS and the polls
};

/// Runs processes concurrently; the caller starts them and collects their ends.
class ProcessPool {
 public:
  ProcessPool() = default;
  ProcessPool(const ProcessPool&) = delete;
  ProcessPool& operator=(const ProcessPool&) = delete;
  ~ProcessPool();  ///< kills what still runs

  /// Starts `spec` under `tag` (the caller's key). Throws std::runtime_error when fork fails;
  /// an exec failure is the child's exit code 127 with the reason on its stderr.
  void Start(int tag, const ProcessSpec& spec);
  /// Waits up to `timeout_s` for ends; enforces the limits meanwhile. (tag, outcome) pairs.
  std::vector<std::pair<int, ProcessOutcome>> Wait(double timeout_s);
  std::size_t Running() const { return running_.size(); }
  /// SIGKILL to every running group, and reaps them.
  void KillAll();

 private:
  struct Child {
    int tag = 0;
    ProcessSpec spec;
    std::chrono::steady_clock::time_point start;
    double peak_rss_mb = 0.0;
    ProcessOutcome::End kill_reason = ProcessOutcome::End::kExited;  ///< set when we kill it
  };
  std::map<pid_t, Child> running_;
};

/// The last non-empty line of a text file ("" when none or unreadable).
std::string LastLine(const std::string& path);

}  // namespace mopad::suite
