#pragma once
// The suite's scoreboard (docs/suites.md): the per-case table (verdict, the main figures, the
// message, a link to the case's report), each group's figures pooled as mean ± sd over its
// seeds, the paper's tables (SM3's structure, SM4's openings, Table 3's service components per
// class) pooled the same way, the pooled checks; the HTML adds the distribution of each main
// figure over the cases of each group, drawn as inline SVG (self-contained: no scripts, no
// external files). Lengths are shown in cm, shares in %.

#include <string>
#include <vector>

#include "suite/case_result.h"
#include "suite/manifest.h"
#include "suite/outputs.h"

namespace mopad::suite {

std::string ScoreboardMarkdown(const Manifest& m, const std::vector<CaseResult>& cases,
                               const SuiteSummary& s);
std::string ScoreboardHtml(const Manifest& m, const std::vector<CaseResult>& cases,
                           const SuiteSummary& s);

}  // namespace mopad::suite
