#include <gtest/gtest.h>

#include <set>

#include <yaml-cpp/yaml.h>

#include "common/error.h"
#include "suite/cases.h"
#include "suite/manifest.h"

namespace mopad::suite {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParseManifest(text, "dir/m.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A path that is the root (`/`, `/.`) names nothing to call the scene after; finding that out
// must end (the parent of "/" is "/") in an input error.
TEST(SuiteManifest, ASceneAtTheFilesystemRootWithoutANameIsRefused) {
  for (const char* path : {"/", "/.", "//", "/./"}) {
    SCOPED_TRACE(path);
    const std::string e = ErrorOf(std::string("scenes:\n  - spec: ") + path + "\n");
    EXPECT_NE(e.find("names no file or folder to call the scene after; got '/"),
              std::string::npos)
        << e;
  }
  EXPECT_EQ(ParseManifest("scenes:\n  - folder: floors/b/\n", "m.yaml").scenes.at(0).name, "b");
  EXPECT_EQ(ParseManifest("scenes:\n  - spec: a.yaml\n", "dir/m.yaml").name, "m");
  EXPECT_EQ(ParseManifest("scenes:\n  - folder: /\n    name: all\n", "m.yaml").scenes.at(0).name,
            "all");
}

TEST(SuiteManifest, RandomFloorsOfAFamilyAreNamedByIt) {
  const Manifest m =
      ParseManifest("scenes:\n  - random: {seeds: 3, rooms: 4, family: hall}\n  - random: "
                    "{seeds: 3, rooms: 4}\n",
                    "suites/f.yaml");
  ASSERT_EQ(m.scenes.size(), 2u);
  EXPECT_EQ(m.scenes[0].name, "random-hall-s3-r4");
  EXPECT_EQ(m.scenes[0].random_family, "hall");
  EXPECT_EQ(m.scenes[1].name, "random-s3-r4");
  EXPECT_EQ(m.scenes[1].random_family, "office");
}

TEST(SuiteManifest, ParsesScenesSeedsConfigsSweepsLimitsAndChecks) {
  const Manifest m = ParseManifest(R"(suite: demo
scenes:
  - spec: ../scenes/one_room.yaml
  - folder: /abs/floor
    limits: {wall_s: 5}
  - random: {seeds: 1-2, rooms: [3, 5]}
  - import: {file: fzk.ifc, storey: "0. EG", args: [--ceiling-from-spaces]}
seeds: [1-3, 7]
configs:
  base: null
  nodetail: {detail: {enabled: false}}
sweeps:
  - {key: room.scan.scan_step_deg, values: [0.2, 0.4]}
limits: {wall_s: 600, memory_mb: 4000}
keep: models
run_args: [--step-deg, "0.5"]
checks:
  - sm5_tp_rate >= 0.9
  - mean(d_h_mean) <= 1 cm
)",
                                   "suites/demo.yaml");
  EXPECT_EQ(m.name, "demo");
  ASSERT_EQ(m.scenes.size(), 7u);  // spec, folder, 4 random, import
  EXPECT_EQ(m.scenes[0].path, "scenes/one_room.yaml");
  EXPECT_EQ(m.scenes[0].name, "one_room");
  EXPECT_EQ(m.scenes[1].name, "floor");
  EXPECT_DOUBLE_EQ(m.scenes[1].limits->wall_s, 5.0);
  EXPECT_DOUBLE_EQ(m.scenes[1].limits->memory_mb, 4000.0);  // the suite's, not given here
  EXPECT_EQ(m.scenes[2].name, "random-s1-r3");
  EXPECT_EQ(m.scenes[5].name, "random-s2-r5");
  EXPECT_EQ(m.scenes[6].kind, SceneEntry::Kind::kImport);
  EXPECT_EQ(m.scenes[6].path, "suites/fzk.ifc");
  EXPECT_EQ(m.scenes[6].args, std::vector<std::string>{"--ceiling-from-spaces"});
  EXPECT_EQ(m.seeds, (std::vector<std::uint64_t>{1, 2, 3, 7}));
  ASSERT_EQ(m.configs.size(), 2u);
  EXPECT_EQ(m.configs[1].name, "nodetail");
  EXPECT_EQ(m.keep, "models");
  EXPECT_DOUBLE_EQ(m.limits.memory_mb, 4000.0);
  ASSERT_EQ(m.checks.size(), 1u);
  ASSERT_EQ(m.pooled_checks.size(), 1u);
  EXPECT_DOUBLE_EQ(m.pooled_checks[0].bound, 0.01);
  // 7 scenes x 2 configs x 2 sweep values x 4 seeds.
  const std::vector<Case> cases = ExpandCases(m);
  ASSERT_EQ(cases.size(), 7u * 2 * 2 * 4);
  EXPECT_EQ(cases[0].id, "one_room/base/room.scan.scan_step_deg=0.2/seed-1");
  EXPECT_DOUBLE_EQ(cases[4 * 4].limits.wall_s, 5.0);  // the folder scene's own limit
  EXPECT_DOUBLE_EQ(cases[0].limits.wall_s, 600.0);
}

TEST(SuiteManifest, UnknownKeysAndBadValuesNameFileAndLine) {
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\nsedes: [1]\n").find("dir/m.yaml:3: error: unknown key 'sedes'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\n    colour: red\n").find("dir/m.yaml:3"),
            std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\nchecks:\n  - sm5 ~ 3\n").find("dir/m.yaml:4: error: bad check"),
            std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\nseeds: 3-1\n").find("dir/m.yaml:3"), std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - random: {seeds: 1, rooms: 12}\n").find("2-10"), std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - random: {seeds: 1, rooms: 3, family: atrium}\n")
                .find(":2: error: bad random.family"),
            std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\n  - spec: b/a.yaml\n").find("two scenes named 'a'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("seeds: [1]\n").find("scenes: missing"), std::string::npos);
  EXPECT_NE(ErrorOf("scenes:\n  - spec: a.yaml\n    folder: b\n").find("exactly one source"),
            std::string::npos);
  EXPECT_NE(ErrorOf("scenes: [\n").find("dir/m.yaml:"), std::string::npos);
}

TEST(SuiteCases, IdsAreTheSameWhateverTheShardCount) {
  const Manifest m = ParseManifest(
      "scenes:\n  - spec: a.yaml\n  - spec: b.yaml\n  - random: {seeds: 4, rooms: 3}\nseeds: 1-5\n",
      "m.yaml");
  const std::vector<Case> all = ExpandCases(m);
  ASSERT_EQ(all.size(), 15u);
  std::set<std::string> ids;
  for (const auto& c : all) ids.insert(c.id);
  EXPECT_EQ(ids.size(), all.size());
  EXPECT_EQ(all[0].id, "a/seed-1");
  EXPECT_EQ(all[14].id, "random-s4-r3/seed-5");
  for (int n : {1, 2, 3, 4, 7, 20}) {
    std::multiset<std::string> seen;
    for (int i = 1; i <= n; ++i) {
      const Shard s = ParseShard(std::to_string(i) + "/" + std::to_string(n));
      for (const auto& c : ExpandCases(m))
        if (s.Contains(c)) seen.insert(c.id);
    }
    EXPECT_EQ(std::set<std::string>(seen.begin(), seen.end()), ids) << n << " shards";
    EXPECT_EQ(seen.size(), ids.size()) << n << " shards overlap";
  }
  EXPECT_THROW(ParseShard("0/3"), InputError);
  EXPECT_THROW(ParseShard("4/3"), InputError);
  EXPECT_THROW(ParseShard("1-3"), InputError);
}

TEST(SuiteCases, TheCaseConfigIsTheOverlayWithTheSweepKeysSet) {
  const Manifest m = ParseManifest(R"(scenes: [{spec: a.yaml}]
configs:
  nodetail: {detail: {enabled: false}, room: {max_scans: 8}}
sweeps:
  - {key: room.scan.scan_step_deg, values: [0.4]}
)",
                                   "m.yaml");
  const std::vector<Case> cases = ExpandCases(m);
  ASSERT_EQ(cases.size(), 1u);
  const YAML::Node y = YAML::Load(CaseConfigYaml(m, cases[0]));
  EXPECT_FALSE(y["detail"]["enabled"].as<bool>());
  EXPECT_EQ(y["room"]["max_scans"].as<int>(), 8);
  EXPECT_DOUBLE_EQ(y["room"]["scan"]["scan_step_deg"].as<double>(), 0.4);
  const Manifest plain = ParseManifest("scenes: [{spec: a.yaml}]\n", "m.yaml");
  EXPECT_EQ(CaseConfigYaml(plain, ExpandCases(plain)[0]), "");
}

}  // namespace
}  // namespace mopad::suite
