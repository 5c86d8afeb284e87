// `mopad eval --model`: the steps, one function each — read the model into the evaluator's
// records in its own frame (ReadIfcModel, ReadJsonModel), place it in the world (Place, FitPose),
// gather the truth of every room (LoadTruth), score (Score), write (WriteOutputs). The header
// says what is read and scored; docs/evaluation.md describes each figure.
#include "evaluation/model_evaluation.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "common/polygon.h"
#include "evaluation/json_number.h"
#include "evaluation/metrics_components.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_openings.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_wall_endpoints.h"
#include "evaluation/model_files.h"
#include "evaluation/report_tables.h"
#include "evaluation/run_evaluation_report.h"
#include "evaluation/truth_models.h"
#include "modelling/model_io.h"
#include "modelling/sm5_io.h"
#include "scenes/bim_import.h"
#include "scenes/door_angles.h"
#include "scenes/scene_paths.h"

namespace mopad::evaluation {

namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

/// `mopad eval --model --config`: the run evaluation's parameters plus the wall endpoints and
/// the pose fit.
struct ModelEvalParams {
  EvalParams eval;
  WallEndpointParams wall_endpoints;
  double fit_max_distance = 0.30;  ///< m, a sample farther from a truth surface is ignored, (0, 2]
  double fit_spacing = 0.10;       ///< m, sample spacing on the model's surfaces, [0.01, 1]
  int fit_iterations = 30;         ///< Gauss-Newton steps, [1, 1000]
  template <class V>
  void Visit(V& v) {
    eval.Visit(v);
    v("wall_endpoints", wall_endpoints);
    v("fit_max_distance", fit_max_distance, Bounds{1e-6, 2.0});
    v("fit_spacing", fit_spacing, Bounds{0.01, 1.0});
    v("fit_iterations", fit_iterations, Bounds{1, 1000});
  }
};

// The model as the evaluator's records.
struct ModelRecords {
  std::string format;          // "ifc" | "mopad-sm3"
  std::vector<Patch> patches;  // walls, floors, ceilings
  std::vector<ColumnObject> columns;
  std::vector<Room> rooms;
  std::vector<OpeningRecord> openings;
  std::vector<ComponentRecord> components;
  bool has_openings = false, has_components = false;
  int doors_with_state = 0;
  std::vector<std::string> notes;  // what the reading reported
};

double Number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end != text.c_str() && std::isfinite(v) ? v : NAN;
}

ModelRecords ReadIfcModel(const ModelEvalOptions& o) {
  scenes::BimImportParams params;
  params.storey = o.storey;
  params.as_is = true;
  // A wall 30 cm off its space's outline is still that room's wall (patch matching accepts 20 cm
  // plane errors, the wall endpoints 30 cm).
  params.wall_search = 0.30;
  const scenes::BimImport model = scenes::ImportBim(o.model, params);
  const scenes::IfcProperties props = scenes::ReadIfcProperties(o.model);
  // The model's spaces joined by open passages are one room, as the truth's are.
  const OpenPlanTruth merged = MergeOpenPlanRooms(model.truth);
  const scenes::GroundTruth& g = merged.truth;
  ModelRecords m;
  m.format = "ifc";
  m.notes = model.report;
  for (const auto& [room, members] : merged.members) {
    std::string list;
    for (const auto& r : members) list += (list.empty() ? "" : ", ") + r;
    m.notes.push_back("spaces " + list + " joined by open passages: one room " + room);
  }
  m.notes.insert(m.notes.end(), merged.notes.begin(), merged.notes.end());
  if (g.rooms.empty())
    throw InputError(o.model, "no IfcSpace on the storey", "",
                     "spaces: they tell a wall's room face from its back");
  std::set<std::string> seen_columns, seen_openings;
  for (const scenes::Room& room : g.rooms) {
    std::vector<Patch> patches;
    try {
      patches = TruthPatches(g, room.id);
    } catch (const InputError& e) {
      m.notes.push_back(std::string("space ") + room.id + ": no surfaces (" + e.what() + ")");
    }
    for (Patch& p : patches)
      if (p.cls != SurfaceClass::kColumn) m.patches.push_back(std::move(p));
    for (ColumnObject& c : TruthColumns(g, room.id))
      if (seen_columns.insert(c.id).second) m.columns.push_back(std::move(c));
    for (OpeningRecord& r : TruthOpenings(g, room.id)) {
      r.state.clear();
      r.angle_deg = NAN;
      const auto guid = model.opening_guids.find(r.id);
      const auto p = guid == model.opening_guids.end() ? props.end() : props.find(guid->second);
      if (r.type == "door" && p != props.end()) {
        const auto state = p->second.find("MoPAD_Opening.State");
        const auto angle = p->second.find("MoPAD_Opening.OpeningAngle");
        if (state != p->second.end()) r.state = state->second;
        if (angle != p->second.end()) r.angle_deg = Number(angle->second) * 180.0 / kPi;
      }
      if (!r.state.empty() && seen_openings.insert(r.id).second) ++m.doors_with_state;
      m.openings.push_back(std::move(r));
    }
    for (ComponentRecord& c : TruthComponents(g, room.id)) {
      const auto guid = model.component_guids.find(c.id);
      const auto p = guid == model.component_guids.end() ? props.end() : props.find(guid->second);
      if (p != props.end()) {
        const auto cls = p->second.find("MoPAD_Component.Class");
        if (cls != p->second.end() && !cls->second.empty()) c.class_name = cls->second;
        const auto alpha = p->second.find("MoPAD_Component.Alpha");
        if (alpha != p->second.end() && std::isfinite(Number(alpha->second)))
          c.alpha = Number(alpha->second);
        const auto found_by = p->second.find("MoPAD_Component.FoundBy");
        if (found_by != p->second.end()) c.found_by = found_by->second;
      }
      m.components.push_back(std::move(c));
    }
  }
  m.rooms = TruthFloorplan(g);
  m.has_openings = true;
  m.has_components = true;
  return m;
}

ModelRecords ReadJsonModel(const ModelEvalOptions& o) {
  ModelRecords m;
  m.format = "mopad-sm3";
  {
    std::ifstream f(o.model);
    const ojson j = ojson::parse(f, nullptr, /*allow_exceptions=*/false);
    if (j.is_object() && j.contains("rooms"))  // the floor model: walls on their axes
      throw InputError(o.model, "a floor model (floor/sm3.json) is not scored as JSON", "",
                       "its export (export/model.ifc) or a room's sm3.json");
  }
  const Sm3Model sm3 = ReadSm3(o.model);
  std::vector<Patch> all;
  for (const Sm3Patch& p : sm3.patches) all.push_back(p.patch);
  for (const Patch& p : all)
    if (p.cls != SurfaceClass::kColumn) m.patches.push_back(p);
  m.columns = GroupModelColumns(all);
  int n = 0;
  for (const Patch& p : all) {
    if (p.cls != SurfaceClass::kFloor) continue;
    Room r{sm3.room + (n++ ? "_" + std::to_string(n) : std::string()), {}};
    for (const Vec3& v : p.polygon) r.polygon.emplace_back(v.x(), v.y());
    m.rooms.push_back(r);
  }
  const fs::path dir = fs::path(o.model).parent_path();
  if (fs::exists(dir / "sm4.json")) {
    m.openings = ModelOpenings(modelling::ReadSm4((dir / "sm4.json").string()), Pose3::Identity());
    m.has_openings = true;
    for (const auto& r : m.openings) m.doors_with_state += r.type == "door" && !r.state.empty();
  }
  if (fs::exists(dir / "sm5.json")) {
    m.components =
        ModelComponents(modelling::ReadSm5((dir / "sm5.json").string()), Pose3::Identity());
    m.has_components = true;
  }
  return m;
}

// Every record of `m` moved by `X` (a pose of the model frame in the world).
void Place(ModelRecords& m, const Pose3& X) {
  for (Patch& p : m.patches) p = Transformed(p, X);
  for (ColumnObject& c : m.columns) {
    for (Patch& f : c.faces) f = Transformed(f, X);
    c = MakeColumnObject(c.id, c.faces);
  }
  for (Room& r : m.rooms)
    for (Vec2& v : r.polygon) v = (X * Vec3(v.x(), v.y(), 0.0)).head<2>();
  for (OpeningRecord& r : m.openings) {
    for (Vec3& v : r.corners) v = X * v;
    r.normal = X.linear() * r.normal;
  }
  for (ComponentRecord& c : m.components) {
    c.centre = X * c.centre;
    c.normal = X.linear() * c.normal;
  }
}

// The height of the floor patches carrying the most area, heights within 5 cm one level; NaN
// without floors.
double MainFloorZ(const std::vector<Patch>& patches) {
  std::vector<std::pair<double, double>> levels;  // (z, area)
  for (const Patch& p : patches) {
    if (p.cls != SurfaceClass::kFloor || p.polygon.empty()) continue;
    double z = 0.0;
    for (const Vec3& v : p.polygon) z += v.z();
    levels.emplace_back(z / static_cast<double>(p.polygon.size()), PolygonArea3d(p.polygon));
  }
  double best_z = NAN, best_area = 0.0;
  for (const auto& [z, area] : levels) {
    double sum = 0.0;
    for (const auto& [z2, a2] : levels)
      if (std::abs(z2 - z) <= 0.05) sum += a2;
    if (sum > best_area) best_area = sum, best_z = z;
  }
  return best_z;
}

struct FitResult {
  Pose3 delta = Pose3::Identity();  // applied after the given pose
  double rms = NAN;                 // m, point-to-plane residual of the used samples
  long samples = 0, used = 0;
};

// 4-DoF point-to-plane alignment of the model's surfaces to the truth's (see the header):
// samples of every model patch, each against the nearest truth patch of its class whose
// polygon it falls in and whose normal agrees within 30 deg, within `max_distance`.
FitResult FitPose(const std::vector<Patch>& model, const std::vector<Patch>& truth,
                  const ModelEvalParams& params) {
  struct Sample {
    Vec3 p, n;
    SurfaceClass cls;
  };
  std::vector<Sample> samples;
  for (const Patch& p : model) {
    double area = 0.0;
    for (const Vec3& s : SamplePatch(p, params.fit_spacing, &area))
      samples.push_back({s, p.normal.normalized(), p.cls});
  }
  struct TruthPlane {
    PlaneFrame frame;
    std::vector<Vec2> polygon;
    SurfaceClass cls;
  };
  std::vector<TruthPlane> planes;
  for (const Patch& t : truth) {
    TruthPlane tp{PlaneFrame::Of(t), {}, t.cls};
    for (const Vec3& v : t.polygon) tp.polygon.push_back(tp.frame.To2d(v));
    planes.push_back(std::move(tp));
  }
  Vec3 centre = Vec3::Zero();
  for (const auto& s : samples) centre += s.p;
  if (!samples.empty()) centre /= static_cast<double>(samples.size());
  FitResult fit;
  fit.samples = static_cast<long>(samples.size());
  double yaw = 0.0;
  Vec3 t = Vec3::Zero();
  const double cos_normal = std::cos(DegToRad(30.0));
  for (int it = 0; it < params.fit_iterations; ++it) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    double sq = 0.0;
    long used = 0;
    for (const Sample& sample : samples) {
      const Vec3 p = R * (sample.p - centre) + centre + t;
      const Vec3 n_model = R * sample.n;
      double best = params.fit_max_distance;
      const TruthPlane* hit = nullptr;
      for (const TruthPlane& tp : planes) {
        if (tp.cls != sample.cls || tp.frame.n.dot(n_model) < cos_normal) continue;
        const double d = tp.frame.SignedDistance(p);
        if (std::abs(d) >= std::abs(best) || !PointInPolygon(tp.frame.To2d(p), tp.polygon))
          continue;
        best = d;
        hit = &tp;
      }
      if (!hit) continue;
      const Vec3& n = hit->frame.n;
      Eigen::Vector4d J;
      J << n.x(), n.y(), n.z(), n.dot(Vec3::UnitZ().cross(p - centre - t));
      H += J * J.transpose();
      b -= J * best;
      sq += best * best;
      ++used;
    }
    fit.used = used;
    fit.rms = used ? std::sqrt(sq / static_cast<double>(used)) : NAN;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(H);
    if (used < 10 || eig.eigenvalues().minCoeff() < 1e-6 * std::max(1.0, eig.eigenvalues().maxCoeff()))
      throw InputError("--align fit", "the model's surfaces do not fix the pose",
                       std::to_string(used) + " samples on truth surfaces",
                       "walls in two directions and a floor or ceiling within " +
                           FormatFixed(params.fit_max_distance, 2) + " m of the truth's");
    const Eigen::Vector4d step = H.ldlt().solve(b);
    t += step.head<3>();
    yaw += step[3];
    if (step.head<3>().norm() < 1e-7 && std::abs(step[3]) < 1e-9) break;
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  fit.delta = Pose3::Identity();
  fit.delta.linear() = R;
  fit.delta.translation() = centre + t - R * centre;
  return fit;
}

// The truth of every room of the scene, open-plan rooms merged.
struct TruthRecords {
  std::vector<Patch> patches;  // walls, floors, ceilings
  std::vector<Patch> structure;  // the same with column faces (ISPRS)
  std::vector<ColumnObject> columns;
  std::vector<Room> rooms;
  std::vector<OpeningRecord> openings;
  std::vector<ComponentRecord> components;
  std::vector<std::string> notes;
};

TruthRecords LoadTruth(const ModelEvalOptions& o) {
  std::optional<scenes::GroundTruth> sidecar;
  if (!o.truth_file.empty()) {
    sidecar = scenes::ReadGroundTruth(o.truth_file);
  } else {
    // The truth only (no ray-casting world): a spec is generated with the door angles.
    scenes::LoadedScene loaded =
        scenes::LoadSceneArg(o.scene, scenes::ParseDoorAngles(o.doors, "--doors"), "--doors");
    if (!loaded.truth)
      throw InputError(o.scene, "scene has no truth sidecar", "", "--truth FILE");
    sidecar = std::move(loaded.truth);
  }
  const OpenPlanTruth op = MergeOpenPlanRooms(*sidecar);
  TruthRecords t;
  t.notes = op.notes;
  std::set<std::string> seen_columns;
  for (const scenes::Room& room : op.truth.rooms) {
    for (const Patch& p : TruthPatches(op.truth, room.id)) {
      t.structure.push_back(p);
      if (p.cls != SurfaceClass::kColumn) t.patches.push_back(p);
    }
    for (ColumnObject& c : TruthColumns(op.truth, room.id))
      if (seen_columns.insert(c.id).second) t.columns.push_back(std::move(c));
    for (OpeningRecord& r : TruthOpenings(op.truth, room.id)) t.openings.push_back(std::move(r));
    for (ComponentRecord& c : TruthComponents(op.truth, room.id))
      t.components.push_back(std::move(c));
  }
  t.rooms = TruthFloorplan(op.truth);
  return t;
}

struct Scores {
  PatchEvaluation patches;
  ColumnEvaluation columns;
  IsprsResult isprs;
  FloorplanResult floorplan;
  WallEndpointEvaluation walls;
  std::optional<OpeningEvaluation> openings;
  std::optional<ComponentEvaluation> components;
};

Scores Score(const ModelRecords& m, const TruthRecords& t, const ModelEvalParams& params) {
  Scores s;
  s.patches = EvaluatePatches(m.patches, t.patches, params.eval.patches);
  s.columns = EvaluateColumns(m.columns, t.columns, params.eval.columns, params.eval.patches);
  s.patches.detection[static_cast<int>(SurfaceClass::kColumn)] = s.columns.detection;
  std::vector<Patch> structure = m.patches;
  for (const ColumnObject& c : m.columns)
    structure.insert(structure.end(), c.faces.begin(), c.faces.end());
  s.isprs = EvaluateIsprs(structure, t.structure, params.eval.isprs);
  s.floorplan = EvaluateFloorplan(m.rooms, t.rooms, params.eval.floorplan);
  s.walls = EvaluateWallEndpoints(m.patches, t.patches, params.wall_endpoints);
  if (m.has_openings) s.openings = EvaluateOpenings(m.openings, t.openings, params.eval.openings);
  if (m.has_components)
    s.components = EvaluateComponents(m.components, t.components, params.eval.components);
  return s;
}

ojson PoseJson(const Pose3& X) {
  const double yaw = std::atan2(X.linear()(1, 0), X.linear()(0, 0));
  return {{"x", X.translation().x()},
          {"y", X.translation().y()},
          {"z", X.translation().z()},
          {"yaw_deg", RadToDeg(yaw)}};
}

ojson DetectionJson(const ClassDetection& d) {
  return {{"n_truth", d.n_truth}, {"n_model", d.n_model}, {"tp", d.tp}, {"fp", d.fp},
          {"fn", d.fn}, {"precision", Num<ojson>(d.Precision())},
          {"recall", Num<ojson>(d.Recall())}};
}

ojson SummaryJson(const Scores& s, const ModelRecords& m, const ModelEvalParams& params) {
  ojson summary;
  ojson det;
  for (auto c : AllSurfaceClasses())
    det[SurfaceClassName(c)] = DetectionJson(s.patches.detection[static_cast<int>(c)]);
  summary["detection"] = det;
  summary["d_v"] = ojson::parse(ToJson(s.patches.d_v).dump());
  summary["d_h"] = ojson::parse(ToJson(s.patches.d_h).dump());
  summary["phi_deg"] = ojson::parse(ToJson(s.patches.phi_deg).dump());
  const int b = s.isprs.BufferIndex(params.eval.report_buffer);
  summary["isprs_buffer"] = params.eval.report_buffer;
  summary["isprs_completeness"] = Num<ojson>(s.isprs.all.completeness[b]);
  summary["isprs_correctness"] = Num<ojson>(s.isprs.all.correctness[b]);
  summary["room_iou_mean"] = Num<ojson>(s.floorplan.mean_truth_iou);
  summary["rooms"] = {{"n_truth", s.floorplan.rooms.n_truth},
                      {"n_model", s.floorplan.rooms.n_predicted},
                      {"tp", s.floorplan.rooms.tp}};
  summary["wall_endpoints"] = ToJson(s.walls);
  summary["wall_endpoints"].erase("walls");
  if (s.openings) {
    ojson o = ojson::parse(ToJson(*s.openings).dump());
    o["doors_with_state_in_model"] = m.doors_with_state;
    summary["openings"] = o;
  } else {
    summary["openings"] = nullptr;
  }
  if (s.components) {
    ojson c = ojson::parse(ToJson(*s.components).dump());
    c.erase("pairs");
    summary["components"] = c;
  } else {
    summary["components"] = nullptr;
  }
  return summary;
}

std::string WallEndpointMarkdown(const WallEndpointEvaluation& e) {
  std::string out = "| threshold | within | precision | recall | F |\n|---|---|---|---|---|\n";
  for (const auto& s : e.scores)
    out += "| " + FormatFixed(s.threshold * 100, 0) + " cm | " + std::to_string(s.endpoints.tp) +
           " | " + FormatFixed(s.endpoints.precision, 3) + " | " +
           FormatFixed(s.endpoints.recall, 3) + " | " + FormatFixed(s.endpoints.f1, 3) + " |\n";
  out += "\n" + std::to_string(e.model_walls) + " model walls, " + std::to_string(e.truth_walls) +
         " truth walls, " + std::to_string(e.pairs.size()) + " paired; endpoint error mean " +
         FormatFixed(e.endpoint_error.mean * 100, 2) + " cm, max " +
         FormatFixed(e.endpoint_error.max * 100, 2) + " cm.\n";
  return out;
}

std::string Printed(const Scores& s, const ModelRecords& m, const ModelEvalParams& params,
                    const std::string& dir) {
  auto cell = [](const ClassDetection& d) {
    return std::to_string(d.tp) + "/" + std::to_string(d.n_truth) + " fp " + std::to_string(d.fp);
  };
  std::string out;
  const auto& det = s.patches.detection;
  out += "model " + m.format + ": " + std::to_string(m.rooms.size()) + " rooms, " +
         std::to_string(m.patches.size()) + " surfaces, " + std::to_string(m.columns.size()) +
         " columns, " + std::to_string(m.openings.size()) + " opening sides, " +
         std::to_string(m.components.size()) + " components\n";
  out += "walls " + cell(det[0]) + ", floors " + cell(det[1]) + ", ceilings " + cell(det[2]) +
         ", columns " + cell(det[3]) + "\n";
  out += "d_v " + FormatFixed(s.patches.d_v.mean * 100, 2) + " cm, d_h " +
         FormatFixed(s.patches.d_h.mean * 100, 2) + " cm, phi " +
         FormatFixed(s.patches.phi_deg.mean, 4) + " deg; ISPRS at " +
         FormatFixed(params.eval.report_buffer * 100, 0) + " cm: completeness " +
         FormatFixed(s.isprs.all.completeness[s.isprs.BufferIndex(params.eval.report_buffer)], 4) +
         ", correctness " +
         FormatFixed(s.isprs.all.correctness[s.isprs.BufferIndex(params.eval.report_buffer)], 4) +
         "\n";
  out += "rooms: mean IoU " + FormatFixed(s.floorplan.mean_truth_iou, 4) + " (" +
         std::to_string(s.floorplan.rooms.tp) + "/" + std::to_string(s.floorplan.rooms.n_truth) +
         " above " + FormatFixed(params.eval.floorplan.room_iou_threshold, 2) + ")\n";
  out += "wall endpoints P/R/F:";
  for (const auto& w : s.walls.scores)
    out += " @" + FormatFixed(w.threshold * 100, 0) + "cm " + FormatFixed(w.endpoints.precision, 3) +
           "/" + FormatFixed(w.endpoints.recall, 3) + "/" + FormatFixed(w.endpoints.f1, 3);
  out += "\n";
  if (s.openings)
    out += "openings: P " + FormatFixed(s.openings->precision, 3) + ", R " +
           FormatFixed(s.openings->recall, 3) + ", door states right " +
           std::to_string(s.openings->door_state_right) + "/" +
           std::to_string(s.openings->doors) + " (" + std::to_string(m.doors_with_state) +
           " doors of the model carry a state)\n";
  if (s.components && !s.components->classes.empty()) {
    const ComponentClassRow* all = nullptr;
    for (const auto& c : s.components->classes)
      if (c.class_name == "all") all = &c;
    if (all)
      out += "components: " + std::to_string(all->tp) + "/" + std::to_string(all->n) + " fp " +
             std::to_string(all->fp) + "\n";
  }
  out += "wrote " + dir + "/{evaluation.json,evaluation.md,eval.effective.yaml}\n";
  return out;
}

}  // namespace

Pose3 ParsePlanPose(const std::string& text, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(Number(item));
  if (v.size() != 4 || std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }))
    throw InputError(what, "not a pose", "'" + text + "'", "x,y,z,yaw_deg (metres, degrees)");
  Pose3 X = Pose3::Identity();
  X.linear() = Eigen::AngleAxisd(DegToRad(v[3]), Vec3::UnitZ()).toRotationMatrix();
  X.translation() = Vec3(v[0], v[1], v[2]);
  return X;
}

ModelEvaluation EvaluateModel(const ModelEvalOptions& o) {
  ModelEvalParams params;
  if (!o.config.empty()) params = LoadParamsFile<ModelEvalParams>(o.config);
  ValidateParams(params, "eval.");
  if (!fs::is_regular_file(o.model))
    throw InputError(o.model, "model file not found", "", "an .ifc or a mopad-sm3 .json");
  std::string ext = fs::path(o.model).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".ifc" && ext != ".json")
    throw InputError(o.model, "unknown model format", "'" + ext + "'",
                     ".ifc (IFC 2x3 or IFC4) or .json (mopad-sm3)");
  if (o.out.empty()) throw InputError("-o", "missing", "", "an output folder for --model");
  const TruthRecords truth = LoadTruth(o);
  ModelRecords model = ext == ".ifc" ? ReadIfcModel(o) : ReadJsonModel(o);
  Pose3 X = o.X_WE;
  std::optional<FitResult> fit;
  if (o.fit) {
    ModelRecords placed = model;
    Place(placed, X);
    // Coarse step: the floor level carrying the most area onto the truth's (a model kept in its
    // file's heights against an imported scene, whose storey floor was moved to z = 0).
    const double dz = MainFloorZ(truth.patches) - MainFloorZ(placed.patches);
    if (std::isfinite(dz)) {
      Pose3 lift = Pose3::Identity();
      lift.translation().z() = dz;
      X = lift * X;
      Place(placed, lift);
    }
    fit = FitPose(placed.patches, truth.patches, params);
    X = fit->delta * X;
  }
  Place(model, X);
  const Scores s = Score(model, truth, params);

  ojson json;
  json["format"] = "mopad-model-evaluation";
  json["version"] = 1;
  json["model"] = fs::absolute(o.model).string();
  json["model_format"] = model.format;
  json["scene"] = o.truth_file.empty() ? fs::absolute(o.scene).string() : std::string();
  json["truth"] = o.truth_file;
  json["doors"] = o.doors;
  json["pose"] = PoseJson(X);
  json["pose_source"] = o.fit ? "fit" : "given";
  if (fit)
    json["fit"] = {{"samples", fit->samples},
                   {"used", fit->used},
                   {"rms_m", Num<ojson>(fit->rms)},
                   {"delta", PoseJson(fit->delta)}};
  json["reading"] = model.notes;
  json["summary"] = SummaryJson(s, model, params);
  json["patches"] = ojson::parse(ToJson(s.patches).dump());
  json["isprs"] = ojson::parse(ToJson(s.isprs).dump());
  json["floorplan"] = ojson::parse(ToJson(s.floorplan).dump());
  json["wall_endpoints"] = ToJson(s.walls);
  if (s.openings) json["openings"] = ojson::parse(ToJson(*s.openings).dump());
  if (s.components) json["components"] = ojson::parse(ToJson(*s.components).dump());
  if (!truth.notes.empty()) json["truth_notes"] = truth.notes;

  std::string md = "# Model evaluation\n\nModel `" + o.model + "` (" + model.format +
                   ") against the truth of `" + (o.truth_file.empty() ? o.scene : o.truth_file) +
                   "`; model pose in the world " + PoseJson(X).dump() + " (" +
                   (o.fit ? "fitted" : "given") + ").\n\n## Surfaces\n\n" +
                   MarkdownPatchTable(s.patches) + "\n## ISPRS\n\n" +
                   MarkdownIsprsTable(s.isprs, params.eval.report_buffer) +
                   "\n## Rooms\n\n" + MarkdownFloorplanTable(s.floorplan) +
                   "\n## Wall endpoints (CV4AEC)\n\n" + WallEndpointMarkdown(s.walls);
  if (s.openings) md += "\n## Openings\n\n" + MarkdownOpeningsTable(*s.openings);
  if (s.components) md += "\n## Components\n\n" + MarkdownComponentsTable(*s.components);
  md += "\n## What the reading reported\n\n";
  for (const auto& n : model.notes) md += "- " + n + "\n";

  const fs::path dir(o.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(o.out, "cannot create directory", ec.message());
  WriteWholeFile((dir / "evaluation.json").string(), json.dump(2) + "\n");
  WriteWholeFile((dir / "evaluation.md").string(), md);
  WriteWholeFile((dir / "eval.effective.yaml").string(), YAML::Dump(SaveParams(params)) + "\n");
  return {Printed(s, model, params, dir.string()), json["summary"]};
}

}  // namespace mopad::evaluation
