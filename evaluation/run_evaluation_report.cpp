// EvaluateRun's outputs (evaluation/run_evaluation_report.h): evaluation.json, evaluation.md, the
// rooms' ISPRS plots and truth DSM3 files, and the tables `mopad eval` prints. Numbers are
// formatted with fixed digits (common/format.h), so the bytes are deterministic.
#include "evaluation/run_evaluation_report.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "evaluation/json_number.h"
#include "evaluation/report_tables.h"

namespace mopad::evaluation {
namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

constexpr int kStructure = static_cast<int>(VoxelLabel::kStructure);

// printf into a growing string: the tables `mopad eval` prints.
template <class... A>
void Append(std::string& out, const char* format, A... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  out += buf;
}

ojson Ord(const nlohmann::json& j) { return ojson::parse(j.dump()); }

ojson CountsJson(const std::vector<std::uint8_t>& labels) {
  const auto c = CountVoxelLabels(labels);
  ojson j;
  for (std::size_t i = 0; i < c.size(); ++i) j[Dsm3LabelNames()[i]] = c[i];
  return j;
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
                       {"plan_iou", Num<ojson>(p.plan_iou)},
                       {"centre_error_m", Num<ojson>(p.centre_error)},
                       {"area_error_m2", Num<ojson>(p.area_error)},
                       {"diameter_error_m", Num<ojson>(p.diameter_error)},
                       {"height_error_m", Num<ojson>(p.height_error)},
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
  WriteWholeFile(path, data);
}

ojson MissionSummaryJson(const MissionFigures& m) {
  return {{"coverage_of_observable_min", Num<ojson>(m.coverage_min)},
          {"registration_translation_max_m", Num<ojson>(m.translation_max_m)},
          {"registration_rotation_max_deg", Num<ojson>(m.rotation_max_deg)},
          {"sm1_label_accuracy",
           m.sm1_points > 0 ? Num<ojson>(m.sm1_correct / m.sm1_points) : ojson(nullptr)}};
}

ojson FloorSummaryJson(const FloorEvaluation& floor) {
  const ClassDetection& w = floor.faces.detection[static_cast<int>(SurfaceClass::kWall)];
  return {{"wall_faces", {{"n_truth", w.n_truth}, {"tp", w.tp}, {"fp", w.fp}}},
          {"d_v", Ord(ToJson(floor.faces.d_v))},
          {"d_h", Ord(ToJson(floor.faces.d_h))},
          {"thickness_error_m", Ord(ToJson(floor.thickness_error))},
          {"room_alignment_m", Ord(ToJson(floor.room_alignment))},
          {"face_pairs_correct", floor.correct_pairs},
          {"face_pairs_truth", floor.truth_pairs},
          {"doors_merged_correct", floor.merged_correct},
          {"doors_between_rooms", floor.truth_doors},
          {"door_side_offset_m", Ord(ToJson(floor.door_side_offset))}};
}

// The as-built block: the same SM3 figures against the as-built surfaces, and the truth's own
// departure from its design per class.
ojson AsBuiltJson(const AsBuiltFigures& a) {
  ojson j;
  j["d_v"] = Ord(ToJson(a.patches.d_v));
  j["d_h"] = Ord(ToJson(a.patches.d_h));
  j["phi_deg"] = Ord(ToJson(a.patches.phi_deg));
  ojson dev;
  for (const auto& [name, d] :
       {std::pair<const char*, const AsBuiltFigures::Deviation&>{"wall", a.wall},
        {"floor", a.floor},
        {"ceiling", a.ceiling}})
    dev[name] = {{"elements", d.elements},
                 {"rms_mm", Num<ojson>(d.rms_mm)},
                 {"max_mm", Num<ojson>(d.max_mm)},
                 {"tilt_mean_deg", Num<ojson>(d.tilt_mean_deg)},
                 {"tilt_max_deg", Num<ojson>(d.tilt_max_deg)}};
  j["truth_deviation"] = dev;
  return j;
}

// evaluation.json's "summary": the pooled figures (the pairs of SM5 stay per room).
ojson SummaryJson(const EvalParams& params, const std::vector<RoomResult>& rooms,
                  const PooledFigures& p, const std::vector<std::string>& truth_notes) {
  ojson summary;
  summary["rooms"] = rooms.size();
  ojson det;
  for (auto c : AllSurfaceClasses()) {
    const auto& d = p.patches.detection[static_cast<int>(c)];
    det[SurfaceClassName(c)] = {{"n_truth", d.n_truth}, {"tp", d.tp}, {"fp", d.fp}, {"fn", d.fn}};
  }
  summary["detection"] = det;
  summary["d_v"] = Ord(ToJson(p.patches.d_v));
  summary["d_h"] = Ord(ToJson(p.patches.d_h));
  summary["phi_deg"] = Ord(ToJson(p.patches.phi_deg));
  summary["columns"] = ColumnsJson(p.columns, /*with_pairs=*/false);
  summary["isprs_buffer"] = params.report_buffer;
  summary["isprs_completeness"] = Num<ojson>(p.isprs_completeness);
  summary["isprs_correctness"] = Num<ojson>(p.isprs_correctness);
  summary["dsm3_structure_iou"] = p.any_dsm3 ? Num<ojson>(p.dsm3.iou[kStructure]) : ojson(nullptr);
  summary["floorplan_mean_iou"] = Num<ojson>(p.floorplan.mean_truth_iou);
  summary["mission"] = MissionSummaryJson(p.mission);
  summary["openings"] = p.openings ? Ord(ToJson(*p.openings)) : ojson(nullptr);
  if (p.components) {
    ojson c = Ord(ToJson(*p.components));
    c.erase("pairs");
    summary["components"] = c;
  } else {
    summary["components"] = nullptr;
  }
  summary["floor"] = p.floor ? FloorSummaryJson(*p.floor) : ojson(nullptr);
  if (p.as_built) summary["as_built"] = AsBuiltJson(*p.as_built);
  if (!truth_notes.empty()) summary["truth_notes"] = truth_notes;
  return summary;
}

ojson RoomJson(const RoomResult& r) {
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
  return x;
}

std::string DetectionCell(const ClassDetection& d) {
  return std::to_string(d.tp) + "/" + std::to_string(d.n_truth) + " (" + std::to_string(d.fp) + ")";
}

// evaluation.md's first table: one row per room and "all".
std::string RoomsMarkdownTable(const EvalParams& params, const std::vector<RoomResult>& rooms,
                               const PooledFigures& p) {
  std::ostringstream md;
  md << "| room | walls TP/N (FP) | floors | ceilings | columns | d_v mean (cm) | d_h mean (cm) "
        "| "
        "Phi mean (deg) | compl@"
     << FormatFixed(params.report_buffer * 100, 0) << "cm | corr@"
     << FormatFixed(params.report_buffer * 100, 0) << "cm | DSM3 structure IoU |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rooms) {
    const int b = r.isprs.BufferIndex(params.report_buffer);
    md << "| " << r.run.room;
    for (int c = 0; c < kNumSurfaceClasses; ++c)
      md << " | " << DetectionCell(r.patches.detection[c]);
    md << " | " << FormatFixed(r.patches.d_v.mean * 100, 2) << " | "
       << FormatFixed(r.patches.d_h.mean * 100, 2) << " | "
       << FormatFixed(r.patches.phi_deg.mean, 4) << " | "
       << FormatFixed(r.isprs.all.completeness[b], 4) << " | "
       << FormatFixed(r.isprs.all.correctness[b], 4) << " | "
       << (r.has_dsm3 ? FormatFixed(r.dsm3.iou[kStructure], 4) : std::string("-")) << " |\n";
  }
  md << "| **all**";
  for (int c = 0; c < kNumSurfaceClasses; ++c) md << " | " << DetectionCell(p.patches.detection[c]);
  md << " | " << FormatFixed(p.patches.d_v.mean * 100, 2) << " | "
     << FormatFixed(p.patches.d_h.mean * 100, 2) << " | " << FormatFixed(p.patches.phi_deg.mean, 4)
     << " | " << FormatFixed(p.isprs_completeness, 4) << " | "
     << FormatFixed(p.isprs_correctness, 4) << " | "
     << (p.any_dsm3 ? FormatFixed(p.dsm3.iou[kStructure], 4) : std::string("-")) << " |\n\n";
  if (p.as_built) {
    const AsBuiltFigures& a = *p.as_built;
    md << "The building stands off its design (as-built geometry, docs/realism.md): the figures "
          "above are against the design; against the as-built surfaces d_v "
       << FormatFixed(a.patches.d_v.mean * 100, 2) << " cm, d_h "
       << FormatFixed(a.patches.d_h.mean * 100, 2) << " cm, Phi "
       << FormatFixed(a.patches.phi_deg.mean, 4) << " deg. The truth's walls depart from their "
       << "design planes by " << FormatFixed(a.wall.rms_mm, 1) << " mm rms (max "
       << FormatFixed(a.wall.max_mm, 1) << " mm) and tilt " << FormatFixed(a.wall.tilt_mean_deg, 3)
       << " deg (max " << FormatFixed(a.wall.tilt_max_deg, 3) << "); floors "
       << FormatFixed(a.floor.rms_mm, 1) << " mm rms, ceilings " << FormatFixed(a.ceiling.rms_mm, 1)
       << " mm rms.\n\n";
  }
  return md.str();
}

// evaluation.md's section of one room.
std::string RoomMarkdown(const RoomResult& r, const EvalParams& params) {
  std::ostringstream md;
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
  if (r.has_dsm3) md << "### DSM3 voxels\n\n" << MarkdownConfusionTable(r.dsm3) << "\n";
  if (r.openings) md << "### SM4 openings\n\n" << MarkdownOpeningsTable(*r.openings) << "\n";
  if (r.components)
    md << "### SM5 service components\n\n" << MarkdownComponentsTable(*r.components) << "\n";
  if (r.mission)
    md << "### Mission figures\n\ncoverage of observable "
       << FormatFixed(MissionNumber(r.mission, "coverage_of_observable"), 4)
       << ", registration error max "
       << FormatFixed(MissionNumber(r.mission, "registration_error_max", "translation_m") * 100, 2)
       << " cm, SM1 label accuracy "
       << FormatFixed(MissionNumber(r.mission, "sm1_labels", "accuracy"), 4) << "\n\n";
  return md.str();
}

// A detection as the printed tables show it: "TP/N", with "+FP" when there are false positives.
std::string PrintedCell(const ClassDetection& d) {
  std::string cell = std::to_string(d.tp) + "/" + std::to_string(d.n_truth);
  if (d.fp) {
    cell += '+';
    cell += std::to_string(d.fp);
    cell += "FP";
  }
  return cell;
}

std::string ColumnsLine(const ColumnEvaluation& c) {
  std::string out;
  Append(out,
         "columns (objects): %d/%d TP, %d FP; plan IoU mean %s, centre error mean %s cm, "
         "diameter error mean %s cm, height error mean %s cm; square-column faces d_h %s cm, "
         "Phi %s deg\n",
         c.detection.tp, c.detection.n_truth, c.detection.fp,
         FormatFixed(c.plan_iou.mean, 3).c_str(), FormatFixed(c.centre_error.mean * 100, 2).c_str(),
         FormatFixed(c.diameter_error.mean * 100, 2).c_str(),
         FormatFixed(c.height_error.mean * 100, 2).c_str(),
         FormatFixed(c.face_accuracy.d_h.mean * 100, 2).c_str(),
         FormatFixed(c.face_accuracy.phi_deg.mean, 4).c_str());
  return out;
}

std::string FloorLine(const FloorEvaluation& f) {
  const ClassDetection& w = f.faces.detection[static_cast<int>(SurfaceClass::kWall)];
  std::string out;
  Append(out,
         "floor model: %d walls (%d two-sided); wall faces %d/%d (%d FP), d_v mean %s max %s cm, "
         "d_h mean %s max %s cm; face pairs %d/%d correct of %d truth; thickness error mean %s "
         "max %s cm; room-to-room alignment mean %s max %s cm; doors merged %d correct of %d (%d "
         "between rooms, %d one-sided); door side "
         "offset mean %s max %s cm\n",
         f.walls, f.two_sided_walls, w.tp, w.n_truth, w.fp,
         FormatFixed(f.faces.d_v.mean * 100, 2).c_str(),
         FormatFixed(f.faces.d_v.max * 100, 2).c_str(),
         FormatFixed(f.faces.d_h.mean * 100, 2).c_str(),
         FormatFixed(f.faces.d_h.max * 100, 2).c_str(), f.correct_pairs, f.model_pairs,
         f.truth_pairs, FormatFixed(f.thickness_error.mean * 100, 2).c_str(),
         FormatFixed(f.thickness_error.max * 100, 2).c_str(),
         FormatFixed(f.room_alignment.mean * 100, 2).c_str(),
         FormatFixed(f.room_alignment.max * 100, 2).c_str(), f.merged_correct, f.merged_doors,
         f.truth_doors, f.one_sided_doors, FormatFixed(f.door_side_offset.mean * 100, 2).c_str(),
         FormatFixed(f.door_side_offset.max * 100, 2).c_str());
  return out;
}

}  // namespace

nlohmann::ordered_json EvaluationJson(const std::string& run_dir, const std::string& truth_file,
                                      const EvalParams& params,
                                      const std::vector<RoomResult>& rooms,
                                      const PooledFigures& pooled,
                                      const std::vector<std::string>& truth_notes) {
  ojson j;
  j["format"] = "mopad-evaluation";
  j["version"] = 1;
  j["run_dir"] = run_dir;
  j["truth"] = truth_file.empty() ? "scene" : truth_file;
  j["summary"] = SummaryJson(params, rooms, pooled, truth_notes);
  ojson per_room = ojson::array();
  for (const auto& r : rooms) per_room.push_back(RoomJson(r));
  j["rooms"] = per_room;
  j["floorplan"] = Ord(ToJson(pooled.floorplan));
  j["dsm3_all_rooms"] = pooled.any_dsm3 ? Ord(ToJson(pooled.dsm3)) : ojson(nullptr);
  j["floor"] = pooled.floor ? ToJson(*pooled.floor) : ojson(nullptr);
  return j;
}

std::string EvaluationMarkdown(const std::string& run_dir, const EvalParams& params,
                               const std::vector<RoomResult>& rooms, const PooledFigures& pooled,
                               const std::vector<std::string>& truth_notes) {
  std::ostringstream md;
  md << "# Evaluation of `" << run_dir << "`\n\n";
  md << RoomsMarkdownTable(params, rooms, pooled);
  for (const auto& note : truth_notes) md << "Note: " << note << ".\n\n";
  md << "## Floorplan (all rooms)\n\n" << MarkdownFloorplanTable(pooled.floorplan) << "\n";
  if (pooled.any_dsm3)
    md << "## DSM3 (all rooms)\n\n" << MarkdownConfusionTable(pooled.dsm3) << "\n";
  if (pooled.floor)
    md << "## Floor model (floor/)\n\n" << MarkdownFloorTable(*pooled.floor) << "\n";
  if (pooled.components)
    md << "## SM5 service components (all rooms)\n\n"
       << MarkdownComponentsTable(*pooled.components) << "\n";
  for (const auto& r : rooms) md << RoomMarkdown(r, params);
  return md.str();
}

void WriteRoomFiles(const std::string& dir, const std::vector<RoomResult>& rooms) {
  for (const auto& r : rooms) {
    WriteWholeFile((fs::path(dir) / ("isprs_" + r.run.room + ".svg")).string(),
                   IsprsSvgPlot(r.isprs, "ISPRS surfaces, room " + r.run.room) + "\n");
    if (r.has_dsm3)
      WriteTruthDsm3Ply((fs::path(dir) / ("dsm3_truth_" + r.run.room + ".ply")).string(),
                        r.dsm3_voxels, r.dsm3_truth);
  }
}

std::string PrintedTables(const EvalParams& params, const std::vector<RoomResult>& rooms,
                          const PooledFigures& p, const std::string& dir) {
  std::string out;
  Append(out, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s %7s\n", "room", "walls", "floor",
         "ceiling", "columns", "d_v(cm)", "d_h(cm)", "phi(deg)", "compl", "corr", "dsm3", "cover");
  for (const auto& r : rooms) {
    const int b = r.isprs.BufferIndex(params.report_buffer);
    Append(out, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s %7s\n", r.run.room.c_str(),
           PrintedCell(r.patches.detection[0]).c_str(), PrintedCell(r.patches.detection[1]).c_str(),
           PrintedCell(r.patches.detection[2]).c_str(), PrintedCell(r.columns.detection).c_str(),
           FormatFixed(r.patches.d_v.mean * 100, 2).c_str(),
           FormatFixed(r.patches.d_h.mean * 100, 2).c_str(),
           FormatFixed(r.patches.phi_deg.mean, 4).c_str(),
           FormatFixed(r.isprs.all.completeness[b], 4).c_str(),
           FormatFixed(r.isprs.all.correctness[b], 4).c_str(),
           r.has_dsm3 ? FormatFixed(r.dsm3.iou[kStructure], 4).c_str() : "-",
           FormatFixed(MissionNumber(r.mission, "coverage_of_observable"), 3).c_str());
  }
  Append(out, "%-6s %-12s %-8s %-8s %-8s %8s %8s %9s %7s %7s %7s\n", "all",
         PrintedCell(p.patches.detection[0]).c_str(), PrintedCell(p.patches.detection[1]).c_str(),
         PrintedCell(p.patches.detection[2]).c_str(), PrintedCell(p.patches.detection[3]).c_str(),
         FormatFixed(p.patches.d_v.mean * 100, 2).c_str(),
         FormatFixed(p.patches.d_h.mean * 100, 2).c_str(),
         FormatFixed(p.patches.phi_deg.mean, 4).c_str(),
         FormatFixed(p.isprs_completeness, 4).c_str(), FormatFixed(p.isprs_correctness, 4).c_str(),
         p.any_dsm3 ? FormatFixed(p.dsm3.iou[kStructure], 4).c_str() : "-");
  if (p.columns.detection.n_truth + p.columns.detection.n_model > 0) out += ColumnsLine(p.columns);
  Append(out, "floorplan: mean room IoU %s, corner recall@10cm %s; ISPRS at %s cm buffer\n",
         FormatFixed(p.floorplan.mean_truth_iou, 4).c_str(),
         p.floorplan.corners.size() > 1
             ? FormatFixed(p.floorplan.corners[1].score.recall, 3).c_str()
             : "-",
         FormatFixed(params.report_buffer * 100, 0).c_str());
  if (p.floor) out += FloorLine(*p.floor);
  Append(out, "wrote %s/{evaluation.json,evaluation.md,isprs_*.svg,dsm3_truth_*.ply}\n",
         dir.c_str());
  return out;
}

}  // namespace mopad::evaluation
