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
#include "evaluation/run_evaluation.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "evaluation/metrics_components.h"
#include "evaluation/metrics_floor.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_openings.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"
#include "evaluation/model_files.h"
#include "evaluation/report_tables.h"
#include "evaluation/truth_models.h"
#include "modelling/model_io.h"
#include "modelling/sm5_io.h"
#include "runfolder/layout.h"
#include "runfolder/run_record.h"
#include "scenes/ground_truth.h"
#include "sim/scene_world.h"

namespace mopad::evaluation {
namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

// printf into a growing string: the tables `mopad eval` prints.
template <class... A>
void Append(std::string& out, const char* format, A... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  out += buf;
}

struct EvalParams {
  PatchMatchParams patches;
  ColumnMatchParams columns;
  IsprsParams isprs;
  FloorplanParams floorplan;
  TruthDsm3Params dsm3;
  OpeningMatchParams openings;
  ComponentMatchParams components;
  FloorEvalParams floor;
  double report_buffer = 0.05;  ///< m, ISPRS buffer of the summary and tables, [0, 1]
  template <class V>
  void Visit(V& v) {
    v("patches", patches);
    v("columns", columns);
    v("isprs", isprs);
    v("floorplan", floorplan);
    v("dsm3", dsm3);
    v("openings", openings);
    v("components", components);
    v("floor", floor);
    v("report_buffer", report_buffer, Bounds{0.0, 1.0});
  }
};

ojson Ord(const nlohmann::json& j) { return ojson::parse(j.dump()); }
ojson Num(double x) { return std::isfinite(x) ? ojson(x) : ojson(nullptr); }

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

Patch ToWorld(const Patch& p, const Pose3& X_WM) {
  Patch w = p;
  for (auto& v : w.polygon) v = X_WM * v;
  w.normal = X_WM.linear() * p.normal;
  return w;
}

struct RoomResult {
  RunInfo run;
  std::string model_room;                      // the robot's name of the room (its sm3.json "room")
  const scenes::GroundTruth* truth = nullptr;  // open-plan rooms merged (MergeOpenPlanRooms)
  std::string truth_room;                      // run.room's room in *truth
  std::vector<std::string> joined;             // the sidecar rooms it stands for, when merged
  std::size_t model_patches = 0;
  PatchEvaluation patches;  // walls, floors, ceilings
  ColumnEvaluation columns;
  IsprsResult isprs;
  std::optional<Room> floor;  // SM3 floor in world plan
  bool has_dsm3 = false;
  std::vector<std::uint8_t> dsm3_truth, dsm3_pred;
  Dsm3Voxels dsm3_voxels;  // the robot's grid and voxel list
  ConfusionMatrix dsm3;
  std::size_t scanners = 0;
  std::optional<ojson> mission;
  std::optional<OpeningEvaluation> openings;      // SM4, when the run wrote sm4.json
  std::optional<ComponentEvaluation> components;  // SM5, when the run wrote sm5.json
};

ojson CountsJson(const std::vector<std::uint8_t>& labels) {
  const auto c = CountVoxelLabels(labels);
  ojson j;
  for (std::size_t i = 0; i < c.size(); ++i) j[Dsm3LabelNames()[i]] = c[i];
  return j;
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

double MissionNumber(const std::optional<ojson>& m, const char* key, const char* sub = nullptr) {
  if (!m || !m->contains(key)) return NAN;
  const ojson* j = &(*m)[key];
  if (sub) {
    if (!j->is_object() || !j->contains(sub)) return NAN;
    j = &(*j)[sub];
  }
  return j->is_number() ? j->get<double>() : NAN;
}

ojson DetectionJson(const ClassDetection& d) {
  return {{"n_truth", d.n_truth}, {"n_model", d.n_model}, {"tp", d.tp}, {"fp", d.fp}, {"fn", d.fn}};
}

// Column objects (docs/evaluation.md): detection, error stats, pairs, face metrics.
ojson ColumnsJson(const ColumnEvaluation& c, bool with_pairs) {
  ojson j;
  j["detection"] = DetectionJson(c.detection);
  j["plan_iou"] = Ord(ToJson(c.plan_iou));
  j["centre_error_m"] = Ord(ToJson(c.centre_error));
  j["area_error_m2"] = Ord(ToJson(c.area_error));
  j["diameter_error_m"] = Ord(ToJson(c.diameter_error));
  j["height_error_m"] = Ord(ToJson(c.height_error));
  j["polygonal_faces"] = {{"detection", DetectionJson(c.face_detection)},
                          {"d_v", Ord(ToJson(c.face_accuracy.d_v))},
                          {"d_h", Ord(ToJson(c.face_accuracy.d_h))},
                          {"phi_deg", Ord(ToJson(c.face_accuracy.phi_deg))}};
  if (with_pairs) {
    ojson pairs = ojson::array();
    for (const auto& p : c.pairs)
      pairs.push_back({{"model", p.model_id},
                       {"truth", p.truth_id},
                       {"plan_iou", Num(p.plan_iou)},
                       {"centre_error_m", Num(p.centre_error)},
                       {"area_error_m2", Num(p.area_error)},
                       {"diameter_error_m", Num(p.diameter_error)},
                       {"height_error_m", Num(p.height_error)},
                       {"faces_compared", p.faces_compared}});
    j["pairs"] = pairs;
    j["unmatched_model"] = c.unmatched_model_ids;
    j["unmatched_truth"] = c.unmatched_truth_ids;
  }
  return j;
}

std::string ColumnsMarkdown(const ColumnEvaluation& c) {
  std::ostringstream md;
  md << "TP " << c.detection.tp << " / " << c.detection.n_truth << " truth, FP " << c.detection.fp
     << ", FN " << c.detection.fn << " (plan IoU > 0.5).\n\n";
  md << "| model | truth | plan IoU | centre error (cm) | diameter error (cm) | area error (cm^2) "
        "| height error (cm) | faces d_h (cm) | faces Phi (deg) |\n";
  md << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& p : c.pairs) {
    const auto& a = p.faces.accuracy[static_cast<int>(SurfaceClass::kColumn)];
    md << "| " << p.model_id << " | " << p.truth_id << " | " << FormatFixed(p.plan_iou, 3) << " | "
       << FormatFixed(p.centre_error * 100, 2) << " | " << FormatFixed(p.diameter_error * 100, 2)
       << " | " << FormatFixed(p.area_error * 1e4, 1) << " | "
       << FormatFixed(p.height_error * 100, 2) << " | "
       << (p.faces_compared ? FormatFixed(a.d_h.mean * 100, 2) : std::string("round")) << " | "
       << (p.faces_compared ? FormatFixed(a.phi_deg.mean, 4) : std::string("round")) << " |\n";
  }
  for (const auto& id : c.unmatched_model_ids) md << "| " << id << " (FP) | - | | | | | | | |\n";
  for (const auto& id : c.unmatched_truth_ids) md << "| - | " << id << " (FN) | | | | | | | |\n";
  return md.str();
}

// The truth DSM3 in the dsm3.ply format of docs/models.md (map frame, the robot's grid), for
// viewers next to the robot's own file.
void WriteTruthDsm3Ply(const std::string& path, const Dsm3Voxels& grid_of,
                       const std::vector<std::uint8_t>& labels) {
  static const char* kFileNames[] = {"unseen",  "empty",  "structure", "occluded_structure",
                                     "clutter", "opening"};
  std::uint8_t to_file[6] = {};
  for (int c = 0; c < 6; ++c)
    for (int v = 0; v < 6; ++v)
      if (Dsm3LabelNames()[c] == kFileNames[v]) to_file[c] = static_cast<std::uint8_t>(v);
  const VoxelGrid& g = grid_of.grid;
  char buf[256];
  std::string data = "ply\nformat binary_little_endian 1.0\n";
  std::snprintf(buf, sizeof buf,
                "comment mopad_dsm3_voxel_size %.6f\ncomment mopad_dsm3_origin %.6f %.6f %.6f\n",
                g.voxel_size, g.origin.x(), g.origin.y(), g.origin.z());
  data += buf;
  std::snprintf(buf, sizeof buf, "comment mopad_dsm3_dims %d %d %d\n", g.dims[0], g.dims[1],
                g.dims[2]);
  data += buf;
  for (int v = 0; v < 6; ++v)
    data += "comment mopad_dsm3_label " + std::to_string(v) + " " + kFileNames[v] + "\n";
  data += "comment mopad_dsm3_truth 1\nelement vertex " + std::to_string(labels.size()) +
          "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar scalar_label\n"
          "property int scalar_i\nproperty int scalar_j\nproperty int scalar_k\nend_header\n";
  for (std::size_t n = 0; n < labels.size(); ++n) {
    const Vec3 c = g.Centre(grid_of.ijk[n]);
    const float xyz[3] = {static_cast<float>(c.x()), static_cast<float>(c.y()),
                          static_cast<float>(c.z())};
    data.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    data.push_back(static_cast<char>(to_file[labels[n]]));
    const std::int32_t ijk[3] = {grid_of.ijk[n][0], grid_of.ijk[n][1], grid_of.ijk[n][2]};
    data.append(reinterpret_cast<const char*>(ijk), sizeof ijk);
  }
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot write the file");
  f << data;
}

}  // namespace

RunEvaluation EvaluateRun(const std::string& run_dir, const std::string& truth_file,
                          const std::string& config, const std::string& out) {
  std::string report;
  EvalParams params;
  if (!config.empty()) params = LoadParamsFile<EvalParams>(config);
  ValidateParams(params, "eval.");
  const std::vector<RunInfo> runs = ReadRuns(run_dir);
  std::optional<scenes::GroundTruth> truth_override;
  if (!truth_file.empty()) truth_override = scenes::ReadGroundTruth(truth_file);

  std::map<std::string, sim::SceneWorld> worlds;   // by scene argument and door overrides
  std::map<std::string, OpenPlanTruth> open_plan;  // the same keys ("" = --truth)
  std::vector<std::string> truth_notes;
  std::vector<RoomResult> results;
  for (const auto& run : runs) {
    const std::string where = runfolder::Join(run.dir, runfolder::kRunJson);
    std::string scene = run.scene;
    if (!fs::exists(scene) && fs::exists(fs::path(run.dir) / scene))
      scene = (fs::path(run.dir) / scene).string();
    if (!fs::exists(scene))
      throw InputError(where, "scene: not found", "'" + run.scene + "'",
                       "a generated scene folder or a spec .yaml");
    std::string key = scene;
    for (const auto& d : run.doors) key += "\n" + d;
    if (!worlds.count(key)) worlds.emplace(key, sim::LoadSceneWorld(scene, run.doors));
    const sim::SceneWorld& mw = worlds.at(key);
    const scenes::GroundTruth* sidecar = truth_override ? &*truth_override
                                         : mw.truth     ? &*mw.truth
                                                        : nullptr;
    if (!sidecar)
      throw InputError(where, "scene has no truth sidecar", "'" + scene + "'", "--truth FILE");
    const std::string truth_key = truth_override ? std::string() : key;
    if (!open_plan.count(truth_key)) {
      open_plan.emplace(truth_key, MergeOpenPlanRooms(*sidecar));
      for (const auto& note : open_plan.at(truth_key).notes)
        if (std::find(truth_notes.begin(), truth_notes.end(), note) == truth_notes.end())
          truth_notes.push_back(note);
    }
    const OpenPlanTruth& op = open_plan.at(truth_key);
    const scenes::GroundTruth* truth = &op.truth;
    if (!sidecar->FindRoom(run.room)) {
      std::string ids;
      for (const auto& x : sidecar->rooms) ids += (ids.empty() ? "" : ", ") + x.id;
      throw InputError(where, "room: not a room of the truth", "'" + run.room + "'",
                       "one of " + ids);
    }
    const std::string truth_room = op.room_of.at(run.room);
    if (run.sm3.empty()) throw InputError(where, "files.sm3: missing field");

    RoomResult r;
    r.run = run;
    r.truth = truth;
    r.truth_room = truth_room;
    if (op.members.count(truth_room)) r.joined = op.members.at(truth_room);
    const Sm3Model sm3 = ReadSm3(run.sm3);
    r.model_room = sm3.room;
    std::vector<Patch> model;
    for (const auto& p : sm3.patches) model.push_back(ToWorld(p.patch, run.X_WM));
    r.model_patches = model.size();
    const std::vector<Patch> truth_patches = TruthPatches(*truth, truth_room);
    // Columns are scored as objects, the other classes patch by patch.
    auto no_columns = [](const std::vector<Patch>& v) {
      std::vector<Patch> out;
      for (const auto& p : v)
        if (p.cls != SurfaceClass::kColumn) out.push_back(p);
      return out;
    };
    try {
      r.patches = EvaluatePatches(no_columns(model), no_columns(truth_patches), params.patches);
      r.columns = EvaluateColumns(GroupModelColumns(model), TruthColumns(*truth, truth_room),
                                  params.columns, params.patches);
      r.isprs = EvaluateIsprs(model, truth_patches, params.isprs);
    } catch (const InputError& e) {
      throw InputError(run.sm3 + ": " + e.what());
    }
    double best = 0.0;
    for (const auto& p : model)
      if (p.cls == SurfaceClass::kFloor && PolygonArea3d(p.polygon) > best) {
        best = PolygonArea3d(p.polygon);
        Room room{truth_room, {}};
        for (const auto& v : p.polygon) room.polygon.emplace_back(v.x(), v.y());
        r.floor = room;
      }
    if (!run.dsm3.empty()) {
      const Dsm3Voxels dsm = ReadDsm3(run.dsm3);
      const std::string poses = runfolder::Join(run.dir, runfolder::kScanPoses);
      if (!fs::exists(poses))
        throw InputError(where, "scan_poses.tum missing beside run.json", "",
                         "the scanner poses for the truth DSM3");
      std::vector<Vec3> scanners;
      for (const auto& p : ReadTumPositions(poses)) scanners.push_back(run.X_WM * p);
      r.scanners = scanners.size();
      r.dsm3_truth = TruthDsm3(*mw.world, *truth, truth_room, dsm.grid, dsm.ijk, run.X_WM, scanners,
                               params.dsm3);
      r.dsm3_pred = dsm.labels;
      r.dsm3_voxels = dsm;
      r.dsm3 = ComputeDsm3Confusion(r.dsm3_truth, r.dsm3_pred);
      r.has_dsm3 = true;
    }
    const fs::path mission = runfolder::Join(run.dir, runfolder::kRoomEvaluation);
    if (fs::exists(mission)) {
      std::ifstream f(mission);
      try {
        r.mission = ojson::parse(f);
      } catch (const std::exception& e) {
        throw InputError(mission.string(), std::string("malformed JSON: ") + e.what());
      }
      // Our own output written into the run dir (-o RUN_DIR) is not the mission's.
      if (r.mission->contains("format") && (*r.mission)["format"] == "mopad-evaluation")
        r.mission.reset();
    }
    if (!run.sm4.empty() && fs::exists(run.sm4)) {
      const modelling::Sm4Model sm4 = modelling::ReadSm4(run.sm4);
      r.openings = EvaluateOpenings(ModelOpenings(sm4, run.X_WM), TruthOpenings(*truth, truth_room),
                                    params.openings);
    }
    const fs::path sm5 = runfolder::Join(run.dir, runfolder::kSm5);
    if (fs::exists(sm5))
      r.components = EvaluateComponents(ModelComponents(modelling::ReadSm5(sm5.string()), run.X_WM),
                                        TruthComponents(*truth, truth_room), params.components);
    results.push_back(std::move(r));
  }

  // Floorplan over all rooms: the evaluated rooms' truth polygons vs the SM3 floors.
  std::vector<Room> predicted, truth_rooms;
  {
    std::vector<std::string> seen;
    for (const auto& r : results) {
      if (r.floor) predicted.push_back(*r.floor);
      if (std::find(seen.begin(), seen.end(), r.truth_room) != seen.end()) continue;
      seen.push_back(r.truth_room);
      for (const auto& t : TruthFloorplan(*r.truth))
        if (t.id == r.truth_room) truth_rooms.push_back(t);
    }
  }
  const FloorplanResult plan = EvaluateFloorplan(predicted, truth_rooms, params.floorplan);

  // The floor model (RUN_DIR/floor/, the floor mission's), against the evaluated rooms' truth.
  std::optional<FloorEvaluation> floor;
  const fs::path floor_dir = runfolder::Join(run_dir, runfolder::kFloorDir);
  if (!results.empty() && fs::exists(floor_dir / "sm3.json")) {
    std::map<std::string, std::string> truth_room;
    std::vector<std::string> rooms;
    for (const auto& r : results) {
      truth_room[r.model_room] = r.truth_room;
      if (std::find(rooms.begin(), rooms.end(), r.truth_room) == rooms.end())
        rooms.push_back(r.truth_room);
    }
    floor = EvaluateFloor(modelling::ReadFloorModel(floor_dir.string()), results.front().run.X_WM,
                          truth_room, MakeFloorTruth(*results.front().truth, rooms), params.floor);
  }

  // Pooled figures.
  PatchEvaluation pooled;
  ColumnEvaluation pooled_columns;
  std::vector<std::uint8_t> all_truth, all_pred;
  for (const auto& r : results) {
    for (int c = 0; c < kNumSurfaceClasses; ++c) {
      auto& d = pooled.detection[c];
      const auto& s = r.patches.detection[c];
      d.n_truth += s.n_truth, d.n_model += s.n_model, d.tp += s.tp, d.fp += s.fp, d.fn += s.fn;
      pooled.accuracy[c].d_v.Merge(r.patches.accuracy[c].d_v);
      pooled.accuracy[c].d_h.Merge(r.patches.accuracy[c].d_h);
      pooled.accuracy[c].phi_deg.Merge(r.patches.accuracy[c].phi_deg);
    }
    {
      auto& d = pooled_columns.detection;
      const auto& s = r.columns.detection;
      d.n_truth += s.n_truth, d.n_model += s.n_model, d.tp += s.tp, d.fp += s.fp, d.fn += s.fn;
      auto& fd = pooled_columns.face_detection;
      const auto& fs = r.columns.face_detection;
      fd.n_truth += fs.n_truth, fd.n_model += fs.n_model, fd.tp += fs.tp, fd.fp += fs.fp,
          fd.fn += fs.fn;
      pooled_columns.face_accuracy.d_v.Merge(r.columns.face_accuracy.d_v);
      pooled_columns.face_accuracy.d_h.Merge(r.columns.face_accuracy.d_h);
      pooled_columns.face_accuracy.phi_deg.Merge(r.columns.face_accuracy.phi_deg);
      pooled_columns.plan_iou.Merge(r.columns.plan_iou);
      pooled_columns.centre_error.Merge(r.columns.centre_error);
      pooled_columns.area_error.Merge(r.columns.area_error);
      pooled_columns.diameter_error.Merge(r.columns.diameter_error);
      pooled_columns.height_error.Merge(r.columns.height_error);
    }
    pooled.d_v.Merge(r.patches.d_v);
    pooled.d_h.Merge(r.patches.d_h);
    pooled.phi_deg.Merge(r.patches.phi_deg);
    all_truth.insert(all_truth.end(), r.dsm3_truth.begin(), r.dsm3_truth.end());
    all_pred.insert(all_pred.end(), r.dsm3_pred.begin(), r.dsm3_pred.end());
  }
  // The column class of every detection table counts column objects.
  pooled.detection[static_cast<int>(SurfaceClass::kColumn)] = pooled_columns.detection;
  for (auto& r : results)
    r.patches.detection[static_cast<int>(SurfaceClass::kColumn)] = r.columns.detection;
  const bool any_dsm3 = !all_truth.empty();
  const ConfusionMatrix pooled_dsm3 = ComputeDsm3Confusion(all_truth, all_pred);
  const auto [compl_b, corr_b] = PooledIsprs(results, params.report_buffer);
  const int structure = static_cast<int>(VoxelLabel::kStructure);

  // evaluation.json
  ojson j;
  j["format"] = "mopad-evaluation";
  j["version"] = 1;
  j["run_dir"] = run_dir;
  j["truth"] = truth_file.empty() ? "scene" : truth_file;
  ojson summary;
  summary["rooms"] = results.size();
  ojson det;
  for (auto c : AllSurfaceClasses()) {
    const auto& d = pooled.detection[static_cast<int>(c)];
    det[SurfaceClassName(c)] = {{"n_truth", d.n_truth}, {"tp", d.tp}, {"fp", d.fp}, {"fn", d.fn}};
  }
  summary["detection"] = det;
  summary["d_v"] = Ord(ToJson(pooled.d_v));
  summary["d_h"] = Ord(ToJson(pooled.d_h));
  summary["phi_deg"] = Ord(ToJson(pooled.phi_deg));
  summary["columns"] = ColumnsJson(pooled_columns, /*with_pairs=*/false);
  summary["isprs_buffer"] = params.report_buffer;
  summary["isprs_completeness"] = Num(compl_b);
  summary["isprs_correctness"] = Num(corr_b);
  summary["dsm3_structure_iou"] = any_dsm3 ? Num(pooled_dsm3.iou[structure]) : ojson(nullptr);
  summary["floorplan_mean_iou"] = Num(plan.mean_truth_iou);
  {
    // The missions' own figures (per-pulse truth during the run), pooled over rooms.
    double cov_min = NAN, t_max = NAN, r_max = NAN, points = 0, correct = 0;
    for (const auto& r : results) {
      const double cov = MissionNumber(r.mission, "coverage_of_observable");
      const double t = MissionNumber(r.mission, "registration_error_max", "translation_m");
      const double rot = MissionNumber(r.mission, "registration_error_max", "rotation_deg");
      const double n = MissionNumber(r.mission, "sm1_labels", "points");
      const double c = MissionNumber(r.mission, "sm1_labels", "correct");
      if (std::isfinite(cov)) cov_min = std::isfinite(cov_min) ? std::min(cov_min, cov) : cov;
      if (std::isfinite(t)) t_max = std::isfinite(t_max) ? std::max(t_max, t) : t;
      if (std::isfinite(rot)) r_max = std::isfinite(r_max) ? std::max(r_max, rot) : rot;
      if (std::isfinite(n) && std::isfinite(c)) points += n, correct += c;
    }
    summary["mission"] = {
        {"coverage_of_observable_min", Num(cov_min)},
        {"registration_translation_max_m", Num(t_max)},
        {"registration_rotation_max_deg", Num(r_max)},
        {"sm1_label_accuracy", points > 0 ? Num(correct / points) : ojson(nullptr)}};
  }
  std::vector<OpeningEvaluation> opening_parts;
  for (const auto& r : results)
    if (r.openings) opening_parts.push_back(*r.openings);
  const std::optional<OpeningEvaluation> pooled_openings =
      opening_parts.empty() ? std::nullopt
                            : std::optional<OpeningEvaluation>(PoolOpenings(opening_parts));
  summary["openings"] = pooled_openings ? Ord(ToJson(*pooled_openings)) : ojson(nullptr);
  std::vector<ComponentEvaluation> component_parts;
  for (const auto& r : results)
    if (r.components) component_parts.push_back(*r.components);
  std::optional<ComponentEvaluation> pooled_components;
  if (!component_parts.empty()) pooled_components = PoolComponents(component_parts);
  if (pooled_components) {  // the pairs stay per room
    ojson c = Ord(ToJson(*pooled_components));
    c.erase("pairs");
    summary["components"] = c;
  } else {
    summary["components"] = nullptr;
  }
  if (floor) {
    const ClassDetection& w = floor->faces.detection[static_cast<int>(SurfaceClass::kWall)];
    summary["floor"] = {{"wall_faces", {{"n_truth", w.n_truth}, {"tp", w.tp}, {"fp", w.fp}}},
                        {"d_v", Ord(ToJson(floor->faces.d_v))},
                        {"d_h", Ord(ToJson(floor->faces.d_h))},
                        {"thickness_error_m", Ord(ToJson(floor->thickness_error))},
                        {"room_alignment_m", Ord(ToJson(floor->room_alignment))},
                        {"face_pairs_correct", floor->correct_pairs},
                        {"face_pairs_truth", floor->truth_pairs},
                        {"doors_merged_correct", floor->merged_correct},
                        {"doors_between_rooms", floor->truth_doors},
                        {"door_side_offset_m", Ord(ToJson(floor->door_side_offset))}};
  } else {
    summary["floor"] = nullptr;
  }
  if (!truth_notes.empty()) summary["truth_notes"] = truth_notes;
  j["summary"] = summary;
  ojson rooms = ojson::array();
  for (const auto& r : results) {
    ojson x;
    x["room"] = r.run.room;
    if (!r.joined.empty()) x["truth_rooms"] = r.joined;
    x["run_dir"] = r.run.dir;
    x["seed"] = r.run.seed;
    x["model_patches"] = r.model_patches;
    x["sm3"] = Ord(ToJson(r.patches));
    x["columns"] = ColumnsJson(r.columns, /*with_pairs=*/true);
    x["isprs"] = Ord(ToJson(r.isprs));
    if (r.has_dsm3) {
      x["dsm3"] = Ord(ToJson(r.dsm3));
      x["dsm3_scanner_positions"] = r.scanners;
      x["dsm3_truth_counts"] = CountsJson(r.dsm3_truth);
      x["dsm3_model_counts"] = CountsJson(r.dsm3_pred);
    } else {
      x["dsm3"] = nullptr;
    }
    x["mission"] = r.mission ? *r.mission : ojson(nullptr);
    x["openings"] = r.openings ? Ord(ToJson(*r.openings)) : ojson(nullptr);
    x["components"] = r.components ? Ord(ToJson(*r.components)) : ojson(nullptr);
    rooms.push_back(x);
  }
  j["rooms"] = rooms;
  j["floorplan"] = Ord(ToJson(plan));
  j["dsm3_all_rooms"] = any_dsm3 ? Ord(ToJson(pooled_dsm3)) : ojson(nullptr);
  j["floor"] = floor ? ToJson(*floor) : ojson(nullptr);

  const fs::path dir = out.empty() ? fs::path(runfolder::Join(run_dir, runfolder::kEvalDir)) : fs::path(out);
  fs::create_directories(dir);
  std::ofstream(dir / "evaluation.json") << j.dump(2) << "\n";
  std::ofstream(dir / "eval.effective.yaml") << YAML::Dump(SaveParams(params)) << "\n";

  // evaluation.md
  std::ostringstream md;
  md << "# Evaluation of `" << run_dir << "`\n\n";
  md << "| room | walls TP/N (FP) | floors | ceilings | columns | d_v mean (cm) | d_h mean (cm) "
        "| "
        "Phi mean (deg) | compl@"
     << FormatFixed(params.report_buffer * 100, 0) << "cm | corr@"
     << FormatFixed(params.report_buffer * 100, 0) << "cm | DSM3 structure IoU |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto det_cell = [](const ClassDetection& d) {
    return std::to_string(d.tp) + "/" + std::to_string(d.n_truth) + " (" + std::to_string(d.fp) +
           ")";
  };
  for (const auto& r : results) {
    const int b = r.isprs.BufferIndex(params.report_buffer);
    md << "| " << r.run.room;
    for (int c = 0; c < kNumSurfaceClasses; ++c) md << " | " << det_cell(r.patches.detection[c]);
    md << " | " << FormatFixed(r.patches.d_v.mean * 100, 2) << " | "
       << FormatFixed(r.patches.d_h.mean * 100, 2) << " | "
       << FormatFixed(r.patches.phi_deg.mean, 4) << " | "
       << FormatFixed(r.isprs.all.completeness[b], 4) << " | "
       << FormatFixed(r.isprs.all.correctness[b], 4) << " | "
       << (r.has_dsm3 ? FormatFixed(r.dsm3.iou[structure], 4) : std::string("-")) << " |\n";
  }
  md << "| **all**";
  for (int c = 0; c < kNumSurfaceClasses; ++c) md << " | " << det_cell(pooled.detection[c]);
  md << " | " << FormatFixed(pooled.d_v.mean * 100, 2) << " | "
     << FormatFixed(pooled.d_h.mean * 100, 2) << " | " << FormatFixed(pooled.phi_deg.mean, 4)
     << " | " << FormatFixed(compl_b, 4) << " | " << FormatFixed(corr_b, 4) << " | "
     << (any_dsm3 ? FormatFixed(pooled_dsm3.iou[structure], 4) : std::string("-")) << " |\n\n";
  for (const auto& note : truth_notes) md << "Note: " << note << ".\n\n";
  md << "## Floorplan (all rooms)\n\n" << MarkdownFloorplanTable(plan) << "\n";
  if (any_dsm3) md << "## DSM3 (all rooms)\n\n" << MarkdownConfusionTable(pooled_dsm3) << "\n";
  if (floor) md << "## Floor model (floor/)\n\n" << MarkdownFloorTable(*floor) << "\n";
  if (pooled_components)
    md << "## SM5 service components (all rooms)\n\n"
       << MarkdownComponentsTable(*pooled_components) << "\n";
  for (const auto& r : results) {
    md << "## Room " << r.run.room << "\n\n";
    if (!r.joined.empty()) {
      md << "Scored against the truth rooms";
      for (std::size_t k = 0; k < r.joined.size(); ++k)
        md << (k == 0 ? " " : k + 1 == r.joined.size() ? " and " : ", ") << r.joined[k];
      md << " as one room: open passages without a wall join them.\n\n";
    }
    md << "### SM3 structural elements\n\n" << MarkdownPatchTable(r.patches) << "\n";
    if (r.columns.detection.n_truth + r.columns.detection.n_model > 0)
      md << "### Columns (objects)\n\n" << ColumnsMarkdown(r.columns) << "\n";
    md << "### ISPRS surfaces\n\n"
       << MarkdownIsprsTable(r.isprs, params.report_buffer) << "\n"
       << IsprsSvgPlot(r.isprs, "ISPRS surfaces, room " + r.run.room) << "\n\n";
    std::ofstream(dir / ("isprs_" + r.run.room + ".svg"))
        << IsprsSvgPlot(r.isprs, "ISPRS surfaces, room " + r.run.room) << "\n";
    if (r.has_dsm3)
      WriteTruthDsm3Ply((dir / ("dsm3_truth_" + r.run.room + ".ply")).string(), r.dsm3_voxels,
                        r.dsm3_truth);
    if (r.has_dsm3) md << "### DSM3 voxels\n\n" << MarkdownConfusionTable(r.dsm3) << "\n";
    if (r.openings) md << "### SM4 openings\n\n" << MarkdownOpeningsTable(*r.openings) << "\n";
    if (r.components)
      md << "### SM5 service components\n\n" << MarkdownComponentsTable(*r.components) << "\n";
    if (r.mission)
      md << "### Mission figures\n\ncoverage of observable "
         << FormatFixed(MissionNumber(r.mission, "coverage_of_observable"), 4)
         << ", registration error max "
         << FormatFixed(MissionNumber(r.mission, "registration_error_max", "translation_m") * 100,
                        2)
         << " cm, SM1 label accuracy "
         << FormatFixed(MissionNumber(r.mission, "sm1_labels", "accuracy"), 4) << "\n\n";
  }
  std::ofstream(dir / "evaluation.md") << md.str();

  // Summary on stdout.
  Append(report, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s %7s\n", "room", "walls",
         "floor", "ceiling", "columns", "d_v(cm)", "d_h(cm)", "phi(deg)", "compl", "corr", "dsm3",
         "cover");
  auto cell = [](const ClassDetection& d) {
    return std::to_string(d.tp) + "/" + std::to_string(d.n_truth) +
           (d.fp ? "+" + std::to_string(d.fp) + "FP" : "");
  };
  for (const auto& r : results) {
    const int b = r.isprs.BufferIndex(params.report_buffer);
    Append(report, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s %7s\n", r.run.room.c_str(),
           cell(r.patches.detection[0]).c_str(), cell(r.patches.detection[1]).c_str(),
           cell(r.patches.detection[2]).c_str(), cell(r.columns.detection).c_str(),
           FormatFixed(r.patches.d_v.mean * 100, 2).c_str(),
           FormatFixed(r.patches.d_h.mean * 100, 2).c_str(),
           FormatFixed(r.patches.phi_deg.mean, 4).c_str(),
           FormatFixed(r.isprs.all.completeness[b], 4).c_str(),
           FormatFixed(r.isprs.all.correctness[b], 4).c_str(),
           r.has_dsm3 ? FormatFixed(r.dsm3.iou[structure], 4).c_str() : "-",
           FormatFixed(MissionNumber(r.mission, "coverage_of_observable"), 3).c_str());
  }
  Append(report, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s\n", "all",
         cell(pooled.detection[0]).c_str(), cell(pooled.detection[1]).c_str(),
         cell(pooled.detection[2]).c_str(), cell(pooled.detection[3]).c_str(),
         FormatFixed(pooled.d_v.mean * 100, 2).c_str(),
         FormatFixed(pooled.d_h.mean * 100, 2).c_str(), FormatFixed(pooled.phi_deg.mean, 4).c_str(),
         FormatFixed(compl_b, 4).c_str(), FormatFixed(corr_b, 4).c_str(),
         any_dsm3 ? FormatFixed(pooled_dsm3.iou[structure], 4).c_str() : "-");
  if (pooled_columns.detection.n_truth + pooled_columns.detection.n_model > 0)
    Append(report,
           "columns (objects): %d/%d TP, %d FP; plan IoU mean %s, centre error mean %s cm, "
           "diameter error mean %s cm, height error mean %s cm; square-column faces d_h %s cm, "
           "Phi %s deg\n",
           pooled_columns.detection.tp, pooled_columns.detection.n_truth,
           pooled_columns.detection.fp, FormatFixed(pooled_columns.plan_iou.mean, 3).c_str(),
           FormatFixed(pooled_columns.centre_error.mean * 100, 2).c_str(),
           FormatFixed(pooled_columns.diameter_error.mean * 100, 2).c_str(),
           FormatFixed(pooled_columns.height_error.mean * 100, 2).c_str(),
           FormatFixed(pooled_columns.face_accuracy.d_h.mean * 100, 2).c_str(),
           FormatFixed(pooled_columns.face_accuracy.phi_deg.mean, 4).c_str());
  Append(report, "floorplan: mean room IoU %s, corner recall@10cm %s; ISPRS at %s cm buffer\n",
         FormatFixed(plan.mean_truth_iou, 4).c_str(),
         plan.corners.size() > 1 ? FormatFixed(plan.corners[1].score.recall, 3).c_str() : "-",
         FormatFixed(params.report_buffer * 100, 0).c_str());
  if (floor) {
    const ClassDetection& w = floor->faces.detection[static_cast<int>(SurfaceClass::kWall)];
    Append(report,
           "floor model: %d walls (%d two-sided); wall faces %d/%d (%d FP), d_v mean %s max %s cm, "
           "d_h mean %s max %s cm; face pairs %d/%d correct of %d truth; thickness error mean %s "
           "max %s cm; room-to-room alignment mean %s max %s cm; doors merged %d correct of %d (%d "
           "between rooms, %d one-sided); door side "
           "offset mean %s max %s cm\n",
           floor->walls, floor->two_sided_walls, w.tp, w.n_truth, w.fp,
           FormatFixed(floor->faces.d_v.mean * 100, 2).c_str(),
           FormatFixed(floor->faces.d_v.max * 100, 2).c_str(),
           FormatFixed(floor->faces.d_h.mean * 100, 2).c_str(),
           FormatFixed(floor->faces.d_h.max * 100, 2).c_str(), floor->correct_pairs,
           floor->model_pairs, floor->truth_pairs,
           FormatFixed(floor->thickness_error.mean * 100, 2).c_str(),
           FormatFixed(floor->thickness_error.max * 100, 2).c_str(),
           FormatFixed(floor->room_alignment.mean * 100, 2).c_str(),
           FormatFixed(floor->room_alignment.max * 100, 2).c_str(), floor->merged_correct,
           floor->merged_doors, floor->truth_doors, floor->one_sided_doors,
           FormatFixed(floor->door_side_offset.mean * 100, 2).c_str(),
           FormatFixed(floor->door_side_offset.max * 100, 2).c_str());
  }
  Append(report, "wrote %s/{evaluation.json,evaluation.md,isprs_*.svg,dsm3_truth_*.ply}\n",
         dir.string().c_str());
  return {report, summary, pooled_components};
}

}  // namespace mopad::evaluation
