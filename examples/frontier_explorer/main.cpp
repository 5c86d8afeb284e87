// frontier_explorer: a robot brain of its own (frontier_brain.h) driving OpenMoPAD's simulated
// robot through the robot boundary, then scored by OpenMoPAD's evaluator. This file is the
// world side (the harness): it makes the scene, places the robot, keeps the truth, writes
// run.json and runs the evaluator. The brain gets the robot as an interfaces::RobotPlatform and
// nothing else.
//
//   frontier_explorer [--scene SCENE] [--out DIR] [--seed N] [--max-scans N] [--step-deg D]
//                     [--time-budget S]
// SCENE: a spec .yaml (generated into DIR/scene, as `mopad run` does) or a scene folder
// (`mopad scene generate`); default: the installed office_5rooms.yaml, `mopad run`'s scene.
// Writes DIR/room/ (the robot's models and run.json) and DIR/eval/ (the evaluator's files).
// Exit codes: 0 done, 2 bad arguments or input, 3 internal error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "common/error.h"
#include "evaluation/run_evaluation.h"
#include "frontier_brain.h"
#include "mission/drive_mission.h"
#include "mission/sim_robot.h"
#include "runfolder/run_record.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "scenes/start_spot.h"
#include "sim/scene_world.h"

namespace {

namespace fs = std::filesystem;

struct Args {
  std::string scene = FRONTIER_DEFAULT_SCENE;
  std::string out = "out/frontier";
  std::uint64_t seed = 1;
  frontier::ExplorerParams explorer;
};

Args Parse(int argc, char** argv) {
  Args a;
  for (int k = 1; k < argc; ++k) {
    const std::string flag = argv[k];
    if (k + 1 >= argc) throw mopad::InputError(flag + ": error: missing value");
    const std::string value = argv[++k];
    if (flag == "--scene")
      a.scene = value;
    else if (flag == "--out")
      a.out = value;
    else if (flag == "--seed")
      a.seed = std::stoull(value);
    else if (flag == "--max-scans")
      a.explorer.max_scans = std::stoi(value);
    else if (flag == "--step-deg")
      a.explorer.scan_step_deg = std::stod(value);
    else if (flag == "--time-budget")
      a.explorer.time_budget = std::stod(value);
    else
      throw mopad::InputError(flag +
                              ": error: unknown option; expected --scene, --out, --seed, "
                              "--max-scans, --step-deg or --time-budget");
  }
  return a;
}

// The scene folder: a spec is generated into `out`/scene, a folder is used where it is.
std::string SceneFolder(const std::string& scene, const std::string& out) {
  if (fs::path(scene).extension() != ".yaml") return fs::absolute(scene).string();
  const std::string dir = fs::absolute(fs::path(out) / "scene").string();
  mopad::scenes::WriteGeneratedScene(mopad::scenes::Generate(mopad::scenes::LoadSceneSpec(scene)),
                                     dir);
  return dir;
}

double Number(const nlohmann::ordered_json& j) { return j.is_number() ? j.get<double>() : NAN; }

int Run(const Args& a) {
  // World side: the scene with its truth, and where the harness puts the robot.
  const std::string scene = SceneFolder(a.scene, a.out);
  const mopad::sim::SceneWorld mw = mopad::sim::LoadSceneWorld(scene);
  if (!mw.truth) throw mopad::InputError(scene, "the scene has no truth sidecar");
  mopad::mission::DriveParams drive;
  drive.seed = a.seed;
  const mopad::scenes::StartSpot start =
      mopad::scenes::ChooseStart(mw.world->scene(), *mw.truth, mopad::sim::FootprintOf(drive.body));
  std::printf("scene %s: %zu rooms; the robot starts in %s at (%.2f, %.2f) m\n", scene.c_str(),
              mw.truth->rooms.size(), start.room.c_str(), start.X_WB.x, start.X_WB.y);
  mopad::mission::SimRobot robot(*mw.world, drive, start.X_WB, a.seed);

  // Robot side: the brain sees the platform only.
  const frontier::ExplorerResult result = frontier::Explore(
      robot, a.explorer, [](const std::string& line) { std::printf("  %s\n", line.c_str()); });
  const std::string room_dir = (fs::path(a.out) / "room").string();
  const std::size_t patches = frontier::WriteRoomFiles(result, "explored_room", room_dir);
  int registered = 0;
  for (const auto& s : result.scans) registered += s.registered;

  // World side again: where the map lies in the world (the true start) and which truth room
  // the robot explored go into run.json; then the evaluator scores the robot's files.
  mopad::runfolder::RunRecord run;
  run.scene = scene;
  run.room = start.room;
  run.seed = a.seed;
  run.X_WM = robot.X_MW().To3d().inverse();
  mopad::runfolder::WriteRunJson(room_dir, run);
  const mopad::Pose2 truth = robot.TruePoseInMap();
  std::printf(
      "explored: %zu scans (%d registered), %.1f m driven by odometry, %.0f s, %d frontiers "
      "left, stop: %s\n",
      result.scans.size(), registered, result.odometry_distance, robot.Time(),
      result.frontiers_left, result.stop_reason.c_str());
  std::printf("model: %zu points, %zu perimeter corners, %zu SM3 patches; end pose error %.3f m\n",
              result.model.PointCount(), result.model.Perimeter().size(), patches,
              std::hypot(result.final_pose_M.x - truth.x, result.final_pose_M.y - truth.y));

  const std::string eval_dir = (fs::path(a.out) / "eval").string();
  const mopad::evaluation::RunEvaluation e =
      mopad::evaluation::EvaluateRun(room_dir, "", "", eval_dir);
  std::printf("%s", e.tables.c_str());
  const auto& walls = e.summary["detection"]["wall"];
  std::printf(
      "scored: walls %d of %d found (%d false), ISPRS completeness %.3f correctness %.3f, "
      "floor-plan IoU %.3f (%s)\n",
      walls["tp"].get<int>(), walls["n_truth"].get<int>(), walls["fp"].get<int>(),
      Number(e.summary["isprs_completeness"]), Number(e.summary["isprs_correctness"]),
      Number(e.summary["floorplan_mean_iou"]), (fs::path(eval_dir) / "evaluation.json").c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(Parse(argc, argv));
  } catch (const mopad::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 3;
  }
}
