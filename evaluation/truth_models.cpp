#include "evaluation/truth_models.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/polygon.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_voxels.h"

namespace mopad::evaluation {
namespace {

using scenes::ElementClass;

// Orients `poly` CCW seen from `n` (reverses it when its Newell vector disagrees).
void OrientTo(std::vector<Vec3>& poly, const Vec3& n) {
  if (NewellVector(poly).dot(n) < 0.0) std::reverse(poly.begin(), poly.end());
}

const scenes::Room& FindRoomOrThrow(const scenes::GroundTruth& truth, const std::string& room) {
  const scenes::Room* r = truth.FindRoom(room);
  if (!r) {
    std::string ids;
    for (const auto& x : truth.rooms) ids += (ids.empty() ? "" : ", ") + x.id;
    throw InputError("truth", "unknown room", "'" + room + "'", "one of " + ids);
  }
  return *r;
}

bool InRoom(const scenes::StructuralElement& e, const std::string& room) {
  return std::find(e.rooms.begin(), e.rooms.end(), room) != e.rooms.end();
}

// A ceiling tilted from level by more than 8 deg (a roof's underside): its normal is its own.
bool IsSloped(const scenes::StructuralElement& e) {
  const double down = -e.normal.normalized().z();
  return e.element_class == ElementClass::kCeiling && down > 0.0 && down <= 0.99;
}

// A wall's opening rectangle in its own (u, v) coordinates.
struct Rect {
  std::string id;
  double u0, u1, v0, v1;
};

// One structural surface of the room with, for walls, the wall frame and its openings.
struct TruthSurface {
  Patch patch;
  bool wall = false;
  Vec3 origin = Vec3::Zero(), u_axis = Vec3::UnitX();
  Vec3 v_axis = Vec3::UnitZ();  // up in the wall's plane (+z for a plumb wall)
  double length = 0.0, height = 0.0;
  std::vector<Rect> openings;
};

// Up in the plane of a wall with normal n and axis u: +z for a plumb wall (exactly, when n and u
// are horizontal), the in-plane up of a leaning one (an as-built truth, scenes/as_built.h).
Vec3 WallUp(const Vec3& n, const Vec3& u) {
  const Vec3 z = Vec3::UnitZ();
  if (n.z() == 0.0 && u.z() == 0.0) return z;
  return (z - z.dot(n) * n - z.dot(u) * u).normalized();
}

// A wall face that is its rectangle: no polygon, several, or four vertices each at its foot or
// its top (a face under a sloped ceiling — a gable, a trapezoid — is not).
bool Rectangular(const scenes::StructuralElement& w) {
  if (w.polygons.size() != 1) return true;
  const Vec3 up = WallUp(w.normal.normalized(), w.u_axis.normalized());
  for (const auto& p : w.polygons[0]) {
    const double v = up.dot(p - w.origin);
    if (std::abs(v) > 1e-3 && std::abs(v - w.height) > 1e-3) return false;
  }
  return w.polygons[0].size() == 4;
}

std::vector<Vec3> WallRect(const Vec3& o, const Vec3& u, double u0, double u1, double v0, double v1,
                           const Vec3& z = Vec3::UnitZ()) {
  return {o + u0 * u + v0 * z, o + u1 * u + v0 * z, o + u1 * u + v1 * z, o + u0 * u + v1 * z};
}

std::vector<TruthSurface> RoomSurfaces(const scenes::GroundTruth& truth,
                                       const std::string& room_id) {
  const scenes::Room& room = FindRoomOrThrow(truth, room_id);
  std::vector<TruthSurface> out;
  for (const auto& e : truth.elements) {
    if (!scenes::IsStructural(e.element_class) || !InRoom(e, room_id)) continue;
    switch (e.element_class) {
      case ElementClass::kWall: {
        TruthSurface s;
        s.wall = true;
        s.origin = e.origin;
        s.u_axis = e.u_axis.normalized();
        s.v_axis = WallUp(e.normal.normalized(), s.u_axis);
        s.length = e.length;
        s.height = e.height;
        s.patch.id = e.id;
        s.patch.cls = SurfaceClass::kWall;
        s.patch.normal = e.normal.normalized();
        // A face under a sloped ceiling (a gable, scenes/bim_sloped_ceilings.cpp) is its own
        // polygon; every other wall its rectangle.
        s.patch.polygon = Rectangular(e)
                              ? WallRect(s.origin, s.u_axis, 0.0, e.length, 0.0, e.height, s.v_axis)
                              : e.polygons[0];
        OrientTo(s.patch.polygon, s.patch.normal);
        for (const auto& o : truth.openings) {
          if (std::find(o.host_walls.begin(), o.host_walls.end(), e.id) == o.host_walls.end())
            continue;
          if (o.corners.empty()) continue;
          Rect r{o.id, 1e300, -1e300, 1e300, -1e300};
          for (const auto& c : o.corners) {
            const double u = s.u_axis.dot(c - s.origin), v = s.v_axis.dot(c - s.origin);
            r.u0 = std::min(r.u0, u), r.u1 = std::max(r.u1, u);
            r.v0 = std::min(r.v0, v), r.v1 = std::max(r.v1, v);
          }
          r.u0 = std::max(r.u0, 0.0), r.u1 = std::min(r.u1, e.length);
          r.v0 = std::max(r.v0, 0.0), r.v1 = std::min(r.v1, e.height);
          if (r.u1 > r.u0 && r.v1 > r.v0) s.openings.push_back(r);
        }
        out.push_back(std::move(s));
        break;
      }
      case ElementClass::kFloor:
      case ElementClass::kCeiling: {
        const bool floor = e.element_class == ElementClass::kFloor;
        // Level (+-z); an as-built slab (scenes/as_built.h) has its own fitted normal, and so
        // has a sloped ceiling (a roof over an attic, tilted more than 8 deg).
        const Vec3 level = floor ? Vec3(Vec3::UnitZ()) : Vec3(-Vec3::UnitZ());
        const double along = e.normal.normalized().dot(level);
        const Vec3 n = (truth.as_built.Enabled() && along > 0.99) || IsSloped(e)
                           ? Vec3(e.normal.normalized())
                           : level;
        std::vector<std::vector<Vec3>> polys = e.polygons;
        if (polys.empty()) {
          std::vector<Vec3> p;
          for (const auto& q : room.polygon)
            p.emplace_back(q.x(), q.y(), floor ? room.floor_z : room.ceiling_z);
          polys.push_back(p);
        }
        for (std::size_t k = 0; k < polys.size(); ++k) {
          TruthSurface s;
          s.patch.id = polys.size() == 1 ? e.id : e.id + "_" + std::to_string(k);
          s.patch.cls = floor ? SurfaceClass::kFloor : SurfaceClass::kCeiling;
          s.patch.normal = n;
          s.patch.polygon = polys[k];
          OrientTo(s.patch.polygon, n);
          out.push_back(std::move(s));
        }
        break;
      }
      case ElementClass::kColumn: {
        Vec3 centre = Vec3::Zero();
        int count = 0;
        for (const auto& p : e.polygons)
          for (const auto& v : p) centre += v, ++count;
        if (count == 0) break;
        centre /= count;
        for (std::size_t k = 0; k < e.polygons.size(); ++k) {
          TruthSurface s;
          s.patch.id = e.id + "_" + std::to_string(k);
          s.patch.cls = SurfaceClass::kColumn;
          s.patch.polygon = e.polygons[k];
          Vec3 n = NewellVector(s.patch.polygon);
          if (n.norm() < 1e-12) continue;
          Vec3 fc = Vec3::Zero();
          for (const auto& v : s.patch.polygon) fc += v;
          fc /= static_cast<double>(s.patch.polygon.size());
          if (n.dot(fc - centre) < 0.0) {
            std::reverse(s.patch.polygon.begin(), s.patch.polygon.end());
            n = -n;
          }
          s.patch.normal = n.normalized();
          out.push_back(std::move(s));
        }
        break;
      }
      default:
        break;
    }
  }
  if (out.empty())
    throw InputError("truth", "room has no structural elements", "'" + room_id + "'");
  return out;
}

}  // namespace

namespace {

bool IsFlat(const scenes::StructuralElement& e) {
  return e.element_class == ElementClass::kFloor || e.element_class == ElementClass::kCeiling;
}

// The rooms joined by open passages (connections without a door), as groups of indices into
// truth.rooms: union-find, each group's root its first room in sidecar order; groups in the
// order of their first room, members in sidecar order.
std::vector<std::vector<std::size_t>> OpenPassageGroups(const scenes::GroundTruth& truth) {
  const std::size_t n = truth.rooms.size();
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < n; ++i) index[truth.rooms[i].id] = i;
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& c : truth.connections) {
    if (!c.door.empty() || !index.count(c.room_a) || !index.count(c.room_b)) continue;
    const std::size_t a = find(index[c.room_a]), b = find(index[c.room_b]);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t g = 0; g < n; ++g) {
    if (find(g) != g) continue;
    std::vector<std::size_t> group;
    for (std::size_t i = 0; i < n; ++i)
      if (find(i) == g) group.push_back(i);
    groups.push_back(std::move(group));
  }
  return groups;
}

// The rooms of `truth` with each group merged into its first room (plan the union of the
// group's plans, floor the lowest, ceiling the highest); fills out.room_of, out.members and,
// for a group whose plans are not one simple outline (kept as separate rooms), out.notes.
std::vector<scenes::Room> MergeRoomGroups(const scenes::GroundTruth& truth,
                                          const std::vector<std::vector<std::size_t>>& groups,
                                          OpenPlanTruth& out) {
  for (const scenes::Room& r : truth.rooms) out.room_of[r.id] = r.id;
  std::vector<scenes::Room> rooms;
  for (const std::vector<std::size_t>& group : groups) {
    const std::size_t g = group[0];
    if (group.size() == 1) {
      rooms.push_back(truth.rooms[g]);
      continue;
    }
    std::vector<std::vector<Vec2>> plans;
    std::string ids;
    for (std::size_t i : group) {
      plans.push_back(truth.rooms[i].polygon);
      ids += (ids.empty() ? "" : ", ") + truth.rooms[i].id;
    }
    const auto outline = UnionOfTiledPolygons(plans);
    if (!outline) {
      out.notes.push_back("rooms " + ids +
                          " are joined by open passages but their plans do not form one simple "
                          "outline: scored as separate rooms");
      for (std::size_t i : group) rooms.push_back(truth.rooms[i]);
      continue;
    }
    scenes::Room merged = truth.rooms[g];
    merged.polygon = *outline;
    for (std::size_t i : group) {
      merged.floor_z = std::min(merged.floor_z, truth.rooms[i].floor_z);
      merged.ceiling_z = std::max(merged.ceiling_z, truth.rooms[i].ceiling_z);
      out.room_of[truth.rooms[i].id] = merged.id;
      out.members[merged.id].push_back(truth.rooms[i].id);
    }
    rooms.push_back(std::move(merged));
  }
  return rooms;
}

// `id` replaced by its merged room (unchanged when it names no sidecar room).
void MapRoom(const std::map<std::string, std::string>& room_of, std::string& id) {
  const auto it = room_of.find(id);
  if (it != room_of.end()) id = it->second;
}

// Every id mapped to its merged room, repeats dropped (first occurrence kept).
void MapRooms(const std::map<std::string, std::string>& room_of, std::vector<std::string>& ids) {
  for (auto& id : ids) MapRoom(room_of, id);
  std::vector<std::string> unique;
  for (const auto& id : ids)
    if (std::find(unique.begin(), unique.end(), id) == unique.end()) unique.push_back(id);
  ids = std::move(unique);
}

// The elements with their rooms mapped. A floor or ceiling without polygons gets its room's
// plan at its height (as RoomSurfaces does); with `join_faces`, the floors (ceilings) of one
// merged room and one height become the first one, holding all their polygons.
std::vector<scenes::StructuralElement> MapElements(const scenes::GroundTruth& truth,
                                                   const OpenPlanTruth& out, bool join_faces) {
  std::vector<scenes::StructuralElement> elements;
  for (const auto& e0 : truth.elements) {
    scenes::StructuralElement e = e0;
    const bool flat = IsFlat(e);
    if (flat && e.polygons.empty() && e.rooms.size() == 1) {
      const scenes::Room* r = truth.FindRoom(e.rooms[0]);
      if (r) {
        std::vector<Vec3> p;
        const double z = e.element_class == ElementClass::kFloor ? r->floor_z : r->ceiling_z;
        for (const auto& q : r->polygon) p.emplace_back(q.x(), q.y(), z);
        e.polygons.push_back(std::move(p));
      }
    }
    MapRooms(out.room_of, e.rooms);
    if (join_faces && flat && !IsSloped(e) && e.rooms.size() == 1 &&
        out.members.count(e.rooms[0]) && !e.polygons.empty()) {
      const double z = e.polygons[0][0].z();
      auto same = std::find_if(elements.begin(), elements.end(), [&](const auto& x) {
        return x.element_class == e.element_class && !IsSloped(x) && x.rooms == e.rooms &&
               !x.polygons.empty() && std::abs(x.polygons[0][0].z() - z) <= 1e-3;
      });
      if (same != elements.end()) {
        same->polygons.insert(same->polygons.end(), e.polygons.begin(), e.polygons.end());
        continue;
      }
    }
    elements.push_back(std::move(e));
  }
  return elements;
}

// A joined floor or ceiling of a merged room whose pieces tile one simple outline becomes that
// outline (one polygon); pieces that do not stay as they are, one patch each.
void UnitePieces(std::vector<scenes::StructuralElement>& elements, const OpenPlanTruth& out) {
  for (auto& e : elements) {
    if (!IsFlat(e) || e.polygons.size() < 2 || e.rooms.size() != 1 ||
        !out.members.count(e.rooms[0]))
      continue;
    std::vector<std::vector<Vec2>> plans;
    for (const auto& p : e.polygons) {
      std::vector<Vec2> q;
      for (const auto& v : p) q.emplace_back(v.x(), v.y());
      plans.push_back(std::move(q));
    }
    const auto outline = UnionOfTiledPolygons(plans);
    if (!outline) continue;
    const double z = e.polygons[0][0].z();
    std::vector<Vec3> p;
    for (const auto& q : *outline) p.emplace_back(q.x(), q.y(), z);
    e.polygons = {std::move(p)};
  }
}

// Where the walls a join removed went: the wall each joined, and its origin's u along it.
struct JoinedWalls {
  std::map<std::string, std::string> wall_of;  // merged-away wall id -> the wall it joined
  std::map<std::string, double> u_shift;       // m, its origin's u along that wall
};

// Walls of a merged room that continue one another across a boundary without a wall (the same
// plane, the same height band, one ending where the next begins) become one wall face, until
// no two join.
JoinedWalls JoinContinuingWalls(std::vector<scenes::StructuralElement>& elements,
                                const OpenPlanTruth& out) {
  JoinedWalls j;
  for (bool joined = true; joined;) {
    joined = false;
    for (auto& w : elements) {
      if (w.element_class != ElementClass::kWall || w.rooms.size() != 1 ||
          !out.members.count(w.rooms[0]) || w.length <= 0.0 || !Rectangular(w))
        continue;
      const Vec3 u = w.u_axis.normalized(), end = w.origin + w.length * u;
      auto next = std::find_if(elements.begin(), elements.end(), [&](const auto& x) {
        return &x != &w && x.element_class == ElementClass::kWall && Rectangular(x) &&
               x.rooms == w.rooms && x.u_axis.normalized().dot(u) > std::cos(DegToRad(0.5)) &&
               x.normal.normalized().dot(w.normal.normalized()) > std::cos(DegToRad(0.5)) &&
               (x.origin - end).norm() <= 1e-3 && std::abs(x.height - w.height) <= 1e-3;
      });
      if (next == elements.end()) continue;
      const std::string gone = next->id;
      const double shift = w.length;
      w.length += next->length;
      w.polygons = {WallRect(w.origin, u, 0.0, w.length, 0.0, w.height)};
      j.wall_of[gone] = w.id;
      j.u_shift[gone] = shift;
      for (auto& [from, to] : j.wall_of)
        if (to == gone) to = w.id, j.u_shift[from] += shift;
      elements.erase(next);
      joined = true;
      break;
    }
  }
  return j;
}

// Openings, service components, furniture, details and connections of out.truth moved to the
// merged rooms and joined walls (an opening's u shifted along its new wall); the open passages
// inside a merged room are dropped. `connections` are the sidecar's.
void MapRoomAndWallReferences(const std::vector<scenes::RoomConnection>& connections,
                              const JoinedWalls& walls, OpenPlanTruth& out) {
  for (auto& o : out.truth.openings) {
    MapRooms(out.room_of, o.rooms);
    MapRoom(out.room_of, o.swing_room);
    if (!o.host_walls.empty() && walls.wall_of.count(o.host_walls[0])) {
      const double shift = walls.u_shift.at(o.host_walls[0]);
      o.u0 += shift;
      o.u1 += shift;
    }
    for (auto& h : o.host_walls)
      if (walls.wall_of.count(h)) h = walls.wall_of.at(h);
  }
  for (auto& c : out.truth.service_components) {
    MapRoom(out.room_of, c.room);
    if (walls.wall_of.count(c.host)) c.host = walls.wall_of.at(c.host);
  }
  for (auto& f : out.truth.furniture) MapRoom(out.room_of, f.room);
  for (auto& f : out.truth.details) MapRoom(out.room_of, f.room);
  std::vector<scenes::RoomConnection> kept;
  for (auto c : connections) {
    MapRoom(out.room_of, c.room_a);
    MapRoom(out.room_of, c.room_b);
    if (c.door.empty() && c.room_a == c.room_b) continue;
    kept.push_back(std::move(c));
  }
  out.truth.connections = std::move(kept);
}

}  // namespace

OpenPlanTruth MergeOpenPlanRooms(const scenes::GroundTruth& truth, bool join_faces) {
  OpenPlanTruth out;
  out.truth = truth;
  std::vector<scenes::Room> rooms = MergeRoomGroups(truth, OpenPassageGroups(truth), out);
  if (out.members.empty()) return out;
  out.truth.rooms = std::move(rooms);
  std::vector<scenes::StructuralElement> elements = MapElements(truth, out, join_faces);
  JoinedWalls walls;
  if (join_faces) {
    UnitePieces(elements, out);
    walls = JoinContinuingWalls(elements, out);
  }
  out.truth.elements = std::move(elements);
  MapRoomAndWallReferences(truth.connections, walls, out);
  return out;
}

std::vector<Patch> TruthPatches(const scenes::GroundTruth& truth, const std::string& room) {
  std::vector<Patch> out;
  for (auto& s : RoomSurfaces(truth, room)) out.push_back(std::move(s.patch));
  return out;
}

std::vector<ColumnObject> TruthColumns(const scenes::GroundTruth& truth, const std::string& room) {
  FindRoomOrThrow(truth, room);
  std::vector<ColumnObject> out;
  for (const auto& e : truth.elements)
    if (e.element_class == ElementClass::kColumn && InRoom(e, room)) {
      std::vector<Patch> faces;
      for (auto& s : RoomSurfaces(truth, room))
        if (s.patch.cls == SurfaceClass::kColumn &&
            s.patch.id.compare(0, e.id.size() + 1, e.id + "_") == 0)
          faces.push_back(std::move(s.patch));
      if (!faces.empty()) out.push_back(MakeColumnObject(e.id, faces));
    }
  return out;
}

std::vector<Patch> TruthOpeningPatches(const scenes::GroundTruth& truth, const std::string& room) {
  std::vector<Patch> out;
  for (const auto& s : RoomSurfaces(truth, room))
    for (const auto& r : s.openings) {
      Patch p;
      p.id = r.id + "@" + s.patch.id;
      p.cls = SurfaceClass::kWall;
      p.normal = s.patch.normal;
      p.polygon = WallRect(s.origin, s.u_axis, r.u0, r.u1, r.v0, r.v1, s.v_axis);
      OrientTo(p.polygon, p.normal);
      out.push_back(std::move(p));
    }
  return out;
}

std::vector<Room> TruthFloorplan(const scenes::GroundTruth& truth) {
  std::vector<Room> out;
  for (const auto& r : truth.rooms) out.push_back(Room{r.id, r.polygon});
  return out;
}

std::array<std::int64_t, 6> CountVoxelLabels(const std::vector<std::uint8_t>& labels) {
  std::array<std::int64_t, 6> c{};
  for (auto l : labels)
    if (l < 6) ++c[l];
  return c;
}

namespace {

// Casts rays from `origin` to each target and reports, per target, whether the first hit is at
// t >= |target - origin| - tolerance (a miss counts as visible). Parallel into fixed slots.
std::vector<std::uint8_t> CastVisible(const sim::EmbreeWorld& world, const Vec3& origin,
                                      const std::vector<Vec3>& targets, double tolerance) {
  std::vector<std::uint8_t> out(targets.size(), 0);
  constexpr std::size_t kChunk = 1024;
  const std::size_t chunks = (targets.size() + kChunk - 1) / kChunk;
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    const std::size_t b = c * kChunk, e = std::min(targets.size(), b + kChunk);
    std::vector<Eigen::Vector3f> o(e - b, origin.cast<float>()), d(e - b);
    std::vector<double> dist(e - b);
    std::vector<sim::RayHit> hits(e - b);
    for (std::size_t i = b; i < e; ++i) {
      const Vec3 v = targets[i] - origin;
      dist[i - b] = v.norm();
      d[i - b] = (v / std::max(dist[i - b], 1e-12)).cast<float>();
    }
    world.IntersectMany(o, d, 0.0f, std::numeric_limits<float>::infinity(), hits);
    for (std::size_t i = b; i < e; ++i)
      out[i] = !hits[i - b].hit() || hits[i - b].t >= dist[i - b] - tolerance;
  });
  return out;
}

std::vector<Vec3> SampleTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double h) {
  const double l = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
  const int n = std::max(1, static_cast<int>(std::ceil(l / h)));
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>((n + 1) * (n + 2) / 2));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      out.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
  return out;
}

// The listed voxels on a dense index of their grid (map frame): every grid cell holds its first
// listed voxel, -1 when none is listed. Several listed entries of one cell share its state.
class VoxelIndex {
 public:
  VoxelIndex(const VoxelGrid& grid, const std::vector<std::array<int, 3>>& voxels,
             std::int64_t max_grid_voxels)
      : grid_(grid) {
    const auto& d = grid.dims;
    if (!(grid.voxel_size > 0.0) || d[0] <= 0 || d[1] <= 0 || d[2] <= 0)
      throw InputError("dsm3 grid", "empty grid or non-positive voxel size");
    const std::int64_t total = std::int64_t{d[0]} * d[1] * d[2];
    if (total > max_grid_voxels)
      throw InputError("dsm3 grid", "grid too large for the truth DSM3",
                       std::to_string(total) + " voxels", "<= " + std::to_string(max_grid_voxels));
    slot_.assign(static_cast<std::size_t>(total), -1);
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      const auto& v = voxels[i];
      for (int a = 0; a < 3; ++a)
        if (v[a] < 0 || v[a] >= d[a])
          throw InputError("dsm3 voxels", "voxel index outside the grid");
      auto& s = slot_[Linear(v)];
      if (s < 0) s = static_cast<std::int32_t>(i);
    }
  }
  /// The first listed voxel of the cell of `v`, -1 when none is listed.
  std::int32_t First(const std::array<int, 3>& v) const { return slot_[Linear(v)]; }
  /// The first listed voxel of the cell holding `p_M`, -1 outside the grid or when none is.
  std::int32_t At(const Vec3& p_M) const {
    const auto& d = grid_.dims;
    const Vec3 q = (p_M - grid_.origin) / grid_.voxel_size;
    const double fi = std::floor(q.x()), fj = std::floor(q.y()), fk = std::floor(q.z());
    if (fi < 0 || fj < 0 || fk < 0 || fi >= d[0] || fj >= d[1] || fk >= d[2]) return -1;
    return First({int(fi), int(fj), int(fk)});
  }

 private:
  std::size_t Linear(const std::array<int, 3>& v) const {
    const auto& d = grid_.dims;
    return (static_cast<std::size_t>(v[2]) * d[1] + v[1]) * d[0] + v[0];
  }
  const VoxelGrid& grid_;
  std::vector<std::int32_t> slot_;
};

// What the truth puts in each listed voxel (indexed like `voxels`; 0 or 1).
struct VoxelFlags {
  explicit VoxelFlags(std::size_t n)
      : has_struct(n, 0),
        struct_visible(n, 0),
        has_opening(n, 0),
        has_clutter(n, 0),
        inside(n, 0),
        visible(n, 0) {}
  std::vector<std::uint8_t> has_struct, struct_visible, has_opening, has_clutter;
  std::vector<std::uint8_t> inside;   // centre inside the room prism
  std::vector<std::uint8_t> visible;  // centre seen from a scanner (checked for empty only)
};

// A structural surface sample (world frame) and its voxel.
struct SurfaceSample {
  Vec3 p_W, n_W;
  std::int32_t voxel;
};

// Rules 1-2: samples the room's surfaces at spacing h, flags the voxels holding a structural or
// an opening sample, and returns the structural samples.
std::vector<SurfaceSample> SampleSurfaces(const std::vector<TruthSurface>& surfaces,
                                          const VoxelIndex& index, const Pose3& X_MW,
                                          double voxel_size, double h, VoxelFlags& flags) {
  std::vector<SurfaceSample> samples;
  for (const auto& surf : surfaces) {
    double area = 0.0;
    const std::vector<Vec3> pts = SamplePatch(surf.patch, h, &area);
    const Vec3 n_W = surf.patch.normal.normalized();
    const Vec3 nudge_M = X_MW.linear() * n_W * (1e-6 * voxel_size);
    for (const Vec3& p : pts) {
      bool in_opening = false;
      if (surf.wall) {
        const double u = surf.u_axis.dot(p - surf.origin), v = surf.v_axis.dot(p - surf.origin);
        for (const auto& r : surf.openings)
          if (u >= r.u0 && u <= r.u1 && v >= r.v0 && v <= r.v1) in_opening = true;
      }
      const std::int32_t vox = index.At(X_MW * p + nudge_M);
      if (vox < 0) continue;
      if (in_opening) {
        flags.has_opening[vox] = 1;
      } else {
        flags.has_struct[vox] = 1;
        samples.push_back({p, n_W, vox});
      }
    }
  }
  return samples;
}

// Structure against occluded structure: a structural voxel is seen when one of its samples is,
// scanner by scanner (samples of voxels already seen are skipped).
void MarkSeenStructure(const sim::EmbreeWorld& world, const std::vector<Vec3>& scanners_W,
                       const std::vector<SurfaceSample>& samples, const TruthDsm3Params& params,
                       VoxelFlags& flags) {
  const double el_lo = std::sin(DegToRad(params.elevation_min_deg));
  const double el_hi = std::sin(DegToRad(params.elevation_max_deg));
  for (const Vec3& c : scanners_W) {
    std::vector<Vec3> targets;
    std::vector<std::int32_t> owner;
    for (const auto& smp : samples) {
      if (flags.struct_visible[smp.voxel]) continue;
      const Vec3 v = smp.p_W - c;
      const double dist = v.norm();
      if (dist < params.range_min || dist > params.range_max || dist < 1e-9) continue;
      if (smp.n_W.dot(c - smp.p_W) <= 0.0) continue;
      const double sz = v.z() / dist;
      if (sz < el_lo || sz > el_hi) continue;
      targets.push_back(smp.p_W);
      owner.push_back(smp.voxel);
    }
    const auto vis = CastVisible(world, c, targets, params.hit_tolerance);
    for (std::size_t i = 0; i < vis.size(); ++i)
      if (vis[i]) flags.struct_visible[owner[i]] = 1;
  }
}

// Flags the voxels whose centre lies in the room prism (plan polygon, floor_z..ceiling_z).
void MarkInside(const scenes::Room& room, const std::vector<TruthSurface>& surfaces,
                const VoxelGrid& grid, const std::vector<std::array<int, 3>>& voxels,
                const Pose3& X_WM, VoxelFlags& flags) {
  // Sloped ceilings (normal facing down into the room), in plan: above one is outside.
  std::vector<std::pair<const Patch*, std::vector<Vec2>>> slopes;
  for (const auto& s : surfaces)
    if (s.patch.cls == SurfaceClass::kCeiling && s.patch.normal.z() > -0.99 &&
        s.patch.normal.z() < 0.0 && !s.patch.polygon.empty()) {
      std::vector<Vec2> plan;
      for (const auto& v : s.patch.polygon) plan.emplace_back(v.x(), v.y());
      slopes.emplace_back(&s.patch, std::move(plan));
    }
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const Vec3 c = X_WM * grid.Centre(voxels[i]);
    bool inside = c.z() >= room.floor_z && c.z() <= room.ceiling_z &&
                  PointInPolygon(Vec2(c.x(), c.y()), room.polygon);
    for (const auto& [patch, plan] : slopes)
      if (inside && PointInPolygon(Vec2(c.x(), c.y()), plan))
        inside = patch->normal.dot(c - patch->polygon[0]) >= 0.0;
    flags.inside[i] = inside;
  }
}

// Rule 3: flags the voxels holding a sample of non-structural scene geometry within two voxels
// of the room's box.
void MarkClutter(const sim::EmbreeWorld& world, const scenes::Room& room, const VoxelIndex& index,
                 const Pose3& X_MW, double voxel_size, double h, VoxelFlags& flags) {
  Eigen::AlignedBox3d box;
  for (const auto& q : room.polygon) {
    box.extend(Vec3(q.x(), q.y(), room.floor_z));
    box.extend(Vec3(q.x(), q.y(), room.ceiling_z));
  }
  box.min() -= Vec3::Constant(2.0 * voxel_size);
  box.max() += Vec3::Constant(2.0 * voxel_size);
  for (const auto& part : world.scene().parts) {
    if (scenes::IsStructural(part.element_class)) continue;
    for (const auto& t : part.triangles) {
      const Vec3 a = part.positions[t[0]].cast<double>(), b = part.positions[t[1]].cast<double>(),
                 c = part.positions[t[2]].cast<double>();
      Eigen::AlignedBox3d tb(a);
      tb.extend(b), tb.extend(c);
      if (!tb.intersects(box)) continue;
      for (const Vec3& p : SampleTriangle(a, b, c, h)) {
        const std::int32_t vox = index.At(X_MW * p);
        if (vox >= 0) flags.has_clutter[vox] = 1;
      }
    }
  }
}

// Rule 4: flags the inside voxels holding nothing whose centre a scanner sees.
void MarkSeenEmpty(const sim::EmbreeWorld& world, const std::vector<Vec3>& scanners_W,
                   const VoxelGrid& grid, const std::vector<std::array<int, 3>>& voxels,
                   const VoxelIndex& index, const Pose3& X_WM, const TruthDsm3Params& params,
                   VoxelFlags& flags) {
  const double el_lo = std::sin(DegToRad(params.elevation_min_deg));
  const double el_hi = std::sin(DegToRad(params.elevation_max_deg));
  for (const Vec3& c : scanners_W) {
    std::vector<Vec3> targets;
    std::vector<std::int32_t> owner;
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      if (!flags.inside[i] || flags.visible[i] || flags.has_struct[i] || flags.has_opening[i] ||
          flags.has_clutter[i])
        continue;
      if (index.First(voxels[i]) != static_cast<std::int32_t>(i)) continue;  // duplicate entry
      const Vec3 p = X_WM * grid.Centre(voxels[i]);
      const Vec3 v = p - c;
      const double dist = v.norm();
      if (dist > params.range_max) continue;
      if (dist > 1e-9) {
        const double sz = v.z() / dist;
        if (sz < el_lo || sz > el_hi) continue;
      }
      targets.push_back(p);
      owner.push_back(static_cast<std::int32_t>(i));
    }
    const auto vis = CastVisible(world, c, targets, 0.0);
    for (std::size_t i = 0; i < vis.size(); ++i)
      if (vis[i]) flags.visible[owner[i]] = 1;
  }
}

// The first rule that holds (file comment), for every listed voxel; duplicates share the first
// entry's state.
std::vector<std::uint8_t> Labels(const std::vector<std::array<int, 3>>& voxels,
                                 const VoxelIndex& index, const VoxelFlags& flags) {
  std::vector<std::uint8_t> labels(voxels.size(), static_cast<std::uint8_t>(VoxelLabel::kUnseen));
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const std::int32_t k = index.First(voxels[i]);
    VoxelLabel l = VoxelLabel::kUnseen;
    if (flags.has_struct[k])
      l = flags.struct_visible[k] ? VoxelLabel::kStructure : VoxelLabel::kOccludedStructure;
    else if (flags.has_opening[k])
      l = VoxelLabel::kOpening;
    else if (flags.inside[k] && flags.has_clutter[k])
      l = VoxelLabel::kClutter;
    else if (flags.inside[k] && flags.visible[k])
      l = VoxelLabel::kEmpty;
    labels[i] = static_cast<std::uint8_t>(l);
  }
  return labels;
}

}  // namespace

std::vector<std::uint8_t> TruthDsm3(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                                    const std::string& room_id, const VoxelGrid& grid,
                                    const std::vector<std::array<int, 3>>& voxels,
                                    const Pose3& X_WM, const std::vector<Vec3>& scanners_W,
                                    const TruthDsm3Params& params) {
  ValidateParams(params, "truth_dsm3.");
  const scenes::Room& room = FindRoomOrThrow(truth, room_id);
  const std::vector<TruthSurface> surfaces = RoomSurfaces(truth, room_id);
  const VoxelIndex index(grid, voxels, params.max_grid_voxels);
  const Pose3 X_MW = X_WM.inverse();
  const double s = grid.voxel_size;
  const double h = s / params.samples_per_voxel;
  VoxelFlags flags(voxels.size());
  const std::vector<SurfaceSample> samples = SampleSurfaces(surfaces, index, X_MW, s, h, flags);
  MarkSeenStructure(world, scanners_W, samples, params, flags);
  MarkInside(room, surfaces, grid, voxels, X_WM, flags);
  MarkClutter(world, room, index, X_MW, s, h, flags);
  MarkSeenEmpty(world, scanners_W, grid, voxels, index, X_WM, params, flags);
  return Labels(voxels, index, flags);
}

}  // namespace mopad::evaluation
