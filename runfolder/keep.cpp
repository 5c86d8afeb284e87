#include "runfolder/keep.h"

#include <algorithm>
#include <filesystem>
#include <set>
#include <vector>

#include "common/error.h"

namespace mopad::runfolder {

namespace fs = std::filesystem;

namespace {

const std::set<std::string> kClouds = {".ply", ".las"};
const std::set<std::string> kModels = {".glb", ".ifc", ".png", ".tum"};

std::string Extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

}  // namespace

KeepLevel ParseKeepLevel(const std::string& text, const std::string& option) {
  if (text == "summary") return KeepLevel::kSummary;
  if (text == "models") return KeepLevel::kModels;
  if (text == "all") return KeepLevel::kAll;
  throw InputError(option, "bad keep level", "'" + text + "'", "summary, models or all");
}

const char* ToString(KeepLevel level) {
  switch (level) {
    case KeepLevel::kSummary: return "summary";
    case KeepLevel::kModels: return "models";
    default: return "all";
  }
}

bool Keeps(KeepLevel level, const std::string& path) {
  const std::string e = Extension(path);
  if (kClouds.count(e)) return level == KeepLevel::kAll;
  if (kModels.count(e)) return level != KeepLevel::kSummary;
  return true;
}

std::uintmax_t PruneRunFolder(const std::string& dir, KeepLevel level) {
  if (level == KeepLevel::kAll) return 0;
  std::uintmax_t removed = 0;
  std::vector<fs::path> files, dirs;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (it->is_directory(ec)) dirs.push_back(it->path());
    else if (it->is_regular_file(ec) && !Keeps(level, it->path().string())) files.push_back(it->path());
  }
  std::set<fs::path> emptied;  // folders that lost a file, and their parents up to `dir`
  for (const auto& f : files) {
    const auto size = fs::file_size(f, ec);
    if (!fs::remove(f, ec)) continue;
    removed += size;
    for (fs::path d = f.parent_path(); d != fs::path(dir) && d.has_relative_path();
         d = d.parent_path())
      emptied.insert(d);
  }
  // Deepest first, so a folder emptied by its children's removal goes too.
  std::sort(dirs.begin(), dirs.end(), [](const fs::path& a, const fs::path& b) {
    return a.string().size() > b.string().size();
  });
  for (const auto& d : dirs)
    if (emptied.count(d) && fs::is_empty(d, ec)) fs::remove(d, ec);
  return removed;
}

}  // namespace mopad::runfolder
