#include "scenes/scene_spec.h"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "scenes/bsc_catalogue.h"
#include "scenes/geometry.h"

namespace mopad::scenes {
namespace {

std::string Describe(const YAML::Node& n) {
  if (!n || n.IsNull()) return "null";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a sequence";
  return "a map";
}

/// Reads the keys of one YAML map, remembering which keys exist so Finish() can reject typos.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string file, std::string ctx)
      : node_(node), file_(std::move(file)), ctx_(std::move(ctx)) {
    if (!node_.IsMap())
      throw InputError(YamlWhere(file_, node_), "'" + ctx_ + "' must be a map", Describe(node_));
  }
  std::string Where() const { return YamlWhere(file_, node_); }
  std::string Where(const char* key) const { return YamlWhere(file_, node_[key]); }
  bool Has(const char* key) {
    known_.insert(key);
    return static_cast<bool>(node_[key]);
  }
  YAML::Node Node(const char* key) {
    known_.insert(key);
    return node_[key];
  }
  std::string Name(const char* key) const { return ctx_.empty() ? key : ctx_ + "." + key; }
  const std::string& Context() const { return ctx_; }

  template <class T>
  bool Scalar(const char* key, T* out, const std::string& type) {
    const YAML::Node n = Node(key);
    if (!n) return false;
    try {
      if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
      *out = n.as<T>();
    } catch (const YAML::Exception&) {
      throw InputError(YamlWhere(file_, n), "wrong type for '" + Name(key) + "'", Describe(n),
                       type);
    }
    return true;
  }
  bool Str(const char* key, std::string* out) { return Scalar(key, out, "a string"); }
  bool Num(const char* key, double* out, double lo, double hi) {
    if (!Scalar(key, out, "a number")) return false;
    if (!std::isfinite(*out) || *out < lo || *out > hi)
      throw InputError(Where(key), "'" + Name(key) + "' out of range", FormatShortest(*out),
                       "[" + FormatShortest(lo) + ", " + FormatShortest(hi) + "]");
    return true;
  }
  bool Int(const char* key, int* out, int lo, int hi) {
    if (!Scalar(key, out, "an integer")) return false;
    if (*out < lo || *out > hi)
      throw InputError(Where(key), "'" + Name(key) + "' out of range", std::to_string(*out),
                       "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return true;
  }
  std::vector<double> Numbers(const YAML::Node& n, const std::string& name, std::size_t count,
                              const std::string& expected) {
    if (!n.IsSequence() || (count > 0 && n.size() != count))
      throw InputError(YamlWhere(file_, n), "wrong type for '" + name + "'", Describe(n), expected);
    std::vector<double> v;
    for (const auto& x : n) {
      try {
        if (!x.IsScalar()) throw YAML::Exception(x.Mark(), "not a scalar");
        v.push_back(x.as<double>());
      } catch (const YAML::Exception&) {
        throw InputError(YamlWhere(file_, x), "wrong type in '" + name + "'", Describe(x),
                         "a number");
      }
      if (!std::isfinite(v.back()))
        throw InputError(YamlWhere(file_, x), "non-finite number in '" + name + "'");
    }
    return v;
  }
  bool Vec2(const char* key, Eigen::Vector2d* out) {
    const YAML::Node n = Node(key);
    if (!n) return false;
    const auto v = Numbers(n, Name(key), 2, "[x, y]");
    *out = {v[0], v[1]};
    return true;
  }
  bool Colour(const char* key, Rgb* out) {
    const YAML::Node n = Node(key);
    if (!n) return false;
    const auto v = Numbers(n, Name(key), 3, "[r, g, b] in [0, 1]");
    for (double c : v)
      if (c < 0.0 || c > 1.0)
        throw InputError(YamlWhere(file_, n), "'" + Name(key) + "' out of range", FormatShortest(c),
                         "[0, 1]");
    *out = {v[0], v[1], v[2]};
    return true;
  }
  bool StrList(const char* key, std::vector<std::string>* out) {
    const YAML::Node n = Node(key);
    if (!n) return false;
    if (!n.IsSequence())
      throw InputError(YamlWhere(file_, n), "wrong type for '" + Name(key) + "'", Describe(n),
                       "a list of strings");
    out->clear();
    for (const auto& x : n) {
      if (!x.IsScalar())
        throw InputError(YamlWhere(file_, x), "wrong type in '" + Name(key) + "'", Describe(x),
                         "a string");
      out->push_back(x.Scalar());
    }
    return true;
  }
  void Finish() const { RejectUnknownKeys(node_, known_, file_, ctx_.empty() ? "" : ctx_ + "."); }
  const std::string& file() const { return file_; }

 private:
  YAML::Node node_;
  std::string file_, ctx_;
  std::set<std::string> known_;
};

void ReadMaterial(MapReader& parent, const char* key, MaterialSpec* m) {
  const YAML::Node n = parent.Node(key);
  if (!n) return;
  MapReader r(n, parent.file(), parent.Name(key));
  r.Colour("colour", &m->colour);
  r.Num("roughness", &m->roughness, 0, 1);
  r.Num("metallic", &m->metallic, 0, 1);
  r.Num("transmission", &m->transmission, 0, 1);
  r.Num("nir_reflectance", &m->nir_reflectance, -1, 1);
  r.Finish();
}

void ReadPosition(MapReader& r, WallPosition* p) {
  p->has_at = r.Vec2("at", &p->at);
  const bool has_wall = r.Int("wall", &p->wall, 0, 1000);
  const bool has_offset = r.Num("offset", &p->offset, 0, 1000);
  if (p->has_at == has_wall)
    throw InputError(r.Where(), "'" + r.Context() + "' needs exactly one of 'at' or 'wall'");
  if (has_wall != has_offset)
    throw InputError(r.Where(), "'" + r.Context() + "': 'wall' and 'offset' go together");
}

template <class F>
void ForEachItem(const YAML::Node& root, const char* key, const std::string& file, F&& f) {
  const YAML::Node list = root[key];
  if (!list) return;
  if (!list.IsSequence())
    throw InputError(YamlWhere(file, list), std::string("'") + key + "' must be a list",
                     Describe(list));
  for (std::size_t i = 0; i < list.size(); ++i) {
    MapReader r(list[i], file, std::string(key) + "[" + std::to_string(i) + "]");
    f(r);
    r.Finish();
  }
}

void ReadMaterials(MapReader& top, MaterialsSpec* out) {
  const YAML::Node m = top.Node("materials");
  if (!m) return;
  MapReader r(m, top.file(), "materials");
  ReadMaterial(r, "wall", &out->wall);
  ReadMaterial(r, "floor", &out->floor);
  ReadMaterial(r, "ceiling", &out->ceiling);
  ReadMaterial(r, "column", &out->column);
  ReadMaterial(r, "facade", &out->facade);
  ReadMaterial(r, "door_frame", &out->door_frame);
  ReadMaterial(r, "door_leaf", &out->door_leaf);
  ReadMaterial(r, "window_frame", &out->window_frame);
  ReadMaterial(r, "glass", &out->glass);
  ReadMaterial(r, "desk", &out->desk);
  ReadMaterial(r, "cabinet", &out->cabinet);
  ReadMaterial(r, "shelf", &out->shelf);
  ReadMaterial(r, "chair", &out->chair);
  r.Finish();
}

// The top-level keys (name, seed, heights, materials); the item lists are read after.
void ReadTop(const YAML::Node& root, const std::string& file, SceneSpec* s) {
  MapReader top(root, file, "");
  top.Str("name", &s->name);
  top.Scalar("seed", &s->seed, "a non-negative integer");
  top.Num("storey_height", &s->storey_height, 2.0, 10.0);
  top.Num("ceiling_height", &s->ceiling_height, 2.0, 10.0);
  top.Num("wall_thickness", &s->wall_thickness, 0.05, 1.0);
  ReadMaterials(top, &s->materials);
  if (const YAML::Node a = top.Node("as_built"); a)
    s->as_built = LoadParams<AsBuiltParams>(a, file);
  if (const YAML::Node d = top.Node("details"); d) s->details = LoadParams<DetailsParams>(d, file);
  for (const char* k : {"rooms", "doors", "windows", "columns", "furniture", "bscs"}) top.Node(k);
  top.Finish();
}

RoomSpec ReadRoom(MapReader& r, const std::string& file) {
  RoomSpec room;
  room.where = r.Where();
  if (!r.Str("id", &room.id)) throw InputError(r.Where(), "room without 'id'");
  const YAML::Node poly = r.Node("polygon");
  if (!poly || !poly.IsSequence())
    throw InputError(poly ? YamlWhere(file, poly) : r.Where(),
                     "room '" + room.id + "' needs 'polygon': a list of [x, y]", Describe(poly));
  for (const auto& p : poly) {
    const auto v = r.Numbers(p, r.Name("polygon"), 2, "[x, y]");
    room.polygon.emplace_back(v[0], v[1]);
  }
  room.where = YamlWhere(file, poly);
  r.Num("ceiling_height", &room.ceiling_height, 0.0, 10.0);
  return room;
}

DoorSpec ReadDoor(MapReader& r) {
  DoorSpec d;
  d.where = r.Where();
  if (!r.Str("id", &d.id)) throw InputError(r.Where(), "door without 'id'");
  std::vector<std::string> between;
  if (!r.StrList("between", &between) || between.size() != 2)
    throw InputError(r.Where(), "door '" + d.id + "' needs 'between: [ROOM, ROOM|outside]'");
  d.room_a = between[0];
  d.room_b = between[1];
  ReadPosition(r, &d.position);
  r.Num("width", &d.width, 0.5, 3.0);
  r.Num("height", &d.height, 1.5, 5.0);
  r.Num("frame_width", &d.frame_width, 0.01, 0.3);
  r.Num("frame_protrusion", &d.frame_protrusion, 0.002, 0.1);
  r.Num("leaf_thickness", &d.leaf_thickness, 0.01, 0.1);
  d.has_frame_colour = r.Colour("frame_colour", &d.frame_colour);
  d.has_leaf_colour = r.Colour("leaf_colour", &d.leaf_colour);
  if (r.Str("hinge", &d.hinge) && d.hinge != "left" && d.hinge != "right")
    throw InputError(r.Where("hinge"), "invalid 'hinge'", "'" + d.hinge + "'", "left or right");
  r.Str("swing_into", &d.swing_into);
  r.Num("angle_deg", &d.angle_deg, 0.0, 110.0);
  return d;
}

WindowSpec ReadWindow(MapReader& r) {
  WindowSpec w;
  w.where = r.Where();
  if (!r.Str("id", &w.id)) throw InputError(r.Where(), "window without 'id'");
  if (!r.Str("room", &w.room)) throw InputError(r.Where(), "window '" + w.id + "' needs 'room'");
  ReadPosition(r, &w.position);
  r.Num("width", &w.width, 0.3, 6.0);
  r.Num("height", &w.height, 0.3, 3.0);
  r.Num("sill_height", &w.sill_height, 0.0, 2.5);
  r.Num("frame_width", &w.frame_width, 0.01, 0.2);
  r.Num("frame_protrusion", &w.frame_protrusion, 0.002, 0.1);
  r.Num("transmission", &w.transmission, -1.0, 1.0);
  return w;
}

ColumnSpec ReadColumn(MapReader& r) {
  ColumnSpec c;
  c.where = r.Where();
  if (!r.Str("id", &c.id)) throw InputError(r.Where(), "column without 'id'");
  if (!r.Str("room", &c.room)) throw InputError(r.Where(), "column '" + c.id + "' needs 'room'");
  if (r.Str("shape", &c.shape) && c.shape != "rect" && c.shape != "round")
    throw InputError(r.Where("shape"), "invalid 'shape'", "'" + c.shape + "'", "rect or round");
  if (!r.Vec2("position", &c.position))
    throw InputError(r.Where(), "column '" + c.id + "' needs 'position'");
  if (r.Vec2("size", &c.size) && (c.size.x() <= 0.0 || c.size.y() <= 0.0))
    throw InputError(r.Where("size"), "column size must be positive");
  r.Num("radius", &c.radius, 0.02, 2.0);
  r.Int("segments", &c.segments, 6, 64);
  r.Num("yaw_deg", &c.yaw_deg, -360.0, 360.0);
  return c;
}

FurnitureSpec ReadFurnitureItem(MapReader& r) {
  FurnitureSpec f;
  f.where = r.Where();
  if (!r.Str("room", &f.room)) throw InputError(r.Where(), "furniture entry needs 'room'");
  if (!r.Str("type", &f.type)) throw InputError(r.Where(), "furniture entry needs 'type'");
  r.Int("count", &f.count, 1, 200);
  f.has_position = r.Vec2("position", &f.position);
  r.Num("yaw_deg", &f.yaw_deg, -360.0, 360.0);
  if (f.has_position && f.count != 1)
    throw InputError(r.Where(), "furniture with 'position' must have count 1");
  return f;
}

BscSpecEntry ReadBsc(MapReader& r) {
  BscSpecEntry b;
  b.where = r.Where();
  if (!r.Str("class", &b.class_name)) throw InputError(r.Where(), "bsc entry needs 'class'");
  r.Int("count", &b.count, 1, 500);
  r.StrList("rooms", &b.rooms);
  r.Str("placement", &b.placement);
  r.Str("above", &b.above);
  r.Num("height", &b.height, -1.0, 10.0);
  r.Str("room", &b.room);
  const bool has_wall = r.Int("wall", &b.wall, 0, 1000);
  r.Num("u", &b.u, 0.0, 1000.0);
  const bool has_pos = r.Vec2("position", &b.position);
  b.is_explicit = has_wall || has_pos;
  if (b.is_explicit && (b.room.empty() || b.count != 1 || (has_wall && has_pos)))
    throw InputError(r.Where(),
                     "explicit bsc needs 'room' and either 'wall'+'u' or 'position', count 1");
  if (!b.is_explicit && !b.room.empty())
    throw InputError(r.Where("room"), "'room' is for explicit placement; use 'rooms' for rules");
  return b;
}

SceneSpec Parse(const YAML::Node& root, const std::string& file) {
  SceneSpec s;
  s.source = file;
  if (!root || root.IsNull()) throw InputError(file, "empty scene spec");
  ReadTop(root, file, &s);
  ForEachItem(root, "rooms", file, [&](MapReader& r) { s.rooms.push_back(ReadRoom(r, file)); });
  ForEachItem(root, "doors", file, [&](MapReader& r) { s.doors.push_back(ReadDoor(r)); });
  ForEachItem(root, "windows", file, [&](MapReader& r) { s.windows.push_back(ReadWindow(r)); });
  ForEachItem(root, "columns", file, [&](MapReader& r) { s.columns.push_back(ReadColumn(r)); });
  ForEachItem(root, "furniture", file,
              [&](MapReader& r) { s.furniture.push_back(ReadFurnitureItem(r)); });
  ForEachItem(root, "bscs", file, [&](MapReader& r) { s.bscs.push_back(ReadBsc(r)); });
  ValidateSceneSpec(s);
  return s;
}

// ---- validation -------------------------------------------------------------------------------

double PolygonDistance(const Polygon2& a, const Polygon2& b) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& p : a) d = std::min(d, DistanceToBoundary(p, b));
  for (const auto& p : b) d = std::min(d, DistanceToBoundary(p, a));
  return d;
}

Polygon2 ColumnFootprint(const ColumnSpec& c) {
  Polygon2 poly;
  if (c.shape == "round") {
    for (int i = 0; i < c.segments; ++i) {
      const double a = 2.0 * 3.14159265358979323846 * i / c.segments;
      poly.emplace_back(c.position.x() + c.radius * std::cos(a),
                        c.position.y() + c.radius * std::sin(a));
    }
  } else {
    const double y = c.yaw_deg * 3.14159265358979323846 / 180.0;
    const Eigen::Vector2d ex(std::cos(y), std::sin(y)), ey(-std::sin(y), std::cos(y));
    const double hx = 0.5 * c.size.x(), hy = 0.5 * c.size.y();
    for (auto [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      poly.push_back(c.position + sx * hx * ex + sy * hy * ey);
  }
  return poly;
}

}  // namespace

const RoomSpec* SceneSpec::FindRoom(const std::string& id) const {
  for (const auto& r : rooms)
    if (r.id == id) return &r;
  return nullptr;
}

namespace {

void CheckUniqueId(std::set<std::string>* ids, const std::string& where, const std::string& id) {
  if (id.empty() || id == "outside")
    throw InputError(where, "invalid id", "'" + id + "'", "a non-empty id other than 'outside'");
  if (!ids->insert(id).second) throw InputError(where, "duplicate id '" + id + "'");
}

const RoomSpec& RoomOf(const SceneSpec& s, const std::string& where, const std::string& id) {
  const RoomSpec* r = s.FindRoom(id);
  if (!r) throw InputError(where, "unknown room '" + id + "'");
  return *r;
}

double CeilingOf(const SceneSpec& s, const RoomSpec& r) {
  return r.ceiling_height > 0.0 ? r.ceiling_height : s.ceiling_height;
}

void ValidateRooms(const SceneSpec& s, std::set<std::string>* ids) {
  for (const auto& r : s.rooms) {
    CheckUniqueId(ids, r.where, r.id);
    std::string why;
    if (!IsSimplePolygon(r.polygon, &why))
      throw InputError(r.where, "room '" + r.id + "' polygon is not simple: " + why);
    if (SignedArea(r.polygon) <= 0.0)
      throw InputError(r.where, "room '" + r.id + "' polygon is clockwise", "",
                       "counter-clockwise");
    if (r.ceiling_height != 0.0 && (r.ceiling_height < 2.0 || r.ceiling_height > s.storey_height))
      throw InputError(r.where, "room '" + r.id + "' ceiling_height out of range",
                       FormatShortest(r.ceiling_height), "[2, storey_height]");
  }
}

// Rooms neither overlap nor come closer than one wall thickness.
void ValidateRoomsApart(const SceneSpec& s) {
  for (std::size_t i = 0; i < s.rooms.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const auto &a = s.rooms[i], &b = s.rooms[j];
      if (PolygonsIntersect(a.polygon, b.polygon))
        throw InputError(a.where, "room '" + a.id + "' overlaps room '" + b.id + "'");
      const double d = PolygonDistance(a.polygon, b.polygon);
      if (d < s.wall_thickness - 1e-6)
        throw InputError(
            a.where, "room '" + a.id + "' is closer to room '" + b.id + "' than the wall thickness",
            FormatShortest(d) + " m", ">= " + FormatShortest(s.wall_thickness) + " m");
    }
  }
}

void ValidateDoors(const SceneSpec& s, std::set<std::string>* ids) {
  for (const auto& d : s.doors) {
    CheckUniqueId(ids, d.where, d.id);
    const RoomSpec& a = RoomOf(s, d.where, d.room_a);
    double ch = CeilingOf(s, a);
    if (d.room_b != "outside") {
      const RoomSpec& b = RoomOf(s, d.where, d.room_b);
      if (d.room_b == d.room_a)
        throw InputError(d.where, "door '" + d.id + "' joins a room to itself");
      ch = std::min(ch, CeilingOf(s, b));
    }
    if (d.height + d.frame_width > ch - 0.01)
      throw InputError(
          d.where, "door '" + d.id + "' too high for its rooms",
          FormatShortest(d.height) + " m + frame " + FormatShortest(d.frame_width) + " m",
          "<= " + FormatShortest(ch - 0.01) + " m");
    if (!d.swing_into.empty() && d.swing_into != d.room_a &&
        (d.swing_into != d.room_b || d.room_b == "outside"))
      throw InputError(d.where, "door '" + d.id + "' swing_into must be one of its rooms",
                       "'" + d.swing_into + "'");
    if (d.position.wall >= static_cast<int>(a.polygon.size()))
      throw InputError(d.where, "door '" + d.id + "' wall index out of range",
                       std::to_string(d.position.wall), "< " + std::to_string(a.polygon.size()));
  }
}

void ValidateWindows(const SceneSpec& s, std::set<std::string>* ids) {
  for (const auto& w : s.windows) {
    CheckUniqueId(ids, w.where, w.id);
    const RoomSpec& r = RoomOf(s, w.where, w.room);
    if (w.sill_height < w.frame_width + 0.01)
      throw InputError(w.where, "window '" + w.id + "' sill too low for its frame",
                       FormatShortest(w.sill_height), ">= frame_width + 0.01");
    if (w.sill_height + w.height + w.frame_width > CeilingOf(s, r) - 0.01)
      throw InputError(w.where, "window '" + w.id + "' reaches the ceiling",
                       FormatShortest(w.sill_height + w.height) + " m",
                       "<= ceiling - frame_width - 0.01");
    if (w.position.wall >= static_cast<int>(r.polygon.size()))
      throw InputError(w.where, "window '" + w.id + "' wall index out of range",
                       std::to_string(w.position.wall), "< " + std::to_string(r.polygon.size()));
  }
}

void ValidateColumns(const SceneSpec& s, std::set<std::string>* ids) {
  for (const auto& c : s.columns) {
    CheckUniqueId(ids, c.where, c.id);
    const RoomSpec& r = RoomOf(s, c.where, c.room);
    if (!PolygonInside(ColumnFootprint(c), r.polygon))
      throw InputError(c.where, "column '" + c.id + "' is not inside room '" + c.room + "'");
  }
}

void ValidateFurniture(const SceneSpec& s) {
  for (const auto& f : s.furniture) {
    RoomOf(s, f.where, f.room);
    if (f.type != "desk" && f.type != "cabinet" && f.type != "shelf" && f.type != "chair")
      throw InputError(f.where, "unknown furniture type", "'" + f.type + "'",
                       "desk, cabinet, shelf or chair");
  }
}

void ValidateBscs(const SceneSpec& s) {
  std::set<std::string> placed_classes;
  for (const auto& b : s.bscs) {
    const BscSpec* cat = FindBsc(b.class_name);
    if (!cat) throw InputError(b.where, "unknown bsc class", "'" + b.class_name + "'");
    for (const auto& r : b.rooms) RoomOf(s, b.where, r);
    const bool ceiling_class = cat->mounting == interfaces::Mounting::kCeiling;
    static const std::set<std::string> kPlacements{
        "", "wall", "ceiling", "beside_door", "under_window", "above_door", "above"};
    if (!kPlacements.count(b.placement))
      throw InputError(b.where, "unknown placement", "'" + b.placement + "'",
                       "wall, ceiling, beside_door, under_window, above_door or above");
    if (ceiling_class != (b.placement == "ceiling" || (b.placement.empty() && ceiling_class)))
      throw InputError(b.where,
                       "placement '" + b.placement + "' does not suit class '" + b.class_name + "'",
                       "", ceiling_class ? "ceiling" : "a wall placement");
    if (b.placement == "above") {
      if (!placed_classes.count(b.above))
        throw InputError(b.where, "placement 'above' needs an earlier entry of class",
                         "'" + b.above + "'");
    } else if (!b.above.empty()) {
      throw InputError(b.where, "'above' is only for placement 'above'");
    }
    if (b.is_explicit) {
      const RoomSpec& r = RoomOf(s, b.where, b.room);
      if (ceiling_class != (b.wall < 0))
        throw InputError(b.where, ceiling_class ? "ceiling bsc needs 'position', not 'wall'"
                                                : "wall bsc needs 'wall' and 'u'");
      if (b.wall >= static_cast<int>(r.polygon.size()))
        throw InputError(b.where, "bsc wall index out of range", std::to_string(b.wall),
                         "< " + std::to_string(r.polygon.size()));
      if (ceiling_class && !PointInPolygon(b.position, r.polygon))
        throw InputError(b.where, "bsc position is outside room '" + b.room + "'");
    }
    placed_classes.insert(b.class_name);
  }
}

}  // namespace

void ValidateSceneSpec(const SceneSpec& s) {
  const std::string& src = s.source;
  if (s.name.empty()) throw InputError(src, "scene 'name' is empty");
  if (s.ceiling_height > s.storey_height)
    throw InputError(src, "ceiling_height above storey_height", FormatShortest(s.ceiling_height),
                     "<= " + FormatShortest(s.storey_height));
  if (s.rooms.empty()) throw InputError(src, "scene has no rooms", "0", ">= 1");
  std::set<std::string> ids;
  ValidateRooms(s, &ids);
  ValidateRoomsApart(s);
  ValidateDoors(s, &ids);
  ValidateWindows(s, &ids);
  ValidateColumns(s, &ids);
  ValidateFurniture(s);
  ValidateBscs(s);
}

SceneSpec LoadSceneSpec(const std::string& path) { return Parse(LoadYamlFile(path), path); }

SceneSpec ParseSceneSpec(const std::string& yaml_text, const std::string& name) {
  return Parse(LoadYamlString(yaml_text, name), name);
}

// ---- writing ----------------------------------------------------------------------------------

namespace {

void EmitNum(YAML::Emitter& e, const char* key, double v) {
  e << YAML::Key << key << YAML::Value << FormatShortest(v);
}
void EmitVec(YAML::Emitter& e, const char* key, const std::vector<double>& v) {
  e << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double x : v) e << FormatShortest(x);
  e << YAML::EndSeq;
}
// A parameter struct's fields in its Visit order: numbers as EmitNum, seeds as integers.
struct ParamsEmitter {
  YAML::Emitter& e;
  void operator()(const char* key, const double& v, Bounds = {}) { EmitNum(e, key, v); }
  void operator()(const char* key, const std::uint64_t& v, Bounds = {}) {
    e << YAML::Key << key << YAML::Value << v;
  }
};
template <class T>
void EmitParams(YAML::Emitter& e, const char* key, T params) {
  e << YAML::Key << key << YAML::Value << YAML::BeginMap;
  ParamsEmitter emit{e};
  params.Visit(emit);
  e << YAML::EndMap;
}

void EmitMaterial(YAML::Emitter& e, const char* key, const MaterialSpec& m) {
  e << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  EmitVec(e, "colour", {m.colour[0], m.colour[1], m.colour[2]});
  EmitNum(e, "roughness", m.roughness);
  EmitNum(e, "metallic", m.metallic);
  EmitNum(e, "transmission", m.transmission);
  EmitNum(e, "nir_reflectance", m.nir_reflectance);
  e << YAML::EndMap;
}
void EmitPosition(YAML::Emitter& e, const WallPosition& p) {
  if (p.has_at) {
    EmitVec(e, "at", {p.at.x(), p.at.y()});
  } else {
    e << YAML::Key << "wall" << YAML::Value << p.wall;
    EmitNum(e, "offset", p.offset);
  }
}

void EmitMaterials(YAML::Emitter& e, const MaterialsSpec& m) {
  e << YAML::Key << "materials" << YAML::Value << YAML::BeginMap;
  EmitMaterial(e, "wall", m.wall);
  EmitMaterial(e, "floor", m.floor);
  EmitMaterial(e, "ceiling", m.ceiling);
  EmitMaterial(e, "column", m.column);
  EmitMaterial(e, "facade", m.facade);
  EmitMaterial(e, "door_frame", m.door_frame);
  EmitMaterial(e, "door_leaf", m.door_leaf);
  EmitMaterial(e, "window_frame", m.window_frame);
  EmitMaterial(e, "glass", m.glass);
  EmitMaterial(e, "desk", m.desk);
  EmitMaterial(e, "cabinet", m.cabinet);
  EmitMaterial(e, "shelf", m.shelf);
  EmitMaterial(e, "chair", m.chair);
  e << YAML::EndMap;
}

void EmitRooms(YAML::Emitter& e, const SceneSpec& s) {
  e << YAML::Key << "rooms" << YAML::Value << YAML::BeginSeq;
  for (const auto& r : s.rooms) {
    e << YAML::BeginMap << YAML::Key << "id" << YAML::Value << r.id;
    e << YAML::Key << "polygon" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const auto& p : r.polygon)
      e << YAML::Flow << YAML::BeginSeq << FormatShortest(p.x()) << FormatShortest(p.y())
        << YAML::EndSeq;
    e << YAML::EndSeq;
    EmitNum(e, "ceiling_height", r.ceiling_height > 0.0 ? r.ceiling_height : s.ceiling_height);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

void EmitDoors(YAML::Emitter& e, const std::vector<DoorSpec>& doors) {
  e << YAML::Key << "doors" << YAML::Value << YAML::BeginSeq;
  for (const auto& d : doors) {
    e << YAML::BeginMap << YAML::Key << "id" << YAML::Value << d.id;
    e << YAML::Key << "between" << YAML::Value << YAML::Flow << YAML::BeginSeq << d.room_a
      << d.room_b << YAML::EndSeq;
    EmitPosition(e, d.position);
    EmitNum(e, "width", d.width);
    EmitNum(e, "height", d.height);
    EmitNum(e, "frame_width", d.frame_width);
    EmitNum(e, "frame_protrusion", d.frame_protrusion);
    EmitNum(e, "leaf_thickness", d.leaf_thickness);
    if (d.has_frame_colour)
      EmitVec(e, "frame_colour", {d.frame_colour[0], d.frame_colour[1], d.frame_colour[2]});
    if (d.has_leaf_colour)
      EmitVec(e, "leaf_colour", {d.leaf_colour[0], d.leaf_colour[1], d.leaf_colour[2]});
    e << YAML::Key << "hinge" << YAML::Value << d.hinge;
    e << YAML::Key << "swing_into" << YAML::Value
      << (d.swing_into.empty() ? d.room_a : d.swing_into);
    EmitNum(e, "angle_deg", d.angle_deg);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

void EmitWindows(YAML::Emitter& e, const std::vector<WindowSpec>& windows) {
  e << YAML::Key << "windows" << YAML::Value << YAML::BeginSeq;
  for (const auto& w : windows) {
    e << YAML::BeginMap << YAML::Key << "id" << YAML::Value << w.id;
    e << YAML::Key << "room" << YAML::Value << w.room;
    EmitPosition(e, w.position);
    EmitNum(e, "width", w.width);
    EmitNum(e, "height", w.height);
    EmitNum(e, "sill_height", w.sill_height);
    EmitNum(e, "frame_width", w.frame_width);
    EmitNum(e, "frame_protrusion", w.frame_protrusion);
    EmitNum(e, "transmission", w.transmission);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

void EmitColumns(YAML::Emitter& e, const std::vector<ColumnSpec>& columns) {
  e << YAML::Key << "columns" << YAML::Value << YAML::BeginSeq;
  for (const auto& c : columns) {
    e << YAML::BeginMap << YAML::Key << "id" << YAML::Value << c.id;
    e << YAML::Key << "room" << YAML::Value << c.room;
    e << YAML::Key << "shape" << YAML::Value << c.shape;
    EmitVec(e, "position", {c.position.x(), c.position.y()});
    EmitVec(e, "size", {c.size.x(), c.size.y()});
    EmitNum(e, "radius", c.radius);
    e << YAML::Key << "segments" << YAML::Value << c.segments;
    EmitNum(e, "yaw_deg", c.yaw_deg);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

void EmitFurniture(YAML::Emitter& e, const std::vector<FurnitureSpec>& furniture) {
  e << YAML::Key << "furniture" << YAML::Value << YAML::BeginSeq;
  for (const auto& f : furniture) {
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "room" << YAML::Value << f.room;
    e << YAML::Key << "type" << YAML::Value << f.type;
    e << YAML::Key << "count" << YAML::Value << f.count;
    if (f.has_position) {
      EmitVec(e, "position", {f.position.x(), f.position.y()});
      EmitNum(e, "yaw_deg", f.yaw_deg);
    }
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

void EmitBscs(YAML::Emitter& e, const std::vector<BscSpecEntry>& bscs) {
  e << YAML::Key << "bscs" << YAML::Value << YAML::BeginSeq;
  for (const auto& b : bscs) {
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "class" << YAML::Value << b.class_name;
    e << YAML::Key << "count" << YAML::Value << b.count;
    if (!b.rooms.empty()) {
      e << YAML::Key << "rooms" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const auto& r : b.rooms) e << r;
      e << YAML::EndSeq;
    }
    if (!b.placement.empty()) e << YAML::Key << "placement" << YAML::Value << b.placement;
    if (!b.above.empty()) e << YAML::Key << "above" << YAML::Value << b.above;
    EmitNum(e, "height", b.height);
    if (b.is_explicit) {
      e << YAML::Key << "room" << YAML::Value << b.room;
      if (b.wall >= 0) {
        e << YAML::Key << "wall" << YAML::Value << b.wall;
        EmitNum(e, "u", b.u);
      } else {
        EmitVec(e, "position", {b.position.x(), b.position.y()});
      }
    }
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
}

}  // namespace

std::string SceneSpecToYaml(const SceneSpec& s) {
  YAML::Emitter e;
  e << YAML::BeginMap;
  e << YAML::Key << "name" << YAML::Value << s.name;
  e << YAML::Key << "seed" << YAML::Value << s.seed;
  EmitNum(e, "storey_height", s.storey_height);
  EmitNum(e, "ceiling_height", s.ceiling_height);
  EmitNum(e, "wall_thickness", s.wall_thickness);
  EmitMaterials(e, s.materials);
  EmitRooms(e, s);
  EmitDoors(e, s.doors);
  EmitWindows(e, s.windows);
  EmitColumns(e, s.columns);
  EmitFurniture(e, s.furniture);
  EmitBscs(e, s.bscs);
  if (s.as_built.Enabled()) EmitParams(e, "as_built", s.as_built);
  if (s.details.Enabled()) EmitParams(e, "details", s.details);
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

}  // namespace mopad::scenes
