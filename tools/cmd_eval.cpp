// `mopad eval --model FILE --scene SCENE [--pose x,y,z,yaw_deg] [--align fit] -o DIR` scores a
// building model another program made (IFC 2x3 / IFC4, or a mopad-sm3 .json) against the same
// truth with the same metrics plus the CV4AEC wall endpoints and room IoU
// (evaluation/model_evaluation.h).
// `mopad eval RUN_DIR [--truth FILE] [--config YAML] -o DIR`: scores the robot's structural
// models of one room run (RUN_DIR/run.json) or of every room of a main-job folder
// (RUN_DIR/rooms/*/run.json) against the scene's truth:
//   SM3     - walls, floors, ceilings: detection TP/FP/FN per class, d_v, d_h, Phi
//             (EvaluatePatches); columns as objects (EvaluateColumns: plan IoU > 0.5, centre,
//             footprint and height errors, face metrics of polygonal columns only); ISPRS
//             completeness/correctness/accuracy curves per class over all patches (EvaluateIsprs);
//   DSM3    - per-voxel confusion and per-class IoU against the truth DSM3 on the robot's grid
//             (TruthDsm3 with the true scanner centres = scan_poses.tum mapped by X_WM);
//   plan    - over all rooms, each room's SM3 floor polygon in the world vs the truth rooms
//             (EvaluateFloorplan);
//   mission - the run's own evaluation.json (coverage, registration, SM1 labels) carried over.
// Every figure is described in docs/evaluation.md.
// Writes DIR/evaluation.json, DIR/evaluation.md (tables + inline SVG plots), per room an SVG
// plot and the truth DSM3 (dsm3_truth_<room>.ply, dsm3.ply's format), and DIR/eval.effective.yaml;
// prints a summary table. Model files are read with evaluation/model_files.h (docs/models.md);
// their frame is the run's map frame.
#include <cstdio>
#include <memory>
#include <string>

#include "common/error.h"
#include "evaluation/model_evaluation.h"
#include "evaluation/run_evaluation.h"
#include "tools/commands.h"

namespace mopad::tools {

void RegisterEvalCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "eval", "Score a run's structural models (SM3, floorplan, DSM3) against the scene's truth");
  auto run_dir = std::make_shared<std::string>();
  auto truth_file = std::make_shared<std::string>();
  auto config = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto model = std::make_shared<evaluation::ModelEvalOptions>();
  auto pose = std::make_shared<std::string>();
  auto align = std::make_shared<std::string>("none");
  auto* run_opt = cmd->add_option("RUN_DIR", *run_dir,
                                  "A room run (run.json) or a main-job folder (rooms/*/run.json)");
  auto* model_opt = cmd->add_option(
      "--model", model->model,
      "Score this building model instead of a run: .ifc (IFC 2x3 / IFC4) or a mopad-sm3 .json");
  auto* scene_opt = cmd->add_option("--scene", model->scene,
                                    "With --model: the scene (folder, scene file or spec .yaml)");
  auto* doors_opt = cmd->add_option("--doors", model->doors,
                                    "With --model: door angles ID=DEG of the truth's world")
                        ->delimiter(',');
  auto* storey_opt = cmd->add_option("--storey", model->storey,
                                     "With --model: the IFC storey (Name or GlobalId)");
  auto* pose_opt = cmd->add_option("--pose", *pose,
                                   "With --model: the model frame's pose in the world, "
                                   "x,y,z,yaw_deg (default 0,0,0,0)");
  auto* align_opt = cmd->add_option("--align", *align,
                                    "With --model: none (the pose as given) or fit (refined by "
                                    "aligning the surfaces)")
                        ->check(CLI::IsMember({"none", "fit"}));
  for (auto* o : {scene_opt, doors_opt, storey_opt, pose_opt, align_opt}) o->needs(model_opt);
  model_opt->excludes(run_opt);
  cmd->add_option("--truth", *truth_file,
                  "Truth sidecar (scene.truth.json) overriding the scene's");
  cmd->add_option("--config", *config, "YAML overriding the evaluation parameters");
  cmd->add_option("-o,--output", *out, "Output folder (default: RUN_DIR/eval)");
  cmd->footer(
      "Writes DIR/evaluation.json, evaluation.md, isprs_<room>.svg, dsm3_truth_<room>.ply and "
      "eval.effective.yaml; DIR is RUN_DIR/eval unless -o (docs/evaluation.md). With --model, "
      "-o DIR is required and DIR gets evaluation.json, evaluation.md and eval.effective.yaml.");
  cmd->callback([=] {
    if (model_opt->count() > 0) {
      evaluation::ModelEvalOptions o = *model;
      if (o.scene.empty() && truth_file->empty())
        throw InputError("--model: error: no truth; expected --scene SCENE or --truth FILE");
      o.truth_file = *truth_file;
      o.config = *config;
      o.out = *out;
      if (!pose->empty()) o.X_WE = evaluation::ParsePlanPose(*pose, "--pose");
      o.fit = *align == "fit";
      std::fputs(evaluation::EvaluateModel(o).tables.c_str(), stdout);
      return;
    }
    if (run_dir->empty())
      throw InputError("mopad eval: error: RUN_DIR is required (or --model FILE --scene SCENE)");
    std::fputs(evaluation::EvaluateRun(*run_dir, *truth_file, *config, *out).tables.c_str(),
               stdout);
  });
}

}  // namespace mopad::tools
