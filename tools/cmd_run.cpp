// `mopad run`: the main job (README, mission/main_job.h). The default scene (or --spec, or
// --scene), the floor mission from the start pose (or, with --room, a fresh robot in each listed
// room), `mopad eval` over all rooms, summary.json and the report.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "common/format.h"
#include "common/wall_clock.h"
#include "mission/run_checkpoint.h"
#include "mission/run_job.h"
#include "runfolder/keep.h"
#include "tools/commands.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;

// SIGINT / SIGTERM: the job stops before its next room and still writes its evaluation,
// exports and report; the checkpoint says "stopped" and the process exits with 128 + the
// signal's number. A second signal ends the process at once.
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
extern "C" void OnStopSignal(int sig) {
  g_signal = sig;
  g_stop = true;
  std::signal(sig, SIG_DFL);
}

// Progress for a person: on a terminal one live line rewritten in place, else plain lines.
std::function<void(const std::string&)> ProgressPrinter(bool quiet, WallClock::time_point t0) {
  if (quiet) return {};
  const bool tty = isatty(fileno(stdout)) != 0;
  return [tty, t0](const std::string& line) {
    const std::string text = "[" + FormatFixed(SecondsSince(t0), 0) + " s] " + line;
    if (tty)
      std::printf("\r\033[K%s", text.c_str());
    else
      std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  };
}

// What `mopad run` was given on the command line.
struct RunArgs {
  std::string out = "out/run", spec_path, scene_dir, config, start, resume, keep = "all", realism;
  std::uint64_t seed = 1;
  double step = 0.2;
  std::vector<std::string> rooms;
  bool quiet = false;
  CLI::Option* seed_opt = nullptr;
  CLI::Option* step_opt = nullptr;
};

void AddRunOptions(CLI::App* cmd, RunArgs& a) {
  auto* out_opt = cmd->add_option("-o,--output", a.out, "Output folder")->default_val("out/run");
  auto* spec_opt = cmd->add_option("--spec", a.spec_path,
                                   "Scene spec YAML (default: the embedded office_5rooms)");
  auto* scene_opt =
      cmd->add_option("--scene", a.scene_dir,
                      "A scene folder with its truth (mopad scene generate|random|import)")
          ->excludes(spec_opt);
  a.seed_opt = cmd->add_option("--seed", a.seed,
                               "Run seed: sensor noise, odometry, localisation (default: the "
                               "config's drive.seed, else 1)");
  a.step_opt = cmd->add_option("--step-deg", a.step,
                               "TLS angular step of the room scans in degrees (default: the "
                               "config's scan_step_deg, else 0.2)")
                   ->check(CLI::Range(0.02, 5.0));
  auto* config_opt =
      cmd->add_option("--config", a.config, "YAML overriding FloorMissionParams fields");
  auto* realism_opt = cmd->add_option(
      "--realism", a.realism,
      "Realism profile of the world: ideal, typical, hard (docs/realism.md; default: the "
      "config's realism, else ideal)");
  auto* rooms_opt = cmd->add_option(
      "--room", a.rooms,
      "Per-room mode: a fresh robot placed in each of these rooms (default: the floor mission)");
  auto* start_opt =
      cmd->add_option("--start", a.start,
                      "Floor mission start pose in the scene frame 'x,y,yaw_deg' (default: a free "
                      "spot of the scene's first room)");
  cmd->add_option("--resume", a.resume,
                  "Finish the run in DIR after its process was killed: the job runs again from "
                  "DIR/checkpoint/ (its scene, config, seed, start) and writes the files an "
                  "uninterrupted run writes (docs/floor-mission.md, Resume); no other run option "
                  "but --keep")
      ->excludes(out_opt, spec_opt, scene_opt, a.seed_opt, a.step_opt, config_opt, rooms_opt,
                 start_opt, realism_opt);
  cmd->add_option("--keep", a.keep,
                  "What the finished run folder keeps: summary (JSON, YAML, reports), models (+ "
                  "glTF, IFC, images, trajectories) or all (+ the point clouds; docs/suites.md)")
      ->check(CLI::IsMember({"summary", "models", "all"}))
      ->default_val("all");
  cmd->add_flag("-q,--quiet", a.quiet, "No progress lines (results and errors only)");
  cmd->footer(
      "Writes DIR/summary.json, report.html, report.md, dtt.json, trajectory_true.tum, "
      "trajectory_estimated.tum and floor/ (sm3.json, sm4.json: the floor model) for the floor "
      "mission, rooms/<ID>/ (models, scans, evaluation), "
      "eval/ and export/ (model.ifc, model.glb, sm1.las; docs/exports.md).");
}

// The run's inputs: from the command line (a checkpoint records them in `dir` before anything
// else happens), or, with --resume, from that checkpoint. None when a resumed run is complete.
std::optional<mission::RunCheckpoint> CheckpointOf(const RunArgs& a, fs::path& dir) {
  if (!a.resume.empty()) {
    dir = a.resume;
    mission::RunCheckpoint ck = mission::RunCheckpoint::Open(dir.string());
    if (ck.Complete()) {
      std::printf("%s: the run is complete (checkpoint/manifest.json); nothing to resume\n",
                  dir.string().c_str());
      return std::nullopt;
    }
    std::printf(
        "resuming %s (resume %d): the job runs again from its checkpoint; the %d "
        "rooms it recorded are re-run and checked\n",
        dir.string().c_str(), ck.Resumes(), ck.RecordedRooms());
    return ck;
  }
  dir = a.out;
  mission::RunRequest r;
  r.out = a.out;
  r.spec_path = a.spec_path;
  r.scene_dir = a.scene_dir;
  r.config = a.config;
  if (a.seed_opt->count() > 0) r.seed = a.seed;
  if (a.step_opt->count() > 0) r.step_deg = a.step;
  if (!a.realism.empty()) r.realism = a.realism;
  r.rooms = a.rooms;
  if (!a.start.empty()) r.start_W = ParsePoseArg("--start", a.start);
  return mission::StartRun(r);
}

// The main job on the checkpoint's inputs, into `dir`. False when a signal stopped it before
// all its rooms.
bool RunJob(mission::RunCheckpoint& ck, const fs::path& dir, bool quiet,
            WallClock::time_point t_start) {
  // From here on a signal is an orderly stop (the checkpoint exists; the scene may still load).
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  const bool tty = isatty(fileno(stdout)) != 0 && !quiet;
  mission::RunHooks hooks;
  hooks.progress = ProgressPrinter(quiet, t_start);
  hooks.print = [tty](const std::string& line) {
    std::printf(tty ? "\r\033[K%s\n" : "%s\n", line.c_str());
    std::fflush(stdout);
  };
  hooks.stop_requested = [] { return g_stop.load(); };
  const bool finished = mission::RunFromCheckpoint(ck, dir.string(), hooks, t_start);
  std::printf("%s in %.1f s; wrote %s/{summary.json,report.html,report.md,rooms/*/,eval/}\n",
              finished ? "done" : "stopped", SecondsSince(t_start), dir.string().c_str());
  return finished;
}

}  // namespace

void RegisterRunCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run",
      "Main job: the floor mission on the default scene (one robot, room by room through the "
      "doors it finds), models, evaluation and a report");
  auto args = std::make_shared<RunArgs>();
  AddRunOptions(cmd, *args);
  cmd->callback([args] {
    const auto t_start = WallClock::now();
    fs::path dir;
    std::optional<mission::RunCheckpoint> ck = CheckpointOf(*args, dir);
    const bool finished = !ck || RunJob(*ck, dir, args->quiet, t_start);
    // Also on a complete run given to --resume: `--resume DIR --keep LEVEL` slims a finished
    // folder.
    const runfolder::KeepLevel keep = runfolder::ParseKeepLevel(args->keep);
    const std::uintmax_t freed = runfolder::PruneRunFolder(dir.string(), keep);
    if (keep != runfolder::KeepLevel::kAll && !args->quiet)
      std::printf("--keep %s: removed %.1f MB of files the level does not keep\n",
                  runfolder::ToString(keep), static_cast<double>(freed) / 1e6);
    if (!finished) {
      const int sig = g_signal.load();
      std::fflush(stdout);
      std::fprintf(stderr,
                   "mopad: stopped by %s before all rooms were done; %s holds the rooms done "
                   "(summary.json); finish the run with: mopad run --resume %s\n",
                   sig == SIGTERM  ? "SIGTERM"
                   : sig == SIGINT ? "SIGINT"
                                   : "a signal",
                   dir.string().c_str(), dir.string().c_str());
      throw CLI::RuntimeError(128 + (sig > 0 ? sig : SIGTERM));
    }
  });
}

}  // namespace mopad::tools
