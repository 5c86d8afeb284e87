#pragma once
// `mopad run` as a library call, for the CLI (tools/cmd_run.cpp) and the Python module's
// mopad.run(): the request (scene, config, seed, step, start, rooms) becomes the run's
// checkpoint (mission/run_checkpoint.h) before any work; the job then makes or loads the scene
// and runs the main job (mission/main_job.h) into the run folder. Both callers give the same
// bytes for the same request.
//
// World side (mission/): it makes scenes and reads their truth.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/wall_clock.h"
#include "mission/run_checkpoint.h"
#include "scenes/scene_spec.h"

namespace mopad::mission {

/// The scene spec a run generates its world from: the inputs' spec with the run's as-built
/// geometry and details (sim::RunGeometry, sim::RunDetails: realism.geometry and
/// realism.details, drawn from the run seed) when it has them.
/// Precondition: the inputs name a spec, not a scene folder.
scenes::SceneSpec RunSceneSpec(const RunInputs& inputs);

/// What a caller asks of the main job (the options of `mopad run` but --resume and --keep).
struct RunRequest {
  std::string out = "out/run";  ///< the run folder
  /// Scene spec YAML; with `scene_dir` also empty, the embedded office_5rooms spec.
  std::string spec_path;
  /// A scene folder with its truth (excludes `spec_path`). With the realism's as-built geometry
  /// on, a generated folder's spec.effective.yaml is what the run generates from.
  std::string scene_dir;
  std::string config;     ///< YAML overriding FloorMissionParams fields; empty: the defaults
  std::optional<std::uint64_t> seed;   ///< overrides room.drive.seed (run seed)
  std::optional<double> step_deg;      ///< overrides room.scan.scan_step_deg (deg, 0.02-5)
  std::optional<std::string> realism;  ///< replaces room.realism by this profile (sim/realism.h)
  std::vector<std::string> rooms;      ///< per-room mode in these rooms; empty: the floor mission
  std::optional<Pose2> start_W;        ///< floor mission start (world); default: a free spot
};

/// Reads and checks the request (InputError, before any work, for a bad config, spec, field
/// or both scene sources) and writes OUT/checkpoint/.
RunCheckpoint StartRun(const RunRequest& request);

/// What the job tells its caller while it runs; every hook is optional.
struct RunHooks {
  std::function<void(const std::string&)> progress;  ///< one line per event (rooms, scans)
  std::function<void(const std::string&)> print;     ///< result lines (scene, rooms, tables)
  /// Asked before each room: true ends the job there (MainJobOptions::stop_requested).
  std::function<bool()> stop_requested;
};

/// The main job on the checkpoint's inputs, into `run_dir` (the folder the checkpoint was
/// created or opened in): a generated scene is written to DIR/scene/ first. InputError for a
/// scene without truth or one changed since the run started. False when `stop_requested`
/// ended it before all its rooms. `t_start` is when the caller began (reporting only).
bool RunFromCheckpoint(RunCheckpoint& checkpoint, const std::string& run_dir,
                       const RunHooks& hooks, WallClock::time_point t_start);

}  // namespace mopad::mission
