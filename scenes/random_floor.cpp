#include "scenes/random_floor.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <string>

#include "common/error.h"
#include "common/rng.h"
#include "scenes/generator.h"
#include "scenes/geometry.h"
#include "scenes/random_floor_internal.h"
#include "scenes/scene_check.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;

using namespace random_floor;  // NOLINT: this file's own layout vocabulary

constexpr int kMaxAttempts = 60;

Polygon2 Simplify(const Polygon2& in) {
  Polygon2 p;
  for (const auto& v : in)
    if (p.empty() || (v - p.back()).norm() > 1e-9) p.push_back(v);
  while (p.size() > 1 && (p.front() - p.back()).norm() < 1e-9) p.pop_back();
  bool changed = true;
  while (changed && p.size() > 3) {
    changed = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vector2d &a = p[(i + p.size() - 1) % p.size()], &b = p[i], &c = p[(i + 1) % p.size()];
      const double cr = (b - a).x() * (c - b).y() - (b - a).y() * (c - b).x();
      if (std::abs(cr) < 1e-9) {
        p.erase(p.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  return p;
}

/// Union of two cells sharing part of a side where one side's interval contains the other's.
/// Empty if they do not qualify or the union would be a plain rectangle.
Polygon2 MergeCells(Cell a, Cell b) {
  auto merge_x = [](const Cell& l, const Cell& r) -> Polygon2 {
    // l on the left of x = l.x1 == r.x0.
    const bool l_contains = l.y0 <= r.y0 + 1e-9 && r.y1 <= l.y1 + 1e-9;
    const bool r_contains = r.y0 <= l.y0 + 1e-9 && l.y1 <= r.y1 + 1e-9;
    if (!l_contains && !r_contains) return {};
    if (std::abs(l.y0 - r.y0) < 1e-9 && std::abs(l.y1 - r.y1) < 1e-9) return {};
    const double s = l.x1;
    return Simplify({{l.x0, l.y0},
                     {s, l.y0},
                     {s, r.y0},
                     {r.x1, r.y0},
                     {r.x1, r.y1},
                     {s, r.y1},
                     {s, l.y1},
                     {l.x0, l.y1}});
  };
  if (std::abs(a.x1 - b.x0) < 1e-9) return merge_x(a, b);
  if (std::abs(b.x1 - a.x0) < 1e-9) return merge_x(b, a);
  // Shared horizontal line: swap axes, merge, swap back (which reverses orientation).
  auto swap = [](const Cell& c) { return Cell{c.y0, c.x0, c.y1, c.x1}; };
  Polygon2 p;
  if (std::abs(a.y1 - b.y0) < 1e-9)
    p = merge_x(swap(a), swap(b));
  else if (std::abs(b.y1 - a.y0) < 1e-9)
    p = merge_x(swap(b), swap(a));
  if (p.empty()) return p;
  for (auto& v : p) v = Vector2d(v.y(), v.x());
  std::reverse(p.begin(), p.end());
  return p;
}

/// Inward offset of an orthogonal CCW polygon by d.
Polygon2 Shrink(const Polygon2& p, double d) {
  Polygon2 out;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector2d e0 = (p[i] - p[(i + n - 1) % n]).normalized();
    const Vector2d e1 = (p[(i + 1) % n] - p[i]).normalized();
    const Vector2d n0(-e0.y(), e0.x()), n1(-e1.y(), e1.x());
    out.push_back(p[i] + d * (n0 + n1));
  }
  return out;
}

/// Shared centre-line segment of two blocks (longest collinear, opposite-edge overlap).
struct Shared {
  Vector2d a, b;  // endpoints
  double length = 0.0;
};

Shared SharedSegment(const Polygon2& p, const Polygon2& q) {
  Shared best;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vector2d &a = p[i], &b = p[(i + 1) % p.size()];
    const Vector2d d = (b - a).normalized();
    for (std::size_t j = 0; j < q.size(); ++j) {
      const Vector2d &c = q[j], &e = q[(j + 1) % q.size()];
      if ((e - c).normalized().dot(d) > -0.999999) continue;
      const Vector2d nrm(-d.y(), d.x());
      if (std::abs((c - a).dot(nrm)) > 1e-9 || std::abs((e - a).dot(nrm)) > 1e-9) continue;
      const double s0 = std::max(0.0, std::min((c - a).dot(d), (e - a).dot(d)));
      const double s1 = std::min((b - a).norm(), std::max((c - a).dot(d), (e - a).dot(d)));
      if (s1 - s0 > best.length) best = {a + s0 * d, a + s1 * d, s1 - s0};
    }
  }
  return best;
}

/// Outer edges: parts of block edges on the footprint boundary [0, W] x [0, D].
std::vector<std::pair<Vector2d, Vector2d>> OuterEdges(const Polygon2& p, double W, double D) {
  std::vector<std::pair<Vector2d, Vector2d>> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vector2d &a = p[i], &b = p[(i + 1) % p.size()];
    const bool on = (std::abs(a.y()) < 1e-9 && std::abs(b.y()) < 1e-9) ||
                    (std::abs(a.y() - D) < 1e-9 && std::abs(b.y() - D) < 1e-9) ||
                    (std::abs(a.x()) < 1e-9 && std::abs(b.x()) < 1e-9) ||
                    (std::abs(a.x() - W) < 1e-9 && std::abs(b.x() - W) < 1e-9);
    if (on) out.emplace_back(a, b);
  }
  return out;
}

Layout MakeLayout(CounterRng& rng, int rooms, bool merge) {
  Layout L;
  const int cells_needed = rooms + (merge ? 1 : 0);
  std::vector<Cell> cells;
  int corridor = -1;
  if (rooms >= 3 && rng.Bernoulli(0.75)) {
    // A corridor band across the footprint with offices on one or both sides.
    const int offices = cells_needed - 1;
    const bool two_sides = offices >= 3 || rng.Bernoulli(0.5);
    const int south = two_sides ? (offices + 1) / 2 : offices;
    const int north = offices - south;
    const double ds = Round(rng.Uniform(4.5, 7.0));
    const double dn = north > 0 ? Round(rng.Uniform(4.5, 7.0)) : 0.0;
    const double c = Round(rng.Uniform(1.9, 2.5));
    const int widest = std::max(south, north);
    L.W = Round(widest * rng.Uniform(3.6, 5.2));
    L.D = ds + c + dn;
    auto strip = [&](double y0, double y1, int n) {
      const auto xs = Cuts(rng, 0.0, L.W, n, kMinCell);
      for (int i = 0; i < n; ++i) cells.push_back({xs[i], y0, xs[i + 1], y1});
    };
    strip(0.0, ds, south);
    corridor = static_cast<int>(cells.size());
    cells.push_back({0.0, ds, L.W, ds + c});
    if (north > 0) strip(ds + c, L.D, north);
  } else {
    // Guillotine subdivision: split the largest cell across its longer side.
    const double area = cells_needed * rng.Uniform(20.0, 32.0);
    const double aspect = rng.Uniform(1.0, 1.7);
    L.W = Round(std::sqrt(area * aspect));
    L.D = Round(area / L.W);
    cells.push_back({0.0, 0.0, L.W, L.D});
    while (static_cast<int>(cells.size()) < cells_needed) {
      std::size_t big = 0;
      for (std::size_t i = 1; i < cells.size(); ++i)
        if (cells[i].w() * cells[i].h() > cells[big].w() * cells[big].h()) big = i;
      const Cell c = cells[big];
      const bool vertical = c.w() >= c.h();
      const double len = vertical ? c.w() : c.h();
      if (len < 2 * kMinCell) return {};  // too small: caller retries
      const double f =
          rng.Uniform(std::max(0.35, kMinCell / len), std::min(0.65, 1.0 - kMinCell / len));
      const double cut = Round((vertical ? c.x0 : c.y0) + f * len);
      Cell a = c, b = c;
      if (vertical) {
        a.x1 = cut;
        b.x0 = cut;
      } else {
        a.y1 = cut;
        b.y0 = cut;
      }
      cells[big] = a;
      cells.push_back(b);
    }
  }
  std::vector<bool> used(cells.size(), false);
  if (merge) {
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t i = 0; i < cells.size(); ++i)
      for (std::size_t j = i + 1; j < cells.size(); ++j)
        if (static_cast<int>(i) != corridor && static_cast<int>(j) != corridor &&
            !MergeCells(cells[i], cells[j]).empty())
          pairs.emplace_back(i, j);
    if (pairs.empty()) return {};
    const auto [i, j] = pairs[rng.Below(pairs.size())];
    L.blocks.push_back({MergeCells(cells[i], cells[j]), BlockKind::kOffice});
    used[i] = used[j] = true;
  }
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (!used[i])
      L.blocks.push_back({RectPoly(cells[i]), static_cast<int>(i) == corridor ? BlockKind::kCorridor
                                                                             : BlockKind::kOffice});
  // Corridor first (it becomes R1, the start of the connectivity check), then the rest.
  std::stable_sort(L.blocks.begin(), L.blocks.end(),
                   [](const Block& a, const Block& b) { return a.hub() && !b.hub(); });
  return L;
}

// One room per block, its outline the block shrunk by half a wall: R1, R2, ... in block order.
std::vector<std::string> AddRooms(const Layout& L, SceneSpec* s) {
  const double t2 = 0.5 * kWall;
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < L.blocks.size(); ++i) {
    RoomSpec r;
    r.id = "R" + std::to_string(i + 1);
    r.polygon = Shrink(L.blocks[i].poly, t2);
    r.where = s->source;
    s->rooms.push_back(r);
    ids.push_back(r.id);
  }
  return ids;
}

// Doors: a random spanning tree of open doors from R1, extra doors in mixed states. False if
// the blocks are not connected. `doors` counts the doors made (ids D1, D2, ...).
bool AddDoors(CounterRng& rng, const Layout& L, int rooms, const std::vector<std::string>& ids,
              SceneSpec* s, int* doors) {
  struct Pair {
    int a, b;
    Shared seg;
  };
  std::vector<Pair> pairs;
  for (int i = 0; i < rooms; ++i)
    for (int j = i + 1; j < rooms; ++j) {
      const Shared sh = SharedSegment(L.blocks[i].poly, L.blocks[j].poly);
      if (sh.length >= kMinDoorOverlap) pairs.push_back({i, j, sh});
    }
  std::vector<bool> in_tree(static_cast<std::size_t>(rooms), false), pair_used(pairs.size(), false);
  in_tree[0] = true;
  auto add_door = [&](const Pair& p, bool open) {
    DoorSpec d;
    d.id = "D" + std::to_string(++*doors);
    // The room off the hub, or a random one, gets the leaf.
    int swing = L.blocks[p.a].hub()
                    ? p.b
                    : (L.blocks[p.b].hub() ? p.a : (rng.Bernoulli(0.5) ? p.a : p.b));
    d.room_a = ids[p.a];
    d.room_b = ids[p.b];
    d.swing_into = ids[swing];
    d.width =
        open ? std::array{0.9, 0.9, 1.0}[rng.Below(3)] : std::array{0.8, 0.9, 1.0}[rng.Below(3)];
    d.hinge = rng.Bernoulli(0.5) ? "left" : "right";
    if (open) {
      d.angle_deg = std::array{90.0, 90.0, 95.0, 100.0}[rng.Below(4)];
    } else {
      d.angle_deg = rng.Bernoulli(0.5) ? 0.0 : Round(rng.Uniform(10.0, 75.0), 5.0);
    }
    const double m = std::min(0.5 * p.seg.length, 1.6);
    const double pos = rng.Uniform(m, p.seg.length - m);
    d.position.has_at = true;
    d.position.at = p.seg.a + (p.seg.b - p.seg.a).normalized() * Round(pos);
    d.where = s->source;
    s->doors.push_back(d);
  };
  int added = 1;
  if (L.doors_from_hub) {
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (pairs[k].a != 0 || in_tree[pairs[k].b]) continue;
      pair_used[k] = true;
      in_tree[pairs[k].b] = true;
      add_door(pairs[k], true);
      ++added;
    }
  }
  while (added < rooms) {
    std::vector<std::size_t> frontier;
    for (std::size_t k = 0; k < pairs.size(); ++k)
      if (in_tree[pairs[k].a] != in_tree[pairs[k].b]) frontier.push_back(k);
    if (frontier.empty()) return false;  // not connected: retry
    const std::size_t k = frontier[rng.Below(frontier.size())];
    pair_used[k] = true;
    in_tree[pairs[k].a] = in_tree[pairs[k].b] = true;
    add_door(pairs[k], true);
    ++added;
  }
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (!pair_used[k] && rng.Bernoulli(L.extra_door_probability)) add_door(pairs[k], false);
  return true;
}

// Outer walls: an exit from R1 (closed), windows on offices. Returns the windows per room.
std::map<int, int> AddOuterOpenings(CounterRng& rng, const Layout& L, int rooms,
                                    const std::vector<std::string>& ids, SceneSpec* s, int* doors) {
  int windows = 0;
  std::map<int, int> windows_of;
  for (int i = 0; i < rooms; ++i) {
    const auto edges = OuterEdges(L.blocks[i].poly, L.W, L.D);
    bool exit_done = i != 0 || !rng.Bernoulli(0.7);
    for (const auto& [a, b] : edges) {
      const double len = (b - a).norm();
      const Vector2d dir = (b - a) / len;
      if (!exit_done && len >= 2.4) {
        DoorSpec d;
        d.id = "D" + std::to_string(++*doors);
        d.room_a = ids[i];
        d.room_b = "outside";
        d.swing_into = ids[i];
        d.width = 1.0;
        d.angle_deg = 0.0;
        d.position.has_at = true;
        d.position.at = a + dir * Round(0.5 * len);
        d.where = s->source;
        s->doors.push_back(d);
        exit_done = true;
        continue;
      }
      if (L.blocks[i].kind == BlockKind::kCorridor || len < 2.2) continue;
      const int n = len >= 6.0 ? 2 : 1;
      for (int k = 0; k < n; ++k) {
        WindowSpec w;
        w.id = "W" + std::to_string(++windows);
        w.room = ids[i];
        w.width = std::min(Round(rng.Uniform(1.0, 1.8)), 0.5 * len / n);
        w.height = 1.2;
        w.sill_height = 0.9;
        w.position.has_at = true;
        w.position.at = a + dir * Round((k + 0.5) * len / n);
        w.where = s->source;
        s->windows.push_back(w);
        ++windows_of[i];
      }
    }
  }
  return windows_of;
}

// Columns: a grid in a hall, sometimes one in a big office.
void AddColumns(CounterRng& rng, const Layout& L, int rooms, const std::vector<std::string>& ids,
                SceneSpec* s) {
  for (int i = 0; i < rooms; ++i) {
    if (L.blocks[i].kind != BlockKind::kHall) continue;
    const bool round = rng.Bernoulli(0.5);
    for (const Vector2d& at : HallColumnGrid(s->rooms[i].polygon)) {
      ColumnSpec c;
      c.id = "C" + std::to_string(s->columns.size() + 1);
      c.room = ids[i];
      c.shape = round ? "round" : "rect";
      c.radius = 0.25;
      c.size = {0.45, 0.45};
      c.position = at;
      c.where = s->source;
      s->columns.push_back(c);
    }
  }
  for (int i = 0; i < rooms; ++i) {
    const double area = SignedArea(s->rooms[i].polygon);
    if (L.blocks[i].hub() || area < 30.0 || !rng.Bernoulli(0.3)) continue;
    Eigen::AlignedBox2d box;
    for (const auto& p : s->rooms[i].polygon) box.extend(p);
    ColumnSpec c;
    c.id = "C" + std::to_string(s->columns.size() + 1);
    c.room = ids[i];
    c.shape = rng.Bernoulli(0.5) ? "round" : "rect";
    c.position = box.center();
    if (!PointInPolygon(c.position, s->rooms[i].polygon) ||
        DistanceToBoundary(c.position, s->rooms[i].polygon) < 1.5)
      continue;
    c.where = s->source;
    s->columns.push_back(c);
  }
}

// Service components: counts from the rooms, doors and windows.
void AddServiceComponents(CounterRng& rng, const Layout& L, int rooms,
                          const std::vector<std::string>& ids, int doors,
                          const std::map<int, int>& windows_of, SceneSpec* s) {
  auto bsc = [&](const std::string& cls, int count, const std::vector<std::string>& in,
                 const std::string& placement = "", const std::string& above = "") {
    if (count <= 0) return;
    BscSpecEntry e;
    e.class_name = cls;
    e.count = count;
    e.rooms = in;
    e.placement = placement;
    e.above = above;
    e.where = s->source;
    s->bscs.push_back(e);
  };
  std::vector<std::string> offices;
  for (int i = 0; i < rooms; ++i)
    if (!L.blocks[i].hub()) offices.push_back(ids[i]);
  if (offices.empty()) offices = ids;
  bsc("electrical_panel", 1, {ids[0]});
  bsc("socket_x1", 2 * static_cast<int>(offices.size()), offices);
  bsc("socket_x2", static_cast<int>(rng.Below(offices.size() + 1)), offices);
  bsc("socket_x4", static_cast<int>(rng.Below(offices.size() + 1)), offices);
  bsc("built_in_socket", static_cast<int>(rng.Below(3)), offices);
  bsc("switch", std::max(1, doors - 1), {}, "beside_door");
  bsc("fire_extinguisher", 1 + rooms / 4, {ids[0]});
  bsc("extinguisher_sign", 1 + rooms / 4, {ids[0]}, "above", "fire_extinguisher");
  bsc("fire_alarm_switch", 1, {ids[0]});
  bsc("fire_alarm_switch_sign", 1, {ids[0]}, "above", "fire_alarm_switch");
  int radiators = 0;
  for (const auto& [room, n] : windows_of) radiators += std::min(n, 1);
  bsc("radiator", radiators, {}, "under_window");
  bsc("smoke_detector", rooms, {});
  // A hall needs a detector per ~40 m2 of ceiling (fire codes space them 5-7 m apart).
  for (int i = 0; i < rooms; ++i)
    if (L.blocks[i].kind == BlockKind::kHall)
      bsc("smoke_detector", static_cast<int>(SignedArea(s->rooms[i].polygon) / 40.0), {ids[i]});
  bsc("exit_light", 1, {ids[0]}, "above_door");
}

// Furniture of every office: desks and chairs by floor area, maybe a cabinet and a shelf.
void AddFurniture(CounterRng& rng, const Layout& L, int rooms, const std::vector<std::string>& ids,
                  SceneSpec* s) {
  for (int i = 0; i < rooms; ++i) {
    if (L.blocks[i].hub()) continue;
    const double area = SignedArea(s->rooms[i].polygon);
    const int desks = std::clamp(static_cast<int>(area / 14.0), 1, 4);
    auto furn = [&](const std::string& type, int count) {
      if (count <= 0) return;
      FurnitureSpec f;
      f.room = ids[i];
      f.type = type;
      f.count = count;
      f.where = s->source;
      s->furniture.push_back(f);
    };
    furn("desk", desks);
    furn("chair", desks);
    furn("cabinet", static_cast<int>(rng.Below(2)));
    furn("shelf", static_cast<int>(rng.Below(2)));
  }
}

Layout FamilyLayout(CounterRng& rng, FloorFamily family, int rooms, int attempt) {
  switch (family) {
    case FloorFamily::kCorridor:
      return CorridorLayout(rng, rooms);
    case FloorFamily::kJunction:
      return JunctionLayout(rng, rooms);
    case FloorFamily::kHall:
      return HallLayout(rng, rooms);
    case FloorFamily::kOffice:
    case FloorFamily::kMixed:
      break;
  }
  const bool merge = rooms >= 2 && attempt < kMaxAttempts / 2 && rng.Bernoulli(0.6);
  return MakeLayout(rng, rooms, merge);
}

SceneSpec BuildSpec(std::uint64_t seed, int rooms, FloorFamily family, int attempt) {
  const bool office = family == FloorFamily::kOffice;
  const std::string stream = office ? "" : "/" + FloorFamilyName(family);
  CounterRng rng(seed, "random_floor/layout" + stream,
                 static_cast<std::uint64_t>(rooms * 1000 + attempt));
  Layout L = FamilyLayout(rng, family, rooms, attempt);
  if (static_cast<int>(L.blocks.size()) != rooms) return {};

  SceneSpec s;
  const std::string tag = "s" + std::to_string(seed) + "_r" + std::to_string(rooms);
  s.name = office ? "random_" + tag : "random_" + FloorFamilyName(family) + "_" + tag;
  s.seed = seed;
  s.source = "random_floor(seed=" + std::to_string(seed) + ", rooms=" + std::to_string(rooms) +
             (office ? "" : ", family=" + FloorFamilyName(family)) + ")";
  s.wall_thickness = kWall;
  s.storey_height = 3.0;
  s.ceiling_height = Round(rng.Uniform(2.6, 2.9));
  const std::vector<std::string> ids = AddRooms(L, &s);
  if (L.hub_ceiling > 0.0) {
    s.rooms[0].ceiling_height = L.hub_ceiling;
    s.storey_height = std::max(s.storey_height, Round(L.hub_ceiling + 0.4));
  }
  int doors = 0;
  if (!AddDoors(rng, L, rooms, ids, &s, &doors)) return {};
  const std::map<int, int> windows_of = AddOuterOpenings(rng, L, rooms, ids, &s, &doors);
  AddColumns(rng, L, rooms, ids, &s);
  AddServiceComponents(rng, L, rooms, ids, doors, windows_of, &s);
  AddFurniture(rng, L, rooms, ids, &s);
  return s;
}

}  // namespace

std::string FloorFamilyName(FloorFamily family) {
  switch (family) {
    case FloorFamily::kOffice:
      return "office";
    case FloorFamily::kCorridor:
      return "corridor";
    case FloorFamily::kJunction:
      return "junction";
    case FloorFamily::kHall:
      return "hall";
    case FloorFamily::kMixed:
      return "mixed";
  }
  return "office";
}

FloorFamily ParseFloorFamily(const std::string& name) {
  for (FloorFamily f : {FloorFamily::kOffice, FloorFamily::kCorridor, FloorFamily::kJunction,
                        FloorFamily::kHall, FloorFamily::kMixed})
    if (FloorFamilyName(f) == name) return f;
  throw InputError("", "unknown floor family", "'" + name + "'",
                   "office, corridor, junction, hall or mixed");
}

FloorFamily ResolveFloorFamily(std::uint64_t seed, int rooms, FloorFamily family) {
  if (family != FloorFamily::kMixed) return family;
  // Offices 40 %, each new family 20 %: the established floors stay the most common.
  CounterRng rng(seed, "random_floor/family", static_cast<std::uint64_t>(rooms));
  const double u = rng.Uniform(0.0, 1.0);
  if (u < 0.4) return FloorFamily::kOffice;
  if (u < 0.6) return FloorFamily::kCorridor;
  if (u < 0.8) return FloorFamily::kJunction;
  return FloorFamily::kHall;
}

int MaxRandomRooms(FloorFamily family) {
  return family == FloorFamily::kOffice ? kMaxRandomOfficeRooms : kMaxRandomRooms;
}

SceneSpec RandomFloorSpec(std::uint64_t seed, int rooms, FloorFamily family) {
  const int most = MaxRandomRooms(family);
  if (rooms < kMinRandomRooms || rooms > most)
    throw InputError("", "rooms out of range", std::to_string(rooms),
                     "[" + std::to_string(kMinRandomRooms) + ", " + std::to_string(most) + "]" +
                         (family == FloorFamily::kOffice
                              ? ""
                              : " for the " + FloorFamilyName(family) + " family"));
  family = ResolveFloorFamily(seed, rooms, family);
  // Draw layouts until one realises cleanly: each attempt is a pure function of
  // (seed, rooms, family, attempt), so the result is deterministic.
  std::string last_error;
  for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
    SceneSpec spec = BuildSpec(seed, rooms, family, attempt);
    if (static_cast<int>(spec.rooms.size()) != rooms) continue;
    try {
      ValidateSceneSpec(spec);
      const GeneratedScene g = Generate(spec);
      const CheckReport check = CheckScene(g.scene, g.truth);
      if (check.ok() && check.unreachable_rooms == 0) return spec;
      last_error = "check failed";
    } catch (const InputError& e) {
      last_error = e.what();
    }
  }
  throw std::runtime_error("RandomFloorSpec: no valid layout for seed " + std::to_string(seed) +
                           ", rooms " + std::to_string(rooms) + ", family " +
                           FloorFamilyName(family) + " (last: " + last_error + ")");
}

}  // namespace mopad::scenes
