#include "runfolder/layout.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace mopad::runfolder {

namespace fs = std::filesystem;

std::string Join(const std::string& dir, std::string_view name) {
  return (fs::path(dir) / fs::path(name)).string();
}

std::string RoomDir(const std::string& run_dir, const std::string& id) {
  return (fs::path(run_dir) / fs::path(kRoomsDir) / id).string();
}

std::vector<std::string> RoomFolders(const std::string& run_dir, std::string_view marker) {
  const fs::path root(run_dir);
  std::error_code ec;
  if (fs::exists(root / fs::path(marker), ec)) return {root.string()};
  std::vector<std::string> out;
  const fs::path rooms = root / fs::path(kRoomsDir);
  if (!fs::is_directory(rooms, ec)) return out;
  for (const auto& e : fs::directory_iterator(rooms, ec))
    if (e.is_directory(ec) && fs::exists(e.path() / fs::path(marker), ec))
      out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace mopad::runfolder
