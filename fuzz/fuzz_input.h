#pragma once
// Shared by the libFuzzer targets (docs/reliability.md): the input as a string or
// as a file (readers that take a path), and the one rule of every target: InputError is a clean
// reject; any other exception escapes and libFuzzer reports it (as it reports crashes, leaks,
// sanitizer findings and hangs).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "common/error.h"

namespace mopad::fuzz {

inline std::string AsString(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Writes the input to `<tmp>/mopad_fuzz_<pid>_<name>` (one file per process, rewritten each
/// run) and returns its path: for the readers the CLI gives a path.
inline std::string AsFile(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp && *tmp ? tmp : "/tmp") + "/mopad_fuzz_" +
                           std::to_string(::getpid()) + "_" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();  // the harness itself failed: stop loudly
  if (size && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

/// Runs `f`; InputError (bad input, reported to the user as exit 2) is the expected reject.
template <class F>
int Run(F&& f) {
  try {
    f();
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace mopad::fuzz
