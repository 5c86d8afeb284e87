// `mopad drive SCENE --from x,y,yaw --to x,y,yaw [--seed N] [--max-time S] -o DIR`: one
// closed-loop navigation mission (mission/drive_mission.h). Parse -> load world -> run -> write.
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "common/error.h"
#include "common/params.h"
#include "mission/drive_mission.h"
#include "scenes/generator.h"
#include "scenes/ground_truth.h"
#include "scenes/scene_loader.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/scene_world.h"
#include "tools/commands.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;

}  // namespace

void RegisterDriveCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("drive", "Closed-loop navigation from one pose to another");
  auto scene = std::make_shared<std::string>();
  auto from = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>("out/drive");
  auto seed = std::make_shared<std::uint64_t>(1);
  auto max_time = std::make_shared<double>(600.0);
  auto config = std::make_shared<std::string>();
  auto doors = std::make_shared<std::vector<std::string>>();
  auto via = std::make_shared<std::vector<std::string>>();
  auto kidnap = std::make_shared<std::string>();
  auto bench = std::make_shared<bool>(false);
  cmd->add_option("SCENE", *scene, "Generated scene folder, scene file, or scene spec (.yaml)")
      ->required();
  cmd->add_option("--from", *from, "Start pose x,y,yaw_deg (world frame)")->required();
  cmd->add_option("--to", *to, "Goal pose x,y,yaw_deg (world frame)")->required();
  cmd->add_option("--via", *via,
                  "Waypoint x,y,yaw_deg (world), reached in order before --to; repeatable");
  cmd->add_option(
      "--kidnap", *kidnap,
      "T,x,y,yaw_deg: at simulation time T teleport the true body (test of loss handling)");
  cmd->add_flag("--bench", *bench,
                "Benchmark: print the loop's real-time factor with the TLS scan cost separated");
  auto* seed_opt =
      cmd->add_option("--seed", *seed, "Run seed (default: the config's seed, else 1)");
  auto* max_time_opt =
      cmd->add_option("--max-time", *max_time,
                      "Simulation time limit of the drive in s, from the first scan (default: "
                      "the config's max_time, else 600)");
  cmd->add_option("--config", *config, "YAML overriding DriveParams fields");
  cmd->add_option("--door", *doors, "ID=DEG: set a door's opening angle (spec .yaml only)");
  cmd->add_option("-o,--output", *out, "Output folder")->default_val("out/drive");
  cmd->footer(
      "Writes DIR/trajectory_estimated.tum, trajectory_true.tum, map.png, map.yaml, "
      "map_path.png and summary.json (docs/navigation.md).");
  cmd->callback([=] {
    mission::DriveParams params;
    if (!config->empty()) params = LoadParamsFile<mission::DriveParams>(*config);
    OverrideIfGiven(seed_opt, *seed, params.seed);
    OverrideIfGiven(max_time_opt, *max_time, params.navigator.max_time);
    ValidateParams(params);
    params.Validate();
    mission::DriveRequest req;
    req.X_WB_start = ParsePoseArg("--from", *from);
    req.X_WB_goal = ParsePoseArg("--to", *to);
    for (const auto& v : *via) req.via.push_back(ParsePoseArg("--via", v));
    if (!kidnap->empty()) {
      const auto comma = kidnap->find(',');
      if (comma == std::string::npos)
        throw InputError("--kidnap: error: expected T,x,y,yaw_deg; got '" + *kidnap + "'");
      try {
        req.kidnap_time = std::stod(kidnap->substr(0, comma));
      } catch (const std::exception&) {
        throw InputError("--kidnap: error: bad time; got '" + *kidnap +
                         "', expected T,x,y,yaw_deg");
      }
      if (!(req.kidnap_time > 0.0))
        throw InputError("--kidnap: error: T must be > 0; got '" + *kidnap + "'");
      req.kidnap_to = ParsePoseArg("--kidnap", kidnap->substr(comma + 1));
    }

    const sim::SceneWorld world = sim::LoadSceneWorld(*scene, *doors);
    const mission::DriveResult r = mission::RunDrive(*world.world, params, req);
    mission::WriteDriveOutputs(r, params, req, *out);
    std::printf("%s: %s\n", mission::ToString(r.status), r.message.c_str());
    std::printf(
        "final error %.3f m / %.2f deg; localisation RMS %.3f m, max %.3f m; contacts %d; "
        "path %.2f m; %d TLS scans; sim %.1f s, wall %.1f s, %.1fx real time\n",
        r.goal_error_xy, r.goal_error_yaw_deg, r.loc_rms, r.loc_max, r.contacts, r.path_length,
        r.tls_scans, r.sim_time, r.wall_time, r.RealTimeFactor());
    if (*bench) {
      const double loop_wall = r.wall_time - r.tls_wall_time;
      std::printf("bench: %.1f s simulated in %.2f s wall = %.1fx real time overall\n", r.sim_time,
                  r.wall_time, r.RealTimeFactor());
      std::printf(
          "  TLS (%s, %.2f deg): %d scans, %.1f s simulated standing (from the profile), "
          "%.2f s wall simulating the scanner\n",
          params.tls_profile.c_str(), params.navigator.tls_step_deg, r.tls_scans, r.tls_time,
          r.tls_wall_time);
      std::printf(
          "  loop without the TLS simulation (body, both LRFs, AMCL, maps, planner, controller): "
          "%.1fx real time\n",
          loop_wall > 0 ? r.sim_time / loop_wall : 0.0);
      std::printf(
          "  LRFs (%s): %d sweeps = %.1f Hz for both; AMCL %d updates; %zu plans, %d replans; "
          "%zu control steps\n",
          params.lrf_profile.c_str(), r.lrf_sweeps,
          r.sim_time > 0 ? r.lrf_sweeps / r.sim_time : 0.0, r.amcl_updates, r.plans.size(),
          r.replans, r.truth.size());
    }
    std::printf(
        "wrote %s/{trajectory_estimated.tum,trajectory_true.tum,map.png,map.yaml,"
        "map_path.png,summary.json}\n",
        out->c_str());
  });
}

}  // namespace mopad::tools
