#pragma once
// One case's result: its verdict, checks and figures, and the runner's measurements. The
// runner writes it to DIR/cases/<id>/case.json (atomically) when the case ends; suite.json
// lists them in case order; merge and --resume read them back.
//
// Verdicts: passed (exit 0, every check holds), failed (exit 0, a check does not: the message
// names it, its value and bound), error (exit 2 or 3, or another non-zero code: the message
// is the last line of the case's stderr), timeout (over its wall-time limit), crashed (ended by
// a signal, or killed over its memory limit).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "suite/checks.h"

namespace mopad::suite {

inline constexpr const char* kVerdicts[] = {"passed", "failed", "error", "timeout", "crashed"};

struct CheckOutcome {
  std::string check;   ///< the text as written
  std::string figure;
  std::string op;
  std::optional<double> bound;
  std::optional<double> value;
  bool passed = false;
  std::string group;  ///< pooled checks only
  std::string stat;   ///< pooled checks only
};

CheckOutcome ToOutcome(const CheckResult& r);

struct CaseResult {
  std::string id, group, scene, config;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, std::string>> sweep;
  std::string verdict;  ///< one of kVerdicts
  std::string message;
  std::vector<CheckOutcome> checks;
  Figures figures;
  std::string dir;  ///< "cases/<id>", relative to the suite folder
  // Measurements (vary between runs; never used for ordering or verdicts).
  double wall_s = 0.0;
  double peak_rss_mb = 0.0;
  std::uint64_t bytes_written = 0;
};

/// suite.json's case object (docs/suites.md); key order fixed.
nlohmann::ordered_json ToJson(const CaseResult& r);
nlohmann::ordered_json ToJson(const CheckOutcome& c);
/// Reads ToJson's output; InputError naming `where` when a field is missing or of a wrong type.
CaseResult CaseResultFromJson(const nlohmann::json& j, const std::string& where);

}  // namespace mopad::suite
