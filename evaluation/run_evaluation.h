#pragma once
// `mopad eval`'s work (docs/evaluation.md): the models of a run folder (a room run, or a main-job
// folder with rooms/*/run.json) scored against the scene's truth.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "evaluation/metrics_components.h"

namespace mopad::evaluation {

/// Scores the models of `run_dir` against the truth (`truth_file` overrides the scene's sidecar;
/// `config` is an optional YAML of evaluation parameters; both may be empty) and writes
/// `out` (default run_dir/eval): evaluation.json, evaluation.md, isprs_*.svg, dsm3_truth_*.ply.
/// Returns the tables `mopad eval` prints, the pooled summary (evaluation.json's "summary") and
/// SM5 pooled over the rooms. Throws InputError for bad input.
struct RunEvaluation {
  std::string tables;
  nlohmann::ordered_json summary;
  std::optional<ComponentEvaluation> components;  ///< SM5 of every room; none: no sm5.json
};
RunEvaluation EvaluateRun(const std::string& run_dir, const std::string& truth_file,
                          const std::string& config, const std::string& out);

}  // namespace mopad::evaluation
