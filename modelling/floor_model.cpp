#include "modelling/floor_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>

#include "common/error.h"

namespace mopad::modelling {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One room's wall patch with what the pairing needs.
struct Face {
  int room = -1;           // index into the input rooms
  int patch = -1;          // index into the room's patches
  Vec3 h = Vec3::UnitX();  // horizontal unit normal (into the room)
  Vec3 centroid = Vec3::Zero();
  double z0 = 0, z1 = 0;  // height range of the polygon
};

Vec3 Horizontal(const Vec3& n) { return Vec3(n.x(), n.y(), 0.0); }
// Direction along a wall of horizontal normal h: u = z x h (u x z = h: CCW seen from h's tip).
Vec3 AlongWall(const Vec3& h) { return Vec3(-h.y(), h.x(), 0.0); }

std::pair<double, double> Interval(const std::vector<Vec3>& poly, const Vec3& axis) {
  double lo = 1e300, hi = -1e300;
  for (const Vec3& v : poly) lo = std::min(lo, axis.dot(v)), hi = std::max(hi, axis.dot(v));
  return {lo, hi};
}
std::pair<double, double> Interval(const std::array<Vec3, 4>& c, const Vec3& axis) {
  return Interval(std::vector<Vec3>(c.begin(), c.end()), axis);
}

double Overlap(std::pair<double, double> a, std::pair<double, double> b) {
  return std::min(a.second, b.second) - std::max(a.first, b.first);
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The better-observed of two sides of one door (see the file comment): true when `a` wins.
bool Better(const DetectedOpening& a, int room_a, const DetectedOpening& b, int room_b) {
  const bool leaf_a = std::isfinite(a.opening_angle_deg),
             leaf_b = std::isfinite(b.opening_angle_deg);
  if (leaf_a != leaf_b) return leaf_a;
  if (a.confidence != b.confidence) return a.confidence > b.confidence;
  return room_a < room_b;
}

Vec3 OntoPlane(const Vec3& p, const Plane& plane) { return p - plane.Distance(p) * plane.n; }

// The wall patch a face stands for.
const StructuralPatch& PatchOf(const std::vector<StructuralModel>& sm3, const Face& f) {
  return sm3[f.room].patches[f.patch];
}

// Faces, in room then patch order (their walls checked: a polygon, a vertical finite plane);
// the other patches stay with their room in `out`.
std::vector<Face> CollectFaces(const std::vector<StructuralModel>& sm3, const std::string& where,
                               FloorModel& out) {
  std::vector<Face> faces;
  for (std::size_t r = 0; r < sm3.size(); ++r) {
    StructuralModel keep;
    keep.room = sm3[r].room;
    keep.floor_z = sm3[r].floor_z;
    keep.ceiling_z = sm3[r].ceiling_z;
    for (std::size_t p = 0; p < sm3[r].patches.size(); ++p) {
      const StructuralPatch& sp = sm3[r].patches[p];
      if (sp.patch_class != PatchClass::kWall) {
        keep.patches.push_back(sp);
        continue;
      }
      const std::string name = "room '" + sm3[r].room + "' " + sp.id;
      if (sp.polygon.size() < 3)
        throw InputError(where, name + ": polygon of fewer than 3 vertices",
                         std::to_string(sp.polygon.size()), ">= 3");
      const Vec3 h = Horizontal(sp.plane.n);
      if (!h.allFinite() || h.norm() < 0.5 * sp.plane.n.norm() || !std::isfinite(sp.plane.d))
        throw InputError(where, name + ": wall plane is not vertical or not finite");
      Face f;
      f.room = static_cast<int>(r);
      f.patch = static_cast<int>(p);
      f.h = h.normalized();
      for (const Vec3& v : sp.polygon) {
        if (!v.allFinite()) throw InputError(where, name + ": polygon vertex not finite");
        f.centroid += v;
      }
      f.centroid /= static_cast<double>(sp.polygon.size());
      std::tie(f.z0, f.z1) = Interval(sp.polygon, Vec3::UnitZ());
      faces.push_back(f);
    }
    out.rooms.push_back(std::move(keep));
  }
  return faces;
}

// Each wall's plane, thickness and extent from its faces (`wall_of` each face's wall).
void FitWallPlanes(const std::vector<StructuralModel>& sm3, const std::vector<Face>& faces,
                   const std::vector<int>& wall_of, FloorModel& out) {
  auto patch_of = [&](const Face& f) -> const StructuralPatch& { return PatchOf(sm3, f); };
  const int nf = static_cast<int>(faces.size());
  std::vector<std::vector<int>> members(out.walls.size());
  for (int i = 0; i < nf; ++i) members[wall_of[i]].push_back(i);
  for (std::size_t w = 0; w < out.walls.size(); ++w) {
    FloorWall& wall = out.walls[w];
    const std::vector<int>& m = members[w];
    if (m.size() == 1) {
      wall.plane = patch_of(faces[m[0]]).plane;
      wall.polygon = patch_of(faces[m[0]]).polygon;
      continue;
    }
    const Vec3 h_ref = faces[m[0]].h;
    Vec3 n = Vec3::Zero();
    std::vector<double> length(m.size());
    for (std::size_t k = 0; k < m.size(); ++k) {
      const Face& f = faces[m[k]];
      wall.faces[k].side = f.h.dot(h_ref) >= 0 ? 1 : -1;
      const auto iv = Interval(patch_of(f).polygon, AlongWall(f.h));
      length[k] = std::max(1e-6, iv.second - iv.first);
      n += wall.faces[k].side * length[k] * f.h;
    }
    n.normalize();
    const Vec3 u = AlongWall(n);
    double s[2] = {0, 0}, wsum[2] = {0, 0};
    double u0 = 1e300, u1 = -1e300, z0 = 1e300, z1 = -1e300;
    for (std::size_t k = 0; k < m.size(); ++k) {
      const Face& f = faces[m[k]];
      const int side = wall.faces[k].side > 0 ? 0 : 1;
      s[side] += length[k] * n.dot(f.centroid);
      wsum[side] += length[k];
      const auto iv = Interval(patch_of(f).polygon, u);
      u0 = std::min(u0, iv.first), u1 = std::max(u1, iv.second);
      z0 = std::min(z0, f.z0), z1 = std::max(z1, f.z1);
    }
    const double s_plus = s[0] / wsum[0], s_minus = s[1] / wsum[1];
    wall.thickness = s_plus - s_minus;
    wall.plane.n = n;
    wall.plane.d = -0.5 * (s_plus + s_minus);
    const Vec3 o = -wall.plane.d * n;
    for (const auto& [pu, pz] : {std::pair{u0, z0}, {u1, z0}, {u1, z1}, {u0, z1}})
      wall.polygon.push_back(o + pu * u + pz * Vec3::UnitZ());
  }
}

// Openings: each on its host face's wall, doors seen from both sides merged (the better-observed
// side first), in wall order then along the wall.
void PlaceOpenings(const std::vector<StructuralModel>& sm3, const std::vector<Sm4Model>& sm4,
                   const FloorModelParams& params, const std::vector<Face>& faces,
                   const std::vector<int>& wall_of, const std::vector<int>& index_in_wall,
                   const std::string& where, FloorModel& out) {
  auto room_index = [&](const std::string& name) {
    for (std::size_t r = 0; r < sm3.size(); ++r)
      if (sm3[r].room == name) return static_cast<int>(r);
    return -1;
  };
  auto patch_of = [&](const Face& f) -> const StructuralPatch& { return PatchOf(sm3, f); };
  const int nf = static_cast<int>(faces.size());
  struct Seen {
    int room, wall, side;
    const DetectedOpening* o;
    double u0, u1;
  };
  std::vector<Seen> seen;
  for (const Sm4Model& m4 : sm4) {
    const int r = room_index(m4.room);
    if (r < 0)
      throw InputError(where, "SM4 of room '" + m4.room + "' has no SM3", "",
                       "a room of the SM3 list");
    for (const DetectedOpening& o : m4.openings) {
      int face = -1;
      for (int i = 0; i < nf && face < 0; ++i)
        if (faces[i].room == r && patch_of(faces[i]).id == o.host) face = i;
      if (face < 0)
        throw InputError(where, "room '" + m4.room + "' " + o.id + ": host '" + o.host +
                                    "' is not a wall of the room");
      for (const Vec3& c : o.corners)
        if (!c.allFinite())
          throw InputError(where, "room '" + m4.room + "' " + o.id + ": corner not finite");
      const FloorWall& w = out.walls[wall_of[face]];
      const Vec3 hn = Horizontal(w.plane.n).normalized();
      const auto iv = Interval(o.corners, AlongWall(hn));
      seen.push_back(
          {r, wall_of[face], w.faces[index_in_wall[face]].side, &o, iv.first, iv.second});
    }
  }
  struct Candidate {
    double share;
    int a, b;
  };
  std::vector<Candidate> candidates;
  for (int a = 0; a < static_cast<int>(seen.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(seen.size()); ++b) {
      const Seen& sa = seen[a];
      const Seen& sb = seen[b];
      if (sa.wall != sb.wall || sa.side == sb.side || sa.room == sb.room ||
          sa.o->type != OpeningType::kDoor || sb.o->type != OpeningType::kDoor)
        continue;
      const double narrower = std::min(sa.u1 - sa.u0, sb.u1 - sb.u0);
      const double share = narrower > 0 ? Overlap({sa.u0, sa.u1}, {sb.u0, sb.u1}) / narrower : 0;
      if (share >= params.min_door_overlap) candidates.push_back({share, a, b});
    }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.share > y.share; });
  std::vector<int> partner(seen.size(), -1);
  for (const Candidate& c : candidates)
    if (partner[c.a] < 0 && partner[c.b] < 0) partner[c.a] = c.b, partner[c.b] = c.a;

  struct Item {
    int wall;
    double u;
    int first;
  };
  std::vector<Item> items;
  for (int a = 0; a < static_cast<int>(seen.size()); ++a) {
    if (partner[a] >= 0 && partner[a] < a) continue;
    int first = a;
    if (partner[a] >= 0 &&
        !Better(*seen[a].o, seen[a].room, *seen[partner[a]].o, seen[partner[a]].room))
      first = partner[a];
    items.push_back({seen[a].wall, 0.5 * (seen[first].u0 + seen[first].u1), first});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& x, const Item& y) {
    return std::tie(x.wall, x.u) < std::tie(y.wall, y.u);
  });
  for (const Item& it : items) {
    const Seen& s = seen[it.first];
    const FloorWall& w = out.walls[s.wall];
    FloorOpening fo;
    fo.opening = *s.o;
    fo.opening.id = "opening_" + std::to_string(out.openings.size() + 1);
    fo.opening.host = w.id;
    const Plane unit{w.plane.n / w.plane.n.norm(), w.plane.d / w.plane.n.norm()};
    for (Vec3& c : fo.opening.corners) c = OntoPlane(c, unit);
    fo.rooms.push_back(sm3[s.room].room);
    fo.sides.push_back(*s.o);
    if (partner[it.first] >= 0) {
      const Seen& t = seen[partner[it.first]];
      fo.rooms.push_back(sm3[t.room].room);
      fo.sides.push_back(*t.o);
    }
    out.openings.push_back(std::move(fo));
  }
}

}  // namespace

void FloorModelParams::Validate() const {
  ValidateParams(*this, "floor_model.");
  if (min_thickness > max_thickness)
    throw InputError("", "parameter 'floor_model.min_thickness' exceeds 'max_thickness'",
                     std::to_string(min_thickness), "<= " + std::to_string(max_thickness));
}

FloorModel BuildFloorModel(const std::vector<StructuralModel>& sm3,
                           const std::vector<Sm4Model>& sm4, const FloorModelParams& params) {
  params.Validate();
  const std::string where = "floor model";
  for (std::size_t r = 0; r < sm3.size(); ++r) {
    if (sm3[r].room.empty())
      throw InputError(where, "room " + std::to_string(r) + " has no name", "", "a room name");
    for (std::size_t q = 0; q < r; ++q)
      if (sm3[q].room == sm3[r].room)
        throw InputError(where, "room '" + sm3[r].room + "' listed twice");
  }

  FloorModel out;
  const std::vector<Face> faces = CollectFaces(sm3, where, out);
  auto patch_of = [&](const Face& f) -> const StructuralPatch& { return PatchOf(sm3, f); };

  // Pairs of faces of one wall, and the walls as connected groups of faces.
  const int nf = static_cast<int>(faces.size());
  const double cos_max = std::cos(params.max_angle_deg * kPi / 180.0);
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  struct Pair {
    int a, b;
    double thickness, overlap;
  };
  std::vector<Pair> pairs;
  for (int i = 0; i < nf; ++i)
    for (int j = i + 1; j < nf; ++j) {
      const Face& fi = faces[i];
      const Face& fj = faces[j];
      if (fi.room == fj.room || fi.h.dot(fj.h) > -cos_max) continue;
      const StructuralPatch& pi = patch_of(fi);
      const StructuralPatch& pj = patch_of(fj);
      const Vec3 u = AlongWall(fi.h);
      const auto ui = Interval(pi.polygon, u), uj = Interval(pj.polygon, u);
      const double along = Overlap(ui, uj);
      const double high = std::min(fi.z1, fj.z1) - std::max(fi.z0, fj.z0);
      if (along < params.min_overlap || high < params.min_overlap) continue;
      // Each face's centroid slid along the wall to the middle of the overlap.
      const double um = 0.5 * (std::max(ui.first, uj.first) + std::min(ui.second, uj.second));
      const Vec3 ci = fi.centroid + (um - u.dot(fi.centroid)) * u;
      const Vec3 cj = fj.centroid + (um - u.dot(fj.centroid)) * u;
      // Back to back: each lies behind the other's plane (the normals point into the rooms).
      const double t_ij = -pj.plane.Distance(ci) / pj.plane.n.norm();
      const double t_ji = -pi.plane.Distance(cj) / pi.plane.n.norm();
      if (std::min(t_ij, t_ji) < params.min_thickness ||
          std::max(t_ij, t_ji) > params.max_thickness)
        continue;
      pairs.push_back({i, j, 0.5 * (t_ij + t_ji), along});
      const int ri = Find(parent, i), rj = Find(parent, j);
      if (ri != rj) parent[std::max(ri, rj)] = std::min(ri, rj);
    }

  std::vector<int> wall_of(nf, -1), index_in_wall(nf, -1);
  for (int i = 0; i < nf; ++i) {
    const int root = Find(parent, i);
    if (wall_of[root] < 0) {  // roots are each group's lowest face index: groups in face order
      wall_of[root] = static_cast<int>(out.walls.size());
      out.walls.emplace_back();
      out.walls.back().id = "wall_" + std::to_string(out.walls.size());
    }
    wall_of[i] = wall_of[root];
    FloorWall& w = out.walls[wall_of[i]];
    index_in_wall[i] = static_cast<int>(w.faces.size());
    w.faces.push_back({sm3[faces[i].room].room, patch_of(faces[i]), 1});
  }
  for (const Pair& p : pairs) {
    FloorWall& w = out.walls[wall_of[p.a]];
    w.pairs.push_back({index_in_wall[p.a], index_in_wall[p.b], p.thickness, p.overlap});
  }

  FitWallPlanes(sm3, faces, wall_of, out);
  PlaceOpenings(sm3, sm4, params, faces, wall_of, index_in_wall, where, out);
  return out;
}

std::vector<std::string> ShareDoors(const FloorModel& floor, std::vector<Sm4Model>& sm4,
                                    double tolerance) {
  std::vector<std::uint8_t> changed(sm4.size(), 0);
  auto room_of = [&](const std::string& name) {
    for (std::size_t r = 0; r < sm4.size(); ++r)
      if (sm4[r].room == name) return static_cast<int>(r);
    return -1;
  };
  for (const FloorOpening& fo : floor.openings) {
    if (fo.opening.type != OpeningType::kDoor || fo.sides.empty()) continue;
    const DetectedOpening& chosen = fo.sides[0];
    if (fo.sides.size() == 2) {
      const int r = room_of(fo.rooms[1]);
      if (r < 0) continue;
      for (DetectedOpening& o : sm4[r].openings) {
        if (o.id != fo.sides[1].id) continue;
        // The same state with the leaf measured here too, or unseen from both sides: this
        // room's reading stands.
        if (o.state == chosen.state &&
            (std::isfinite(o.opening_angle_deg) || !std::isfinite(chosen.opening_angle_deg)))
          continue;
        o.state_from = fo.rooms[0];
        o.own_state = o.state;
        o.own_opening_angle_deg = o.opening_angle_deg;
        o.own_clear_width_m = o.clear_width_m;
        o.state = chosen.state;
        o.opening_angle_deg = chosen.opening_angle_deg;
        o.clear_width_m = chosen.clear_width_m;
        changed[r] = 1;
      }
      continue;
    }
    // Seen from one room: the other face of its wall.
    const FloorWall* wall = nullptr;
    for (const FloorWall& w : floor.walls)
      if (w.id == fo.opening.host) wall = &w;
    if (wall == nullptr) continue;
    int seen_side = 0;
    for (const WallFace& f : wall->faces)
      if (f.room == fo.rooms[0] && f.patch.id == chosen.host) seen_side = f.side;
    if (seen_side == 0) continue;
    for (const WallFace& f : wall->faces) {
      if (f.side == seen_side || f.room == fo.rooms[0]) continue;
      const int r = room_of(f.room);
      if (r < 0) continue;
      const Vec3 h = Horizontal(f.patch.plane.n).normalized();
      const Vec3 u = AlongWall(h);
      const auto door_u = Interval(chosen.corners, u);
      const auto door_z = Interval(chosen.corners, Vec3::UnitZ());
      const auto face_u = Interval(f.patch.polygon, u);
      const auto face_z = Interval(f.patch.polygon, Vec3::UnitZ());
      if (door_u.first < face_u.first - tolerance || door_u.second > face_u.second + tolerance ||
          door_z.first < face_z.first - tolerance || door_z.second > face_z.second + tolerance)
        continue;
      bool taken = false;
      for (const DetectedOpening& o : sm4[r].openings)
        if (o.host == f.patch.id && Overlap(Interval(o.corners, u), door_u) > 0.0) taken = true;
      if (taken) break;
      DetectedOpening d;
      d.type = OpeningType::kDoor;
      d.host = f.patch.id;
      const Plane unit{f.patch.plane.n / f.patch.plane.n.norm(),
                       f.patch.plane.d / f.patch.plane.n.norm()};
      // Seen from this face the wall's u runs the other way: (u0, v0) is the other's (u1, v0).
      const std::array<int, 4> order{1, 0, 3, 2};
      for (int k = 0; k < 4; ++k) d.corners[k] = OntoPlane(chosen.corners[order[k]], unit);
      d.state = chosen.state;
      d.opening_angle_deg = chosen.opening_angle_deg;
      d.clear_width_m = chosen.clear_width_m;
      d.confidence = chosen.confidence;
      d.state_from = d.found_from = fo.rooms[0];
      d.id = "opening_" + std::to_string(sm4[r].openings.size() + 1);
      sm4[r].openings.push_back(d);
      changed[r] = 1;
      break;
    }
  }
  std::vector<std::string> out;
  for (std::size_t r = 0; r < sm4.size(); ++r)
    if (changed[r]) out.push_back(sm4[r].room);
  return out;
}

}  // namespace mopad::modelling
