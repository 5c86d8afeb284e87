#include "mission/run_job.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "io/text_file.h"
#include "mission/default_scene.h"
#include "mission/main_job.h"
#include "report/report.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "scenes/scene_summary.h"
#include "sim/realism.h"
#include "sim/scene_world.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;

nlohmann::ordered_json SceneJson(const std::string& source, const std::string& name,
                                 const scenes::SceneSummary& s) {
  return {{"spec", source},
          {"name", name},
          {"rooms", s.rooms},
          {"walls", s.walls},
          {"doors", s.doors},
          {"windows", s.windows},
          {"service_components", s.bsc_total},
          {"triangles", s.triangles}};
}

report::ReportTable SceneTable(const scenes::SceneSummary& s) {
  return {"Scene",
          {"item", "count"},
          {{"rooms", std::to_string(s.rooms)},
           {"walls", std::to_string(s.walls)},
           {"doors (open / semi-open / closed)",
            std::to_string(s.doors) + " (" + std::to_string(s.doors_open) + " / " +
                std::to_string(s.doors_semi_open) + " / " + std::to_string(s.doors_closed) + ")"},
           {"windows", std::to_string(s.windows)},
           {"service components", std::to_string(s.bsc_total)},
           {"furniture", std::to_string(s.furniture)},
           {"triangles", std::to_string(s.triangles)}},
          ""};
}

}  // namespace

scenes::SceneSpec RunSceneSpec(const RunInputs& in) {
  scenes::SceneSpec spec = scenes::ParseSceneSpec(in.spec_text, in.spec_name);
  const sim::RealismParams& realism = in.params.room.realism;
  if (realism.geometry.Enabled())
    spec.as_built = sim::RunGeometry(realism, in.params.room.drive.seed);
  if (realism.details.Enabled()) spec.details = sim::RunDetails(realism, in.params.room.drive.seed);
  return spec;
}

RunCheckpoint StartRun(const RunRequest& r) {
  if (!r.spec_path.empty() && !r.scene_dir.empty())
    throw InputError("a run takes a scene spec or a scene folder, not both");
  RunInputs in;
  if (!r.config.empty()) in.params = LoadParamsFile<FloorMissionParams>(r.config);
  if (r.step_deg) in.params.room.scan.scan_step_deg = *r.step_deg;
  if (r.seed) in.params.room.drive.seed = *r.seed;
  if (r.realism) in.params.room.realism = sim::RealismProfile(*r.realism);
  ValidateParams(in.params, "room.");
  in.rooms = r.rooms;
  in.start_W = r.start_W;
  if (r.scene_dir.empty()) {
    in.spec_name = r.spec_path.empty() ? kDefaultSceneSpecName : r.spec_path;
    in.spec_text = r.spec_path.empty() ? kDefaultSceneSpec : io::ReadTextFile(r.spec_path);
    in.scene_source = in.spec_name;
  } else if (const fs::path spec = fs::path(r.scene_dir) / "spec.effective.yaml";
             in.params.room.realism.ChangesTheBuilding() && fs::exists(spec)) {
    // A generated scene folder carries the spec it was made from; the building as built is
    // made from that spec (the design's files are the same bytes, scenes/generator.h).
    in.spec_name = spec.string();
    in.spec_text = io::ReadTextFile(spec.string());
    in.scene_source = r.scene_dir;
  } else {
    in.scene_folder = fs::absolute(r.scene_dir).string();
    in.scene_source = r.scene_dir;
  }
  fs::create_directories(r.out);
  return RunCheckpoint::Create(r.out, in);
}

bool RunFromCheckpoint(RunCheckpoint& ck, const std::string& run_dir, const RunHooks& hooks,
                       WallClock::time_point t_start) {
  const RunInputs& in = ck.Inputs();
  const fs::path dir(run_dir);
  // The world (truth side): a generated scene is written out so that `mopad eval` can
  // re-read it; a given scene folder is used where it is.
  MainJobOptions o;
  o.dir = dir.string();
  o.rooms = in.rooms;
  o.start_W = in.start_W;
  if (in.scene_folder.empty()) {
    const scenes::SceneSpec spec = RunSceneSpec(in);
    scenes::WriteGeneratedScene(scenes::Generate(spec), (dir / "scene").string());
    o.scene_name = spec.name;
    o.scene_source = in.scene_source;
  } else if (in.params.room.realism.ChangesTheBuilding() && hooks.print) {
    hooks.print(
        "realism: the as-built geometry and details apply to generated scenes; the scene "
        "folder " +
        in.scene_folder + " has no spec.effective.yaml and is used as it is");
  }
  const std::string scene_folder =
      in.scene_folder.empty() ? (dir / "scene").string() : in.scene_folder;
  ck.SetScene(scene_folder);
  const sim::SceneWorld mw = sim::LoadSceneWorld(scene_folder);
  if (!mw.truth)
    throw InputError(scene_folder + ": error: the scene has no truth sidecar (scene.truth.json)");
  if (o.scene_name.empty()) o.scene_name = mw.truth->scene_name, o.scene_source = in.scene_source;
  const scenes::SceneSummary summary =
      scenes::Summarise(mw.world->scene(), &*mw.truth, scene_folder + "/scene.glb");
  o.t_generate = SecondsSince(t_start);
  o.scene_json = SceneJson(o.scene_source, o.scene_name, summary);
  o.scene_table = SceneTable(summary);
  if (hooks.print)
    hooks.print("scene: " + o.scene_name + ", " + std::to_string(summary.rooms) + " rooms, " +
                std::to_string(summary.walls) + " walls, " + std::to_string(summary.doors) +
                " doors, " + std::to_string(summary.windows) + " windows, " +
                std::to_string(summary.bsc_total) + " service components, " +
                std::to_string(summary.triangles) + " triangles (" + FormatFixed(o.t_generate, 2) +
                " s)");
  o.progress = hooks.progress;
  o.print = hooks.print;
  o.stop_requested = hooks.stop_requested;
  o.checkpoint = &ck;
  return RunMainJob(mw, ck.Inputs().params, o);
}

}  // namespace mopad::mission
