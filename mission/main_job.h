#pragma once
// The main job (`mopad run`, README): on a scene with truth, either the floor mission (one
// robot from the start pose through every room it can reach, mission/floor_job.h) or, with a
// list of rooms, the harness's per-room mode (a fresh robot placed in each listed room,
// mission/room_job.h); then `mopad eval` over every room (DIR/eval/), DIR/summary.json and the
// report (DIR/report.html, DIR/report.md).

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mission/floor_job.h"
#include "report/report.h"
#include "sim/scene_world.h"

namespace mopad::mission {

class RunCheckpoint;

struct MainJobOptions {
  std::string dir = "out/run";
  std::vector<std::string> rooms;  ///< non-empty: per-room mode in these rooms
  std::optional<Pose2> start_W;    ///< floor mission start (world); default: a free spot
  std::string scene_name, scene_source;
  nlohmann::ordered_json scene_json;  ///< the scene's counts, for summary.json
  report::ReportTable scene_table;    ///< the same, for the report
  double t_generate = 0.0;            ///< s spent making the scene (reporting only)
  /// Hears one line per event (rooms, scans, doors); the CLI prints it.
  std::function<void(const std::string&)> progress;
  /// Hears the job's result lines (rooms, evaluation tables); the CLI prints them.
  std::function<void(const std::string&)> print;
  /// Asked before each room (of the floor mission or the per-room mode): true ends the job
  /// there; the rooms done are evaluated, exported and reported as usual, and the checkpoint
  /// says "stopped" (`--resume` finishes the run).
  std::function<bool()> stop_requested;
  /// Optional: hears every room's boundary and is marked complete when the run folder is
  /// written (`mopad run --resume`, mission/run_checkpoint.h).
  RunCheckpoint* checkpoint = nullptr;
};

/// Runs the job and writes the run folder. Robot failures are recorded per room (status and
/// reason) and the job goes on; InputError for a scene without truth rooms. Returns false when
/// `stop_requested` ended it before all its rooms, true when it ran to its end.
bool RunMainJob(const sim::SceneWorld& mw, const FloorMissionParams& params,
                const MainJobOptions& options);

}  // namespace mopad::mission
