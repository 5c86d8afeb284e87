#include "evaluation/metrics_floor.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "common/format.h"
#include "evaluation/json_number.h"
#include "evaluation/report_tables.h"
#include "evaluation/truth_models.h"

namespace mopad::evaluation {
namespace {

using ojson = nlohmann::ordered_json;
using modelling::StructuralModel;

Vec3 Centroid(const std::vector<Vec3>& poly) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& v : poly) c += v;
  return c / static_cast<double>(std::max<std::size_t>(1, poly.size()));
}

Vec3 Centre(const std::array<Vec3, 4>& corners, const Pose3& X_WM) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& v : corners) c += X_WM * v;
  return c / 4.0;
}

Vec3 AlongWall(const Vec3& n) {
  const Vec3 u(-n.y(), n.x(), 0.0);
  return u.norm() > 0 ? u.normalized() : Vec3::UnitX();
}

double Overlap(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const Vec3& u) {
  double a0 = 1e300, a1 = -1e300, b0 = 1e300, b1 = -1e300;
  for (const Vec3& v : a) a0 = std::min(a0, u.dot(v)), a1 = std::max(a1, u.dot(v));
  for (const Vec3& v : b) b0 = std::min(b0, u.dot(v)), b1 = std::max(b1, u.dot(v));
  return std::min(a1, b1) - std::max(a0, b0);
}

ojson Stats(const ErrorStats& s) { return ojson::parse(ToJson(s).dump()); }

// The truth room of a robot room; InputError when the run has none.
const std::string& TruthRoomOf(const std::map<std::string, std::string>& truth_room,
                               const std::string& robot_room) {
  const auto it = truth_room.find(robot_room);
  if (it == truth_room.end())
    throw InputError("floor/sm3.json", "room '" + robot_room + "' has no run among rooms/*");
  return it->second;
}

// The floor walls' faces in the world as patches ("<robot room>/<patch>"), wall by wall, face
// by face; first_face[w] indexes wall w's first face. Counts the walls and two-sided walls.
std::vector<Patch> WorldFaces(const modelling::FloorModel& model, const Pose3& X_WM,
                              std::vector<int>& first_face, FloorEvaluation& e) {
  std::vector<Patch> faces;
  for (const modelling::FloorWall& w : model.walls) {
    ++e.walls;
    if (w.TwoSided()) ++e.two_sided_walls;
    first_face.push_back(static_cast<int>(faces.size()));
    for (const modelling::WallFace& f : w.faces) {
      Patch p;
      p.id = f.room + "/" + f.patch.id;
      p.cls = SurfaceClass::kWall;
      for (const Vec3& v : f.patch.polygon) p.polygon.push_back(X_WM * v);
      p.normal = X_WM.linear() * f.patch.plane.n;
      faces.push_back(std::move(p));
    }
  }
  return faces;
}

// Truth pairs: antiparallel faces of two rooms (within 1 deg), back to back at most
// max_truth_thickness apart, overlapping along the wall. [i][j] is the pair's thickness (m),
// NaN for two faces that are not a pair; counts the pairs.
std::vector<std::vector<double>> TruthPairThickness(const FloorTruth& truth,
                                                    double max_truth_thickness,
                                                    FloorEvaluation& e) {
  const int nt = static_cast<int>(truth.faces.size());
  std::vector<std::vector<double>> truth_t(nt, std::vector<double>(nt, NAN));
  const double cos1 = std::cos(3.14159265358979323846 / 180.0);
  for (int i = 0; i < nt; ++i)
    for (int j = i + 1; j < nt; ++j) {
      const Patch& a = truth.faces[i];
      const Patch& b = truth.faces[j];
      const Vec3 na = a.normal.normalized(), nb = b.normal.normalized();
      if (truth.face_rooms[i] == truth.face_rooms[j] || na.dot(nb) > -cos1) continue;
      const Vec3 ca = Centroid(a.polygon), cb = Centroid(b.polygon);
      const double t = -na.dot(cb - ca);  // b behind a
      const double t2 = -nb.dot(ca - cb);
      if (t <= 0 || t2 <= 0 || std::max(t, t2) > max_truth_thickness ||
          Overlap(a.polygon, b.polygon, AlongWall(na)) <= 0)
        continue;
      truth_t[i][j] = truth_t[j][i] = 0.5 * (t + t2);
      ++e.truth_pairs;
    }
  return truth_t;
}

// Every face pair of the floor model, correct when its faces match the two faces of a truth
// pair (e.faces must hold the face matching), with its thickness error.
void ScoreFacePairs(const modelling::FloorModel& model, const std::vector<Patch>& faces,
                    const std::vector<int>& first_face, const FloorTruth& truth,
                    const std::vector<std::vector<double>>& truth_t, FloorEvaluation& e) {
  std::vector<int> truth_of(faces.size(), -1);
  for (const PatchPair& p : e.faces.pairs) truth_of[p.model_index] = p.truth_index;
  const std::size_t nt = truth.faces.size();
  std::vector<std::vector<char>> found(nt, std::vector<char>(nt, 0));
  for (std::size_t w = 0; w < model.walls.size(); ++w)
    for (const modelling::WallFacePair& p : model.walls[w].pairs) {
      const int a = first_face[w] + p.a, b = first_face[w] + p.b;
      FloorPairResult r;
      r.wall = model.walls[w].id;
      r.face_a = faces[a].id;
      r.face_b = faces[b].id;
      r.thickness = p.thickness;
      r.truth_thickness = NAN;
      const int ta = truth_of[a], tb = truth_of[b];
      if (ta >= 0) r.truth_a = truth.faces[ta].id;
      if (tb >= 0) r.truth_b = truth.faces[tb].id;
      if (ta >= 0 && tb >= 0 && std::isfinite(truth_t[ta][tb])) {
        r.truth_thickness = truth_t[ta][tb];
        r.correct = true;
        ++e.correct_pairs;
        e.thickness_error.Add(std::abs(r.thickness - r.truth_thickness));
        if (!found[ta][tb]) ++e.truth_pairs_found;
        found[ta][tb] = found[tb][ta] = 1;
      }
      ++e.model_pairs;
      e.pairs.push_back(std::move(r));
    }
}

// Each room's offset against the truth: the least-squares plan translation from its matched
// wall faces (e.faces), solvable when they span two directions.
void SolveRoomOffsets(const modelling::FloorModel& model, const std::vector<Patch>& faces,
                      const FloorTruth& truth, const std::map<std::string, std::string>& truth_room,
                      FloorEvaluation& e) {
  std::vector<std::string> face_room;
  for (const modelling::FloorWall& w : model.walls)
    for (const modelling::WallFace& f : w.faces) face_room.push_back(f.room);
  for (const StructuralModel& r : model.rooms) {
    FloorRoomOffset o;
    o.room = r.room;
    o.truth_room = TruthRoomOf(truth_room, r.room);
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Vec2 b = Vec2::Zero();
    for (const PatchPair& p : e.faces.pairs) {
      if (face_room[p.model_index] != r.room) continue;
      const Patch& t = truth.faces[p.truth_index];
      const Vec2 n = t.normal.head<2>().normalized();
      const double d = n.dot((Centroid(faces[p.model_index].polygon) - t.polygon[0]).head<2>());
      A += n * n.transpose();
      b += n * d;
      ++o.faces;
    }
    // Solvable when the faces span two directions (the smaller eigenvalue clearly non-zero).
    o.solved = o.faces >= 2 && A.determinant() > 1e-3 * A.trace() * A.trace();
    if (o.solved) o.offset = A.ldlt().solve(b);
    e.room_offsets.push_back(o);
  }
}

// |t_a - t_b| for every two solved rooms that share a wall (a correct pair), each pair of rooms
// once, in the order of their first correct pair.
void AddRoomAlignment(FloorEvaluation& e) {
  std::vector<std::pair<std::string, std::string>> neighbours;
  for (const FloorPairResult& p : e.pairs) {
    if (!p.correct) continue;
    std::string a = p.face_a.substr(0, p.face_a.find('/'));
    std::string b = p.face_b.substr(0, p.face_b.find('/'));
    if (b < a) std::swap(a, b);
    if (std::find(neighbours.begin(), neighbours.end(), std::pair{a, b}) == neighbours.end())
      neighbours.emplace_back(a, b);
  }
  auto offset_of = [&](const std::string& room) -> const FloorRoomOffset* {
    for (const FloorRoomOffset& o : e.room_offsets)
      if (o.room == room && o.solved) return &o;
    return nullptr;
  };
  for (const auto& [a, b] : neighbours) {
    const FloorRoomOffset* oa = offset_of(a);
    const FloorRoomOffset* ob = offset_of(b);
    if (oa && ob) e.room_alignment.Add((oa->offset - ob->offset).norm());
  }
}

// The floor model's doors (indices into model.openings) and the truth door each matches (-1
// none): the nearest truth door in plan within max_door_distance, one model door per truth
// door, closest pairs first.
struct DoorMatch {
  std::vector<int> openings;
  std::vector<int> truth_door;
};

DoorMatch MatchDoors(const modelling::FloorModel& model, const Pose3& X_WM, const FloorTruth& truth,
                     double max_door_distance) {
  struct Cand {
    double d;
    int model, truth;
  };
  std::vector<Cand> cands;
  DoorMatch m;
  for (std::size_t k = 0; k < model.openings.size(); ++k) {
    const modelling::DetectedOpening& o = model.openings[k].opening;
    if (o.type != modelling::OpeningType::kDoor) continue;
    const int i = static_cast<int>(m.openings.size());
    m.openings.push_back(static_cast<int>(k));
    const Vec3 c = Centre(o.corners, X_WM);
    for (std::size_t t = 0; t < truth.doors.size(); ++t) {
      const double d = (c - truth.doors[t].centre).head<2>().norm();
      if (d <= max_door_distance) cands.push_back({d, i, static_cast<int>(t)});
    }
  }
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Cand& x, const Cand& y) { return x.d < y.d; });
  m.truth_door.assign(m.openings.size(), -1);
  std::vector<int> taken(truth.doors.size(), 0);
  for (const Cand& c : cands)
    if (m.truth_door[c.model] < 0 && !taken[c.truth])
      m.truth_door[c.model] = c.truth, taken[c.truth] = 1;
  return m;
}

// One result per matched-or-not floor door: merged (two sides) correctly when its rooms are
// its truth door's, with the along-wall offset between its sides; then the truth doors found
// from one side only.
void ScoreDoors(const modelling::FloorModel& model, const Pose3& X_WM, const FloorTruth& truth,
                const std::map<std::string, std::string>& truth_room, const DoorMatch& match,
                FloorEvaluation& e) {
  e.truth_doors = static_cast<int>(truth.doors.size());
  std::vector<int> truth_merged(truth.doors.size(), 0);
  for (std::size_t m = 0; m < match.openings.size(); ++m) {
    const modelling::FloorOpening& fo = model.openings[match.openings[m]];
    const int td = match.truth_door[m];
    FloorDoorResult r;
    r.opening = fo.opening.id;
    for (const std::string& room : fo.rooms) r.rooms.push_back(TruthRoomOf(truth_room, room));
    r.merged = fo.sides.size() == 2;
    if (td >= 0) r.truth = truth.doors[td].id;
    if (r.merged) {
      ++e.merged_doors;
      std::vector<std::string> rooms = r.rooms;
      std::sort(rooms.begin(), rooms.end());
      r.correct = td >= 0 && rooms == truth.doors[td].rooms;
      // The wall's direction: the door's bottom edge, (u0, v0) -> (u1, v0).
      Vec3 along = X_WM.linear() * (fo.opening.corners[1] - fo.opening.corners[0]);
      along.z() = 0;
      along = along.norm() > 0 ? along.normalized() : Vec3::UnitX();
      r.side_offset = std::abs(
          along.dot(Centre(fo.sides[0].corners, X_WM) - Centre(fo.sides[1].corners, X_WM)));
      if (r.correct) {
        ++e.merged_correct;
        e.door_side_offset.Add(r.side_offset);
        truth_merged[td] = 1;
      }
    }
    e.doors.push_back(std::move(r));
  }
  for (std::size_t m = 0; m < match.openings.size(); ++m)
    if (match.truth_door[m] >= 0 && !e.doors[m].merged && !truth_merged[match.truth_door[m]])
      ++e.one_sided_doors;
}

}  // namespace

FloorTruth MakeFloorTruth(const scenes::GroundTruth& truth, const std::vector<std::string>& rooms) {
  FloorTruth out;
  for (const std::string& room : rooms)
    for (Patch& p : TruthPatches(truth, room)) {
      if (p.cls != SurfaceClass::kWall) continue;
      p.id = room + "/" + p.id;
      out.faces.push_back(std::move(p));
      out.face_rooms.push_back(room);
    }
  auto evaluated = [&](const std::string& r) {
    return std::find(rooms.begin(), rooms.end(), r) != rooms.end();
  };
  for (const scenes::Opening& o : truth.openings) {
    if (o.type != scenes::OpeningType::kDoor || o.rooms.size() != 2 || !evaluated(o.rooms[0]) ||
        !evaluated(o.rooms[1]) || o.rooms[0] == o.rooms[1] || o.corners.empty())
      continue;
    FloorTruth::Door d;
    d.id = o.id;
    d.rooms = o.rooms;
    std::sort(d.rooms.begin(), d.rooms.end());
    d.centre = Centroid(o.corners);
    out.doors.push_back(std::move(d));
  }
  return out;
}

FloorEvaluation EvaluateFloor(const modelling::FloorModel& model, const Pose3& X_WM,
                              const std::map<std::string, std::string>& truth_room,
                              const FloorTruth& truth, const FloorEvalParams& params) {
  ValidateParams(params, "floor.");
  FloorEvaluation e;
  std::vector<int> first_face;
  const std::vector<Patch> faces = WorldFaces(model, X_WM, first_face, e);
  e.faces = EvaluatePatches(faces, truth.faces, params.faces);
  const auto truth_t = TruthPairThickness(truth, params.max_truth_thickness, e);
  ScoreFacePairs(model, faces, first_face, truth, truth_t, e);
  SolveRoomOffsets(model, faces, truth, truth_room, e);
  AddRoomAlignment(e);
  ScoreDoors(model, X_WM, truth, truth_room,
             MatchDoors(model, X_WM, truth, params.max_door_distance), e);
  return e;
}

ojson ToJson(const FloorEvaluation& e) {
  ojson j;
  j["walls"] = e.walls;
  j["two_sided_walls"] = e.two_sided_walls;
  j["faces"] = ojson::parse(ToJson(e.faces).dump());
  j["face_pairs"] = {{"truth", e.truth_pairs},
                     {"model", e.model_pairs},
                     {"correct", e.correct_pairs},
                     {"truth_found", e.truth_pairs_found}};
  j["thickness_error_m"] = Stats(e.thickness_error);
  ojson offsets = ojson::array();
  for (const FloorRoomOffset& o : e.room_offsets)
    offsets.push_back(
        {{"room", o.room},
         {"truth_room", o.truth_room},
         {"faces", o.faces},
         {"offset_m", o.solved ? ojson::array({o.offset.x(), o.offset.y()}) : ojson(nullptr)}});
  j["room_offsets"] = offsets;
  j["room_alignment_m"] = Stats(e.room_alignment);
  j["doors"] = {{"truth_between_rooms", e.truth_doors},
                {"merged", e.merged_doors},
                {"merged_correct", e.merged_correct},
                {"one_sided", e.one_sided_doors}};
  j["door_side_offset_m"] = Stats(e.door_side_offset);
  ojson pairs = ojson::array();
  for (const FloorPairResult& p : e.pairs)
    pairs.push_back({{"wall", p.wall},
                     {"faces", {p.face_a, p.face_b}},
                     {"truth", {p.truth_a, p.truth_b}},
                     {"thickness_m", Num<ojson>(p.thickness)},
                     {"truth_thickness_m", Num<ojson>(p.truth_thickness)},
                     {"correct", p.correct}});
  j["pairs"] = pairs;
  ojson doors = ojson::array();
  for (const FloorDoorResult& d : e.doors)
    doors.push_back({{"opening", d.opening},
                     {"rooms", d.rooms},
                     {"truth", d.truth},
                     {"merged", d.merged},
                     {"correct", d.correct},
                     {"side_offset_m", d.merged ? Num<ojson>(d.side_offset) : ojson(nullptr)}});
  j["door_list"] = doors;
  return j;
}

std::string MarkdownFloorTable(const FloorEvaluation& e) {
  const ClassDetection& w = e.faces.detection[static_cast<int>(SurfaceClass::kWall)];
  std::ostringstream md;
  md << "| figure | value |\n|---|---|\n";
  md << "| floor walls (two-sided) | " << e.walls << " (" << e.two_sided_walls << ") |\n";
  md << "| wall faces TP/N (FP) | " << w.tp << "/" << w.n_truth << " (" << w.fp << ") |\n";
  md << "| faces d_v mean / max (cm) | " << FormatFixed(e.faces.d_v.mean * 100, 2) << " / "
     << FormatFixed(e.faces.d_v.max * 100, 2) << " |\n";
  md << "| faces d_h mean / max (cm) | " << FormatFixed(e.faces.d_h.mean * 100, 2) << " / "
     << FormatFixed(e.faces.d_h.max * 100, 2) << " |\n";
  md << "| face pairs correct / model (truth pairs found / truth) | " << e.correct_pairs << " / "
     << e.model_pairs << " (" << e.truth_pairs_found << " / " << e.truth_pairs << ") |\n";
  md << "| thickness error mean / max (cm): alignment across walls | "
     << FormatFixed(e.thickness_error.mean * 100, 2) << " / "
     << FormatFixed(e.thickness_error.max * 100, 2) << " |\n";
  md << "| room-to-room alignment mean / max (cm): rooms sharing a wall | "
     << FormatFixed(e.room_alignment.mean * 100, 2) << " / "
     << FormatFixed(e.room_alignment.max * 100, 2) << " |\n";
  md << "| doors between rooms: merged correctly / merged / truth (one-sided) | "
     << e.merged_correct << " / " << e.merged_doors << " / " << e.truth_doors << " ("
     << e.one_sided_doors << ") |\n";
  md << "| door side offset mean / max (cm): alignment along walls | "
     << FormatFixed(e.door_side_offset.mean * 100, 2) << " / "
     << FormatFixed(e.door_side_offset.max * 100, 2) << " |\n";
  return md.str();
}

}  // namespace mopad::evaluation
