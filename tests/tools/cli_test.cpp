// The `mopad` CLI end to end: it is what users and CI call.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/tools/mopad_cli.h"

namespace {

namespace fs = std::filesystem;

using mopad::test_support::Mopad;
using mopad::test_support::RunFiles;
using mopad::test_support::Src;
using mopad::test_support::TempDir;
using Result = mopad::test_support::CommandResult;  // out: stdout and stderr together

// The default scene is generated once and shared by the tests that read it.
const std::string& OfficeDir() {
  static const std::string dir = [] {
    const std::string d = TempDir("office");
    const Result r = Mopad("scene generate " + Src("scenes/office_5rooms.yaml") + " -o " + d);
    EXPECT_EQ(r.code, 0) << r.out;
    return d;
  }();
  return dir;
}

TEST(Cli, HelpListsTheCommandsAndExitsZero) {
  const Result r = Mopad("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"scene", "scan", "lrf", "bench", "run"})
    EXPECT_NE(r.out.find(c), std::string::npos) << c << "\n" << r.out;
  EXPECT_EQ(Mopad("scene generate --help").code, 0);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(Mopad("").code, 2);
  EXPECT_EQ(Mopad("no-such-command").code, 2);
  EXPECT_EQ(Mopad("scene generate").code, 2);  // missing spec and -o
}

TEST(Cli, MissingSceneIsOneLineErrorExitTwo) {
  const Result r = Mopad("scene info /nonexistent/scene.glb");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "mopad: /nonexistent/scene.glb: error: no such scene file or folder\n");
}

TEST(Cli, SpecWithUnknownKeyNamesFileAndLine) {
  const std::string d = TempDir("badspec");
  const std::string spec = d + "/bad.yaml";
  std::ifstream in(Src("scenes/one_room.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::ofstream(spec) << text.str() << "colour_of_the_sky: blue\n";
  const Result r = Mopad("scene generate " + spec + " -o " + d + "/out");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(spec + ":"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("colour_of_the_sky"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

TEST(Cli, DefaultSceneHasThePapersCounts) {
  const Result r = Mopad("scene info --json " + OfficeDir());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const auto& t = j.at("truth");
  EXPECT_EQ(t.at("rooms"), 5);
  EXPECT_EQ(t.at("walls"), 24);
  EXPECT_EQ(t.at("doors").at("total"), 13);
  EXPECT_EQ(t.at("windows"), 10);
  const auto& b = t.at("service_components");
  EXPECT_EQ(b.at("total"), 116);
  const std::map<std::string, int> table3 = {{"electrical_panel", 4},
                                             {"socket_x1", 20},
                                             {"socket_x2", 6},
                                             {"socket_x4", 11},
                                             {"built_in_socket", 6},
                                             {"switch", 16},
                                             {"fire_extinguisher", 9},
                                             {"radiator", 6},
                                             {"fire_alarm_switch", 8},
                                             {"smoke_detector", 10},
                                             {"exit_light", 3},
                                             {"extinguisher_sign", 9},
                                             {"fire_alarm_switch_sign", 8}};
  for (const auto& [cls, n] : table3) EXPECT_EQ(b.at("per_class").value(cls, -1), n) << cls;
  // Doors: at least one open, the rest a mix of closed and semi-open.
  EXPECT_GE(t.at("doors").at("open"), 1);
  EXPECT_GE(t.at("doors").at("closed"), 1);
  EXPECT_GE(t.at("doors").at("semi_open"), 1);
  // Geometry labels agree with the truth: 24 wall elements carry triangles.
  EXPECT_EQ(j.at("classes").at("wall").at("elements"), 24);
  // Footprint 22.9 m x 19.4 m (outer dimensions, walls included).
  const auto& mn = j.at("bounds").at("min");
  const auto& mx = j.at("bounds").at("max");
  EXPECT_NEAR(mx[0].get<double>() - mn[0].get<double>(), 22.9, 0.05);
  EXPECT_NEAR(mx[1].get<double>() - mn[1].get<double>(), 19.4, 0.05);
}

TEST(Cli, DefaultSceneValidates) {
  const Result r = Mopad("scene validate " + OfficeDir());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find(": 0 errors"), std::string::npos) << r.out;
}

TEST(Cli, ValidateCatchesTruthThatDisagreesWithGeometry) {
  // Regression: a service component moved along its wall in the truth only was not caught.
  const std::string d = TempDir("badtruth");
  fs::copy(OfficeDir(), d, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::ifstream in(d + "/scene.truth.json");
  auto truth = nlohmann::json::parse(in);
  in.close();
  truth["service_components"][0]["centre"][0] =
      truth["service_components"][0]["centre"][0].get<double>() + 0.5;
  truth["service_components"][0]["centre"][1] =
      truth["service_components"][0]["centre"][1].get<double>() + 0.5;
  std::ofstream(d + "/scene.truth.json") << truth.dump();
  const Result r = Mopad("scene validate " + d);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("does not match its truth centre"), std::string::npos) << r.out;
}

// Runs the Khronos validator on `glb`; empty when node or the validator is not installed.
std::optional<std::string> KhronosValidate(const std::string& glb, int* status) {
  const fs::path modules(MOPAD_NODE_MODULES);
  if (std::system("node --version >/dev/null 2>&1") != 0 ||
      !fs::exists(modules / "gltf-validator" / "package.json"))
    return std::nullopt;
  const std::string cmd = "node " + Src("tools/validators/validate_gltf.js") + " " + glb + " " +
                          modules.string() + " 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return std::nullopt;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), p)) out += buf.data();
  *status = pclose(p);
  return out;
}

TEST(Cli, MainJobScansEveryRoomAndWritesModelsEvaluationAndReportDeterministically) {
  const std::string d = TempDir("run");
  const std::string args = "run --spec " + Src("scenes/one_room.yaml") + " --step-deg 0.5 -o ";
  const Result a = Mopad(args + d + "/a");
  ASSERT_EQ(a.code, 0) << a.out;
  const Result b = Mopad(args + d + "/b");
  ASSERT_EQ(b.code, 0) << b.out;
  // A finished run's checkpoint is marked complete; resuming it says so and changes nothing.
  const Result again = Mopad("run --resume " + d + "/a");
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_NE(again.out.find("the run is complete"), std::string::npos) << again.out;
  std::ifstream in(d + "/a/summary.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("rooms").size(), 1u);
  const auto& room = j.at("rooms")[0];
  EXPECT_GE(room.at("scans").get<int>(), 1);
  EXPECT_GT(room.at("evaluation").at("coverage_of_total").get<double>(), 0.5);
  EXPECT_GT(room.at("evaluation").at("sm1_labels").at("accuracy").get<double>(), 0.9);
  for (const char* f :
       {"report.html", "report.md", "scene/scene.glb", "scene/scene.truth.json",
        "rooms/R1/run.json", "rooms/R1/evaluation.json", "rooms/R1/models.glb", "rooms/R1/sm2.json",
        "rooms/R1/dsm3.ply", "eval/evaluation.json", "eval/evaluation.md"})
    EXPECT_TRUE(fs::exists(d + "/a/" + f)) << f;
  // Every file was written whole and renamed into place (common/atomic_file.h): no temporary
  // file remains.
  for (const auto& e : fs::recursive_directory_iterator(d + "/a"))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  // The models are scored against the truth in the same job (mopad eval's figures).
  const auto& ms = j.at("models_evaluation").at("summary");
  EXPECT_EQ(ms.at("detection").at("wall").at("tp").get<int>(),
            ms.at("detection").at("wall").at("n_truth").get<int>());
  EXPECT_GT(ms.at("detection").at("wall").at("n_truth").get<int>(), 0);
  EXPECT_GT(ms.at("isprs_completeness").get<double>(), 0.9);
  {
    std::ifstream ea(d + "/a/eval/evaluation.json"), eb(d + "/b/eval/evaluation.json");
    auto ja = nlohmann::json::parse(ea), jb = nlohmann::json::parse(eb);
    ja.erase("run_dir"), jb.erase("run_dir");  // the two output folders differ
    for (auto* x : {&ja, &jb})
      for (auto& r : (*x)["rooms"])
        r.erase("run_dir"), r["mission"].erase("seconds");  // wall clock
    EXPECT_EQ(ja.dump(), jb.dump()) << "eval/evaluation.json differs between two runs";
  }
  for (const char* f : {"/rooms/R1/sm1.ply", "/rooms/R1/sm3.json", "/rooms/R1/trajectory_true.tum",
                        "/rooms/R1/scans.json", "/floor/sm3.json", "/floor/sm4.json"}) {
    std::ifstream fa(d + "/a" + f, std::ios::binary), fb(d + "/b" + f, std::ios::binary);
    std::string sa((std::istreambuf_iterator<char>(fa)), {});
    std::string sb((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_FALSE(sa.empty()) << f;
    if (std::string(f) == "/rooms/R1/scans.json") {  // wall-clock timings differ; drop them
      auto strip = [](std::string s) {
        auto js = nlohmann::json::parse(s);
        js.erase("wall_time");
        if (js.contains("detail")) js["detail"].erase("wall_time");
        for (auto& x : js["scans"]) x.erase("seconds");
        return js.dump();
      };
      sa = strip(sa), sb = strip(sb);
    }
    EXPECT_TRUE(sa == sb) << f << " differs between two runs with the same seed";
  }
  int status = 0;
  if (const auto out = KhronosValidate(d + "/a/rooms/R1/models.glb", &status)) {
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << *out;
    EXPECT_NE(out->find("errors=0 "), std::string::npos) << *out;
  }
  // The deliverables (docs/exports.md) of two runs of the same seed: the same bytes.
  for (const char* run : {"/a", "/b"}) {
    const Result e = Mopad("export all " + d + run);
    ASSERT_EQ(e.code, 0) << e.out;
  }
  auto bytes = [](const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), {});
  };
  for (const char* f : {"model.ifc", "model.glb", "sm1.las"}) {
    const std::string fa = bytes(d + "/a/export/" + f);
    EXPECT_FALSE(fa.empty()) << f;
    EXPECT_TRUE(fa == bytes(d + "/b/export/" + f)) << f << " differs between two runs";
  }
}

TEST(Cli, ResumeWithoutACheckpointOrWithOtherRunOptionsIsOneLineExitTwo) {
  const std::string d = TempDir("resume_empty");
  const Result r = Mopad("run --resume " + d);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("error: nothing to resume"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  fs::create_directories(d + "/checkpoint");
  std::ofstream(d + "/checkpoint/manifest.json") << "{\"format\": \"mopad-checkpoint\", \"ver";
  const Result torn = Mopad("run --resume " + d);
  EXPECT_EQ(torn.code, 2) << torn.out;
  EXPECT_NE(torn.out.find("corrupt checkpoint manifest"), std::string::npos) << torn.out;
  EXPECT_EQ(std::count(torn.out.begin(), torn.out.end(), '\n'), 1) << torn.out;
  EXPECT_EQ(Mopad("run --resume " + d + " --seed 2").code, 2);
}

TEST(Cli, RunKilledWithSigkillAfterItsFirstRoomAndResumedWritesTheFilesOfAnUninterruptedRun) {
  const std::string d = TempDir("resume_kill");
  const std::string spec = Src("scenes/two_rooms_door.yaml");
  const std::string args = "run -q --spec " + spec + " --step-deg 0.5 -o " + d + "/run";
  // The uninterrupted run writes to the same path (eval/ names its run folder), then moves aside.
  ASSERT_EQ(Mopad(args).code, 0);
  fs::rename(d + "/run", d + "/whole");

  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(127);
    execl(MOPAD_BINARY, "mopad", "run", "-q", "--spec", spec.c_str(), "--step-deg", "0.5", "-o",
          (d + "/run").c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Killed as soon as its checkpoint holds the first room: in the middle of the second.
  bool first_room = false;
  for (int k = 0; k < 2400 && !first_room; ++k) {
    usleep(50000);
    std::ifstream m(d + "/run/checkpoint/manifest.json");
    const std::string s((std::istreambuf_iterator<char>(m)), {});
    first_room = s.find("\"index\": 1") != std::string::npos;
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(first_room) << "the run wrote no room boundary in 120 s";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";
  EXPECT_FALSE(fs::exists(d + "/run/summary.json"));

  const Result resumed = Mopad("run -q --resume " + d + "/run");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  const auto whole = RunFiles(d + "/whole"), run = RunFiles(d + "/run");
  ASSERT_GT(whole.size(), 20u);
  for (const auto& [name, bytes] : whole) {
    ASSERT_TRUE(run.count(name)) << name << " missing after the resume";
    EXPECT_TRUE(run.at(name) == bytes) << name << " differs after the resume";
  }
  EXPECT_EQ(whole.size(), run.size());
  EXPECT_NE(Mopad("run --resume " + d + "/run").out.find("the run is complete"), std::string::npos);
}

TEST(Cli, ExportHelpNamesItsFilesAndAFolderWithoutModelsIsOneLineExitTwo) {
  const Result help = Mopad("export --help");
  EXPECT_EQ(help.code, 0);
  for (const char* f : {"model.ifc", "model.glb", "sm1.las", "export.json"})
    EXPECT_NE(help.out.find(f), std::string::npos) << f << "\n" << help.out;
  const std::string d = TempDir("export_empty");
  const Result r = Mopad("export all " + d);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("error: no model to export"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

TEST(Cli, EvalModelInputErrorsAreOneLineExitTwoBeforeAnyFile) {
  const std::string d = TempDir("eval_model_bad");
  const std::string out = d + "/out";
  for (const std::string& args :
       {"eval --model " + d + "/none.ifc --scene " + OfficeDir() + " -o " + out,
        "eval --model " + Src("README.md") + " --scene " + OfficeDir() + " -o " + out,
        "eval --model " + d + "/none.ifc -o " + out,  // no truth
        "eval --model x.ifc --scene " + OfficeDir() + " --pose 1,2 -o " + out,
        std::string("eval")}) {
    const Result r = Mopad(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << "\n" << r.out;
  }
  // Usage errors (CLI11): exit 2 with the help hint.
  EXPECT_EQ(Mopad("eval --model x.ifc --scene s --align maybe -o " + out).code, 2);
  EXPECT_EQ(Mopad("eval " + d + " --model x.ifc").code, 2);
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, DefaultSceneGlbPassesTheKhronosValidator) {
  int status = 0;
  const auto out = KhronosValidate(OfficeDir() + "/scene.glb", &status);
  if (!out)
    GTEST_SKIP() << "node or npm gltf-validator not installed (scripts/test.sh installs it)";
  std::printf("%s", out->c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << *out;
  EXPECT_NE(out->find("errors=0 "), std::string::npos) << *out;
}

TEST(Cli, SameSpecGivesIdenticalBytes) {
  const std::string d = TempDir("twice");
  ASSERT_EQ(Mopad("scene generate " + Src("scenes/two_rooms_door.yaml") + " -o " + d + "/a").code,
            0);
  ASSERT_EQ(Mopad("scene generate " + Src("scenes/two_rooms_door.yaml") + " -o " + d + "/b").code,
            0);
  for (const char* f : {"scene.glb", "scene.truth.json"}) {
    std::ifstream a(d + "/a/" + f, std::ios::binary), b(d + "/b/" + f, std::ios::binary);
    const std::string sa((std::istreambuf_iterator<char>(a)), {});
    const std::string sb((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(sa.empty());
    EXPECT_TRUE(sa == sb) << f;
  }
}

TEST(Cli, RandomFloorValidates) {
  const std::string d = TempDir("random");
  const Result g = Mopad("scene random --seed 11 --rooms 6 -o " + d);
  ASSERT_EQ(g.code, 0) << g.out;
  const Result v = Mopad("scene validate " + d);
  EXPECT_EQ(v.code, 0) << v.out;
  EXPECT_EQ(Mopad("scene random --seed 1 --rooms 41 -o " + d + "/x").code, 2);
}

TEST(Cli, CatalogueHasTheEighteenModels) {
  const std::string d = TempDir("catalogue");
  const Result r = Mopad("scene catalogue -o " + d);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("wrote 18 object models"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d + "/catalogue.yaml"));
}

TEST(Cli, KitHouseInfoThroughBothLoaders) {
  const std::string ifc = Src("../shared/testdata/external/kit_fzk_haus/AC14-FZK-Haus.ifc");
  const std::string glb = Src("../shared/testdata/external/kit_fzk_haus/AC14-FZK-Haus.assimp.glb");
  if (!fs::exists(ifc)) GTEST_SKIP() << "shared test data absent";
  const Result a = Mopad("scene info --json " + ifc);
  const Result b = Mopad("scene info --json " + glb);
  ASSERT_EQ(a.code, 0) << a.out;
  ASSERT_EQ(b.code, 0) << b.out;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja.at("triangles"), jb.at("triangles"));
  EXPECT_EQ(ja.at("classes"), jb.at("classes"));
}

}  // namespace

namespace {
std::string ReadFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
}  // namespace

// Parameter precedence (docs/architecture.md): a flag given on the command line, over the
// --config file, over the default; the effective config records what ran, seed included.
TEST(Cli, AFlagOverridesTheConfigFileWhichOverridesTheDefault) {
  const std::string dir = TempDir("precedence");
  const std::string cfg = dir + "/drive.yaml";
  std::ofstream(cfg) << "seed: 7\nmax_time: 3.5\n";
  const std::string base =
      "drive " + Src("scenes/two_rooms_door.yaml") + " --from 1.5,2,0 --to 8,2,0 ";
  const Result file = Mopad(base + "--config " + cfg + " -o " + dir + "/file");
  ASSERT_EQ(file.code, 0) << file.out;
  const std::string eff_file = ReadFile(dir + "/file/drive.effective.yaml");
  EXPECT_NE(eff_file.find("seed: 7\n"), std::string::npos) << eff_file;
  EXPECT_NE(eff_file.find("max_time: 3.5\n"), std::string::npos) << eff_file;
  const Result flag =
      Mopad(base + "--config " + cfg + " --seed 9 --max-time 4.5 -o " + dir + "/flag");
  ASSERT_EQ(flag.code, 0) << flag.out;
  const std::string eff_flag = ReadFile(dir + "/flag/drive.effective.yaml");
  EXPECT_NE(eff_flag.find("seed: 9\n"), std::string::npos) << eff_flag;
  EXPECT_NE(eff_flag.find("max_time: 4.5\n"), std::string::npos) << eff_flag;
  const Result none = Mopad(base + "--max-time 2.5 -o " + dir + "/default");
  ASSERT_EQ(none.code, 0) << none.out;
  const std::string eff_default = ReadFile(dir + "/default/drive.effective.yaml");
  EXPECT_NE(eff_default.find("seed: 1\n"), std::string::npos) << eff_default;
  EXPECT_NE(eff_default.find("max_time: 2.5\n"), std::string::npos) << eff_default;
}

namespace {

// The "W x H" a `mopad scene plan` run reports ("wrote FILE (W x H)").
std::string PlanSize(const std::string& out) {
  const auto open = out.rfind('(');
  return open == std::string::npos ? "" : out.substr(open + 1, out.find(')', open) - open - 1);
}

}  // namespace

// `scene plan --config`: the file's value is used, a given flag overrides it, a flag not given
// does not.
TEST(Cli, ScenePlanTakesItsParamsFromTheConfigAndAFlagOverridesIt) {
  const std::string dir = TempDir("plan_config");
  const std::string cfg = dir + "/plan.yaml";
  std::ofstream(cfg) << "pixel_size: 0.05\nmargin: 0\n";
  const Result def = Mopad("scene plan " + OfficeDir() + " -o " + dir + "/default.png");
  const Result file = Mopad("scene plan " + OfficeDir() + " --config " + cfg + " -o " + dir +
                            "/file.png --cut-height 1.0");
  const Result flag = Mopad("scene plan " + OfficeDir() + " --config " + cfg +
                            " --pixel-size 0.1 -o " + dir + "/flag.png");
  ASSERT_EQ(def.code, 0) << def.out;
  ASSERT_EQ(file.code, 0) << file.out;
  ASSERT_EQ(flag.code, 0) << flag.out;
  int dw = 0, dh = 0, fw = 0, fh = 0, gw = 0, gh = 0;
  ASSERT_EQ(std::sscanf(PlanSize(def.out).c_str(), "%d x %d", &dw, &dh), 2) << def.out;
  ASSERT_EQ(std::sscanf(PlanSize(file.out).c_str(), "%d x %d", &fw, &fh), 2) << file.out;
  ASSERT_EQ(std::sscanf(PlanSize(flag.out).c_str(), "%d x %d", &gw, &gh), 2) << flag.out;
  // Default 0.02 m pixels with a 1 m margin; the file's 0.05 m with none; the flag's 0.1 m.
  EXPECT_NEAR(fw, (dw * 0.02 - 2.0) / 0.05, 2.0) << def.out << file.out;
  EXPECT_NEAR(gw, (dw * 0.02 - 2.0) / 0.1, 2.0) << def.out << flag.out;
  EXPECT_NEAR(gh * 2.0, fh, 2.0) << file.out << flag.out;
}

TEST(Cli, SceneImportAndPlanRejectAnUnknownConfigKeyWithItsLine) {
  const std::string dir = TempDir("scene_config_typo");
  const std::string cfg = dir + "/typo.yaml";
  std::ofstream(cfg) << "door_angle_deg: 45\ndoor_angel: 30\n";
  const Result imp = Mopad("scene import no_such.ifc --config " + cfg + " -o " + dir + "/out");
  EXPECT_EQ(imp.code, 2) << imp.out;
  EXPECT_NE(imp.out.find(cfg + ":2:"), std::string::npos) << imp.out;
  EXPECT_NE(imp.out.find("door_angel"), std::string::npos) << imp.out;
  EXPECT_EQ(std::count(imp.out.begin(), imp.out.end(), '\n'), 1) << imp.out;
  std::ofstream(cfg) << "pixel_size: 0.05\ncut_hieght: 1\n";
  const Result plan =
      Mopad("scene plan " + OfficeDir() + " --config " + cfg + " -o " + dir + "/p.png");
  EXPECT_EQ(plan.code, 2) << plan.out;
  EXPECT_NE(plan.out.find(cfg + ":2:"), std::string::npos) << plan.out;
  EXPECT_NE(plan.out.find("cut_hieght"), std::string::npos) << plan.out;
}

// `scene import --config`: the storey the file names is the one looked for, and --storey
// overrides it (the KIT house has no such storeys: the refusal names the one used).
TEST(Cli, SceneImportTakesItsParamsFromTheConfigAndAFlagOverridesIt) {
  const std::string ifc = Src("../shared/testdata/external/kit_fzk_haus/AC14-FZK-Haus.ifc");
  if (!fs::exists(ifc)) GTEST_SKIP() << "shared test data absent";
  const std::string dir = TempDir("import_config");
  const std::string cfg = dir + "/import.yaml";
  std::ofstream(cfg) << "storey: From the file\nceiling_from_spaces: true\n";
  const Result file = Mopad("scene import " + ifc + " --config " + cfg + " -o " + dir + "/a");
  EXPECT_EQ(file.code, 2) << file.out;
  EXPECT_NE(file.out.find("From the file"), std::string::npos) << file.out;
  const Result flag = Mopad("scene import " + ifc + " --config " + cfg +
                            " --storey 'From the flag' -o " + dir + "/b");
  EXPECT_EQ(flag.code, 2) << flag.out;
  EXPECT_NE(flag.out.find("From the flag"), std::string::npos) << flag.out;
  EXPECT_EQ(flag.out.find("From the file"), std::string::npos) << flag.out;
}

// A start in a wall or outside the building is refused before any work, in one line naming the
// nearest free spot (the harness's free-space map, scenes/start_spot.h).
TEST(Cli, RunStartInAWallOrOutsideTheBuildingIsOneLineExitTwoNamingTheNearestFreeSpot) {
  // The wall between the open-plan office R1 and the hall H runs along y 7.4-7.6.
  const Result wall =
      Mopad("run --scene " + OfficeDir() + " --start 3.0,7.5,0 -q -o " + TempDir("start_wall"));
  EXPECT_EQ(wall.code, 2) << wall.out;
  EXPECT_NE(wall.out.find("--start 3.00,7.50,0.0: error: in collision with the scene "
                          "(wall_R1_4); nearest free spot"),
            std::string::npos)
      << wall.out;
  EXPECT_NE(wall.out.find("; nearest free spot "), std::string::npos) << wall.out;
  // One error line (stdout's scene line may come before or after it).
  const std::size_t line = wall.out.find("mopad: --start");
  ASSERT_NE(line, std::string::npos) << wall.out;
  EXPECT_NE(wall.out.substr(line, wall.out.find('\n', line) - line).find("nearest free spot"),
            std::string::npos)
      << wall.out;
  EXPECT_EQ(wall.out.find("error", wall.out.find('\n', line)), std::string::npos) << wall.out;
  const Result out =
      Mopad("run --scene " + OfficeDir() + " --start -5,-5,0 -q -o " + TempDir("start_out"));
  EXPECT_EQ(out.code, 2) << out.out;
  EXPECT_NE(out.out.find("outside the building"), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("nearest free spot"), std::string::npos) << out.out;
}

// The number of lines of `out` that hold "error".
int ErrorLines(const std::string& out) {
  std::istringstream in(out);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.find("error") != std::string::npos;
  return n;
}

// Input errors of `mopad run` are input errors: exit 2 and one line naming the value and what
// is expected, before any work (no room run, no summary; a bad config or argument before the
// output folder exists).
TEST(Cli, RunInputErrorsAreOneLineExitTwoBeforeAnyWork) {
  struct Case {
    std::string args, message;
    bool folder;  // the output folder may exist (the scene had to be read to know)
  };
  const std::string cfg = TempDir("bad_configs");
  fs::create_directories(cfg);
  const auto config = [&](const std::string& name, const std::string& text) {
    std::ofstream(cfg + "/" + name) << text;
    return "--config " + cfg + "/" + name;
  };
  const std::vector<Case> cases = {
      {"--start 500,500,0", "--start 500.00,500.00,0.0: error: outside the building", true},
      {"--start nan,1,0", "--start: error: not a finite number; got 'nan,1,0'", false},
      {"--room NOPE", "--room: error: unknown room; got 'NOPE', expected one of R1, ", true},
      {"--room R1 --room NOPE", "--room: error: unknown room; got 'NOPE'", true},
      {config("step.yaml", "scan_step_deg: -1\n"),
       "step.yaml:1: error: parameter 'scan_step_deg' out of range; got -1.000000, expected "
       "[0.020000, 5.000000]",
       false},
      {config("nan.yaml", "scan_step_deg: .nan\n"),
       "parameter 'scan_step_deg' out of range; got nan", false},
      {config("empty.yaml", "scan_step_deg:\n"),
       "error: wrong type for 'scan_step_deg'; got null, expected a number", false},
      {config("time.yaml", "drive:\n  max_time: 0\n"),
       "time.yaml:2: error: parameter 'drive.max_time' out of range; got 0.000000", false},
      {config("neg_time.yaml", "drive:\n  local_controller:\n    stuck_timeout: -1\n"),
       "parameter 'drive.local_controller.stuck_timeout' out of range; got -1.000000", false},
      {config("profile.yaml", "drive:\n  tls_profile: \"\"\n"),
       "room.drive: error: parameter 'tls_profile' unknown; got '', expected one of riegl_vz400",
       false},
  };
  int i = 0;
  for (const Case& c : cases) {
    const std::string out = TempDir("input_error_" + std::to_string(i++)) + "/run";
    const Result r = Mopad("run --scene " + OfficeDir() + " " + c.args + " -q -o " + out);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find("mopad: "), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(ErrorLines(r.out), 1) << c.args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(out + "/summary.json")) << c.args;
    EXPECT_FALSE(fs::exists(out + "/rooms")) << c.args;
    if (!c.folder) {
      EXPECT_FALSE(fs::exists(out)) << c.args << ": the folder made before the check";
    }
  }
}

// `mopad scan`: an option not given leaves the profile's value (no value stands for "not
// given"), and a given value is used or refused, never ignored.
TEST(Cli, ScanUsesTheProfilesStepUnlessTheFlagIsGivenAndRefusesAGivenZero) {
  const std::string dir = TempDir("scan_step");
  const std::string profile = dir + "/tls.yaml";
  std::ofstream(profile) << "step_deg: 1.5\n";
  const std::string base = "scan " + OfficeDir() + " --pose 3,3,0,0 --profile-file " + profile;
  const Result file = Mopad(base + " -o " + dir + "/file.ply");
  ASSERT_EQ(file.code, 0) << file.out;
  EXPECT_NE(file.out.find("step 1.5 deg"), std::string::npos) << file.out;
  const Result flag = Mopad(base + " --step-deg 2 -o " + dir + "/flag.ply");
  ASSERT_EQ(flag.code, 0) << flag.out;
  EXPECT_NE(flag.out.find("step 2 deg"), std::string::npos) << flag.out;
  const Result zero = Mopad(base + " --step-deg 0 -o " + dir + "/zero.ply");
  EXPECT_EQ(zero.code, 2) << zero.out;
  EXPECT_NE(zero.out.find("step_deg"), std::string::npos) << zero.out;
  const Result rays = Mopad(base + " --footprint-rays 0 -o " + dir + "/rays.ply");
  EXPECT_EQ(rays.code, 2) << rays.out;
  EXPECT_NE(rays.out.find("footprint_rays"), std::string::npos) << rays.out;
}

namespace {

// `mopad suite run` on a real two-case suite (one_room, two seeds, the coarsest scan step):
// each case a mopad run of this binary, checked, pooled, and pruned to --keep summary.
TEST(Cli, SuiteRunsTwoRealCasesAndKeepsTheirSummaries) {
  const std::string d = TempDir("suite");
  {
    std::ofstream m(d + "/mini.yaml");
    m << "suite: mini\nscenes:\n  - spec: " << Src("scenes/one_room.yaml")
      << "\nseeds: 1-2\nrun_args: [--step-deg, \"1.0\"]\nchecks:\n  - rooms_missed <= 0\n"
         "  - wall_recall >= 1\n  - mean(rooms_modelled) >= 1\n";
    std::ofstream bad(d + "/bad.yaml");
    bad << "scenes:\n  - spec: x.yaml\nlimits: {wall_s: 10, memroy_mb: 5}\n";
  }
  const Result r = Mopad("suite run " + d + "/mini.yaml -o " + d + "/out --jobs 2 -q");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(d + "/out/suite.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("cases").size(), 2u);
  for (const auto& c : j.at("cases")) {
    EXPECT_EQ(c.at("verdict"), "passed") << c.dump();
    EXPECT_EQ(c.at("figures").at("rooms_reachable"), 1);
    EXPECT_EQ(c.at("figures").at("rooms_modelled"), 1);
    const std::string dir = d + "/out/" + c.at("dir").get<std::string>();
    EXPECT_TRUE(fs::exists(dir + "/report.html"));
    EXPECT_TRUE(fs::exists(dir + "/rooms/R1/sm3.json"));
    EXPECT_FALSE(fs::exists(dir + "/rooms/R1/sm1.ply"));  // --keep summary (the suite default)
    EXPECT_FALSE(fs::exists(dir + "/export/sm1.las"));
  }
  EXPECT_EQ(j.at("cases")[0].at("id"), "one_room/seed-1");
  EXPECT_EQ(j.at("totals").at("passed"), 2);
  // A second run into the folder without --resume, and a manifest with a typo: exit 2.
  const Result again = Mopad("suite run " + d + "/mini.yaml -o " + d + "/out -q");
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("--resume"), std::string::npos) << again.out;
  const Result bad = Mopad("suite run " + d + "/bad.yaml -o " + d + "/bad_out");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("bad.yaml:3: error: unknown key 'limits.memroy_mb'"), std::string::npos)
      << bad.out;
}

}  // namespace
