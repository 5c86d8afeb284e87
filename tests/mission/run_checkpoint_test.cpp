// `mopad run --resume` (mission/run_checkpoint.h): the checkpoint keeps the run's inputs bit for
// bit, refuses a missing, corrupt or changed one with one line, and a floor mission killed in
// the middle of its second room and resumed writes the bytes of an uninterrupted one
// (scenes/two_rooms_door.yaml: R1 and R2 joined by the open door D1).
#include "mission/run_checkpoint.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"
#include "common/params.h"
#include "io/text_file.h"
#include "mission/run_job.h"
#include "scenes/generator.h"
#include "sim/realism.h"
#include "sim/scene_world.h"
#include "tests/input_error_of.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;

std::string Spec() { return std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml"; }

std::string TempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("mopad_ckpt_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

RunInputs Inputs() {
  RunInputs in;
  in.params.room.scan.scan_step_deg = 0.4;  // coarser than the main job: the test's time
  in.params.room.drive.seed = 3;
  in.spec_name = Spec();
  in.spec_text = io::ReadTextFile(Spec());
  in.scene_source = Spec();
  in.start_W = Pose2{1.5, 2.0, 0.0};
  return in;
}

using test_support::InputErrorOf;

std::string Slurp(const fs::path& p) { return io::ReadTextFile(p.string()); }

// The wall-clock timings of the JSON files (scans.json, summary.json, evaluation.json): the
// only bytes a resumed run may write differently.
void DropTimings(nlohmann::json& j) {
  if (j.is_array())
    for (auto& x : j) DropTimings(x);
  if (!j.is_object()) return;
  for (const char* key :
       {"seconds", "wall_time", "wall_time_s", "tls_wall_time_s", "sm4_seconds", "sm5_seconds"})
    j.erase(key);
  for (auto& [k, v] : j.items()) DropTimings(v);
}

// Every file of a run folder (relative path -> bytes, JSON without its timings), the
// checkpoint aside.
std::map<std::string, std::string> Files(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), dir).generic_string();
    if (rel.rfind("checkpoint/", 0) == 0) continue;
    std::string bytes = Slurp(e.path());
    if (e.path().extension() == ".json") {
      nlohmann::json j = nlohmann::json::parse(bytes);
      DropTimings(j);
      bytes = j.dump(1);
    }
    out[rel] = std::move(bytes);
  }
  return out;
}

TEST(RunCheckpoint, KeepsTheInputsBitForBit) {
  const std::string dir = TempDir("inputs");
  RunInputs in = Inputs();
  // Values whose decimal text is not exact, and fields away from their defaults.
  in.params.room.drive.seed = 123456789012345ull;
  in.params.floor.door_exit = 1.0 / 3.0;
  in.params.floor.max_rooms = 7;
  in.params.room.scan.scan_step_deg = 0.1 + 0.2;
  in.start_W = Pose2{0.1 + 0.2, -1.0 / 7.0, 3.14159265358979 / 3.0};
  in.rooms = {"R2", "R1"};
  RunCheckpoint::Create(dir, in);
  const RunCheckpoint ck = RunCheckpoint::Open(dir);
  EXPECT_FALSE(ck.Complete());
  EXPECT_EQ(ck.Resumes(), 1);
  const RunInputs& back = ck.Inputs();
  EXPECT_EQ(YAML::Dump(SaveParams(back.params)), YAML::Dump(SaveParams(in.params)));
  EXPECT_EQ(back.params.floor.door_exit, in.params.floor.door_exit);
  EXPECT_EQ(back.params.room.scan.scan_step_deg, in.params.room.scan.scan_step_deg);
  ASSERT_TRUE(back.start_W.has_value());
  EXPECT_EQ(back.start_W->x, in.start_W->x);
  EXPECT_EQ(back.start_W->y, in.start_W->y);
  EXPECT_EQ(back.start_W->yaw, in.start_W->yaw);
  EXPECT_EQ(back.rooms, in.rooms);
  EXPECT_EQ(back.spec_text, in.spec_text);
  EXPECT_EQ(back.spec_name, in.spec_name);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "checkpoint" / "manifest.json.tmp"));
  fs::remove_all(dir);
}

TEST(RunCheckpoint, ARunGeneratesItsBuildingAsBuiltFromItsSeedWhenTheRealismSaysSo) {
  RunInputs in = Inputs();
  EXPECT_FALSE(RunSceneSpec(in).as_built.Enabled());  // ideal: the design
  EXPECT_FALSE(RunSceneSpec(in).details.Enabled());
  in.params.room.realism = sim::RealismProfile("typical");
  const scenes::SceneSpec spec = RunSceneSpec(in);
  EXPECT_TRUE(spec.as_built.Enabled());
  EXPECT_EQ(spec.as_built.flatness_mm, in.params.room.realism.geometry.flatness_mm);
  EXPECT_EQ(spec.as_built.seed, 3u);          // the run seed: one run, one building
  EXPECT_TRUE(spec.details.Enabled());        // and its details, from the same seed
  EXPECT_EQ(spec.details.seed, 3u);
  EXPECT_EQ(spec.details.posters_per_room, in.params.room.realism.details.posters_per_room);
  in.params.room.realism.geometry.seed = 11;  // a building of its own
  EXPECT_EQ(RunSceneSpec(in).as_built.seed, 11u);

  // A generated scene folder is built off its design from the spec it carries; without the
  // geometry, or without a spec (an imported storey), the folder is used as it is.
  const std::string dir = TempDir("as_built");
  scenes::WriteGeneratedScene(scenes::Generate(scenes::LoadSceneSpec(Spec())), dir + "/scene");
  RunRequest r;
  r.scene_dir = dir + "/scene";
  r.out = dir + "/typical";
  r.realism = "typical";
  const RunCheckpoint typical = StartRun(r);
  EXPECT_TRUE(typical.Inputs().scene_folder.empty());
  EXPECT_EQ(typical.Inputs().spec_text, Slurp(dir + "/scene/spec.effective.yaml"));
  EXPECT_TRUE(RunSceneSpec(typical.Inputs()).as_built.Enabled());
  r.out = dir + "/ideal";
  r.realism = "ideal";
  EXPECT_FALSE(StartRun(r).Inputs().scene_folder.empty());
  fs::remove(dir + "/scene/spec.effective.yaml");
  r.out = dir + "/typical_no_spec";
  r.realism = "typical";
  EXPECT_FALSE(StartRun(r).Inputs().scene_folder.empty());
  fs::remove_all(dir);
}

TEST(RunCheckpoint, ResumeWithoutACheckpointIsRefusedWithOneLine) {
  const std::string dir = TempDir("missing");
  const std::string e = InputErrorOf([&] { RunCheckpoint::Open(dir); });
  EXPECT_NE(e.find("nothing to resume"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_NE(InputErrorOf([&] { RunCheckpoint::Open(dir + "/no_such"); }).find("does not exist"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(RunCheckpoint, ACorruptOrChangedCheckpointIsRefused) {
  const std::string dir = TempDir("corrupt");
  const fs::path m = fs::path(dir) / "checkpoint" / "manifest.json";
  RunCheckpoint::Create(dir, Inputs());
  const std::string good = Slurp(m);

  io::WriteTextFile(m.string(), good.substr(0, good.size() / 2));  // a torn write
  EXPECT_NE(InputErrorOf([&] { RunCheckpoint::Open(dir); }).find("corrupt checkpoint manifest"),
            std::string::npos);

  io::WriteFileAtomically(m.string(), good);
  const fs::path config = fs::path(dir) / "checkpoint" / "config.yaml";
  const std::string config_text = Slurp(config);
  io::WriteFileAtomically(config.string(), config_text + "# edited\n");
  EXPECT_NE(InputErrorOf([&] { RunCheckpoint::Open(dir); }).find("config differs"),
            std::string::npos);

  io::WriteFileAtomically(config.string(), config_text);
  std::string other = good;
  other.replace(other.find("\"binary_hash\": \"") + 16, 4, "zzzz");
  io::WriteFileAtomically(m.string(), other);
  EXPECT_NE(InputErrorOf([&] { RunCheckpoint::Open(dir); }).find("another mopad binary"),
            std::string::npos);

  other = good;
  other.replace(other.find("mopad-checkpoint"), 16, "mopad-somethingx");
  io::WriteFileAtomically(m.string(), other);
  EXPECT_NE(InputErrorOf([&] { RunCheckpoint::Open(dir); }).find("not a checkpoint"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(RunCheckpoint, ASceneThatChangedIsRefused) {
  const std::string dir = TempDir("scene");
  const fs::path scene = fs::path(dir) / "scene";
  fs::create_directories(scene);
  io::WriteTextFile((scene / "scene.truth.json").string(), "{}");
  RunCheckpoint::Create(dir, Inputs()).SetScene(scene.string());
  RunCheckpoint::Open(dir).SetScene(scene.string());  // unchanged: accepted
  io::WriteTextFile((scene / "scene.truth.json").string(), "{ }");
  EXPECT_NE(InputErrorOf([&] {
              RunCheckpoint::Open(dir).SetScene(scene.string());
            }).find("the scene changed"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(RunCheckpoint, AReplayThatReachesAnotherStateStopsAndACompleteRunSaysSo) {
  const std::string dir = TempDir("replay");
  RunCheckpoint ck = RunCheckpoint::Create(dir, Inputs());
  ck.RoomDone({"room_1", "R1", 5, 12.5, "00000000000000aa"});
  RunCheckpoint again = RunCheckpoint::Open(dir);
  EXPECT_EQ(again.RecordedRooms(), 1);
  EXPECT_THROW(again.RoomDone({"room_1", "R1", 5, 12.5, "00000000000000ab"}), std::runtime_error);
  RunCheckpoint third = RunCheckpoint::Open(dir);
  third.RoomDone({"room_1", "R1", 5, 12.5, "00000000000000aa"});  // replayed as recorded
  third.RoomDone({"room_2", "R2", 9, 30.0, "00000000000000bb"});  // new: recorded
  third.MarkComplete();
  const RunCheckpoint done = RunCheckpoint::Open(dir);
  EXPECT_TRUE(done.Complete());
  EXPECT_EQ(done.RecordedRooms(), 2);
  fs::remove_all(dir);
}

struct SimulatedKill {};  // not a std::exception: nothing on the way catches it

// The floor job as `mopad run` drives it, its room boundaries into `ck`; `kill_at` (optional):
// the progress line at which the process "dies".
void RunWith(const sim::SceneWorld& mw, const std::string& dir, RunCheckpoint& ck,
             const std::string& kill_at = "") {
  const RunInputs& in = ck.Inputs();
  const auto progress = [&](const std::string& line) {
    if (!kill_at.empty() && line.rfind(kill_at, 0) == 0) throw SimulatedKill{};
  };
  RunFloorJob(mw, in.params, in.start_W, dir, false, progress, {},
              [&](const RoomBoundary& b) { ck.RoomDone(b); });
  ck.MarkComplete();
}

TEST(RunCheckpoint, AMissionKilledInItsSecondRoomAndResumedWritesTheBytesOfAnUninterruptedOne) {
  const sim::SceneWorld mw = sim::LoadSceneWorld(Spec());
  const std::string a = TempDir("whole"), b = TempDir("killed");
  RunCheckpoint whole = RunCheckpoint::Create(a, Inputs());
  RunWith(mw, a, whole);

  RunCheckpoint killed = RunCheckpoint::Create(b, Inputs());
  // Killed after R2's second scan: R1's files are written, R2's are not.
  EXPECT_THROW(RunWith(mw, b, killed, "room_2: scan 2,"), SimulatedKill);
  RunCheckpoint resumed = RunCheckpoint::Open(b);
  EXPECT_FALSE(resumed.Complete());
  ASSERT_EQ(resumed.RecordedRooms(), 1);
  RunWith(mw, b, resumed);
  EXPECT_TRUE(RunCheckpoint::Open(b).Complete());

  const auto fa = Files(a), fb = Files(b);
  ASSERT_GT(fa.size(), 10u);
  EXPECT_TRUE(fa.count("rooms/R2/sm1.ply")) << "the mission did not reach R2";
  for (const auto& [name, bytes] : fa) {
    ASSERT_TRUE(fb.count(name)) << name << " missing after the resume";
    EXPECT_TRUE(fb.at(name) == bytes) << name << " differs after the resume";
  }
  EXPECT_EQ(fa.size(), fb.size());
  fs::remove_all(a);
  fs::remove_all(b);
}

}  // namespace
}  // namespace mopad::mission
