#pragma once
// Checks: thresholds on a case's figures (docs/suites.md, "Checks"). A check is written
//
//   FIGURE OP BOUND [UNIT]          per case, e.g. "sm5_tp_rate >= 0.9", "d_h_mean <= 1 cm"
//   STAT(FIGURE) OP BOUND [UNIT]    pooled over a group's seeds, STAT one of mean, min, max
//
// OP is one of >=, <=, >, <, ==, !=. BOUND is a number (UNIT, if given, converts it to SI:
// m, cm, mm, deg, s, %), or, per case, another figure's name ("rooms_modelled >=
// rooms_reachable"). A check whose figure (or bound figure) the case lacks fails with value null.

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mopad::suite {

struct Check {
  std::string text;          ///< as written in the manifest
  std::string stat;          ///< "" per case; "mean" | "min" | "max" pooled
  std::string figure;        ///< the figure's name (suite/figures.h) or a dotted path
  std::string op;            ///< >=, <=, >, <, ==, !=
  double bound = 0.0;        ///< SI, when bound_figure is empty
  std::string bound_figure;  ///< a figure as the bound ("" = the number)
};

/// Parses a check; InputError at `where` naming the text and the expected form.
Check ParseCheck(const std::string& text, const std::string& where);

/// The outcome of a check on one set of figures.
struct CheckResult {
  const Check* check = nullptr;
  std::optional<double> value;  ///< none when the figure is missing
  std::optional<double> bound;  ///< none when the bound figure is missing
  bool passed = false;
};

/// Figures by name (a case's, or a group's pooled statistic of each).
using Figures = std::map<std::string, double>;

/// `op` applied to value and bound.
bool Compare(double value, const std::string& op, double bound);

/// Evaluates `check` (its stat ignored) on `figures`.
CheckResult Evaluate(const Check& check, const Figures& figures);

/// "check 'TEXT': VALUE, bound BOUND" (or "figure F missing") for verdict messages.
std::string Describe(const CheckResult& r);

}  // namespace mopad::suite
