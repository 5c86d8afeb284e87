#include "suite/merge.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "common/error.h"
#include "io/text_file.h"
#include "suite/case_result.h"
#include "suite/cases.h"
#include "suite/outputs.h"
#include "suite/runner.h"

namespace mopad::suite {

namespace fs = std::filesystem;

int MergeSuites(const std::vector<std::string>& dirs, const std::string& out, bool quiet) {
  if (dirs.empty()) throw InputError("mopad suite merge", "no suite folders given");
  std::string text, path;
  for (const std::string& d : dirs) {
    const fs::path copy = fs::path(d) / kManifestCopy;
    if (!fs::is_regular_file(copy))
      throw InputError(d, "not a suite folder", "", "a folder written by `mopad suite run`");
    const std::string t = io::ReadTextFile(copy.string());
    std::string p;
    const fs::path sj = fs::path(d) / "suite.json";
    if (fs::is_regular_file(sj))
      p = nlohmann::json::parse(io::ReadTextFile(sj.string())).value("manifest", "");
    if (text.empty()) {
      text = t;
      path = p;
    } else if (t != text) {
      throw InputError(d, "the folder's suite.manifest.yaml differs from " + dirs[0] + "'s", "",
                       "folders of one manifest");
    }
    if (path.empty()) path = p;
  }
  if (path.empty()) path = (fs::path(dirs[0]) / kManifestCopy).string();
  const Manifest m = ParseManifest(text, path);
  const std::vector<Case> cases = ExpandCases(m);

  std::map<std::string, std::string> source;  // case id -> the folder holding it
  for (const std::string& d : dirs)
    for (const Case& c : cases)
      if (fs::is_regular_file(fs::path(d) / "cases" / c.id / kCaseJson)) {
        if (source.count(c.id))
          throw InputError(d, "case " + c.id + " is finished in two folders", source[c.id] + " and " + d,
                           "each case in one folder (disjoint shards)");
        source[c.id] = d;
      }
  std::vector<std::string> missing;
  for (const Case& c : cases)
    if (!source.count(c.id)) missing.push_back(c.id);
  if (!missing.empty())
    throw InputError(out, std::to_string(missing.size()) + " of " + std::to_string(cases.size()) +
                              " cases are in none of the folders (first: " + missing[0] + ")",
                     "", "every shard's folder");

  fs::create_directories(fs::path(out) / "cases");
  const fs::path copy = fs::path(out) / kManifestCopy;
  if (fs::exists(copy) && io::ReadTextFile(copy.string()) != text)
    throw InputError(out, "the output folder holds another suite");
  io::WriteFileAtomically(copy.string(), text);
  std::vector<CaseResult> results;
  for (const Case& c : cases) {
    const fs::path from = fs::path(source[c.id]) / "cases" / c.id;
    const fs::path to = fs::path(out) / "cases" / c.id;
    if (fs::weakly_canonical(from) != fs::weakly_canonical(to)) {
      fs::remove_all(to);
      fs::create_directories(to.parent_path());
      fs::copy(from, to, fs::copy_options::recursive);
    }
    results.push_back(CaseResultFromJson(
        nlohmann::json::parse(io::ReadTextFile((to / kCaseJson).string())), (to / kCaseJson).string()));
  }
  for (const std::string& d : dirs) {  // made scenes (random floors, imports)
    const fs::path scenes = fs::path(d) / "scenes";
    if (!fs::is_directory(scenes)) continue;
    for (const auto& e : fs::directory_iterator(scenes)) {
      const fs::path to = fs::path(out) / "scenes" / e.path().filename();
      if (fs::exists(to) || fs::weakly_canonical(e.path()) == fs::weakly_canonical(to)) continue;
      fs::create_directories(to.parent_path());
      fs::copy(e.path(), to, fs::copy_options::recursive);
    }
  }
  const SuiteSummary s = WriteSuiteOutputs(out, m, results);
  if (!quiet)
    std::printf("merged %zu folders: %d cases, %d passed; wrote %s/{suite.json,junit.xml,"
                "scoreboard.md,scoreboard.html}\n",
                dirs.size(), s.totals.at("cases"), s.totals.at("passed"), out.c_str());
  return s.all_passed ? 0 : 1;
}

}  // namespace mopad::suite
