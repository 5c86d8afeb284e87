// `mopad run`: the main job (README). The default scene (or --spec), the room job
// (mission/room_job.h) in every room, a room that fails recorded with its reason, `mopad eval`
// over all rooms, summary.json and the report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "evaluation/run_evaluation.h"
#include "mission/report.h"
#include "mission/room_job.h"
#include "mission/room_mission.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/scene_world.h"
#include "tools/commands.h"
#include "tools/default_scene.h"
#include "tools/scene_summary.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a) {
  return std::chrono::duration<double>(Clock::now() - a).count();
}

}  // namespace

void RegisterRunCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run",
      "Main job: the room-scanning mission in every room of the default scene, models, "
      "evaluation and a report");
  auto out = std::make_shared<std::string>("out/run");
  auto spec_path = std::make_shared<std::string>();
  auto seed = std::make_shared<std::uint64_t>(1);
  auto step = std::make_shared<double>(0.2);
  auto config = std::make_shared<std::string>();
  auto rooms = std::make_shared<std::vector<std::string>>();
  cmd->add_option("-o,--output", *out, "Output folder")->default_val("out/run");
  auto scene_dir = std::make_shared<std::string>();
  auto* spec_opt = cmd->add_option("--spec", *spec_path,
                                   "Scene spec YAML (default: the embedded office_5rooms)");
  cmd->add_option("--scene", *scene_dir,
                  "A scene folder with its truth (mopad scene generate|random|import)")
      ->excludes(spec_opt);
  auto* seed_opt =
      cmd->add_option("--seed", *seed,
                      "Run seed: sensor noise, odometry, localisation (default: the config's "
                      "drive.seed, else 1)");
  auto* step_opt =
      cmd->add_option("--step-deg", *step,
                      "TLS angular step of the room scans in degrees (default: the config's "
                      "scan_step_deg, else 0.2)")
          ->check(CLI::Range(0.02, 5.0));
  cmd->add_option("--config", *config, "YAML overriding RoomMissionParams fields");
  cmd->add_option("--room", *rooms, "Only these rooms (default: all)");
  cmd->callback([=] {
    const auto t_start = Clock::now();
    const fs::path dir(*out);
    fs::create_directories(dir);
    mission::RoomMissionParams params;
    if (!config->empty()) params = LoadParamsFile<mission::RoomMissionParams>(*config);
    OverrideIfGiven(step_opt, *step, params.scan_step_deg);
    OverrideIfGiven(seed_opt, *seed, params.drive.seed);
    ValidateParams(params, "room.");

    // 1. The world (truth side): a generated scene is written out so that `mopad eval` can
    //    re-read it; a given scene folder is used where it is.
    auto t0 = Clock::now();
    std::string scene_name, scene_source;
    if (scene_dir->empty()) {
      const scenes::SceneSpec spec =
          spec_path->empty() ? scenes::ParseSceneSpec(kDefaultSceneSpec, kDefaultSceneSpecName)
                             : scenes::LoadSceneSpec(*spec_path);
      scenes::WriteGeneratedScene(scenes::Generate(spec), (dir / "scene").string());
      scene_name = spec.name;
      scene_source = spec_path->empty() ? kDefaultSceneSpecName : *spec_path;
    }
    const std::string scene_folder = scene_dir->empty() ? (dir / "scene").string() : *scene_dir;
    const sim::SceneWorld mw = sim::LoadSceneWorld(scene_folder);
    if (!mw.truth)
      throw InputError(scene_folder + ": error: the scene has no truth sidecar (scene.truth.json)");
    if (scene_name.empty()) scene_name = mw.truth->scene_name, scene_source = scene_folder;
    const SceneSummary summary =
        Summarise(mw.world->scene(), &*mw.truth, scene_folder + "/scene.glb");
    const double t_generate = Seconds(t0);
    std::printf(
        "scene: %s, %zu rooms, %zu walls, %zu doors, %zu windows, %zu service "
        "components, %zu triangles (%.2f s)\n",
        scene_name.c_str(), summary.rooms, summary.walls, summary.doors, summary.windows,
        summary.bsc_total, summary.triangles, t_generate);
    std::vector<std::string> room_ids = *rooms;
    if (room_ids.empty())
      for (const auto& r : mw.truth->rooms) room_ids.push_back(r.id);

    // 2. The room-scanning mission in each room.
    mission::ReportInput report;
    report.title = "OpenMoPAD run: " + scene_name;
    report.truth = &*mw.truth;
    mission::ReportTable rooms_table{"Room missions (robot side)",
                                     {"room", "scans", "robot coverage", "stop reason",
                                      "max processing / scan (s)", "path (m)", "SM1 points"},
                                     {}};
    mission::ReportTable eval_table{"Evaluation against the truth",
                                    {"room", "coverage of observable", "coverage of total",
                                     "registration error max (mm / deg)", "SM1 labels agree"},
                                    {}};
    nlohmann::ordered_json rooms_json = nlohmann::json::array();
    int rooms_failed = 0;
    for (const std::string& id : room_ids) {
      t0 = Clock::now();
      const std::string room_dir = (dir / "rooms" / id).string();
      // A room that fails is recorded with its reason and the run goes on with the next.
      std::optional<mission::RoomJob> job_or;
      try {
        job_or = mission::RunRoomJob(mw, id, params, std::nullopt, room_dir, true);
      } catch (const std::exception& ex) {
        const double t_failed = Seconds(t0);
        std::printf("room %s: failed: %s (%.1f s)\n", id.c_str(), ex.what(), t_failed);
        rooms_table.rows.push_back(
            {id, "-", "-", std::string("failed: ") + ex.what(), "-", "-", "-"});
        rooms_json.push_back(
            {{"room", id}, {"status", "failed"}, {"reason", ex.what()}, {"seconds", t_failed}});
        ++rooms_failed;
        continue;
      }
      const mission::RoomJob& job = *job_or;
      const double t_room = Seconds(t0);
      const auto& m = job.mission;
      double max_proc = 0.0;
      for (const auto& s : m.scans)
        max_proc = std::max(max_proc, s.t_registration + s.t_model + s.t_nbs);
      const double robot_cov = m.scans.empty() ? 0.0 : m.scans.back().coverage.ratio;
      const mission::RoomEvaluation& e = *job.evaluation;
      std::printf(
          "room %s: %zu scans, robot coverage %.3f; evaluation: %.3f of observable, %.3f "
          "of total, registration max %.1f mm / %.3f deg, labels %.4f (%.1f s)\n",
          id.c_str(), m.scans.size(), robot_cov, e.coverage.room.ShareOfObservable(),
          e.coverage.room.ShareOfTotal(), 1000 * e.max_translation_error, e.max_rotation_error_deg,
          e.labels.Accuracy(), t_room);
      rooms_table.rows.push_back({id, std::to_string(m.scans.size()), FormatFixed(robot_cov, 3),
                                  m.stop_reason, FormatFixed(max_proc, 2),
                                  FormatFixed(job.path_length, 2), std::to_string(job.points)});
      eval_table.rows.push_back({id, FormatFixed(e.coverage.room.ShareOfObservable(), 3),
                                 FormatFixed(e.coverage.room.ShareOfTotal(), 3),
                                 FormatFixed(1000 * e.max_translation_error, 1) + " / " +
                                     FormatFixed(e.max_rotation_error_deg, 3),
                                 FormatFixed(e.labels.Accuracy(), 4)});
      for (std::size_t k = 0; k < job.scan_positions_W.size(); ++k) {
        mission::ReportScan rs;
        rs.name = id + "/" + std::to_string(k);
        rs.position = job.scan_positions_W[k];
        if (k == 0) rs.plan_points = job.plan_points_W;
        report.scans.push_back(std::move(rs));
      }
      nlohmann::ordered_json rj;
      rj["room"] = id;
      rj["status"] = "scanned";
      rj["dir"] = "rooms/" + id;
      rj["scans"] = m.scans.size();
      rj["stop_reason"] = m.stop_reason;
      rj["registration_failed"] = m.registration_failed;
      rj["robot_coverage"] = robot_cov;
      rj["max_processing_s"] = max_proc;
      rj["sm4_seconds"] = job.sm4_seconds;
      rj["sm5_seconds"] = job.sm5_seconds;
      rj["components"] = job.components;
      rj["evaluation"] = ToJson(e);
      rj["seconds"] = t_room;
      rooms_json.push_back(std::move(rj));
    }

    // 3. The models against the truth (`mopad eval` over every room): eval/.
    t0 = Clock::now();
    std::printf("models against the truth (mopad eval):\n");
    const evaluation::RunEvaluation run_eval =
        evaluation::EvaluateRun(dir.string(), "", "", (dir / "eval").string());
    std::fputs(run_eval.tables.c_str(), stdout);
    const double t_eval = Seconds(t0);
    const nlohmann::ordered_json& ev_summary = run_eval.summary;
    const mission::ReportTable model_table = mission::ModelScoresTable(ev_summary);

    // 4. Summary and report.
    nlohmann::ordered_json j;
    j["job"] = "run";
    j["scene"] = {{"spec", scene_source},
                  {"name", scene_name},
                  {"rooms", summary.rooms},
                  {"walls", summary.walls},
                  {"doors", summary.doors},
                  {"windows", summary.windows},
                  {"service_components", summary.bsc_total},
                  {"triangles", summary.triangles}};
    j["seed"] = params.drive.seed;
    j["tls_step_deg"] = params.scan_step_deg;
    j["rooms"] = rooms_json;
    j["rooms_failed"] = rooms_failed;
    j["models_evaluation"] = {{"file", "eval/evaluation.json"}, {"summary", ev_summary}};
    j["seconds"] = {{"generate", t_generate}, {"eval", t_eval}, {"total", Seconds(t_start)}};
    std::ofstream(dir / "summary.json") << j.dump(2) << "\n";
    std::ofstream(dir / "room.effective.yaml") << YAML::Dump(SaveParams(params)) << "\n";

    report.subtitle = "The robot scans every room of " + scene_name +
                      " from positions it chooses itself (next best scan, paper §3.1), starting "
                      "at a harness-chosen free spot per room. Seed " +
                      std::to_string(params.drive.seed) + ", TLS step " +
                      FormatFixed(params.scan_step_deg, 3) + " deg.";
    report.tables.push_back(
        {"Scene",
         {"item", "count"},
         {{"rooms", std::to_string(summary.rooms)},
          {"walls", std::to_string(summary.walls)},
          {"doors (open / semi-open / closed)",
           std::to_string(summary.doors) + " (" + std::to_string(summary.doors_open) + " / " +
               std::to_string(summary.doors_semi_open) + " / " +
               std::to_string(summary.doors_closed) + ")"},
          {"windows", std::to_string(summary.windows)},
          {"service components", std::to_string(summary.bsc_total)},
          {"furniture", std::to_string(summary.furniture)},
          {"triangles", std::to_string(summary.triangles)}}});
    report.tables.push_back(std::move(rooms_table));
    report.tables.push_back(std::move(eval_table));
    report.tables.push_back(std::move(model_table));
    report.tables.push_back({"Timing",
                             {"step", "seconds"},
                             {{"generate scene", FormatFixed(t_generate, 2)},
                              {"evaluate models", FormatFixed(t_eval, 2)},
                              {"total", FormatFixed(Seconds(t_start), 2)}}});
    mission::WriteHtmlReport(report, (dir / "report.html").string());
    mission::WriteMarkdownReport(report, (dir / "report.md").string());
    std::printf(
        "%zu rooms in %.1f s; wrote %s/{summary.json,report.html,report.md,rooms/*/,eval/}\n",
        room_ids.size(), Seconds(t_start), dir.string().c_str());
  });
}

}  // namespace mopad::tools
