#include "suite/compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "common/rng.h"
#include "io/json_fields.h"
#include "io/text_file.h"
#include "suite/two_sample.h"

namespace mopad::suite {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::set<std::string> kVerdicts = {"passed", "failed", "error", "timeout", "crashed"};

bool Completed(const std::string& verdict) { return verdict == "passed" || verdict == "failed"; }

SuiteCase ReadCase(const io::JsonFields& f, const json& c, const std::string& field) {
  SuiteCase out;
  out.id = f.String(f.Get(c, "id", field + ".id"), field + ".id");
  out.group = f.String(f.Get(c, "group", field + ".group"), field + ".group");
  out.verdict = f.String(f.Get(c, "verdict", field + ".verdict"), field + ".verdict");
  if (c.contains("scene")) out.scene = f.String(c["scene"], field + ".scene");
  if (c.contains("config")) out.config = f.String(c["config"], field + ".config");
  if (!kVerdicts.count(out.verdict))
    f.Fail(field + ".verdict", "unknown verdict", "'" + out.verdict + "'",
           "passed, failed, error, timeout or crashed");
  const json& figures = f.Get(c, "figures", field + ".figures");
  if (!figures.is_object()) f.Fail(field + ".figures", "not an object", figures.dump());
  for (const auto& [name, value] : figures.items()) {
    if (value.is_null()) continue;  // a figure the case could not measure
    out.figures[name] = f.Number(value, field + ".figures." + name);
  }
  return out;
}

// The minimum effect for a figure whose BASE mean is `base_mean` (CompareParams).
double MinEffect(const CompareParams& p, double base_mean) {
  return std::max(p.min_relative_effect * std::abs(base_mean), p.min_absolute_effect);
}

// The bootstrap interval and the U test of a figure present on both sides.
void Measure(const CompareParams& params, FigureComparison& fc) {
  const std::uint64_t key =
      DeriveKey(DeriveKey(Mix64(static_cast<std::uint64_t>(params.bootstrap_seed)),
                          HashName("suite/compare/bootstrap")),
                HashName(fc.group + "\n" + fc.figure));
  const Interval ci =
      BootstrapMeanDifference(fc.base, fc.next, params.bootstrap_resamples, params.confidence, key);
  fc.ci_low = ci.low;
  fc.ci_high = ci.high;
  const MannWhitneyResult mw = MannWhitneyU(fc.next, fc.base);
  fc.u = mw.u;
  fc.p = mw.p;
  fc.p_adjusted = mw.p;
  fc.exact = mw.exact;
  fc.min_effect = MinEffect(params, fc.base_mean);
}

// Whether a measured figure belongs to the family of tests: a test that cannot reject at level
// alpha (too few seeds for any p below it, or one value on both sides, whose permutation
// distribution is a single point) adds nothing to the family-wise error and is left out
// (Tarone 1990).
bool CanReject(const CompareParams& params, const FigureComparison& fc) {
  const int nb = static_cast<int>(fc.base.size()), nn = static_cast<int>(fc.next.size());
  if (MinimumTwoSidedP(nn, nb) > params.alpha) return false;
  return !(fc.base.front() == fc.base.back() && fc.next.front() == fc.next.back() &&
           fc.base.front() == fc.next.front());  // sorted: front and back bound the values
}

void Classify(const CompareParams& params, FigureComparison& fc) {
  const int nb = static_cast<int>(fc.base.size()), nn = static_cast<int>(fc.next.size());
  if (MinimumTwoSidedP(nn, nb) > params.alpha) {
    fc.change = Change::kTooFewSeeds;
    return;
  }
  // The ranks' direction (NEW tends higher when U > n_new n_base / 2) and the means' must agree.
  const double centre = 0.5 * nn * nb;
  const int rank_dir = fc.u > centre ? 1 : (fc.u < centre ? -1 : 0);
  const int mean_dir = fc.delta > 0 ? 1 : (fc.delta < 0 ? -1 : 0);
  if (!(fc.p_adjusted < params.alpha) || std::abs(fc.delta) <= fc.min_effect ||
      rank_dir != mean_dir) {
    fc.change = Change::kWithinNoise;
    return;
  }
  if (fc.better == "none") {
    fc.change = Change::kChanged;
  } else {
    const bool better = (fc.better == "higher") == (mean_dir > 0);
    fc.change = better ? Change::kImprovement : Change::kRegression;
  }
}

// Holm's step-down adjustment over the figures that can reject (or none when switched off);
// the others keep their own p.
int AdjustForMultipleTests(const CompareParams& params, std::vector<FigureComparison>& figures) {
  std::vector<FigureComparison*> family;
  for (auto& f : figures)
    if (f.change == Change::kWithinNoise && CanReject(params, f)) family.push_back(&f);
  if (!params.holm) return static_cast<int>(family.size());
  std::vector<double> p;
  for (const auto* f : family) p.push_back(f->p);
  const std::vector<double> adjusted = HolmAdjusted(p);
  for (std::size_t i = 0; i < family.size(); ++i) family[i]->p_adjusted = adjusted[i];
  return static_cast<int>(family.size());
}

std::string Num(double v) { return std::isfinite(v) ? FormatNumbers("%.4g", v) : "-"; }

std::string MeanSd(const std::vector<double>& v, double mean, double sd) {
  if (v.empty()) return "-";
  return Num(mean) + " ± " + Num(sd) + " (" + std::to_string(v.size()) + ")";
}

std::string Signed(double v) { return std::string(v > 0 ? "+" : "") + Num(v); }

std::string FigureRow(const FigureComparison& f) {
  const bool both = !f.base.empty() && !f.next.empty();
  std::string rel = "";
  if (both && f.base_mean != 0.0)
    rel = " (" + Signed(100.0 * f.delta / std::abs(f.base_mean)) + " %)";
  return "| " + f.group + " | " + f.figure + (f.unit.empty() ? "" : " [" + f.unit + "]") + " | " +
         MeanSd(f.base, f.base_mean, f.base_sd) + " | " + MeanSd(f.next, f.new_mean, f.new_sd) +
         " | " + (both ? Signed(f.delta) + rel : "-") + " | " +
         (both ? std::string("[") + Num(f.ci_low) + ", " + Num(f.ci_high) + "]" : "-") + " | " +
         (both ? Num(f.p) + (f.exact ? "" : " (approx.)") : "-") + " | " +
         (both ? Num(f.p_adjusted) : "-") + " | " + ChangeName(f.change) + " |\n";
}

const char* kFigureHeader =
    "| group | figure | BASE mean ± sd (n) | NEW mean ± sd (n) | change | CI | p | p Holm | result "
    "|\n|---|---|---|---|---|---|---|---|---|\n";

std::string FigureTable(const Comparison& c, const std::vector<Change>& which) {
  std::string rows;
  for (const auto& f : c.figures)
    if (std::find(which.begin(), which.end(), f.change) != which.end()) rows += FigureRow(f);
  return rows.empty() ? "None.\n" : kFigureHeader + rows;
}

std::string TotalsLine(const std::map<std::string, int>& t) {
  std::string out;
  for (const char* k : {"cases", "passed", "failed", "error", "timeout", "crashed"}) {
    auto it = t.find(k);
    if (it == t.end()) continue;
    out += (out.empty() ? "" : ", ") + std::to_string(it->second) + " " + k;
  }
  return out;
}

}  // namespace

SuiteResults ReadSuiteResults(const std::string& folder) {
  fs::path file(folder);
  if (fs::is_directory(file)) file /= "suite.json";
  SuiteResults out;
  out.path = file.string();
  if (!fs::is_regular_file(file))
    throw InputError(out.path, "no suite results here (a suite folder holds suite.json)");
  const io::JsonFields f{out.path};
  json j;
  try {
    j = json::parse(io::ReadTextFile(out.path));
  } catch (const json::exception& e) {
    throw InputError(out.path, std::string("not valid JSON: ") + e.what());
  }
  f.Header(j, "mopad-suite", 1);
  out.name = f.String(f.Get(j, "suite", "suite"), "suite");
  const json& info = f.Get(j, "figure_info", "figure_info");
  if (!info.is_object()) f.Fail("figure_info", "not an object", info.dump());
  for (const auto& [name, fi] : info.items()) {
    const std::string field = "figure_info." + name;
    FigureInfo& i = out.figure_info[name];
    i.better = f.String(f.Get(fi, "better", field + ".better"), field + ".better");
    if (i.better != "higher" && i.better != "lower" && i.better != "none")
      f.Fail(field + ".better", "unknown direction", "'" + i.better + "'", "higher, lower or none");
    if (fi.contains("unit")) i.unit = f.String(fi["unit"], field + ".unit");
  }
  const json& cases = f.Get(j, "cases", "cases");
  if (!cases.is_array()) f.Fail("cases", "not an array", cases.type_name(), "an array");
  std::set<std::string> ids;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    out.cases.push_back(ReadCase(f, cases[i], "cases[" + std::to_string(i) + "]"));
    if (!ids.insert(out.cases.back().id).second)
      f.Fail("cases[" + std::to_string(i) + "].id", "duplicate case id", out.cases.back().id);
  }
  if (j.contains("totals") && j["totals"].is_object())
    for (const auto& [k, v] : j["totals"].items())
      if (v.is_number_integer()) out.totals[k] = v.get<int>();
  return out;
}

const char* ChangeName(Change c) {
  switch (c) {
    case Change::kWithinNoise:
      return "within noise";
    case Change::kRegression:
      return "regression";
    case Change::kImprovement:
      return "improvement";
    case Change::kChanged:
      return "changed";
    case Change::kTooFewSeeds:
      return "too few seeds";
    case Change::kOnlyInBase:
      return "only in BASE";
    case Change::kOnlyInNew:
      return "only in NEW";
  }
  return "?";
}

int Comparison::Count(Change c) const {
  return static_cast<int>(
      std::count_if(figures.begin(), figures.end(), [c](const auto& f) { return f.change == c; }));
}

int Comparison::BrokenCases() const {
  return static_cast<int>(
      std::count_if(flips.begin(), flips.end(), [](const auto& f) { return f.broke; }));
}

SuiteResults SelectConfig(const SuiteResults& s, const std::string& config,
                          const std::string& label) {
  SuiteResults out = s;
  out.cases.clear();
  out.totals.clear();
  for (const char* k : {"cases", "passed", "failed", "error", "timeout", "crashed"})
    out.totals[k] = 0;
  std::set<std::string> configs;
  for (const SuiteCase& c : s.cases) {
    configs.insert(c.config);
    if (c.config != config) continue;
    const std::string prefix = c.scene + "/" + config;
    const bool named = !config.empty() && c.group.compare(0, prefix.size(), prefix) == 0 &&
                       (c.group.size() == prefix.size() || c.group[prefix.size()] == '/');
    if (!named)
      throw InputError(s.path,
                       "case '" + c.id + "': its group does not begin with its scene and config",
                       "'" + c.group + "'", "'" + prefix + "...'");
    SuiteCase k = c;
    k.group = c.scene + "/" + label + c.group.substr(prefix.size());
    k.id = k.group + c.id.substr(c.group.size());
    ++out.totals["cases"];
    ++out.totals[k.verdict];
    out.cases.push_back(std::move(k));
  }
  if (out.cases.empty()) {
    std::string names;
    for (const std::string& n : configs) names += (names.empty() ? "" : ", ") + ("'" + n + "'");
    throw InputError(s.path, "no case was run with config '" + config + "'", "",
                     "one of its configs: " + names);
  }
  return out;
}

Comparison CompareSuites(const SuiteResults& base, const SuiteResults& next,
                         const CompareParams& params) {
  Comparison c;
  c.base_path = base.path;
  c.new_path = next.path;
  c.base_name = base.name;
  c.new_name = next.name;
  c.base_totals = base.totals;
  c.new_totals = next.totals;
  c.params = params;
  // group -> its cases on each side, in suite order.
  std::map<std::string, std::pair<std::vector<const SuiteCase*>, std::vector<const SuiteCase*>>>
      groups;
  for (const auto& k : base.cases) groups[k.group].first.push_back(&k);
  for (const auto& k : next.cases) groups[k.group].second.push_back(&k);
  for (const auto& [group, sides] : groups) {
    if (sides.second.empty()) c.groups_only_in_base.push_back(group);
    if (sides.first.empty()) c.groups_only_in_new.push_back(group);
    if (sides.first.empty() || sides.second.empty()) continue;
    std::set<std::string> names;
    for (const auto* side : {&sides.first, &sides.second})
      for (const SuiteCase* k : *side)
        for (const auto& [name, value] : k->figures) names.insert(name);
    for (const std::string& name : names) {
      if (!params.figures.empty() &&
          std::find(params.figures.begin(), params.figures.end(), name) == params.figures.end())
        continue;
      FigureComparison fc;
      fc.group = group;
      fc.figure = name;
      FigureInfo info;  // NEW's description, else BASE's, else no direction
      if (auto it = next.figure_info.find(name); it != next.figure_info.end())
        info = it->second;
      else if (auto ib = base.figure_info.find(name); ib != base.figure_info.end())
        info = ib->second;
      fc.better = info.better;
      fc.unit = info.unit;
      for (const SuiteCase* k : sides.first)
        if (k->figures.count(name)) fc.base.push_back(k->figures.at(name));
      for (const SuiteCase* k : sides.second)
        if (k->figures.count(name)) fc.next.push_back(k->figures.at(name));
      // Sorted: the bootstrap's draws then do not depend on the order of the cases.
      std::sort(fc.base.begin(), fc.base.end());
      std::sort(fc.next.begin(), fc.next.end());
      fc.base_mean = Mean(fc.base);
      fc.base_sd = SampleSd(fc.base);
      fc.new_mean = Mean(fc.next);
      fc.new_sd = SampleSd(fc.next);
      if (fc.base.empty()) {
        fc.change = Change::kOnlyInNew;
      } else if (fc.next.empty()) {
        fc.change = Change::kOnlyInBase;
      } else {
        fc.delta = fc.new_mean - fc.base_mean;
        Measure(params, fc);
      }
      c.figures.push_back(std::move(fc));
    }
  }
  for (const std::string& name : params.figures) {
    const auto reports = [&name](const SuiteResults& r) {
      return std::any_of(r.cases.begin(), r.cases.end(),
                         [&name](const SuiteCase& k) { return k.figures.count(name) > 0; });
    };
    if (!reports(base) && !reports(next))
      throw InputError("figures", "no such figure in either suite", "'" + name + "'",
                       "a name of suite.json's figures");
  }
  c.tests = AdjustForMultipleTests(params, c.figures);
  for (auto& f : c.figures)
    if (f.change == Change::kWithinNoise) Classify(params, f);
  std::map<std::string, std::string> base_verdict;
  for (const auto& k : base.cases) base_verdict[k.id] = k.verdict;
  for (const auto& k : next.cases) {
    auto it = base_verdict.find(k.id);
    if (it == base_verdict.end() || it->second == k.verdict) continue;
    c.flips.push_back(
        {k.id, it->second, k.verdict, Completed(it->second) && !Completed(k.verdict)});
  }
  std::sort(c.flips.begin(), c.flips.end(),
            [](const VerdictFlip& a, const VerdictFlip& b) { return a.id < b.id; });
  return c;
}

std::string CompareMarkdown(const Comparison& c) {
  const CompareParams& p = c.params;
  std::string md =
      "# Suite comparison: " + c.new_name + " (NEW) against " + c.base_name + " (BASE)\n\n";
  md += "- BASE: " + c.base_path + " (" + TotalsLine(c.base_totals) + ")\n";
  md += "- NEW: " + c.new_path + " (" + TotalsLine(c.new_totals) + ")\n\n";
  const int regressions = c.Count(Change::kRegression), broken = c.BrokenCases();
  if (c.Regressed()) {
    md += "**Regression beyond noise**: " + std::to_string(regressions) + " figure(s), " +
          std::to_string(broken) + " case(s) that no longer complete.\n\n";
  } else {
    md += "**No regression beyond noise** (" + std::to_string(c.Count(Change::kImprovement)) +
          " improvement(s)).\n\n";
  }
  md +=
      "Per scene group and figure, pooled over seeds: a two-sided Mann-Whitney U test (exact "
      "for up to " +
      std::to_string(kExactMaxTotal) + " values, else the normal approximation), " +
      (p.holm ? "its p corrected by Holm's method over the " + std::to_string(c.tests) +
                    " figures tested (p Holm; alpha " + Num(p.alpha) + " for them all)"
              : "each figure at alpha " + Num(p.alpha) + " (no correction for " +
                    std::to_string(c.tests) + " tests)") +
      ", and a " + Num(100.0 * p.confidence) +
      " % percentile bootstrap interval (CI) of the change of the mean (" +
      std::to_string(p.bootstrap_resamples) + " resamples, seed " +
      std::to_string(p.bootstrap_seed) +
      "). A change counts when p Holm < alpha and it exceeds the larger of " +
      Num(100.0 * p.min_relative_effect) + " % of |BASE mean| and " + Num(p.min_absolute_effect) +
      ".\n\n";
  md += "## Regressions\n\n" + FigureTable(c, {Change::kRegression}) + "\n";
  md += "## Improvements\n\n" + FigureTable(c, {Change::kImprovement}) + "\n";
  md += "## Verdicts that flipped\n\n";
  if (c.flips.empty()) {
    md += "None.\n\n";
  } else {
    md += "| case | BASE | NEW | |\n|---|---|---|---|\n";
    for (const auto& f : c.flips)
      md += "| " + f.id + " | " + f.base + " | " + f.next + " | " +
            (f.broke ? "regression: no longer completes" : "") + " |\n";
    md += "\n";
  }
  md += "## Groups in one suite only\n\n";
  if (c.groups_only_in_base.empty() && c.groups_only_in_new.empty()) md += "None.\n";
  for (const auto& g : c.groups_only_in_base) md += "- only in BASE: " + g + "\n";
  for (const auto& g : c.groups_only_in_new) md += "- only in NEW: " + g + "\n";
  md += "\n## All figures\n\n";
  if (c.figures.empty()) return md + "None.\n";
  md += kFigureHeader;
  for (const auto& f : c.figures) md += FigureRow(f);
  return md;
}

json CompareJson(const Comparison& c) {
  json j = {{"format", "mopad-suite-compare"}, {"version", 1}};
  j["base"] = {{"path", c.base_path}, {"suite", c.base_name}, {"totals", c.base_totals}};
  j["new"] = {{"path", c.new_path}, {"suite", c.new_name}, {"totals", c.new_totals}};
  const CompareParams& p = c.params;
  j["method"] = {{"test", "Mann-Whitney U, two-sided"},
                 {"alpha", p.alpha},
                 {"holm", p.holm},
                 {"tests", c.tests},
                 {"exact_max_total", kExactMaxTotal},
                 {"interval", "percentile bootstrap of mean(NEW) - mean(BASE)"},
                 {"confidence", p.confidence},
                 {"bootstrap_resamples", p.bootstrap_resamples},
                 {"bootstrap_seed", p.bootstrap_seed},
                 {"min_relative_effect", p.min_relative_effect},
                 {"min_absolute_effect", p.min_absolute_effect}};
  auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json figures = json::array();
  for (const auto& f : c.figures) {
    const bool both = !f.base.empty() && !f.next.empty();
    json o = {{"group", f.group},
              {"figure", f.figure},
              {"better", f.better},
              {"unit", f.unit},
              {"result", ChangeName(f.change)},
              {"base",
               {{"n", f.base.size()},
                {"mean", number(f.base_mean)},
                {"sd", number(f.base_sd)},
                {"values", f.base}}},
              {"new",
               {{"n", f.next.size()},
                {"mean", number(f.new_mean)},
                {"sd", number(f.new_sd)},
                {"values", f.next}}}};
    if (both) {
      o["change"] = f.delta;
      o["ci"] = {f.ci_low, f.ci_high};
      o["u"] = f.u;
      o["p"] = f.p;
      o["p_holm"] = f.p_adjusted;
      o["exact"] = f.exact;
      o["min_effect"] = f.min_effect;
    }
    figures.push_back(std::move(o));
  }
  j["figures"] = std::move(figures);
  json flips = json::array();
  for (const auto& f : c.flips)
    flips.push_back({{"id", f.id}, {"base", f.base}, {"new", f.next}, {"broke", f.broke}});
  j["flips"] = std::move(flips);
  j["groups_only_in_base"] = c.groups_only_in_base;
  j["groups_only_in_new"] = c.groups_only_in_new;
  j["summary"] = {
      {"regressions", c.Count(Change::kRegression)},    {"broken_cases", c.BrokenCases()},
      {"improvements", c.Count(Change::kImprovement)},  {"changed", c.Count(Change::kChanged)},
      {"too_few_seeds", c.Count(Change::kTooFewSeeds)}, {"regressed", c.Regressed()}};
  return j;
}

}  // namespace mopad::suite
