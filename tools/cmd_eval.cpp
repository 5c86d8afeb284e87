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
  cmd->add_option("RUN_DIR", *run_dir,
                  "A room run (run.json) or a main-job folder (rooms/*/run.json)")
      ->required();
  cmd->add_option("--truth", *truth_file,
                  "Truth sidecar (scene.truth.json) overriding the scene's");
  cmd->add_option("--config", *config, "YAML overriding the evaluation parameters");
  cmd->add_option("-o,--output", *out, "Output folder (default: RUN_DIR/eval)");
  cmd->footer(
      "Writes DIR/evaluation.json, evaluation.md, isprs_<room>.svg, dsm3_truth_<room>.ply and "
      "eval.effective.yaml; DIR is RUN_DIR/eval unless -o (docs/evaluation.md).");
  cmd->callback([=] {
    std::fputs(evaluation::EvaluateRun(*run_dir, *truth_file, *config, *out).tables.c_str(),
               stdout);
  });
}

}  // namespace mopad::tools
