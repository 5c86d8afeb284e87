// `mopad scan`, `mopad lrf`, `mopad bench raycast`: parse, call sim/sensor_jobs.h.
#include <memory>
#include <string>
#include <vector>

#include "sim/sensor_jobs.h"
#include "tools/commands.h"

namespace mopad::tools {

void RegisterSimCommands(CLI::App& app) {
  // mopad scan
  auto so = std::make_shared<sim::ScanOptions>();
  CLI::App* scan = app.add_subcommand(
      "scan", "Simulate one terrestrial laser scan (binary PLY, optional PTX, truth)");
  scan->add_option("scene", so->scene,
                   "scene folder, scene file (.glb/.gltf/.ifc/...) or spec (.yaml)")
      ->required();
  scan->add_option("--pose", so->pose,
                   "base pose x,y,z,yaw_deg in the world (the scanner sits at the mount)")
      ->required();
  scan->add_option("--profile", so->profile,
                   "built-in TLS profile (riegl_vz400, riegl_vz400_long_range)");
  scan->add_option("--profile-file", so->profile_file,
                   "TLS profile YAML (starts from riegl_vz400 defaults)");
  // Given or not, never a sentinel value: a given 0 is refused by the profile's bounds.
  auto step = std::make_shared<double>();
  auto rays = std::make_shared<int>();
  auto* step_opt =
      scan->add_option("--step-deg", *step, "angular step, deg (default: the profile's)");
  auto* rays_opt = scan->add_option("--footprint-rays", *rays,
                                    "sub-rays per pulse (1, or >= 3 for mixed pixels; default: "
                                    "the profile's)");
  scan->add_option("--seed", so->seed, "run seed");
  scan->add_option("--realism", so->realism,
                   "realism profile: ideal, typical, hard (docs/realism.md); the seed draws the "
                   "instrument's errors")
      ->default_val("ideal");
  scan->add_option("--scan-id", so->scan_id, "scan number (keys the noise)");
  scan->add_option("--threads", so->threads,
                   "worker threads (0 = all); results do not depend on it");
  scan->add_option("--door", so->doors, "door angle before scanning, ID=DEG (repeatable)");
  scan->add_option("-o,--output", so->output, "output binary PLY")->required();
  scan->add_option("--ptx", so->ptx, "also write PTX (ASCII, slow for big scans)");
  scan->add_option("--truth", so->truth, "also write the truth sidecar PLY (evaluator only)");
  scan->callback([=] {
    if (step_opt->count() > 0) so->step_deg = *step;
    if (rays_opt->count() > 0) so->footprint_rays = *rays;
    sim::RunScan(*so);
  });

  // mopad lrf
  auto lo = std::make_shared<sim::LrfOptions>();
  CLI::App* lrf = app.add_subcommand("lrf", "Simulate 2D laser range finder sweeps (CSV or JSON)");
  lrf->add_option("scene", lo->scene, "scene folder, scene file or spec (.yaml)")->required();
  lrf->add_option("--pose", lo->pose, "base pose x,y,z,yaw_deg")->required();
  lrf->add_option("--profile", lo->profile, "hokuyo_utm30lx, sick_lms111, sick_lms111_fine");
  lrf->add_option("--profile-file", lo->profile_file, "LRF profile YAML");
  lrf->add_option("--mount-height", lo->heights,
                  "one LRF per height above base_link, m (repeatable)");
  lrf->add_flag("--paper-rig", lo->paper_rig,
                "the paper's two LRFs: near the scanner and at the base");
  lrf->add_option("--seed", lo->seed, "run seed");
  lrf->add_option("--seq", lo->seq, "sweep number (keys the noise)");
  lrf->add_option("--time", lo->time, "timestamp, s");
  lrf->add_option("--door", lo->doors, "door angle, ID=DEG (repeatable)");
  lrf->add_option("-o,--output", lo->output, "output .csv or .json")->required();
  lrf->callback([lo] { sim::RunLrf(*lo); });

  // mopad bench raycast
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks");
  bench->require_subcommand(1);
  auto bo = std::make_shared<sim::BenchOptions>();
  CLI::App* rc =
      bench->add_subcommand("raycast", "Bare Embree vs the full TLS model on the same ray set");
  rc->add_option("--scene", bo->scene, "scene (default: scenes/office_5rooms.yaml, generated)");
  rc->add_option("--pose", bo->pose,
                 "base pose x,y,z,yaw_deg (default: centroid of the largest room)");
  rc->add_option("--step-deg", bo->step_deg, "angular step, deg");
  rc->add_option("--footprint-rays", bo->footprint_rays, "sub-rays per pulse for (c)");
  rc->add_option("--threads", bo->threads, "threads (0 = all)");
  rc->add_option("--seed", bo->seed, "seed");
  rc->add_option("--repeat", bo->repeat, "runs per measurement; the fastest is reported");
  rc->callback([bo] { sim::RunBench(*bo); });
}

}  // namespace mopad::tools
