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
//   mission - the run's own evaluation.json (coverage, registration, SM1 labels) carried over;
//   floor   - the floor mission's floor model (RUN_DIR/floor/) against the evaluated rooms'
//             truth walls and doors (EvaluateFloor, evaluation/metrics_floor.h).
// Every figure is described in docs/evaluation.md.
// Writes DIR/evaluation.json, DIR/evaluation.md (tables + inline SVG plots), per room an SVG
// plot and the truth DSM3 (dsm3_truth_<room>.ply, dsm3.ply's format), and DIR/eval.effective.yaml;
// prints a summary table. Model files are read with evaluation/model_files.h (docs/models.md);
// their frame is the run's map frame.
// The steps, one function each: the parameters and run.json records (LoadEvalParams, LoadRun);
// per room its world and truth, loaded once per scene (LoadRoom), and its scores (ScoreRoom); the
// figures of all rooms (Pool); then the writers of evaluation/run_evaluation_report.h.
#include "evaluation/run_evaluation.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/params.h"
#include "evaluation/metrics_components.h"
#include "evaluation/metrics_floor.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_openings.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"
#include "evaluation/model_files.h"
#include "evaluation/run_evaluation_report.h"
#include "evaluation/truth_models.h"
#include "modelling/model_io.h"
#include "modelling/sm5_io.h"
#include "runfolder/layout.h"
#include "runfolder/run_record.h"
#include "scenes/as_built.h"
#include "scenes/ground_truth.h"
#include "sim/scene_world.h"

namespace mopad::evaluation {

double MissionNumber(const std::optional<nlohmann::ordered_json>& mission, const char* key,
                     const char* sub) {
  if (!mission || !mission->contains(key)) return NAN;
  const nlohmann::ordered_json* j = &(*mission)[key];
  if (sub) {
    if (!j->is_object() || !j->contains(sub)) return NAN;
    j = &(*j)[sub];
  }
  return j->is_number() ? j->get<double>() : NAN;
}

namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

// The run folder's rooms and the truth they are scored against. Worlds and merged truths are
// loaded once per scene key (the scene and its door overrides), when a room first asks for them;
// rooms point into them, so it stays in place while they are scored.
struct LoadedRun {
  std::vector<RunInfo> runs;                          // run.json of every room, in name order
  std::optional<scenes::GroundTruth> truth_override;  // --truth; none: each scene's sidecar
  std::map<std::string, sim::SceneWorld> worlds;      // by scene key
  std::map<std::string, OpenPlanTruth> open_plan;     // the same keys ("" = --truth)
  // The merged truth as built (scenes::AsBuiltTruth), the same keys, for a scene whose truth
  // records an as-built field.
  std::map<std::string, scenes::GroundTruth> as_built;
  std::vector<std::string> truth_notes;               // the open-plan notes, each once
};

// One room's inputs: its run.json, the world it ran in and the truth it is scored against.
struct RoomInput {
  const RunInfo* run = nullptr;
  std::string where;  // its run.json, for messages
  const sim::SceneWorld* world = nullptr;
  const scenes::GroundTruth* truth = nullptr;  // open-plan rooms merged
  const scenes::GroundTruth* truth_as_built = nullptr;  // *truth as built; none: the design
  std::string truth_room;                      // run->room's room in *truth
  std::vector<std::string> joined;             // the sidecar rooms it stands for, when merged
};

EvalParams LoadEvalParams(const std::string& config) {
  EvalParams params;
  if (!config.empty()) params = LoadParamsFile<EvalParams>(config);
  ValidateParams(params, "eval.");
  return params;
}

// The run.json of every room the run folder holds (runfolder::RoomFolders), in name order.
std::vector<RunInfo> ReadRuns(const std::string& run_dir) {
  if (!fs::is_directory(run_dir))
    throw InputError(run_dir, "run directory not found", "",
                     "a room run (run.json) or a folder with rooms/*/run.json");
  std::vector<RunInfo> runs;
  for (const std::string& room : runfolder::RoomFolders(run_dir, runfolder::kRunJson))
    runs.push_back(runfolder::ReadRunJson(runfolder::Join(room, runfolder::kRunJson)));
  if (runs.empty())
    throw InputError(run_dir, "not a run directory", "no run.json",
                     "RUN_DIR/run.json or RUN_DIR/rooms/*/run.json");
  return runs;
}

// The run.json records and the --truth sidecar (`truth_file`, "" for none); the worlds come later.
LoadedRun LoadRun(const std::string& run_dir, const std::string& truth_file) {
  LoadedRun loaded;
  loaded.runs = ReadRuns(run_dir);
  if (!truth_file.empty()) loaded.truth_override = scenes::ReadGroundTruth(truth_file);
  return loaded;
}

// `run`'s scene resolved against its folder. InputError (at `where`) when it does not exist.
std::string ScenePath(const RunInfo& run, const std::string& where) {
  std::string scene = run.scene;
  if (!fs::exists(scene) && fs::exists(fs::path(run.dir) / scene))
    scene = (fs::path(run.dir) / scene).string();
  if (!fs::exists(scene))
    throw InputError(where, "scene: not found", "'" + run.scene + "'",
                     "a generated scene folder or a spec .yaml");
  return scene;
}

// `run`'s world and truth: the --truth sidecar or the scene's, its open-plan rooms merged.
RoomInput LoadRoom(const RunInfo& run, LoadedRun& loaded) {
  RoomInput in;
  in.run = &run;
  in.where = runfolder::Join(run.dir, runfolder::kRunJson);
  const std::string scene = ScenePath(run, in.where);
  std::string key = scene;
  for (const auto& d : run.doors) key += "\n" + d;
  if (!loaded.worlds.count(key)) loaded.worlds.emplace(key, sim::LoadSceneWorld(scene, run.doors));
  const sim::SceneWorld& mw = loaded.worlds.at(key);
  in.world = &mw;
  const scenes::GroundTruth* sidecar = loaded.truth_override ? &*loaded.truth_override
                                       : mw.truth            ? &*mw.truth
                                                             : nullptr;
  if (!sidecar)
    throw InputError(in.where, "scene has no truth sidecar", "'" + scene + "'", "--truth FILE");
  const std::string truth_key = loaded.truth_override ? std::string() : key;
  if (!loaded.open_plan.count(truth_key)) {
    loaded.open_plan.emplace(truth_key, MergeOpenPlanRooms(*sidecar));
    for (const auto& note : loaded.open_plan.at(truth_key).notes)
      if (std::find(loaded.truth_notes.begin(), loaded.truth_notes.end(), note) ==
          loaded.truth_notes.end())
        loaded.truth_notes.push_back(note);
    const scenes::GroundTruth& merged = loaded.open_plan.at(truth_key).truth;
    if (merged.as_built.Enabled())
      loaded.as_built.emplace(truth_key, scenes::AsBuiltTruth(merged, merged.as_built));
  }
  const OpenPlanTruth& op = loaded.open_plan.at(truth_key);
  in.truth = &op.truth;
  if (loaded.as_built.count(truth_key)) in.truth_as_built = &loaded.as_built.at(truth_key);
  if (!sidecar->FindRoom(run.room)) {
    std::string ids;
    for (const auto& x : sidecar->rooms) ids += (ids.empty() ? "" : ", ") + x.id;
    throw InputError(in.where, "room: not a room of the truth", "'" + run.room + "'",
                     "one of " + ids);
  }
  in.truth_room = op.room_of.at(run.room);
  if (run.sm3.empty()) throw InputError(in.where, "files.sm3: missing field");
  if (op.members.count(in.truth_room)) in.joined = op.members.at(in.truth_room);
  return in;
}

std::vector<Patch> WithoutColumns(const std::vector<Patch>& patches) {
  std::vector<Patch> out;
  for (const auto& p : patches)
    if (p.cls != SurfaceClass::kColumn) out.push_back(p);
  return out;
}

// SM3 (`model`, world frame) against the truth: walls, floors and ceilings patch by patch,
// columns as objects, ISPRS over all patches. A metric's InputError names `sm3_file`.
void ScoreSm3(const std::vector<Patch>& model, const RoomInput& in, const std::string& sm3_file,
              const EvalParams& params, RoomResult& r) {
  const std::vector<Patch> truth_patches = TruthPatches(*in.truth, in.truth_room);
  try {
    r.patches =
        EvaluatePatches(WithoutColumns(model), WithoutColumns(truth_patches), params.patches);
    r.columns = EvaluateColumns(GroupModelColumns(model), TruthColumns(*in.truth, in.truth_room),
                                params.columns, params.patches);
    r.isprs = EvaluateIsprs(model, truth_patches, params.isprs);
    if (in.truth_as_built)
      r.patches_as_built = EvaluatePatches(
          WithoutColumns(model), WithoutColumns(TruthPatches(*in.truth_as_built, in.truth_room)),
          params.patches);
  } catch (const InputError& e) {
    throw InputError(sm3_file + ": " + e.what());
  }
}

// The largest SM3 floor of `model` as a plan room named `room`; none without a floor.
std::optional<Room> LargestFloor(const std::vector<Patch>& model, const std::string& room) {
  std::optional<Room> floor;
  double best = 0.0;
  for (const auto& p : model)
    if (p.cls == SurfaceClass::kFloor && PolygonArea3d(p.polygon) > best) {
      best = PolygonArea3d(p.polygon);
      Room plan{room, {}};
      for (const auto& v : p.polygon) plan.polygon.emplace_back(v.x(), v.y());
      floor = plan;
    }
  return floor;
}

// The run's DSM3 against the truth DSM3 on the robot's grid, seen from the true scanner centres
// (scan_poses.tum beside run.json, mapped by X_WM).
void ScoreDsm3(const RoomInput& in, const EvalParams& params, RoomResult& r) {
  const RunInfo& run = *in.run;
  const Dsm3Voxels dsm = ReadDsm3(run.dsm3);
  const std::string poses = runfolder::Join(run.dir, runfolder::kScanPoses);
  if (!fs::exists(poses))
    throw InputError(in.where, "scan_poses.tum missing beside run.json", "",
                     "the scanner poses for the truth DSM3");
  std::vector<Vec3> scanners;
  for (const auto& p : ReadTumPositions(poses)) scanners.push_back(run.X_WM * p);
  r.scanners = scanners.size();
  r.dsm3_truth = TruthDsm3(*in.world->world, *in.truth, in.truth_room, dsm.grid, dsm.ijk, run.X_WM,
                           scanners, params.dsm3);
  r.dsm3_pred = dsm.labels;
  r.dsm3_voxels = dsm;
  r.dsm3 = ComputeDsm3Confusion(r.dsm3_truth, r.dsm3_pred);
  r.has_dsm3 = true;
}

// The mission's own evaluation.json in `run_dir`; none when absent or when it is this
// evaluator's output (written there by `-o RUN_DIR`).
std::optional<ojson> ReadMissionFigures(const std::string& run_dir) {
  const fs::path path = runfolder::Join(run_dir, runfolder::kRoomEvaluation);
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream f(path);
  std::optional<ojson> mission;
  try {
    mission = ojson::parse(f);
  } catch (const std::exception& e) {
    throw InputError(path.string(), std::string("malformed JSON: ") + e.what());
  }
  if (mission->contains("format") && (*mission)["format"] == "mopad-evaluation")
    return std::nullopt;
  return mission;
}

// One room's models (SM3, DSM3, SM4, SM5 and the mission's figures) against its truth.
RoomResult ScoreRoom(const RoomInput& in, const EvalParams& params) {
  const RunInfo& run = *in.run;
  RoomResult r;
  r.run = run;
  r.truth = in.truth;
  r.truth_room = in.truth_room;
  r.joined = in.joined;
  const Sm3Model sm3 = ReadSm3(run.sm3);
  r.model_room = sm3.room;
  std::vector<Patch> model;
  for (const auto& p : sm3.patches) model.push_back(Transformed(p.patch, run.X_WM));
  r.model_patches = model.size();
  ScoreSm3(model, in, run.sm3, params, r);
  r.floor = LargestFloor(model, in.truth_room);
  if (!run.dsm3.empty()) ScoreDsm3(in, params, r);
  r.mission = ReadMissionFigures(run.dir);
  if (!run.sm4.empty() && fs::exists(run.sm4)) {
    const modelling::Sm4Model sm4 = modelling::ReadSm4(run.sm4);
    r.openings = EvaluateOpenings(ModelOpenings(sm4, run.X_WM),
                                  TruthOpenings(*in.truth, in.truth_room), params.openings);
  }
  const fs::path sm5 = runfolder::Join(run.dir, runfolder::kSm5);
  if (fs::exists(sm5))
    r.components = EvaluateComponents(ModelComponents(modelling::ReadSm5(sm5.string()), run.X_WM),
                                      TruthComponents(*in.truth, in.truth_room), params.components);
  // The column row of every detection table counts column objects.
  r.patches.detection[static_cast<int>(SurfaceClass::kColumn)] = r.columns.detection;
  return r;
}

// Floorplan over all rooms: the evaluated rooms' truth polygons (each once) vs the SM3 floors.
FloorplanResult PoolFloorplan(const std::vector<RoomResult>& rooms, const FloorplanParams& params) {
  std::vector<Room> predicted, truth_rooms;
  std::vector<std::string> seen;
  for (const auto& r : rooms) {
    if (r.floor) predicted.push_back(*r.floor);
    if (std::find(seen.begin(), seen.end(), r.truth_room) != seen.end()) continue;
    seen.push_back(r.truth_room);
    for (const auto& t : TruthFloorplan(*r.truth))
      if (t.id == r.truth_room) truth_rooms.push_back(t);
  }
  return EvaluateFloorplan(predicted, truth_rooms, params);
}

// The floor model (RUN_DIR/floor/, the floor mission's) against the evaluated rooms' truth;
// none when the run has no floor/sm3.json.
std::optional<FloorEvaluation> ScoreFloorModel(const std::string& run_dir,
                                               const std::vector<RoomResult>& rooms,
                                               const FloorEvalParams& params) {
  const fs::path floor_dir = runfolder::Join(run_dir, runfolder::kFloorDir);
  if (rooms.empty() || !fs::exists(floor_dir / "sm3.json")) return std::nullopt;
  std::map<std::string, std::string> truth_room;  // the robot's room name -> the truth's
  std::vector<std::string> truth_rooms;
  for (const auto& r : rooms) {
    truth_room[r.model_room] = r.truth_room;
    if (std::find(truth_rooms.begin(), truth_rooms.end(), r.truth_room) == truth_rooms.end())
      truth_rooms.push_back(r.truth_room);
  }
  return EvaluateFloor(modelling::ReadFloorModel(floor_dir.string()), rooms.front().run.X_WM,
                       truth_room, MakeFloorTruth(*rooms.front().truth, truth_rooms), params);
}

void AddDetection(const ClassDetection& s, ClassDetection& d) {
  d.n_truth += s.n_truth, d.n_model += s.n_model, d.tp += s.tp, d.fp += s.fp, d.fn += s.fn;
}

// Walls, floors and ceilings of all rooms; the column row is the rooms' column objects.
// `of` picks a room's evaluation (the design's or the as-built one; rooms without are skipped).
template <class Of>
PatchEvaluation PoolPatches(const std::vector<RoomResult>& rooms, Of of) {
  PatchEvaluation pooled;
  for (const auto& r : rooms) {
    const PatchEvaluation* e = of(r);
    if (!e) continue;
    for (int c = 0; c < kNumSurfaceClasses; ++c) {
      AddDetection(e->detection[c], pooled.detection[c]);
      pooled.accuracy[c].d_v.Merge(e->accuracy[c].d_v);
      pooled.accuracy[c].d_h.Merge(e->accuracy[c].d_h);
      pooled.accuracy[c].phi_deg.Merge(e->accuracy[c].phi_deg);
    }
    pooled.d_v.Merge(e->d_v);
    pooled.d_h.Merge(e->d_h);
    pooled.phi_deg.Merge(e->phi_deg);
  }
  return pooled;
}

// The models against the as-built truth, and the truth's departure from its design over the
// elements of the scored rooms; none when the scene is its design.
std::optional<AsBuiltFigures> PoolAsBuilt(const std::vector<RoomResult>& rooms) {
  if (rooms.empty() || !rooms.front().truth->as_built.Enabled()) return std::nullopt;
  AsBuiltFigures f;
  f.patches = PoolPatches(rooms, [](const RoomResult& r) {
    return r.patches_as_built ? &*r.patches_as_built : nullptr;
  });
  const scenes::GroundTruth& truth = *rooms.front().truth;
  const scenes::AsBuiltField field(truth.as_built);
  std::set<std::string> scored;
  for (const auto& r : rooms) scored.insert(r.truth_room);
  for (const auto& e : truth.elements) {
    AsBuiltFigures::Deviation* d = e.element_class == scenes::ElementClass::kWall      ? &f.wall
                                   : e.element_class == scenes::ElementClass::kFloor   ? &f.floor
                                   : e.element_class == scenes::ElementClass::kCeiling ? &f.ceiling
                                                                                       : nullptr;
    const bool in_scored = std::any_of(e.rooms.begin(), e.rooms.end(),
                                       [&](const auto& id) { return scored.count(id); });
    if (!d || !in_scored) continue;
    const scenes::SurfaceDeviation s = scenes::MeasureDeviation(e, field);
    ++d->elements;
    d->rms_mm += s.rms_mm;
    d->max_mm = std::max(d->max_mm, s.max_mm);
    d->tilt_mean_deg += s.tilt_deg;
    d->tilt_max_deg = std::max(d->tilt_max_deg, s.tilt_deg);
  }
  for (AsBuiltFigures::Deviation* d : {&f.wall, &f.floor, &f.ceiling})
    if (d->elements > 0) d->rms_mm /= d->elements, d->tilt_mean_deg /= d->elements;
  return f;
}

ColumnEvaluation PoolColumns(const std::vector<RoomResult>& rooms) {
  ColumnEvaluation pooled;
  for (const auto& r : rooms) {
    AddDetection(r.columns.detection, pooled.detection);
    AddDetection(r.columns.face_detection, pooled.face_detection);
    pooled.face_accuracy.d_v.Merge(r.columns.face_accuracy.d_v);
    pooled.face_accuracy.d_h.Merge(r.columns.face_accuracy.d_h);
    pooled.face_accuracy.phi_deg.Merge(r.columns.face_accuracy.phi_deg);
    pooled.plan_iou.Merge(r.columns.plan_iou);
    pooled.centre_error.Merge(r.columns.centre_error);
    pooled.area_error.Merge(r.columns.area_error);
    pooled.diameter_error.Merge(r.columns.diameter_error);
    pooled.height_error.Merge(r.columns.height_error);
  }
  return pooled;
}

// Completeness/correctness of the "all" curve pooled over rooms (area-weighted; rooms never lie
// within the buffer of each other's surfaces, so this equals one evaluation over all patches).
std::pair<double, double> PooledIsprs(const std::vector<RoomResult>& rooms, double buffer) {
  double ref = 0, src = 0, c = 0, k = 0;
  for (const auto& r : rooms) {
    const int b = r.isprs.BufferIndex(buffer);
    const auto& a = r.isprs.all;
    if (a.reference_area > 0 && std::isfinite(a.completeness[b]))
      ref += a.reference_area, c += a.reference_area * a.completeness[b];
    if (a.source_area > 0 && std::isfinite(a.correctness[b]))
      src += a.source_area, k += a.source_area * a.correctness[b];
  }
  return {ref > 0 ? c / ref : NAN, src > 0 ? k / src : NAN};
}

MissionFigures PoolMissionFigures(const std::vector<RoomResult>& rooms) {
  MissionFigures m;
  for (const auto& r : rooms) {
    const double cov = MissionNumber(r.mission, "coverage_of_observable");
    const double t = MissionNumber(r.mission, "registration_error_max", "translation_m");
    const double rot = MissionNumber(r.mission, "registration_error_max", "rotation_deg");
    const double n = MissionNumber(r.mission, "sm1_labels", "points");
    const double c = MissionNumber(r.mission, "sm1_labels", "correct");
    if (std::isfinite(cov))
      m.coverage_min = std::isfinite(m.coverage_min) ? std::min(m.coverage_min, cov) : cov;
    if (std::isfinite(t))
      m.translation_max_m =
          std::isfinite(m.translation_max_m) ? std::max(m.translation_max_m, t) : t;
    if (std::isfinite(rot))
      m.rotation_max_deg =
          std::isfinite(m.rotation_max_deg) ? std::max(m.rotation_max_deg, rot) : rot;
    if (std::isfinite(n) && std::isfinite(c)) m.sm1_points += n, m.sm1_correct += c;
  }
  return m;
}

PooledFigures Pool(const std::string& run_dir, const std::vector<RoomResult>& rooms,
                   const EvalParams& params) {
  PooledFigures p;
  p.floorplan = PoolFloorplan(rooms, params.floorplan);
  p.floor = ScoreFloorModel(run_dir, rooms, params.floor);
  p.patches = PoolPatches(rooms, [](const RoomResult& r) { return &r.patches; });
  p.as_built = PoolAsBuilt(rooms);
  p.columns = PoolColumns(rooms);
  p.patches.detection[static_cast<int>(SurfaceClass::kColumn)] = p.columns.detection;
  std::vector<std::uint8_t> all_truth, all_pred;
  for (const auto& r : rooms) {
    all_truth.insert(all_truth.end(), r.dsm3_truth.begin(), r.dsm3_truth.end());
    all_pred.insert(all_pred.end(), r.dsm3_pred.begin(), r.dsm3_pred.end());
  }
  p.any_dsm3 = !all_truth.empty();
  p.dsm3 = ComputeDsm3Confusion(all_truth, all_pred);
  std::tie(p.isprs_completeness, p.isprs_correctness) = PooledIsprs(rooms, params.report_buffer);
  p.mission = PoolMissionFigures(rooms);
  std::vector<OpeningEvaluation> openings;
  std::vector<ComponentEvaluation> components;
  for (const auto& r : rooms) {
    if (r.openings) openings.push_back(*r.openings);
    if (r.components) components.push_back(*r.components);
  }
  if (!openings.empty()) p.openings = PoolOpenings(openings);
  if (!components.empty()) p.components = PoolComponents(components);
  return p;
}

}  // namespace

RunEvaluation EvaluateRun(const std::string& run_dir, const std::string& truth_file,
                          const std::string& config, const std::string& out) {
  const EvalParams params = LoadEvalParams(config);
  LoadedRun loaded = LoadRun(run_dir, truth_file);
  std::vector<RoomResult> rooms;
  for (const RunInfo& run : loaded.runs) rooms.push_back(ScoreRoom(LoadRoom(run, loaded), params));
  const PooledFigures pooled = Pool(run_dir, rooms, params);

  const ojson json = EvaluationJson(run_dir, truth_file, params, rooms, pooled, loaded.truth_notes);
  const fs::path dir =
      out.empty() ? fs::path(runfolder::Join(run_dir, runfolder::kEvalDir)) : fs::path(out);
  fs::create_directories(dir);
  WriteWholeFile((dir / "evaluation.json").string(), json.dump(2) + "\n");
  WriteWholeFile((dir / "eval.effective.yaml").string(), YAML::Dump(SaveParams(params)) + "\n");
  WriteRoomFiles(dir.string(), rooms);
  WriteWholeFile((dir / "evaluation.md").string(),
                 EvaluationMarkdown(run_dir, params, rooms, pooled, loaded.truth_notes));
  return {PrintedTables(params, rooms, pooled, dir.string()), json.at("summary"),
          pooled.components};
}

}  // namespace mopad::evaluation
