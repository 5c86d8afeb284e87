#pragma once
// `mopad suite compare BASE NEW`: whether a change of the robot stack made a suite's figures
// better or worse beyond the run-to-run noise of its seed repetitions (docs/suites.md,
// "Comparing suites").
//
// Cases are pooled per scene group (suite.json's "group": scene, config, sweep value; never the
// seed), so BASE and NEW may use different seeds. Per group and figure: the change of the mean
// with a bootstrap interval, and a two-sided Mann-Whitney U test (suite/two_sample.h) whose p is
// corrected by Holm's method over all figures and groups tested. A change is a regression when
// the corrected p < alpha, it goes the worse way (figure_info "better"), and it is larger than
// the minimum effect max(min_relative_effect |BASE mean|, min_absolute_effect), so that
// bit-level noise never flags. Cases present in both suites (same id) whose verdict changed are
// listed; a case that completed in BASE (passed or failed) and did not in NEW (error, timeout,
// crashed) is a regression too: a program that broke is not noise.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/params.h"

namespace mopad::suite {

struct CompareParams {
  double alpha = 0.05;  ///< significance level of the two-sided U test, (0, 0.5]
  /// A change smaller than this fraction of |BASE mean| is noise, [0, 1]: 1 % is below any
  /// change a team acts on and far above floating-point noise.
  double min_relative_effect = 0.01;
  /// A change at most this large (the figure's unit) is noise, [0, inf): the floor for figures
  /// whose BASE mean is zero; far below any figure's resolution (1 mm, 1 %, one room).
  double min_absolute_effect = 1e-9;
  /// Holm's correction of the p-values over every figure and group tested, so that the chance
  /// of any false regression in a comparison (the gate's false alarm) stays below alpha however
  /// many figures a suite reports; false: each figure at alpha on its own.
  bool holm = true;
  /// The figures compared (names as in suite.json); empty: every figure. Fewer figures make a
  /// smaller family for Holm's correction, so the ones a team gates on are judged more sharply.
  std::vector<std::string> figures;
  int bootstrap_resamples = 2000;  ///< count, [100, 1000000]
  double confidence = 0.95;        ///< of the bootstrap interval, [0.5, 0.999]
  int bootstrap_seed = 1;          ///< the bootstrap's fixed seed, [0, 2^31)

  template <class V>
  void Visit(V& v) {
    v("alpha", alpha, Bounds{1e-6, 0.5});
    v("min_relative_effect", min_relative_effect, Bounds{0.0, 1.0});
    v("min_absolute_effect", min_absolute_effect, Bounds{0.0, 1e300});
    v("holm", holm);
    v("figures", figures);
    v("bootstrap_resamples", bootstrap_resamples, Bounds{100, 1000000});
    v("confidence", confidence, Bounds{0.5, 0.999});
    v("bootstrap_seed", bootstrap_seed, Bounds{0, 2147483647});
  }
};

/// One case of a suite.json, as far as comparing needs it.
struct SuiteCase {
  std::string id;                         ///< "<group>/seed-<n>"
  std::string group;                      ///< the seeds' common part of the id
  std::string scene;                      ///< the scene's name ("" when suite.json has none)
  std::string config;                     ///< the manifest's config name ("" without configs)
  std::string verdict;                    ///< passed | failed | error | timeout | crashed
  std::map<std::string, double> figures;  ///< finite figures only (null ones are left out)
};

/// How a figure is judged: "higher" or "lower" is better, or "none" (no direction).
struct FigureInfo {
  std::string better = "none";
  std::string unit;
};

/// A suite folder's suite.json (format "mopad-suite", version 1), read for comparing.
struct SuiteResults {
  std::string path;  ///< the suite.json read
  std::string name;  ///< "suite"
  std::map<std::string, FigureInfo> figure_info;
  std::vector<SuiteCase> cases;
  std::map<std::string, int> totals;  ///< "cases", "passed", ... as written
};

/// Reads `folder`/suite.json (or `folder` itself when it is a file). InputError naming the file
/// and the field when it is missing, not JSON, of another format or version, or malformed.
SuiteResults ReadSuiteResults(const std::string& folder);

/// The cases of `s` run with config `config`, their groups (and ids) renamed from
/// "<scene>/<config>..." to "<scene>/<label>...", so that one config of a suite can be compared
/// with another config of the same or another suite (`mopad suite compare --base-config
/// --new-config`); totals counted over those cases. InputError naming the suite.json and the
/// configs it has when no case has `config`.
SuiteResults SelectConfig(const SuiteResults& s, const std::string& config,
                          const std::string& label);

/// What a figure's comparison concluded.
enum class Change {
  kWithinNoise,  ///< not significant, or smaller than the minimum effect
  kRegression,   ///< significant, beyond the minimum effect, the worse way
  kImprovement,  ///< significant, beyond the minimum effect, the better way
  kChanged,      ///< significant and beyond the minimum effect, figure without direction
  kTooFewSeeds,  ///< no sample could be significant at these sizes (MinimumTwoSidedP > alpha)
  kOnlyInBase,   ///< the group has the figure in BASE only
  kOnlyInNew,    ///< the group has the figure in NEW only
};
/// "within noise", "regression", "improvement", "changed", "too few seeds", "only in BASE",
/// "only in NEW".
const char* ChangeName(Change c);

struct FigureComparison {
  std::string group, figure, better, unit;
  std::vector<double> base, next;  ///< the values over the group's cases, sorted
  double base_mean = 0, base_sd = 0, new_mean = 0, new_sd = 0;
  double delta = 0;                ///< new_mean - base_mean
  double ci_low = 0, ci_high = 0;  ///< bootstrap interval of delta
  double u = 0, p = 1;             ///< U of NEW against BASE, two-sided p
  double p_adjusted = 1;           ///< p after Holm's correction (p itself when not tested)
  bool exact = false;              ///< p from the exact distribution
  double min_effect = 0;           ///< the minimum effect applied (figure's unit)
  Change change = Change::kWithinNoise;
};

struct VerdictFlip {
  std::string id, base, next;
  bool broke = false;  ///< completed in BASE, error/timeout/crashed in NEW (a regression)
};

struct Comparison {
  std::string base_path, new_path, base_name, new_name;
  std::map<std::string, int> base_totals, new_totals;
  CompareParams params;
  std::vector<FigureComparison> figures;  ///< by group, then figure (byte order)
  std::vector<VerdictFlip> flips;         ///< by case id
  std::vector<std::string> groups_only_in_base, groups_only_in_new;
  int tests = 0;  ///< figures in the family of tests (Holm's m): both sides, able to reject

  int Count(Change c) const;
  int BrokenCases() const;
  /// Any figure regression or broken case: `mopad suite compare` exits 1.
  bool Regressed() const { return Count(Change::kRegression) + BrokenCases() > 0; }
};

/// Compares NEW against BASE (deterministic: the bootstrap's draws are keyed by the seed, the
/// group and the figure, not by order). InputError when params.figures names a figure neither
/// suite reports.
Comparison CompareSuites(const SuiteResults& base, const SuiteResults& next,
                         const CompareParams& params);

/// The comparison as Markdown: verdict, regressions, improvements, flipped verdicts, groups on
/// one side only, then every figure.
std::string CompareMarkdown(const Comparison& c);

/// The comparison as JSON ("format": "mopad-suite-compare", version 1; docs/suites.md).
nlohmann::json CompareJson(const Comparison& c);

}  // namespace mopad::suite
