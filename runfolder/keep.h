#pragma once
// How much of a finished run folder to keep (`mopad run --keep`, `mopad suite run --keep`;
// docs/suites.md, "Keep levels"). By kind of file, so that it holds for every file a run
// writes, now and later:
//
//   summary  the records and reports: JSON, YAML, Markdown, HTML, SVG (summary.json, eval/,
//            report.html/.md, run.json, the rooms' model JSON sm2-sm5, effective configs)
//   models   + the binary deliverables and images: glTF (.glb), IFC, PNG, TUM trajectories
//   all      + the point clouds (.ply, .las): everything (the default of `mopad run`)
//
// Log files and anything else not named above are kept at every level.

#include <cstdint>
#include <string>

namespace mopad::runfolder {

enum class KeepLevel { kSummary, kModels, kAll };

/// "summary" | "models" | "all"; InputError naming `option` otherwise.
KeepLevel ParseKeepLevel(const std::string& text, const std::string& option = "--keep");
const char* ToString(KeepLevel level);

/// Whether a file named `path` stays at `level` (by its extension).
bool Keeps(KeepLevel level, const std::string& path);

/// Removes, under `dir`, every file `level` does not keep, and the folders left empty.
/// Returns the bytes removed.
std::uintmax_t PruneRunFolder(const std::string& dir, KeepLevel level);

}  // namespace mopad::runfolder
