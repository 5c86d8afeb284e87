// Comparing two suites (suite/compare.h) on synthetic suite.json files: seed noise alone is no
// regression, a shift beyond it is, the better direction decides regression or improvement, too
// few seeds claim nothing, flipped verdicts and groups on one side are listed, bad files fail
// with the file and field named.
#include "suite/compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/params.h"
#include "common/rng.h"
#include "tests/process_temp_dir.h"
#include "tests/suite/synthetic_suite.h"

namespace {

namespace fs = std::filesystem;
using mopad::suite::Change;
using mopad::suite::CompareParams;
using mopad::suite::CompareSuites;
using mopad::suite::Comparison;
using mopad::suite::ReadSuiteResults;
using mopad::test_support::Group;
using mopad::test_support::Suite;
using nlohmann::json;

std::string Write(const std::string& name, const json& suite) {
  const fs::path dir = mopad::test_support::ProcessTempDir("mopad_compare_", "_" + name);
  std::ofstream(dir / "suite.json") << suite.dump(1);
  return dir.string();
}

Comparison Compare(const json& base, const json& next, const CompareParams& p = {}) {
  return CompareSuites(ReadSuiteResults(Write("base", base)), ReadSuiteResults(Write("new", next)),
                       p);
}

const mopad::suite::FigureComparison& Find(const Comparison& c, const std::string& group,
                                           const std::string& figure) {
  for (const auto& f : c.figures)
    if (f.group == group && f.figure == figure) return f;
  throw std::runtime_error("no " + group + " " + figure);
}

TEST(CompareSuites, OtherSeedsOfTheSameCodeAreNoRegression) {
  // Seeds 1-10 against 11-20 in two groups: only seed-to-seed noise differs.
  const json base = Suite({Group("office", 1, 10, 0.9, 0.01), Group("corridor", 1, 10, 0.8, 0.02)});
  const json next =
      Suite({Group("office", 11, 10, 0.9, 0.01), Group("corridor", 11, 10, 0.8, 0.02)});
  const Comparison c = Compare(base, next);
  EXPECT_FALSE(c.Regressed());
  EXPECT_EQ(c.figures.size(), 6u);  // 2 groups x 3 figures
  EXPECT_TRUE(c.flips.empty());     // no case id in both
  for (const auto& f : c.figures) {
    EXPECT_EQ(f.change, Change::kWithinNoise) << f.group << " " << f.figure << " p " << f.p;
    EXPECT_LE(f.ci_low, f.delta);
    EXPECT_GE(f.ci_high, f.delta);
    EXPECT_EQ(f.base.size(), 10u);
  }
  // Identical suites: nothing changed at all.
  const Comparison same = Compare(base, base);
  EXPECT_FALSE(same.Regressed());
  for (const auto& f : same.figures) {
    EXPECT_EQ(f.delta, 0.0);
    EXPECT_EQ(f.p, 1.0);
  }
}

TEST(CompareSuites, AShiftBeyondTheNoiseTheWorseWayIsARegression) {
  const json base = Suite({Group("office", 1, 10, 0.9, 0.01), Group("corridor", 1, 10, 0.8, 0.02)});
  // office: SM5 TP drops by 0.1 (5 noise sd); corridor: d_h grows by 5 mm (lower is better).
  const json next =
      Suite({Group("office", 11, 10, 0.8, 0.01), Group("corridor", 11, 10, 0.8, 0.025)});
  const Comparison c = Compare(base, next);
  EXPECT_TRUE(c.Regressed());
  EXPECT_EQ(c.Count(Change::kRegression), 2);
  const auto& tp = Find(c, "office", "sm5_tp");
  EXPECT_EQ(tp.change, Change::kRegression);
  EXPECT_TRUE(tp.exact);
  EXPECT_LT(tp.p, 0.001);
  EXPECT_LT(tp.ci_high, 0.0);  // the whole interval below zero
  EXPECT_NEAR(tp.delta, -0.1, 0.03);
  EXPECT_EQ(Find(c, "corridor", "d_h_mean").change, Change::kRegression);
  EXPECT_EQ(Find(c, "corridor", "sm5_tp").change, Change::kWithinNoise);
}

TEST(CompareSuites, AShiftTheBetterWayIsAnImprovementAndWithoutDirectionAChange) {
  const json base = Suite({Group("office", 1, 10, 0.8, 0.02)});
  json next = Suite({Group("office", 11, 10, 0.9, 0.01)});
  for (auto& k : next["cases"]) k["figures"]["scans"] = k["figures"]["scans"].get<double>() + 5;
  const Comparison c = Compare(base, next);
  EXPECT_FALSE(c.Regressed());
  EXPECT_EQ(Find(c, "office", "sm5_tp").change, Change::kImprovement);
  EXPECT_EQ(Find(c, "office", "d_h_mean").change, Change::kImprovement);
  EXPECT_EQ(Find(c, "office", "scans").change, Change::kChanged);
}

TEST(CompareSuites, TooFewSeedsClaimNothing) {
  // One seed a side, then three: the exact test cannot reach p < 0.05 (minimum 1, then 0.1),
  // however large the change.
  for (int n : {1, 3}) {
    const Comparison c = Compare(Suite({Group("office", 1, n, 0.9, 0.01)}),
                                 Suite({Group("office", 11, n, 0.5, 0.1)}));
    EXPECT_FALSE(c.Regressed()) << n;
    for (const auto& f : c.figures) EXPECT_EQ(f.change, Change::kTooFewSeeds) << n << f.figure;
    EXPECT_NE(mopad::suite::CompareMarkdown(c).find("too few seeds"), std::string::npos);
  }
  // Four a side can (min p 0.029): a drop of 0.4 is then a regression, when the figure is
  // judged on its own (with Holm over the three figures, 3 x 0.029 is too much).
  CompareParams single;
  single.holm = false;
  const Comparison four = Compare(Suite({Group("office", 1, 4, 0.9, 0.01)}),
                                  Suite({Group("office", 11, 4, 0.5, 0.01)}), single);
  EXPECT_EQ(Find(four, "office", "sm5_tp").change, Change::kRegression);
}

// A suite of `figures` noise-only figures (better: higher) over ten seeds from `first_seed`.
std::string FigureName(int f) {
  std::string name = "f";
  name += std::to_string(f);
  return name;
}

json NoiseSuite(int figures, int first_seed) {
  json suite = Suite({});
  for (int f = 0; f < figures; ++f)
    suite["figure_info"][FigureName(f)] = {{"better", "higher"}, {"unit", ""}};
  for (int s = first_seed; s < first_seed + 10; ++s) {
    json values;
    mopad::CounterRng rng(static_cast<std::uint64_t>(s), "test/noise");
    for (int f = 0; f < figures; ++f) values[FigureName(f)] = 1.0 + 0.1 * rng.Normal();
    suite["cases"].push_back(mopad::test_support::Case("office", s, "passed", values));
  }
  return suite;
}

TEST(CompareSuites, ManyFiguresOfTheSameCodeRaiseNoFalseAlarmWithHolm) {
  // 60 figures of pure noise, seeds 1-10 against 11-20, 21-30, ...: tested one by one at 0.05,
  // about 60 x 0.025 of them look worse by chance in each comparison; Holm's correction keeps
  // the chance of any false alarm per comparison below 0.05.
  CompareParams single;
  single.holm = false;
  int false_alarms_single = 0, false_alarms_holm = 0;
  const json base = NoiseSuite(60, 1);
  for (int block = 1; block <= 5; ++block) {
    const json next = NoiseSuite(60, 1 + 10 * block);
    false_alarms_single += Compare(base, next, single).Count(Change::kRegression);
    const Comparison holm = Compare(base, next);
    false_alarms_holm += holm.Count(Change::kRegression);
    EXPECT_EQ(holm.tests, 60);
  }
  EXPECT_GE(false_alarms_single, 2);  // the problem is real (expected about 7)
  EXPECT_EQ(false_alarms_holm, 0);
  // A real drop of 3 sd in one of the 60 still shows.
  json next = NoiseSuite(60, 11);
  for (auto& k : next["cases"]) k["figures"]["f7"] = k["figures"]["f7"].get<double>() - 0.3;
  const Comparison c = Compare(base, next);
  EXPECT_EQ(Find(c, "office", "f7").change, Change::kRegression);
  EXPECT_EQ(c.Count(Change::kRegression), 1);
  // Gating on a few figures: a family of 2 instead of 60, the same data, a smaller correction.
  CompareParams few;
  few.figures = {"f7", "f8"};
  const Comparison two = Compare(base, next, few);
  EXPECT_EQ(two.tests, 2);
  EXPECT_EQ(two.figures.size(), 2u);
  const auto& f7 = Find(two, "office", "f7");
  EXPECT_EQ(f7.p, Find(c, "office", "f7").p);
  EXPECT_LE(f7.p_adjusted, 2.0 * f7.p);
  EXPECT_LT(f7.p_adjusted, Find(c, "office", "f7").p_adjusted);
  few.figures = {"f7", "no_such_figure"};
  EXPECT_THROW(Compare(base, next, few), mopad::InputError);
}

TEST(CompareSuites, ChangesBelowTheMinimumEffectAreNoise) {
  // A figure constant over seeds moves by 1e-7 (relative 2e-8) everywhere: significant by rank,
  // but far below 1 % of the mean; a zero figure moves by 1e-12, below the absolute floor.
  json base = Suite({Group("office", 1, 10, 0.9, 0.01)});
  json next = Suite({Group("office", 11, 10, 0.9, 0.01)});
  for (auto& k : base["cases"]) k["figures"]["rooms"] = 5.0, k["figures"]["contacts"] = 0.0;
  for (auto& k : next["cases"])
    k["figures"]["rooms"] = 5.0 - 1e-7, k["figures"]["contacts"] = 1e-12;
  base["figure_info"]["rooms"] = {{"better", "higher"}, {"unit", "count"}};
  base["figure_info"]["contacts"] = {{"better", "lower"}, {"unit", "count"}};
  const Comparison c = Compare(base, next);
  EXPECT_LT(Find(c, "office", "rooms").p, 0.001);
  EXPECT_EQ(Find(c, "office", "rooms").change, Change::kWithinNoise);
  EXPECT_EQ(Find(c, "office", "contacts").change, Change::kWithinNoise);
  EXPECT_FALSE(c.Regressed());
  // A whole room lost on every seed is not noise.
  for (auto& k : next["cases"]) k["figures"]["rooms"] = 4.0;
  EXPECT_EQ(Find(Compare(base, next), "office", "rooms").change, Change::kRegression);
  // A stricter --min-effect hides the 5-sd drop of the TP: 0.1 is 11 % of 0.9.
  CompareParams strict;
  strict.min_relative_effect = 0.2;
  const json drop = Suite({Group("office", 11, 10, 0.8, 0.01)});
  EXPECT_EQ(Find(Compare(base, drop, strict), "office", "sm5_tp").change, Change::kWithinNoise);
}

TEST(CompareSuites, FlippedVerdictsAndOneSidedGroupsAreListed) {
  std::vector<json> base_office = Group("office", 1, 5, 0.9, 0.01);
  std::vector<json> new_office = Group("office", 1, 5, 0.9, 0.01);
  new_office[1]["verdict"] = "failed";   // a check near its bound: reported, not a regression
  new_office[2]["verdict"] = "crashed";  // the program broke: a regression
  new_office[2]["figures"] = json::object();
  base_office[3]["verdict"] = "timeout";  // ... and back: fixed
  const Comparison c = Compare(Suite({base_office, Group("old", 1, 3, 0.9, 0.01)}),
                               Suite({new_office, Group("new", 1, 3, 0.9, 0.01)}));
  ASSERT_EQ(c.flips.size(), 3u);
  EXPECT_EQ(c.flips[0].id, "office/seed-2");
  EXPECT_EQ(c.flips[0].base, "passed");
  EXPECT_EQ(c.flips[0].next, "failed");
  EXPECT_FALSE(c.flips[0].broke);
  EXPECT_TRUE(c.flips[1].broke);
  EXPECT_FALSE(c.flips[2].broke);
  EXPECT_EQ(c.BrokenCases(), 1);
  EXPECT_TRUE(c.Regressed());
  EXPECT_EQ(c.groups_only_in_base, std::vector<std::string>{"old"});
  EXPECT_EQ(c.groups_only_in_new, std::vector<std::string>{"new"});
  EXPECT_EQ(Find(c, "office", "sm5_tp").next.size(), 4u);  // the crashed case has no figures
  const std::string md = mopad::suite::CompareMarkdown(c);
  EXPECT_NE(md.find("| office/seed-3 | passed | crashed | regression"), std::string::npos) << md;
  EXPECT_NE(md.find("only in BASE: old"), std::string::npos);
}

TEST(CompareSuites, FigureOnOneSideOnlyIsListedNotJudged) {
  json base = Suite({Group("office", 1, 5, 0.9, 0.01)});
  for (auto& k : base["cases"]) k["figures"]["old_figure"] = 1.0;
  const Comparison c = Compare(base, Suite({Group("office", 6, 5, 0.9, 0.01)}));
  EXPECT_EQ(Find(c, "office", "old_figure").change, Change::kOnlyInBase);
  EXPECT_FALSE(c.Regressed());
}

TEST(CompareSuites, OutputIsDeterministicAndIndependentOfCaseOrder) {
  const json base = Suite({Group("office", 1, 10, 0.9, 0.01)});
  json next = Suite({Group("office", 11, 10, 0.85, 0.01)});
  const std::string a = mopad::suite::CompareJson(Compare(base, next)).dump();
  EXPECT_EQ(a, mopad::suite::CompareJson(Compare(base, next)).dump());
  std::reverse(next["cases"].begin(), next["cases"].end());
  json reversed = mopad::suite::CompareJson(Compare(base, next));
  json first = json::parse(a);
  for (json* j : {&reversed, &first}) (*j)["new"]["path"] = "", (*j)["base"]["path"] = "";
  EXPECT_EQ(first.dump(), reversed.dump());
  EXPECT_EQ(first["format"], "mopad-suite-compare");
  EXPECT_EQ(first["summary"]["regressions"], 1);
}

TEST(CompareParams, EveryFieldIsVisitedAndDefaultsAreValid) {
  EXPECT_TRUE(mopad::FieldsMissingFromVisit(CompareParams{}).empty());
  EXPECT_NO_THROW(mopad::ValidateParams(CompareParams{}));
  CompareParams bad;
  bad.alpha = 0.7;
  EXPECT_THROW(mopad::ValidateParams(bad), mopad::InputError);
}

void ExpectInputError(const json& suite, const std::string& expected) {
  try {
    ReadSuiteResults(Write("bad", suite));
    ADD_FAILURE() << "no error for " << expected;
  } catch (const mopad::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("suite.json"), std::string::npos) << e.what();
  }
}

TEST(ReadSuiteResults, BadFilesNameTheFileAndTheField) {
  const json good = Suite({Group("office", 1, 2, 0.9, 0.01)});
  json j = good;
  j["format"] = "mopad-run";
  ExpectInputError(j, "wrong file format");
  j = good;
  j["version"] = 2;
  ExpectInputError(j, "unsupported version");
  j = good;
  j["cases"][1]["verdict"] = "skipped";
  ExpectInputError(j, "cases[1].verdict: unknown verdict");
  j = good;
  j["cases"][0]["figures"]["sm5_tp"] = "high";
  ExpectInputError(j, "cases[0].figures.sm5_tp: not a number");
  j = good;
  j["cases"][0].erase("group");
  ExpectInputError(j, "cases[0].group: missing field");
  j = good;
  j["figure_info"]["sm5_tp"]["better"] = "up";
  ExpectInputError(j, "figure_info.sm5_tp.better: unknown direction");
  j = good;
  j["cases"][1]["id"] = j["cases"][0]["id"];
  ExpectInputError(j, "duplicate case id");
  // A null figure is one the case could not measure: left out, no error.
  j = good;
  j["cases"][0]["figures"]["sm5_tp"] = nullptr;
  EXPECT_EQ(ReadSuiteResults(Write("null", j)).cases[0].figures.count("sm5_tp"), 0u);

  const fs::path dir = mopad::test_support::ProcessTempDir("mopad_compare_", "_text");
  std::ofstream(dir / "suite.json") << "{\"format\": ";
  EXPECT_THROW(ReadSuiteResults(dir.string()), mopad::InputError);
  EXPECT_THROW(ReadSuiteResults((dir / "absent").string()), mopad::InputError);
}

}  // namespace

namespace {

// Two configs of one suite, compared as BASE and NEW: the groups meet under one label, the
// shift of the one config is found, a config no case ran is refused naming the ones there are.
TEST(SelectConfig, OneConfigOfASuiteIsComparedWithAnother) {
  std::vector<json> a = Group("office/a", 1, 10, 0.80, 0.004);
  std::vector<json> b = Group("office/b", 1, 10, 0.90, 0.004);
  for (json& c : a) c["scene"] = "office", c["config"] = "a";
  for (json& c : b) c["scene"] = "office", c["config"] = "b";
  b[3]["verdict"] = "failed";
  const auto s = ReadSuiteResults(Write("configs", Suite({a, b})));
  const auto base = mopad::suite::SelectConfig(s, "a", "a->b");
  const auto next = mopad::suite::SelectConfig(s, "b", "a->b");
  ASSERT_EQ(base.cases.size(), 10u);
  EXPECT_EQ(base.cases[0].group, "office/a->b");
  EXPECT_EQ(base.cases[0].id, "office/a->b/seed-1");
  EXPECT_EQ(next.totals.at("cases"), 10);
  EXPECT_EQ(next.totals.at("failed"), 1);
  EXPECT_EQ(next.totals.at("passed"), 9);
  const Comparison c = CompareSuites(base, next, CompareParams{});
  EXPECT_EQ(Find(c, "office/a->b", "sm5_tp").change, Change::kImprovement);
  EXPECT_EQ(Find(c, "office/a->b", "d_h_mean").change, Change::kWithinNoise);
  ASSERT_EQ(c.flips.size(), 1u);
  EXPECT_EQ(c.flips[0].id, "office/a->b/seed-4");
  EXPECT_TRUE(c.groups_only_in_base.empty());
  try {
    mopad::suite::SelectConfig(s, "c", "a->c");
    ADD_FAILURE() << "config 'c' accepted";
  } catch (const mopad::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no case was run with config 'c'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("'a', 'b'"), std::string::npos) << e.what();
  }
}

}  // namespace
