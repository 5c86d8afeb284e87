// `mopad dataset`: the steps — read the run's rooms (run.json, scans.json, sm1.ply), load the
// run's world once per scene, label every point by tracing its beam (LabelScan), write the
// scans, the index and the truth. The layout is docs/dataset.md; the header says what is where.
#include "evaluation/dataset.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "io/scan_io.h"
#include "runfolder/layout.h"
#include "runfolder/run_record.h"
#include "scenes/element_class.h"
#include "scenes/ground_truth.h"
#include "sim/scene_world.h"

namespace mopad::evaluation {

namespace {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

// The fixed semantic classes; service components follow from kFirstComponent, one id per
// catalogue class of the truth in name order.
constexpr int kUnlabelled = 0, kWall = 1, kFloor = 2, kCeiling = 3, kColumn = 4, kDoor = 5,
              kWindow = 6, kFurniture = 7, kClutter = 8, kOther = 9, kFirstComponent = 10;
const char* const kFixedNames[] = {"unlabelled", "wall",      "floor",   "ceiling", "column",
                                   "door",       "window",    "furniture", "clutter", "other"};

int FixedClassOf(scenes::ElementClass c) {
  using scenes::ElementClass;
  switch (c) {
    case ElementClass::kWall: return kWall;
    case ElementClass::kFloor: return kFloor;
    case ElementClass::kCeiling: return kCeiling;
    case ElementClass::kColumn: return kColumn;
    case ElementClass::kDoorFrame:
    case ElementClass::kDoorLeaf: return kDoor;
    case ElementClass::kWindowFrame:
    case ElementClass::kWindowGlass: return kWindow;
    case ElementClass::kFurniture: return kFurniture;
    case ElementClass::kClutter: return kClutter;
    default: return kOther;
  }
}

Pose3 PoseOf(const ojson& j, const std::string& where) {
  try {
    const auto& t = j.at("t");
    const auto& q = j.at("q_xyzw");
    Pose3 X = Pose3::Identity();
    X.translation() = Vec3(t.at(0).get<double>(), t.at(1).get<double>(), t.at(2).get<double>());
    X.linear() = Eigen::Quaterniond(q.at(3).get<double>(), q.at(0).get<double>(),
                                    q.at(1).get<double>(), q.at(2).get<double>())
                     .normalized()
                     .toRotationMatrix();
    return X;
  } catch (const std::exception& e) {
    throw InputError(where, "X_MS: not a pose", e.what(), "{\"t\": [x,y,z], \"q_xyzw\": [...]}");
  }
}

ojson MatrixJson(const Pose3& X) {
  ojson m = ojson::array();
  for (int r = 0; r < 4; ++r) {
    ojson row = ojson::array();
    for (int c = 0; c < 4; ++c) row.push_back(X.matrix()(r, c));
    m.push_back(row);
  }
  return m;
}

struct RoomInput {
  runfolder::RunRecord run;
  std::vector<Pose3> X_MS;     // per scan index
  std::vector<bool> detail;    // per scan index
};

RoomInput ReadRoom(const std::string& room_dir) {
  RoomInput in;
  in.run = runfolder::ReadRunJson(runfolder::Join(room_dir, runfolder::kRunJson));
  const std::string scans = runfolder::Join(room_dir, runfolder::kScansLog);
  std::ifstream f(scans);
  if (!f) throw InputError(scans, "missing", "", "the room's scan log (scans.json)");
  ojson j;
  try {
    j = ojson::parse(f);
  } catch (const std::exception& e) {
    throw InputError(scans, std::string("malformed JSON: ") + e.what());
  }
  if (!j.contains("scans") || !j["scans"].is_array())
    throw InputError(scans, "scans: missing or not an array");
  for (const auto& s : j["scans"]) {
    const std::size_t k = s.value("index", in.X_MS.size());
    if (k != in.X_MS.size()) throw InputError(scans, "scans: indices not 0, 1, 2, ...");
    in.X_MS.push_back(PoseOf(s.contains("X_MS") ? s["X_MS"] : ojson(), scans));
    in.detail.push_back(s.value("detail", false));
  }
  if (in.run.sm1.empty() || !fs::exists(in.run.sm1))
    throw InputError(runfolder::Join(room_dir, runfolder::kRunJson), "files.sm1: missing", "",
                     "the room's SM1 cloud");
  return in;
}

// The labels of one scan's points (map frame) seen from its scanner.
struct Labels {
  std::vector<std::uint8_t> semantic;
  std::vector<std::int32_t> instance;
};

Labels LabelScan(const sim::EmbreeWorld& world, const std::vector<int>& semantic_of_element,
                 const std::vector<int>& fixed_of_part, const Pose3& X_WS, const Pose3& X_WM,
                 const std::vector<Eigen::Vector3f>& points, double tolerance) {
  const std::size_t n = points.size();
  Labels l;
  l.semantic.assign(n, kUnlabelled);
  l.instance.assign(n, -1);
  const Eigen::Vector3f centre = X_WS.translation().cast<float>();
  constexpr std::size_t kChunk = 4096;
  tbb::parallel_for(std::size_t{0}, (n + kChunk - 1) / kChunk, [&](std::size_t c) {
    const std::size_t b = c * kChunk, e = std::min(n, b + kChunk);
    std::vector<Eigen::Vector3f> origins(e - b, centre), dirs(e - b);
    std::vector<float> dist(e - b);
    for (std::size_t i = b; i < e; ++i) {
      const Eigen::Vector3f d = (X_WM * points[i].cast<double>()).cast<float>() - centre;
      dist[i - b] = d.norm();
      dirs[i - b] = dist[i - b] > 1e-6f ? Eigen::Vector3f(d / dist[i - b]) : Eigen::Vector3f::UnitX();
    }
    std::vector<sim::RayHit> hits(e - b);
    world.IntersectMany(origins, dirs, 0.0f, std::numeric_limits<float>::infinity(), hits);
    for (std::size_t i = b; i < e; ++i) {
      const sim::RayHit& h = hits[i - b];
      if (!h.hit() || std::abs(h.t - dist[i - b]) > tolerance) continue;
      const std::int32_t element = world.ElementIndex(h.part);
      l.instance[i] = element;
      l.semantic[i] = static_cast<std::uint8_t>(
          element >= 0 && semantic_of_element[element] >= 0 ? semantic_of_element[element]
                                                              : fixed_of_part[h.part]);
    }
  });
  return l;
}

// Label tables: fixed classes, then one per component class; instances are the world's
// element ids.
struct LabelTables {
  std::vector<int> semantic_of_element;  // per world element, -1 unknown
  std::vector<int> fixed_of_part;        // per scene part
  ojson classes, instances;
};

LabelTables MakeLabelTables(const scenes::GroundTruth& truth, const sim::EmbreeWorld& ew,
                            const std::string& scene) {
  std::set<std::string> component_classes;
  for (const auto& c : truth.service_components) component_classes.insert(c.bsc_class);
  std::map<std::string, int> component_semantic;
  ojson classes = ojson::array();
  for (int i = 0; i < kFirstComponent; ++i) classes.push_back({{"id", i}, {"name", kFixedNames[i]}});
  for (const std::string& c : component_classes) {
    const int id = kFirstComponent + static_cast<int>(component_semantic.size());
    if (id > 255) throw InputError(scene, "more than 246 component classes");
    component_semantic[c] = id;
    classes.push_back({{"id", id}, {"name", "component:" + c}});
  }
  std::map<std::string, std::string> component_class_of;
  for (const auto& c : truth.service_components) component_class_of[c.id] = c.bsc_class;
  const auto& ids = ew.ElementIds();
  std::vector<int> semantic_of_element(ids.size(), -1);
  std::vector<int> fixed_of_part(ew.scene().parts.size(), kOther);
  ojson instances = ojson::array();
  for (std::size_t p = 0; p < ew.scene().parts.size(); ++p) {
    const scenes::MeshPart& part = ew.scene().parts[p];
    fixed_of_part[p] = FixedClassOf(part.element_class);
    const std::int32_t e = ew.ElementIndex(static_cast<std::int32_t>(p));
    if (e < 0 || semantic_of_element[e] >= 0) continue;
    int sem = FixedClassOf(part.element_class);
    if (part.element_class == scenes::ElementClass::kServiceComponent) {
      const auto it = component_class_of.find(part.element_id);
      const std::string cls = it != component_class_of.end() ? it->second : part.subclass;
      if (component_semantic.count(cls)) sem = component_semantic[cls];
    }
    semantic_of_element[e] = sem;
  }
  for (std::size_t e = 0; e < ids.size(); ++e) {
    std::string cls;
    for (std::size_t p = 0; p < ew.scene().parts.size() && cls.empty(); ++p)
      if (ew.ElementIndex(static_cast<std::int32_t>(p)) == static_cast<std::int32_t>(e))
        cls = std::string(scenes::ToString(ew.scene().parts[p].element_class));
    instances.push_back({{"id", e}, {"element", ids[e]}, {"class", cls},
                         {"semantic", semantic_of_element[e] >= 0 ? semantic_of_element[e] : kOther}});
  }

  return {semantic_of_element, fixed_of_part, classes, instances};
}

// One room's scans, labelled, into `dir`/scans/<room>/; their index entries into `scans`.
void WriteRoomScans(const RoomInput& r, const sim::EmbreeWorld& ew, const LabelTables& tables,
                    double tolerance, const fs::path& dir, ojson& scans, DatasetSummary& sum) {
  const io::PointCloud sm1 = io::ReadPly(r.run.sm1);
  const io::ScalarField* scan_field = sm1.Field("scalar_scan");
  const io::ScalarField* label_field = sm1.Field("scalar_label");
  const io::ScalarField* intensity = sm1.Field("scalar_intensity");
  if (!scan_field) throw InputError(r.run.sm1, "no scalar_scan property", "", "an SM1 cloud");
  std::vector<std::vector<std::size_t>> of_scan(r.X_MS.size());
  for (std::size_t i = 0; i < sm1.points.size(); ++i) {
    const double k = scan_field->values[i];
    if (!(k >= 0) || k >= static_cast<double>(r.X_MS.size()))
      throw InputError(r.run.sm1, "scalar_scan out of range", FormatFixed(k, 0),
                       "an index of scans.json");
    of_scan[static_cast<std::size_t>(k)].push_back(i);
  }
  fs::create_directories(dir / "scans" / r.run.room);
  for (std::size_t k = 0; k < r.X_MS.size(); ++k) {
    io::PointCloud c;
    for (std::size_t i : of_scan[k]) {
      c.points.push_back(sm1.points[i]);
      if (!sm1.colors.empty()) c.colors.push_back(sm1.colors[i]);
    }
    const Labels l = LabelScan(ew, tables.semantic_of_element, tables.fixed_of_part,
                               r.run.X_WM * r.X_MS[k],
                               r.run.X_WM, c.points, tolerance);
    io::ScalarField fi{"intensity", io::PlyType::kFloat32, {}};
    io::ScalarField fs_{"semantic", io::PlyType::kUInt8, {}};
    io::ScalarField fin{"instance", io::PlyType::kInt32, {}};
    io::ScalarField fl{"sm1_label", io::PlyType::kUInt8, {}};
    std::map<int, long long> histogram;
    for (std::size_t j = 0; j < of_scan[k].size(); ++j) {
      const std::size_t i = of_scan[k][j];
      fi.values.push_back(intensity ? intensity->values[i] : 0.0);
      fs_.values.push_back(l.semantic[j]);
      fin.values.push_back(l.instance[j]);
      fl.values.push_back(label_field ? label_field->values[i] : 0.0);
      ++histogram[l.semantic[j]];
    }
    c.fields = {fi, fs_, fin, fl};
    c.comments = {"mopad dataset: map frame; docs/dataset.md"};
    char name[32];
    std::snprintf(name, sizeof name, "%03zu.ply", k);
    const std::string file = "scans/" + r.run.room + "/" + name;
    io::WritePly((dir / file).string(), c);
    ojson hist = ojson::object();
    for (const auto& [cls, count] : histogram) hist[std::to_string(cls)] = count;
    scans.push_back({{"room", r.run.room}, {"index", k}, {"file", file},
                     {"points", of_scan[k].size()}, {"detail", static_cast<bool>(r.detail[k])},
                     {"X_MS", MatrixJson(r.X_MS[k])}, {"semantic_histogram", hist}});
    ++sum.scans;
    sum.points += static_cast<long long>(of_scan[k].size());
    sum.unlabelled += histogram.count(kUnlabelled) ? histogram[kUnlabelled] : 0;
  }
  ++sum.rooms;
}

}  // namespace

DatasetSummary WriteDataset(const std::string& run_dir, const std::string& out,
                            double tolerance) {
  if (!(tolerance > 0.0 && tolerance <= 1.0))
    throw InputError("--tolerance", "out of range", FormatFixed(tolerance, 4), "(0, 1] m");
  if (!fs::is_directory(run_dir))
    throw InputError(run_dir, "run directory not found", "",
                     "a room run (run.json) or a folder with rooms/*/run.json");
  std::vector<RoomInput> rooms;
  for (const std::string& dir : runfolder::RoomFolders(run_dir, runfolder::kRunJson))
    rooms.push_back(ReadRoom(dir));
  if (rooms.empty())
    throw InputError(run_dir, "not a run directory", "no run.json",
                     "RUN_DIR/run.json or RUN_DIR/rooms/*/run.json");
  for (const RoomInput& r : rooms)
    if (r.run.scene != rooms.front().run.scene || r.run.doors != rooms.front().run.doors)
      throw InputError(r.run.dir, "rooms of one run in different worlds", "'" + r.run.scene + "'",
                       "one scene and one set of door angles");
  std::string scene = rooms.front().run.scene;
  if (!fs::exists(scene) && fs::exists(fs::path(rooms.front().run.dir) / scene))
    scene = (fs::path(rooms.front().run.dir) / scene).string();
  const sim::SceneWorld world = sim::LoadSceneWorld(scene, rooms.front().run.doors);
  if (!world.truth)
    throw InputError(scene, "scene has no truth sidecar", "", "a scene with scene.truth.json");
  const scenes::GroundTruth& truth = *world.truth;
  const sim::EmbreeWorld& ew = *world.world;

  const LabelTables tables = MakeLabelTables(truth, ew, scene);
  const fs::path dir(out);
  std::error_code ec;
  fs::create_directories(dir / "scans", ec);
  if (ec) throw InputError(out, "cannot create directory", ec.message());
  DatasetSummary sum;
  ojson scans = ojson::array();
  ojson room_list = ojson::array();
  for (const RoomInput& r : rooms) {
    room_list.push_back({{"room", r.run.room}, {"X_WM", MatrixJson(r.run.X_WM)},
                         {"scans", r.X_MS.size()}});
    WriteRoomScans(r, ew, tables, tolerance, dir, scans, sum);
  }
  // The truth as the run's world had it.
  const fs::path truth_src = fs::is_directory(scene) ? fs::path(scene) / "scene.truth.json"
                                                      : fs::path();
  if (!truth_src.empty() && fs::exists(truth_src)) {
    std::ifstream in(truth_src, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    WriteWholeFile((dir / "truth.json").string(), ss.str());
  } else {
    scenes::WriteGroundTruth(truth, (dir / "truth.json").string());
  }
  ojson index;
  index["format"] = "mopad-dataset";
  index["version"] = 1;
  index["scene"] = fs::absolute(scene).string();
  index["doors"] = rooms.front().run.doors;
  index["frame"] =
      "points and X_MS in each room's map frame (REP-105); X_WM maps a room's map frame into "
      "the truth's world frame";
  index["label_tolerance_m"] = tolerance;
  index["semantic_classes"] = tables.classes;
  index["instances"] = tables.instances;
  index["rooms"] = room_list;
  index["scans"] = scans;
  index["truth"] = "truth.json";
  WriteWholeFile((dir / "dataset.json").string(), index.dump(1) + "\n");
  sum.text = "dataset: " + std::to_string(sum.rooms) + " rooms, " + std::to_string(sum.scans) +
             " scans, " + std::to_string(sum.points) + " points (" +
             std::to_string(sum.unlabelled) + " unlabelled) -> " + out + "/dataset.json\n";
  return sum;
}

}  // namespace mopad::evaluation
