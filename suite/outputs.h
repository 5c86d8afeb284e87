#pragma once
// The suite folder's result files (docs/suites.md, "Outputs"), all written from the case
// results and the manifest alone, so a single run, a merge of shards and a resumed run write
// the same bytes apart from the measured fields (wall_s, peak_rss_mb, bytes_written and junit's
// time attributes):
//
//   suite.json       every case (verdict, checks, figures, measurements), pooled figures and
//                    checks, totals
//   junit.xml        one <testcase> per case; failed -> <failure>, error/timeout/crashed -> <error>
//   scoreboard.md    suite/scoreboard.h
//   scoreboard.html  suite/scoreboard.h

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "suite/case_result.h"
#include "suite/manifest.h"
#include "suite/pooled.h"

namespace mopad::suite {

/// Everything the result files show, computed once.
struct SuiteSummary {
  std::vector<PooledFigure> pooled;
  std::vector<CheckOutcome> pooled_checks;
  std::map<std::string, int> totals;  ///< cases and each verdict
  bool all_passed = false;            ///< every case passed and every pooled check holds
};

SuiteSummary Summarise(const Manifest& m, const std::vector<CaseResult>& cases);

nlohmann::ordered_json SuiteJson(const Manifest& m, const std::vector<CaseResult>& cases,
                                 const SuiteSummary& s);
std::string JunitXml(const Manifest& m, const std::vector<CaseResult>& cases,
                     const SuiteSummary& s);

/// Writes the four files into `dir` (each atomically). Returns the summary.
SuiteSummary WriteSuiteOutputs(const std::string& dir, const Manifest& m,
                               const std::vector<CaseResult>& cases);

/// XML text escaping (&, <, >, ", ' and control characters other than tab/newline).
std::string XmlEscape(const std::string& s);

}  // namespace mopad::suite
