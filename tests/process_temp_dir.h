#pragma once
// Scratch folders of one test process, removed when it exits normally: ctest runs every test
// case in a process of its own, and folders named by the process id otherwise pile up in the
// temp folder run after run. MOPAD_KEEP_TEST_DIRS=1 keeps them for a look.

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <set>
#include <string>
#include <system_error>

namespace mopad::test_support {

/// `temp/<prefix><pid><suffix>`, created (emptied first when `fresh`) and removed at exit.
inline std::filesystem::path ProcessTempDir(const std::string& prefix,
                                            const std::string& suffix = "", bool fresh = true) {
  struct Registry {
    std::mutex mutex;
    std::set<std::filesystem::path> dirs;
    ~Registry() {
      const char* keep = std::getenv("MOPAD_KEEP_TEST_DIRS");
      if (keep && std::string(keep) == "1") return;
      std::error_code ec;
      for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
    }
  };
  static Registry registry;
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() /
      (prefix + std::to_string(static_cast<long>(::getpid())) + suffix);
  {
    const std::lock_guard<std::mutex> lock(registry.mutex);
    if (registry.dirs.insert(d).second || fresh) std::filesystem::remove_all(d);
  }
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace mopad::test_support
