#pragma once
// The main job's floor mission (`mopad run`): one simulated robot placed once at the start pose
// runs the robot's floor loop (autonomy/floor_scan.h) over the whole floor; the world side names
// each robot room after the truth room it stands in, keeps the truth for the evaluator and
// writes the run folder:
//   DIR/trajectory_true.tum, DIR/trajectory_estimated.tum  the whole mission (map frame)
//   DIR/dtt.json                                           the Dynamic Traversal Tree
//   DIR/rooms/<ID>/                                        per room, as `mopad room` writes
//                                                          them, all in the one map frame
//   DIR/floor/                                             the floor-level SM3/SM4
// Deterministic: same world + params + seed + start -> same files (timings aside).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "autonomy/floor_scan.h"
#include "mission/room_job.h"
#include "mission/room_mission.h"
#include "modelling/floor_model.h"
#include "sim/scene_world.h"

namespace mopad::mission {

/// The floor mission's params. YAML keys: the room mission's (RoomMissionParams: the room
/// loop's at the top level, `drive`), then the floor loop's (`floor`) and the floor model's
/// (`floor_model`).
struct FloorMissionParams {
  /// The room loop and the simulated robot, with the floor's registration. The floor's target
  /// holds both faces of the walls between rooms: a scan's points match only surfaces seen
  /// from their own side (same_side). It also holds the other rooms' scans and the rays they
  /// cast through the doors: right registrations of a hall's scans put 0.009-0.013 of their
  /// points where one of those saw empty space (registration errors 1-10 mm), above the
  /// one-room bound of 0.006; a room's first scan registers against the same target, rays
  /// through doors included (max_free_space_violation 0.015). Otherwise the room mission's
  /// values: a designated member replaces the member's whole initialiser, so the room loop's
  /// stages and fitness are restated here (a test pins that nothing else differs).
  RoomMissionParams room{.scan = {.icp = {.max_correspondence = autonomy::kAmclPriorIcpStages,
                                          .min_fitness = 0.3,
                                          .max_free_space_violation = 0.015,
                                          .same_side = true},
                                  .entry_icp = {.max_correspondence = autonomy::kAmclPriorIcpStages,
                                                .min_fitness = 0.15,
                                                .max_free_space_violation = 0.015,
                                                .same_side = true,
                                                .weak_search = 0.3}}};
  autonomy::FloorScanParams floor;
  modelling::FloorModelParams floor_model;  ///< joins the rooms' SM3/SM4 into floor/

  template <class V>
  void Visit(V& v) {
    room.Visit(v);
    v("floor", floor);
    v("floor_model", floor_model);
  }
};

/// One visited room of the mission, world side.
struct FloorRoomJob {
  std::string robot_room;       ///< the robot's name ("room_3")
  std::string room;             ///< the truth room it scanned (where its first scan stood)
  std::string dir;              ///< "rooms/<room>" relative to the run folder; empty: not written
  std::string status;           ///< "scanned" or "failed"
  std::string reason;           ///< the room loop's stop reason, or why it failed
  int scans = 0;                ///< room-loop scans
  int door_scans = 0;           ///< door scans listed with the room (in front of its entry door)
  double robot_coverage = 0.0;  ///< the robot's estimate after the last scan, [0, 1]
  /// The robot's estimate after each room-loop scan (CoverageFigures::ratio), [0, 1].
  std::vector<double> robot_coverage_per_scan;
  std::size_t openings = 0;                     ///< SM4: doors and windows found
  std::size_t components = 0;                   ///< SM5: service components found
  double sm4_seconds = 0.0, sm5_seconds = 0.0;  ///< wall time (reporting only)
  std::optional<evaluation::RoomEvaluation> evaluation;
  std::vector<Eigen::Vector3d> scan_positions_W;       ///< true scanner centres (world), for plots
  std::vector<Eigen::Vector3d> door_scan_positions_W;  ///< the room's door scan 1 (world)
  std::vector<Eigen::Vector2f> plan_points_W;          ///< subsample of SM1 near scanner height
  double seconds = 0.0;                                ///< wall time of the room (reporting only)
  double sim_seconds = 0.0;  ///< s, platform time from the room's start to its models
  /// The detail pass (autonomy/detail_pass.h): its scans (in `scans` too) and seconds
  int detail_scans = 0;
  double detail_sim_seconds = 0.0, detail_wall_seconds = 0.0;
  std::vector<std::string> detail_log;  ///< one line per planning round
};

/// The state of the mission after a room, as `mopad run`'s checkpoint records it
/// (mission/run_checkpoint.h): a resumed run checks that it passes the same boundaries.
struct RoomBoundary {
  std::string robot_room;  ///< "room_3"; per-room mode: the room id
  std::string room;        ///< the truth room
  int scans = 0;           ///< TLS scans of the mission so far
  double sim_time = 0.0;   ///< s, the simulation clock
  /// 16 hex digits: FNV-1a of the bits of the counts, the clock, the true and the estimated
  /// pose, the room's status and reason. Equal fingerprints: the replay reached the same state.
  std::string fingerprint;
};

struct FloorJob {
  Pose2 start_W;
  scenes::StartSpot start;  ///< the start, its room and how it was chosen (summary.json)
  autonomy::FloorScanResult mission;
  std::vector<FloorRoomJob> rooms;  ///< in visit order
  DriveResult drive;                ///< the whole mission's driving figures (truth included)
  double max_true_step = 0.0;       ///< m, largest distance between consecutive true poses
  Pose3 X_WM = Pose3::Identity();   ///< the map frame in the world (truth side)
  nlohmann::ordered_json dtt;       ///< what dtt.json holds
};

/// Runs the floor mission from `start_W`, checked against the scene (InputError naming the
/// nearest free spot when it is in collision or outside the building; default:
/// scenes::ChooseStart) and writes the run folder `dir`; with `evaluate`, each room is scored as `mopad room`
/// does (DIR/rooms/<ID>/evaluation.json). `progress` hears one line per robot event;
/// `stop_requested`, asked before each room, ends the mission there (the rooms done are kept);
/// `room_boundary` hears each room's end, its files written.
FloorJob RunFloorJob(const sim::SceneWorld& mw, const FloorMissionParams& params,
                     const std::optional<Pose2>& start_W, const std::string& dir, bool evaluate,
                     const std::function<void(const std::string&)>& progress = {},
                     const std::function<bool()>& stop_requested = {},
                     const std::function<void(const RoomBoundary&)>& room_boundary = {});

}  // namespace mopad::mission
