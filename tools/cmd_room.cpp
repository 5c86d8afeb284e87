// `mopad room SCENE --room ID [--seed N] [--from x,y,yaw] -o DIR`: the robot scans one room
// from positions it chooses itself until the paper's stopping rule holds (mission/room_mission.h),
// writes SM1 and the mission log, then the evaluator scores the run against the truth.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "common/error.h"
#include "common/params.h"
#include "mission/room_job.h"
#include "mission/room_mission.h"
#include "sim/scene_world.h"
#include "tools/commands.h"

namespace mopad::tools {
void RegisterRoomCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "room", "Autonomous scanning of one room (next-best-scan, stopping rule) -> SM1, evaluated");
  auto scene = std::make_shared<std::string>();
  auto room = std::make_shared<std::string>();
  auto from = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>("out/room");
  auto seed = std::make_shared<std::uint64_t>(1);
  auto config = std::make_shared<std::string>();
  auto no_eval = std::make_shared<bool>(false);
  cmd->add_option("SCENE", *scene, "Generated scene folder, scene file, or scene spec (.yaml)")
      ->required();
  cmd->add_option("--room", *room, "Room id (from the truth sidecar)")->required();
  cmd->add_option("--from", *from,
                  "Start pose x,y,yaw_deg (world; default: the free spot of the room farthest "
                  "from walls and furniture)");
  auto* seed_opt =
      cmd->add_option("--seed", *seed, "Run seed (default: the config's drive.seed, else 1)");
  cmd->add_option("--config", *config, "YAML overriding RoomMissionParams fields");
  cmd->add_flag("--no-eval", *no_eval, "Skip the evaluation against the truth");
  cmd->add_option("-o,--output", *out, "Output folder")->default_val("out/room");
  cmd->footer(
      "Writes DIR/sm1.ply, sm2.json, sm3.json, sm4.json, sm5.json, dsm3.ply, models.glb, "
      "orthoimages/, scans.json, model.json, run.json, scan_poses.tum, trajectory_true.tum, "
      "trajectory_estimated.tum, map.png, map.yaml, summary.json, room.effective.yaml and, unless "
      "--no-eval, evaluation.json (docs/models.md, docs/room-scanning.md).");
  cmd->callback([=] {
    mission::RoomMissionParams params;
    if (!config->empty()) params = LoadParamsFile<mission::RoomMissionParams>(*config);
    OverrideIfGiven(seed_opt, *seed, params.drive.seed);
    ValidateParams(params, "room.");
    const sim::SceneWorld mw = sim::LoadSceneWorld(*scene);
    std::optional<Pose2> start;
    if (!from->empty()) start = ParsePoseArg("--from", *from);
    const mission::RoomJob job = mission::RunRoomJob(mw, *room, params, start, *out, !*no_eval);
    const mission::RoomMissionResult& res = job.mission;
    std::printf("room %s: %zu scans; %s\n", room->c_str(), res.scans.size(),
                res.stop_reason.c_str());
    for (const auto& s : res.scans)
      std::printf(
          "  scan %d: coverage %.3f (+%.3f), processing %.2f s (registration %.2f, "
          "model %.2f, nbs %.2f)%s\n",
          s.index, s.coverage.observable_ratio, s.coverage.increment,
          s.t_registration + s.t_model + s.t_nbs, s.t_registration, s.t_model, s.t_nbs,
          s.registered ? "" : "  REGISTRATION FAILED");
    if (res.registration_failed) std::printf("registration failed for at least one scan\n");
    for (const std::string& e : job.fault_events) std::printf("world: %s\n", e.c_str());
    if (job.evaluation) {
      const evaluation::RoomEvaluation& e = *job.evaluation;
      std::printf(
          "evaluation: coverage %.3f of observable (%.1f m2), %.3f of total (%.1f m2); "
          "registration error max %.4f m / %.4f deg; SM1 labels %.4f agree (%llu points)\n",
          e.coverage.room.ShareOfObservable(), e.observable_area, e.coverage.room.ShareOfTotal(),
          e.total_area, e.max_translation_error, e.max_rotation_error_deg, e.labels.Accuracy(),
          static_cast<unsigned long long>(e.labels.points));
    }
    std::printf("wrote %s/{sm1.ply,scans.json,model.json,scan_poses.tum,map.png,%s}\n",
                out->c_str(), *no_eval ? "room.effective.yaml" : "evaluation.json");
  });
}

}  // namespace mopad::tools
