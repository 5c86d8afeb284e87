#pragma once
// Runs a shell command and keeps what it printed and its exit code: the CLI tests' runner.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace mopad::test_support {

struct CommandResult {
  int code = -1;    ///< the exit code; -1 when the command could not run or died of a signal
  std::string out;  ///< what it wrote to stdout (add " 2>&1" to the command for stderr too)
};

/// Runs `command` through /bin/sh (popen) and waits for it.
inline CommandResult RunCommand(const std::string& command) {
  CommandResult r;
  FILE* p = popen(command.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace mopad::test_support
