#pragma once
// Synthetic suite.json contents for the tests of `mopad suite compare`: groups of cases whose
// figures are a level plus seed-keyed noise, as a mission's figures vary over seeds.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/rng.h"

namespace mopad::test_support {

using nlohmann::json;

inline json FigureInfo() {
  return {{"sm5_tp", {{"better", "higher"}, {"unit", ""}}},
          {"d_h_mean", {{"better", "lower"}, {"unit", "m"}}},
          {"scans", {{"better", "none"}, {"unit", "count"}}}};
}

inline json Case(const std::string& group, int seed, const std::string& verdict, json figures) {
  const std::string id = group + "/seed-" + std::to_string(seed);
  return {{"id", id},
          {"group", group},
          {"scene", "scenes/x.yaml"},
          {"seed", seed},
          {"config", ""},
          {"sweep", json::object()},
          {"verdict", verdict},
          {"message", ""},
          {"checks", json::array()},
          {"figures", std::move(figures)},
          {"dir", "cases/" + id},
          {"wall_s", 1.0},
          {"peak_rss_mb", 100.0},
          {"bytes_written", 1000}};
}

// A group's cases over seeds first_seed .. first_seed + n - 1: sm5_tp = tp + 0.02 N(0, 1),
// d_h_mean = dh + 0.001 N(0, 1), scans = 12 + round(N(0, 1)); the noise is keyed by the seed,
// as a mission's is.
inline std::vector<json> Group(const std::string& group, int first_seed, int n, double tp,
                               double dh) {
  std::vector<json> cases;
  for (int s = first_seed; s < first_seed + n; ++s) {
    CounterRng rng(static_cast<std::uint64_t>(s), "test/" + group);
    const double t = tp + 0.02 * rng.Normal(), d = dh + 0.001 * rng.Normal();
    const double scans = 12 + std::round(rng.Normal());
    cases.push_back(Case(group, s, "passed", {{"sm5_tp", t}, {"d_h_mean", d}, {"scans", scans}}));
  }
  return cases;
}

inline json Suite(const std::vector<std::vector<json>>& groups) {
  json cases = json::array();
  for (const auto& g : groups)
    for (const auto& c : g) cases.push_back(c);
  return {{"format", "mopad-suite"},
          {"version", 1},
          {"suite", "synthetic"},
          {"manifest", "suites/synthetic.yaml"},
          {"figure_info", FigureInfo()},
          {"cases", cases},
          {"pooled", json::array()},
          {"totals",
           {{"cases", cases.size()},
            {"passed", cases.size()},
            {"failed", 0},
            {"error", 0},
            {"timeout", 0},
            {"crashed", 0}}}};
}

}  // namespace mopad::test_support
