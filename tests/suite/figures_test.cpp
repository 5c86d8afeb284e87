#include <gtest/gtest.h>

#include "suite/figures.h"
#include "suite/reachable_rooms.h"

namespace mopad::suite {
namespace {

TEST(SuiteFigures, DottedPathsReadKeysListIndicesAndBooleans) {
  const nlohmann::json j = nlohmann::json::parse(
      R"({"a": {"b": [{"c": 3.5}, {"c": true}]}, "s": "text"})");
  EXPECT_EQ(NumberAt(j, "a.b.0.c"), 3.5);
  EXPECT_EQ(NumberAt(j, "a.b.1.c"), 1.0);
  EXPECT_FALSE(NumberAt(j, "a.b.2.c"));
  EXPECT_FALSE(NumberAt(j, "s"));
  EXPECT_FALSE(NumberAt(j, "a.x"));
}

TEST(SuiteFigures, MainFiguresComeFromSummaryAndEvaluation) {
  CaseFiles f;
  f.summary = nlohmann::json::parse(R"({"mission": {"scans": 30, "detail_scans": 10,
      "contacts": 0, "localisation_max_m": 0.04},
      "rooms": [{"room": "R1", "status": "scanned"}, {"room": "R2", "status": "failed"},
                {"room": "", "status": "scanned"}]})");
  f.eval = nlohmann::json::parse(R"({"summary": {"detection": {"wall": {"n_truth": 24, "tp": 23,
      "fp": 1, "fn": 1}}, "components": {"all": {"tp_share": 0.95},
      "classes": [{"class": "switch", "n": 16, "tp_share": 0.875}]}}})");
  f.rooms_reachable = 3;
  const Figures g = ExtractFigures(f, {"summary.mission.contacts", "eval.summary.nothing"});
  EXPECT_EQ(g.at("scans"), 30);
  EXPECT_EQ(g.at("structural_scans"), 20);
  EXPECT_EQ(g.at("rooms_modelled"), 1);  // only R1: R2 failed, "" is no truth room
  EXPECT_EQ(g.at("rooms_missed"), 2);
  EXPECT_DOUBLE_EQ(g.at("wall_precision"), 23.0 / 24.0);
  EXPECT_DOUBLE_EQ(g.at("wall_recall"), 23.0 / 24.0);
  EXPECT_DOUBLE_EQ(g.at("sm5_tp_rate"), 0.95);
  EXPECT_DOUBLE_EQ(g.at("sm5_class.switch.tp_share"), 0.875);
  EXPECT_EQ(g.at("summary.mission.contacts"), 0);
  EXPECT_FALSE(g.count("eval.summary.nothing"));
  EXPECT_FALSE(g.count("sm4_precision"));  // not in the files: not a figure
  EXPECT_EQ(InfoOf("sm5_tp_rate").better, "higher");
  EXPECT_EQ(InfoOf("localisation_max_m").unit, "m");
  EXPECT_EQ(InfoOf("sm5_class.switch.fn_share").better, "lower");
  EXPECT_EQ(InfoOf("summary.x").better, "none");
}

// A -- B (open door, 0.9 m) -- C (closed door); B -- D (open, 0.6 m: too narrow); A -- E
// (open passage); A -- outside.
TEST(SuiteReachableRooms, OpenWideDoorsAndPassagesOnly) {
  scenes::GroundTruth t;
  for (const char* r : {"A", "B", "C", "D", "E"}) t.rooms.push_back({}), t.rooms.back().id = r;
  auto door = [&](const std::string& id, double w, double deg, DoorState s) {
    scenes::Opening o;
    o.id = id;
    o.u0 = 0.0;
    o.u1 = w;
    o.opening_angle = deg * M_PI / 180.0;
    o.state = s;
    t.openings.push_back(o);
  };
  door("D1", 0.9, 90, DoorState::kOpen);
  door("D2", 0.9, 0, DoorState::kClosed);
  door("D3", 0.6, 90, DoorState::kOpen);
  door("D4", 0.9, 90, DoorState::kOpen);
  t.connections = {{"D1", "A", "B"}, {"D2", "B", "C"}, {"D3", "B", "D"}, {"", "A", "E"},
                   {"D4", "A", ""}};
  EXPECT_NEAR(DoorClearWidth(t.openings[0]), 0.9 - 0.04, 1e-12);
  EXPECT_EQ(ReachableRooms(t, "A", 0.64), (std::set<std::string>{"A", "B", "E"}));
  EXPECT_EQ(ReachableRooms(t, "A", 0.5), (std::set<std::string>{"A", "B", "D", "E"}));
  EXPECT_TRUE(ReachableRooms(t, "Z", 0.64).empty());
}

}  // namespace
}  // namespace mopad::suite
