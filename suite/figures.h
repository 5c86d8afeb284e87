#pragma once
// A case's figures (docs/suites.md, "Figures"): the one table of named main figures (what
// the scoreboard shows and `mopad suite compare` judges: direction and unit), and dotted paths
// into the run folder's files, `summary.<path>` (summary.json) and `eval.<path>`
// (eval/evaluation.json), for any number a check needs. Per-class SM5 figures
// `sm5_class.<class>.<field>` (the paper's Table 3) come with every case whose evaluation has
// them.
//
// Timings (wall time, peak memory, bytes written) are measured by the runner and kept in the
// case's own fields (wall_s, peak_rss_mb, bytes_written), never among the figures: the figures
// of a case are the same bytes on every machine and at every --jobs.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "suite/checks.h"

namespace mopad::suite {

/// A named figure's meaning for tables and comparisons.
struct FigureInfo {
  std::string name;
  std::string better;  ///< "higher" | "lower" | "none"
  std::string unit;    ///< "m", "m2", "deg", "s", "" (counts and shares)
  std::string label;   ///< short column title
};

/// The named main figures, in scoreboard order.
const std::vector<FigureInfo>& MainFigures();

/// The info of any figure name: a main figure's, a class figure's, else better "none", unit "".
FigureInfo InfoOf(const std::string& name);

/// What a case's figures are read from.
struct CaseFiles {
  nlohmann::json summary;            ///< summary.json (null when missing)
  nlohmann::json eval;               ///< eval/evaluation.json (null when missing)
  std::optional<int> rooms_reachable;  ///< from the truth (suite/reachable_rooms.h)
};

/// Reads the run folder `dir` (summary.json, eval/evaluation.json) and the scene truth
/// `truth_path` ("" or missing: no reachability figures). Missing or unreadable files leave
/// their part null.
CaseFiles ReadCaseFiles(const std::string& dir, const std::string& truth_path);

/// A number at a dotted path ("a.b.3.c": keys, and indices into lists); booleans are 0/1.
std::optional<double> NumberAt(const nlohmann::json& j, const std::string& path);

/// The case's figures: every main figure the files give, the per-class SM5 figures, and each
/// dotted path in `paths` (summary.X / eval.X) that resolves.
Figures ExtractFigures(const CaseFiles& f, const std::vector<std::string>& paths);

}  // namespace mopad::suite
