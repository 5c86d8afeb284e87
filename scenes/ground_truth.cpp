#include "scenes/ground_truth.h"

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/frames.h"

namespace mopad::scenes {
namespace {

using Json = nlohmann::ordered_json;

// ---- writing ---------------------------------------------------------------------------------

// `+ 0.0` turns -0.0 into 0.0 (same value, tidier file).
Json V2(const Eigen::Vector2d& v) { return Json::array({v.x() + 0.0, v.y() + 0.0}); }
Json V3(const Eigen::Vector3d& v) { return Json::array({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0}); }
Json V3List(const std::vector<Eigen::Vector3d>& vs) {
  Json a = Json::array();
  for (const auto& v : vs) a.push_back(V3(v));
  return a;
}
Json Strings(const std::vector<std::string>& s) {
  Json a = Json::array();
  for (const auto& x : s) a.push_back(x);
  return a;
}
// Furniture and details: labelled boxes.
Json BoxItems(const std::vector<FurnitureItem>& items) {
  Json a = Json::array();
  for (const auto& f : items) {
    a.push_back({{"id", f.id},
                 {"type", f.type},
                 {"room", f.room},
                 {"centre", V3(f.centre)},
                 {"yaw_deg", RadToDeg(f.yaw)},
                 {"size", V3(f.size)}});
  }
  return a;
}

Json ToJson(const GroundTruth& t) {
  Json j;
  j["format_version"] = t.format_version;
  j["scene_name"] = t.scene_name;
  j["units"] = "m";
  j["up_axis"] = "z";
  Json storeys = Json::array();
  for (const auto& s : t.storeys)
    storeys.push_back({{"id", s.id}, {"elevation", s.elevation}, {"height", s.height}});
  j["storeys"] = storeys;
  Json rooms = Json::array();
  for (const auto& r : t.rooms) {
    Json poly = Json::array();
    for (const auto& p : r.polygon) poly.push_back(V2(p));
    rooms.push_back({{"id", r.id},
                     {"storey", r.storey},
                     {"polygon", poly},
                     {"floor_z", r.floor_z},
                     {"ceiling_z", r.ceiling_z}});
  }
  j["rooms"] = rooms;
  Json elements = Json::array();
  for (const auto& e : t.elements) {
    Json polys = Json::array();
    for (const auto& p : e.polygons) polys.push_back(V3List(p));
    Json je{{"id", e.id},
            {"class", std::string(ToString(e.element_class))},
            {"rooms", Strings(e.rooms)},
            {"polygons", polys},
            {"normal", V3(e.normal)}};
    if (e.element_class == ElementClass::kWall) {
      je["origin"] = V3(e.origin);
      je["u_axis"] = V3(e.u_axis);
      je["length"] = e.length;
      je["height"] = e.height;
    }
    elements.push_back(je);
  }
  j["elements"] = elements;
  Json openings = Json::array();
  for (const auto& o : t.openings) {
    Json jo{{"id", o.id},
            {"type", o.type == OpeningType::kDoor ? "door" : "window"},
            {"host_walls", Strings(o.host_walls)},
            {"rooms", Strings(o.rooms)},
            {"rect", {{"u0", o.u0}, {"u1", o.u1}, {"v0", o.v0}, {"v1", o.v1}}},
            {"corners", V3List(o.corners)}};
    if (o.type == OpeningType::kDoor) {
      jo["hinge_side"] = o.hinge_side;
      jo["swing_room"] = o.swing_room;
      jo["opening_angle_deg"] = RadToDeg(o.opening_angle);
      jo["state"] = std::string(ToString(o.state));
      jo["hinge_point"] = V3(o.hinge_point);
      jo["hinge_axis"] = V3(o.hinge_axis);
      jo["leaf_thickness"] = o.leaf_thickness;
    } else {
      jo["sill_height"] = o.sill_height;
    }
    openings.push_back(jo);
  }
  j["openings"] = openings;
  Json bscs = Json::array();
  for (const auto& b : t.service_components) {
    bscs.push_back({{"id", b.id},
                    {"class", b.bsc_class},
                    {"host", b.host},
                    {"room", b.room},
                    {"centre", V3(b.centre)},
                    {"normal", V3(b.normal)},
                    {"size", V3(b.size)}});
  }
  j["service_components"] = bscs;
  j["furniture"] = BoxItems(t.furniture);
  if (!t.details.empty()) j["details"] = BoxItems(t.details);
  Json conns = Json::array();
  for (const auto& c : t.connections)
    conns.push_back({{"door", c.door}, {"room_a", c.room_a}, {"room_b", c.room_b}});
  j["connections"] = conns;
  if (t.as_built.Enabled()) {
    const AsBuiltParams& a = t.as_built;
    j["as_built"] = {{"flatness_mm", a.flatness_mm},
                     {"lean_sigma_deg", a.lean_sigma_deg},
                     {"wavelength", a.wavelength},
                     {"mesh_spacing", a.mesh_spacing},
                     {"seed", a.seed}};
  }
  return j;
}

// ---- reading ---------------------------------------------------------------------------------

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void Fail(const std::string& ctx, const std::string& what,
                         const std::string& got = "", const std::string& expected = "") const {
    throw InputError(path_, (ctx.empty() ? "" : ctx + ": ") + what, got, expected);
  }

  const Json& Field(const Json& obj, const std::string& ctx, const char* key) const {
    auto it = obj.find(key);
    if (it == obj.end()) Fail(ctx, std::string("missing field '") + key + "'");
    return *it;
  }
  void Known(const Json& obj, const std::string& ctx, const std::set<std::string>& keys) const {
    if (!obj.is_object()) Fail(ctx, "must be an object", TypeOf(obj));
    for (auto it = obj.begin(); it != obj.end(); ++it)
      if (!keys.count(it.key())) Fail(ctx, "unknown field '" + it.key() + "'");
  }
  std::string Str(const Json& obj, const std::string& ctx, const char* key) const {
    const Json& v = Field(obj, ctx, key);
    if (!v.is_string()) Fail(ctx + "." + key, "wrong type", TypeOf(v), "a string");
    return v.get<std::string>();
  }
  double Num(const Json& v, const std::string& ctx) const {
    if (!v.is_number()) Fail(ctx, "wrong type", TypeOf(v), "a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) Fail(ctx, "non-finite number");
    return d;
  }
  double Num(const Json& obj, const std::string& ctx, const char* key) const {
    return Num(Field(obj, ctx, key), ctx + "." + key);
  }
  const Json& Arr(const Json& obj, const std::string& ctx, const char* key) const {
    const Json& v = Field(obj, ctx, key);
    if (!v.is_array()) Fail(ctx + "." + key, "wrong type", TypeOf(v), "an array");
    return v;
  }
  Eigen::Vector2d Vec2(const Json& v, const std::string& ctx) const {
    if (!v.is_array() || v.size() != 2) Fail(ctx, "wrong type", TypeOf(v), "[x, y]");
    return {Num(v[0], ctx + "[0]"), Num(v[1], ctx + "[1]")};
  }
  Eigen::Vector3d Vec3(const Json& v, const std::string& ctx) const {
    if (!v.is_array() || v.size() != 3) Fail(ctx, "wrong type", TypeOf(v), "[x, y, z]");
    return {Num(v[0], ctx + "[0]"), Num(v[1], ctx + "[1]"), Num(v[2], ctx + "[2]")};
  }
  Eigen::Vector3d Vec3(const Json& obj, const std::string& ctx, const char* key) const {
    return Vec3(Field(obj, ctx, key), ctx + "." + key);
  }
  std::vector<Eigen::Vector3d> Vec3List(const Json& v, const std::string& ctx) const {
    if (!v.is_array()) Fail(ctx, "wrong type", TypeOf(v), "an array of [x, y, z]");
    std::vector<Eigen::Vector3d> out;
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(Vec3(v[i], ctx + "[" + std::to_string(i) + "]"));
    return out;
  }
  std::vector<std::string> StrList(const Json& obj, const std::string& ctx, const char* key) const {
    const Json& v = Arr(obj, ctx, key);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string())
        Fail(ctx + "." + key + "[" + std::to_string(i) + "]", "wrong type", TypeOf(v[i]),
             "a string");
      out.push_back(v[i].get<std::string>());
    }
    return out;
  }
  Eigen::Vector3d Unit(const Json& obj, const std::string& ctx, const char* key) const {
    const Eigen::Vector3d v = Vec3(obj, ctx, key);
    if (std::abs(v.norm() - 1.0) > 1e-6)
      Fail(ctx + "." + key, "not a unit vector", "norm " + std::to_string(v.norm()), "1");
    return v;
  }
  static std::string TypeOf(const Json& v) {
    if (v.is_null()) return "null";
    if (v.is_boolean()) return "a boolean";
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_array()) return "an array";
    return "an object";
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string At(const std::string& list, std::size_t i) {
  return list + "[" + std::to_string(i) + "]";
}

void CheckUnique(const Reader& r, std::set<std::string>* ids, const std::string& ctx,
                 const std::string& id) {
  if (id.empty()) r.Fail(ctx + ".id", "empty id");
  if (!ids->insert(id).second) r.Fail(ctx + ".id", "duplicate id '" + id + "'");
}

void ReadStoreys(const Json& j, const Reader& r, std::set<std::string>* ids, GroundTruth* t) {
  const Json& storeys = r.Arr(j, "", "storeys");
  for (std::size_t i = 0; i < storeys.size(); ++i) {
    const std::string c = At("storeys", i);
    r.Known(storeys[i], c, {"id", "elevation", "height"});
    Storey s;
    s.id = r.Str(storeys[i], c, "id");
    CheckUnique(r, ids, c, s.id);
    s.elevation = r.Num(storeys[i], c, "elevation");
    s.height = r.Num(storeys[i], c, "height");
    t->storeys.push_back(s);
  }
}

void ReadRooms(const Json& j, const Reader& r, std::set<std::string>* ids, GroundTruth* t) {
  const Json& rooms = r.Arr(j, "", "rooms");
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    const std::string c = At("rooms", i);
    r.Known(rooms[i], c, {"id", "storey", "polygon", "floor_z", "ceiling_z"});
    Room room;
    room.id = r.Str(rooms[i], c, "id");
    CheckUnique(r, ids, c, room.id);
    room.storey = r.Str(rooms[i], c, "storey");
    const Json& poly = r.Arr(rooms[i], c, "polygon");
    for (std::size_t k = 0; k < poly.size(); ++k)
      room.polygon.push_back(r.Vec2(poly[k], At(c + ".polygon", k)));
    if (room.polygon.size() < 3)
      r.Fail(c + ".polygon", "too few vertices", std::to_string(room.polygon.size()), ">= 3");
    room.floor_z = r.Num(rooms[i], c, "floor_z");
    room.ceiling_z = r.Num(rooms[i], c, "ceiling_z");
    t->rooms.push_back(room);
  }
}

void ReadElements(const Json& j, const Reader& r, std::set<std::string>* ids, GroundTruth* t) {
  const Json& elements = r.Arr(j, "", "elements");
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const std::string c = At("elements", i);
    const Json& je = elements[i];
    r.Known(je, c,
            {"id", "class", "rooms", "polygons", "normal", "origin", "u_axis", "length", "height"});
    StructuralElement e;
    e.id = r.Str(je, c, "id");
    CheckUnique(r, ids, c, e.id);
    const std::string cls = r.Str(je, c, "class");
    if (!ParseElementClass(cls, &e.element_class)) r.Fail(c + ".class", "unknown class", cls);
    e.rooms = r.StrList(je, c, "rooms");
    const Json& polys = r.Arr(je, c, "polygons");
    for (std::size_t k = 0; k < polys.size(); ++k)
      e.polygons.push_back(r.Vec3List(polys[k], At(c + ".polygons", k)));
    e.normal = r.Unit(je, c, "normal");
    if (e.element_class == ElementClass::kWall) {
      e.origin = r.Vec3(je, c, "origin");
      e.u_axis = r.Unit(je, c, "u_axis");
      e.length = r.Num(je, c, "length");
      e.height = r.Num(je, c, "height");
    }
    t->elements.push_back(e);
  }
}

Opening ReadOpening(const Json& jo, const std::string& c, const Reader& r,
                    std::set<std::string>* ids) {
  Opening o;
  o.id = r.Str(jo, c, "id");
  CheckUnique(r, ids, c, o.id);
  const std::string type = r.Str(jo, c, "type");
  if (type == "door") {
    o.type = OpeningType::kDoor;
    r.Known(jo, c,
            {"id", "type", "host_walls", "rooms", "rect", "corners", "hinge_side", "swing_room",
             "opening_angle_deg", "state", "hinge_point", "hinge_axis", "leaf_thickness"});
  } else if (type == "window") {
    o.type = OpeningType::kWindow;
    r.Known(jo, c, {"id", "type", "host_walls", "rooms", "rect", "corners", "sill_height"});
  } else {
    r.Fail(c + ".type", "unknown opening type", "'" + type + "'", "door or window");
  }
  o.host_walls = r.StrList(jo, c, "host_walls");
  if (o.host_walls.empty() || o.host_walls.size() > 2)
    r.Fail(c + ".host_walls", "wrong number of host walls", std::to_string(o.host_walls.size()),
           "1 or 2");
  o.rooms = r.StrList(jo, c, "rooms");
  const Json& rect = r.Field(jo, c, "rect");
  r.Known(rect, c + ".rect", {"u0", "u1", "v0", "v1"});
  o.u0 = r.Num(rect, c + ".rect", "u0");
  o.u1 = r.Num(rect, c + ".rect", "u1");
  o.v0 = r.Num(rect, c + ".rect", "v0");
  o.v1 = r.Num(rect, c + ".rect", "v1");
  if (!(o.u0 < o.u1 && o.v0 < o.v1)) r.Fail(c + ".rect", "empty rectangle");
  o.corners = r.Vec3List(r.Field(jo, c, "corners"), c + ".corners");
  if (o.corners.size() != 4)
    r.Fail(c + ".corners", "wrong number of corners", std::to_string(o.corners.size()), "4");
  if (o.type == OpeningType::kDoor) {
    o.hinge_side = r.Str(jo, c, "hinge_side");
    if (o.hinge_side != "left" && o.hinge_side != "right")
      r.Fail(c + ".hinge_side", "invalid value", "'" + o.hinge_side + "'", "left or right");
    o.swing_room = r.Str(jo, c, "swing_room");
    const double deg = r.Num(jo, c, "opening_angle_deg");
    if (deg < 0.0 || deg > 180.0)
      r.Fail(c + ".opening_angle_deg", "out of range", std::to_string(deg), "[0, 180]");
    o.opening_angle = DegToRad(deg);
    const std::string state = r.Str(jo, c, "state");
    o.state = DoorStateFromAngle(o.opening_angle);
    if (state != ToString(o.state))
      r.Fail(c + ".state", "state does not match opening_angle_deg " + std::to_string(deg),
             "'" + state + "'", "'" + std::string(ToString(o.state)) + "'");
    o.hinge_point = r.Vec3(jo, c, "hinge_point");
    o.hinge_axis = r.Unit(jo, c, "hinge_axis");
    o.leaf_thickness = r.Num(jo, c, "leaf_thickness");
  } else {
    o.sill_height = r.Num(jo, c, "sill_height");
  }
  return o;
}

void ReadOpenings(const Json& j, const Reader& r, std::set<std::string>* ids, GroundTruth* t) {
  const Json& openings = r.Arr(j, "", "openings");
  for (std::size_t i = 0; i < openings.size(); ++i)
    t->openings.push_back(ReadOpening(openings[i], At("openings", i), r, ids));
}

void ReadServiceComponents(const Json& j, const Reader& r, std::set<std::string>* ids,
                           GroundTruth* t) {
  const Json& bscs = r.Arr(j, "", "service_components");
  for (std::size_t i = 0; i < bscs.size(); ++i) {
    const std::string c = At("service_components", i);
    r.Known(bscs[i], c, {"id", "class", "host", "room", "centre", "normal", "size"});
    ServiceComponent b;
    b.id = r.Str(bscs[i], c, "id");
    CheckUnique(r, ids, c, b.id);
    b.bsc_class = r.Str(bscs[i], c, "class");
    b.host = r.Str(bscs[i], c, "host");
    b.room = r.Str(bscs[i], c, "room");
    b.centre = r.Vec3(bscs[i], c, "centre");
    b.normal = r.Unit(bscs[i], c, "normal");
    b.size = r.Vec3(bscs[i], c, "size");
    t->service_components.push_back(b);
  }
}

// The boxed items under `key` (furniture, details).
void ReadBoxItems(const Json& j, const Reader& r, const char* key, std::set<std::string>* ids,
                  std::vector<FurnitureItem>* out) {
  const Json& items = r.Arr(j, "", key);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string c = At(key, i);
    r.Known(items[i], c, {"id", "type", "room", "centre", "yaw_deg", "size"});
    FurnitureItem f;
    f.id = r.Str(items[i], c, "id");
    CheckUnique(r, ids, c, f.id);
    f.type = r.Str(items[i], c, "type");
    f.room = r.Str(items[i], c, "room");
    f.centre = r.Vec3(items[i], c, "centre");
    f.yaw = DegToRad(r.Num(items[i], c, "yaw_deg"));
    f.size = r.Vec3(items[i], c, "size");
    out->push_back(f);
  }
}

void ReadConnections(const Json& j, const Reader& r, GroundTruth* t) {
  const Json& conns = r.Arr(j, "", "connections");
  for (std::size_t i = 0; i < conns.size(); ++i) {
    const std::string c = At("connections", i);
    r.Known(conns[i], c, {"door", "room_a", "room_b"});
    t->connections.push_back(
        {r.Str(conns[i], c, "door"), r.Str(conns[i], c, "room_a"), r.Str(conns[i], c, "room_b")});
  }
}

// Cross references: every id mentioned must exist (and be of the right kind).
void CheckReferences(const GroundTruth& t, const Reader& r) {
  auto need_room = [&](const std::string& ctx, const std::string& id, bool allow_empty) {
    if (id.empty() && allow_empty) return;
    if (!t.FindRoom(id)) r.Fail(ctx, "dangling room id '" + id + "'");
  };
  for (std::size_t i = 0; i < t.rooms.size(); ++i) {
    const std::string& s = t.rooms[i].storey;
    bool found = s.empty();
    for (const auto& st : t.storeys) found = found || st.id == s;
    if (!found) r.Fail(At("rooms", i) + ".storey", "dangling storey id '" + s + "'");
  }
  for (std::size_t i = 0; i < t.elements.size(); ++i)
    for (const auto& rid : t.elements[i].rooms) need_room(At("elements", i) + ".rooms", rid, false);
  for (std::size_t i = 0; i < t.openings.size(); ++i) {
    const Opening& o = t.openings[i];
    const std::string c = At("openings", i);
    for (const auto& w : o.host_walls) {
      const StructuralElement* e = t.FindElement(w);
      if (!e || e->element_class != ElementClass::kWall)
        r.Fail(c + ".host_walls", "dangling wall id '" + w + "'");
    }
    for (const auto& rid : o.rooms) need_room(c + ".rooms", rid, true);
    if (o.type == OpeningType::kDoor) need_room(c + ".swing_room", o.swing_room, true);
  }
  for (std::size_t i = 0; i < t.service_components.size(); ++i) {
    const auto& b = t.service_components[i];
    if (!t.FindElement(b.host))
      r.Fail(At("service_components", i) + ".host", "dangling element id '" + b.host + "'");
    need_room(At("service_components", i) + ".room", b.room, true);
  }
  for (std::size_t i = 0; i < t.furniture.size(); ++i)
    need_room(At("furniture", i) + ".room", t.furniture[i].room, true);
  for (std::size_t i = 0; i < t.details.size(); ++i)
    need_room(At("details", i) + ".room", t.details[i].room, true);
  for (std::size_t i = 0; i < t.connections.size(); ++i) {
    const auto& cn = t.connections[i];
    const Opening* o = t.FindOpening(cn.door);
    const bool passage = cn.door.empty() && t.format_version >= kTruthFormatVersionPassages;
    if (passage && (cn.room_b.empty() || cn.room_a == cn.room_b))
      r.Fail(At("connections", i) + ".room_b", "an open passage joins two rooms",
             "'" + cn.room_b + "'", "a room other than room_a");
    if (!passage && (!o || o->type != OpeningType::kDoor))
      r.Fail(At("connections", i) + ".door", "dangling door id '" + cn.door + "'");
    need_room(At("connections", i) + ".room_a", cn.room_a, false);
    need_room(At("connections", i) + ".room_b", cn.room_b, true);
  }
}

GroundTruth FromJson(const Json& j, const Reader& r) {
  GroundTruth t;
  r.Known(j, "",
          {"format_version", "scene_name", "units", "up_axis", "storeys", "rooms", "elements",
           "openings", "service_components", "furniture", "details", "connections", "as_built"});
  const Json& ver = r.Field(j, "", "format_version");
  if (!ver.is_number_integer() ||
      (ver.get<int>() != kTruthFormatVersion && ver.get<int>() != kTruthFormatVersionPassages)) {
    r.Fail(
        "", "unsupported format_version", ver.dump(),
        std::to_string(kTruthFormatVersion) + " or " + std::to_string(kTruthFormatVersionPassages));
  }
  t.format_version = ver.get<int>();
  t.scene_name = r.Str(j, "", "scene_name");
  if (j.contains("units") && j["units"] != "m")
    r.Fail("units", "unsupported", j["units"].dump(), "\"m\"");
  if (j.contains("up_axis") && j["up_axis"] != "z")
    r.Fail("up_axis", "unsupported", j["up_axis"].dump(), "\"z\"");

  std::set<std::string> ids;
  ReadStoreys(j, r, &ids, &t);
  ReadRooms(j, r, &ids, &t);
  ReadElements(j, r, &ids, &t);
  ReadOpenings(j, r, &ids, &t);
  ReadServiceComponents(j, r, &ids, &t);
  ReadBoxItems(j, r, "furniture", &ids, &t.furniture);
  if (j.contains("details")) ReadBoxItems(j, r, "details", &ids, &t.details);
  ReadConnections(j, r, &t);
  if (j.contains("as_built")) {
    const Json& a = j["as_built"];
    r.Known(a, "as_built", {"flatness_mm", "lean_sigma_deg", "wavelength", "mesh_spacing", "seed"});
    t.as_built.flatness_mm = r.Num(a, "as_built", "flatness_mm");
    t.as_built.lean_sigma_deg = r.Num(a, "as_built", "lean_sigma_deg");
    t.as_built.wavelength = r.Num(a, "as_built", "wavelength");
    t.as_built.mesh_spacing = r.Num(a, "as_built", "mesh_spacing");
    const Json& seed = r.Field(a, "as_built", "seed");
    if (!seed.is_number_unsigned())
      r.Fail("as_built.seed", "not a non-negative integer", seed.dump());
    t.as_built.seed = seed.get<std::uint64_t>();
    try {
      ValidateParams(t.as_built, "as_built.");
    } catch (const InputError& e) {
      r.Fail("as_built", e.what());
    }
  }
  CheckReferences(t, r);
  return t;
}

}  // namespace

DoorState DoorStateFromAngle(double lambda_rad) {
  // Paper §3.3: open if 90 <= lambda, semi-open if eps <= lambda < 90, closed if lambda < eps,
  // eps = 5 deg. Compared in degrees with a tolerance for the deg->rad->deg round trip.
  const double deg = RadToDeg(lambda_rad);
  constexpr double kTol = 1e-9;
  if (deg >= 90.0 - kTol) return DoorState::kOpen;
  if (deg >= 5.0 - kTol) return DoorState::kSemiOpen;
  return DoorState::kClosed;
}

const Room* GroundTruth::FindRoom(const std::string& id) const {
  for (const auto& r : rooms)
    if (r.id == id) return &r;
  return nullptr;
}

const StructuralElement* GroundTruth::FindElement(const std::string& id) const {
  for (const auto& e : elements)
    if (e.id == id) return &e;
  return nullptr;
}

const Opening* GroundTruth::FindOpening(const std::string& id) const {
  for (const auto& o : openings)
    if (o.id == id) return &o;
  return nullptr;
}

GroundTruth ReadGroundTruth(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file", "", "an existing scene.truth.json");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // Translate the byte offset into a line number for the `path:line:` prefix.
    const std::size_t byte = std::min<std::size_t>(e.byte, text.size());
    int line = 1;
    for (std::size_t i = 0; i + 1 < byte; ++i) line += text[i] == '\n';
    throw InputError(path + ":" + std::to_string(line), "malformed JSON", e.what());
  } catch (const Json::exception& e) {  // a number beyond double (out_of_range 406)
    throw InputError(path, "malformed JSON", e.what());
  }
  Reader reader(path);
  return FromJson(j, reader);
}

void WriteGroundTruth(const GroundTruth& truth, const std::string& path) {
  WriteWholeFile(path, ToJson(truth).dump(2) + "\n");
}

}  // namespace mopad::scenes
