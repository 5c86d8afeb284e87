#pragma once
// `mopad suite run` (docs/suites.md): each case of the manifest (of this shard) runs in its own
// process, `mopad run ... -o DIR/cases/<id>` (the program running the suite, /proc/self/exe),
// up to `jobs` at a time; when a case ends its verdict is classified and DIR/cases/<id>/case.json
// written atomically, so a runner killed at any moment loses only the cases that were running
// and `resume` reruns just those. Random floors and BIM imports are made once per suite folder
// (DIR/scenes/<name>/) before their cases. The result files (suite/outputs.h) depend on the
// case results alone: not on jobs, the finishing order or the shard split.

#include <functional>
#include <string>
#include <vector>

#include "suite/case_result.h"
#include "suite/cases.h"
#include "suite/manifest.h"
#include "suite/process.h"

namespace mopad::suite {

struct RunOptions {
  std::string out_dir;           ///< DIR
  int jobs = 1;                  ///< cases at a time, >= 1
  Shard shard;                   ///< the cases of this shard only
  bool resume = false;           ///< keep finished cases of DIR, rerun the others
  std::string keep;              ///< `--keep` of the cases ("" = the manifest's)
  std::string program = "/proc/self/exe";  ///< the mopad binary the cases run
  bool progress = false;         ///< a live progress line (a terminal)
  bool quiet = false;            ///< no per-case lines
  /// Tests: the command of a case instead of `program run ...` (empty: the real one).
  std::function<std::vector<std::string>(const Case&, const std::string& case_dir)> command;
};

/// Runs the suite; returns the exit code: 0 every case passed and every pooled check holds,
/// 1 otherwise, 130 when interrupted (SIGINT/SIGTERM: running cases are killed, finished ones
/// kept for --resume). InputError for a bad folder (results of another manifest, or results
/// without --resume).
int RunSuite(const Manifest& m, const RunOptions& o);

/// The `mopad run` arguments (after the program) of case `c` into `case_dir`; `scene_dir` is
/// the prepared scene folder of a random or imported scene.
std::vector<std::string> RunArgs(const Manifest& m, const Case& c, const std::string& case_dir,
                                 const std::string& scene_dir, const std::string& keep,
                                 bool has_config);

/// The verdict of a case whose process ended with `outcome`: checks on the figures of
/// `case_dir` for exit 0; the message from `stderr_last_line` for exit codes; the measured
/// fields from the outcome.
CaseResult Classify(const Manifest& m, const Case& c, const ProcessOutcome& outcome,
                    const std::string& case_dir, const std::string& truth_path,
                    const std::string& stderr_last_line);

/// Bytes of the regular files under `dir`.
std::uint64_t FolderBytes(const std::string& dir);

/// The file names of a suite folder.
inline constexpr const char* kCaseJson = "case.json";
inline constexpr const char* kManifestCopy = "suite.manifest.yaml";

}  // namespace mopad::suite
