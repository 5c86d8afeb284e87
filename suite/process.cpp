#include "suite/process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace mopad::suite {

namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Resident memory of `pid` in MB (VmRSS), 0 when unreadable.
double RssMb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) * 1024.0 / 1e6;
  return 0.0;
}

}  // namespace

ProcessPool::~ProcessPool() { KillAll(); }

void ProcessPool::Start(int tag, const ProcessSpec& spec) {
  std::vector<char*> argv;
  for (const auto& a : spec.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    // The child: only async-signal-safe calls until exec.
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(126);  // the runner died before prctl
    const int out = open(spec.stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(spec.stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0) _exit(127);
    dup2(out, 1);
    dup2(err, 2);
    close(out);
    close(err);
    const int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    execv(argv[0], argv.data());
    const char* msg = "mopad suite: cannot start the case's program: ";
    [[maybe_unused]] auto w = write(2, msg, std::strlen(msg));
    const char* why = std::strerror(errno);
    w = write(2, why, std::strlen(why));
    w = write(2, "\n", 1);
    _exit(127);
  }
  setpgid(pid, pid);  // also from the parent, so a kill right away reaches the group
  Child c;
  c.tag = tag;
  c.spec = spec;
  c.start = std::chrono::steady_clock::now();
  running_[pid] = c;
}

std::vector<std::pair<int, ProcessOutcome>> ProcessPool::Wait(double timeout_s) {
  std::vector<std::pair<int, ProcessOutcome>> done;
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    for (auto it = running_.begin(); it != running_.end();) {
      const pid_t pid = it->first;
      Child& c = it->second;
      int status = 0;
      rusage ru{};
      const pid_t r = wait4(pid, &status, WNOHANG, &ru);
      if (r == pid) {
        ProcessOutcome o;
        o.wall_s = Since(c.start);
        o.peak_rss_mb = std::max(c.peak_rss_mb, ru.ru_maxrss * 1024.0 / 1e6);
        if (c.kill_reason != ProcessOutcome::End::kExited) {
          o.end = c.kill_reason;
        } else if (WIFSIGNALED(status)) {
          o.end = ProcessOutcome::End::kSignalled;
          o.signal = WTERMSIG(status);
        } else {
          o.exit_code = WEXITSTATUS(status);
        }
        done.emplace_back(c.tag, o);
        it = running_.erase(it);
        continue;
      }
      if (c.kill_reason == ProcessOutcome::End::kExited) {
        const double rss = RssMb(pid);
        c.peak_rss_mb = std::max(c.peak_rss_mb, rss);
        if (c.spec.wall_limit_s > 0 && Since(c.start) > c.spec.wall_limit_s) {
          c.kill_reason = ProcessOutcome::End::kTimedOut;
          killpg(pid, SIGKILL);
        } else if (c.spec.memory_limit_mb > 0 && rss > c.spec.memory_limit_mb) {
          c.kill_reason = ProcessOutcome::End::kOverMemory;
          killpg(pid, SIGKILL);
        }
      }
      ++it;
    }
    if (!done.empty() || running_.empty() || Since(t0) >= timeout_s) return done;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

void ProcessPool::KillAll() {
  for (auto& [pid, c] : running_) killpg(pid, SIGKILL);
  for (auto& [pid, c] : running_) {
    int status = 0;
    waitpid(pid, &status, 0);
  }
  running_.clear();
}

std::string LastLine(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, last;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    // A progress line rewritten in place: its last version.
    if (auto cr = line.rfind('\r'); cr != std::string::npos) line = line.substr(cr + 1);
    if (!line.empty()) last = line;
  }
  return last;
}

}  // namespace mopad::suite
