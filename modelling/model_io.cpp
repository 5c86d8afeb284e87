#include "modelling/model_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/error.h"
#include "common/polygon.h"
#include "io/glb_writer.h"
#include "io/scan_io.h"
#include "io/text_file.h"

namespace mopad::modelling {
namespace {

using Json = nlohmann::ordered_json;

// Rounded to 0.1 mm / 1e-6 so that files are stable and readable.
double R(double v, double q = 1e-4) { return std::round(v / q) * q; }
Json V3(const Vec3& v) { return Json::array({R(v.x()), R(v.y()), R(v.z())}); }
Json N3(const Vec3& v) { return Json::array({R(v.x(), 1e-9), R(v.y(), 1e-9), R(v.z(), 1e-9)}); }

Json PatchJson(const StructuralPatch& p) {
  Json jp;
  jp["id"] = p.id;
  jp["class"] = ToString(p.patch_class);
  jp["plane"] = {{"n", N3(p.plane.n)}, {"d", R(p.plane.d, 1e-6)}};
  Json poly = Json::array();
  for (const auto& v : p.polygon) poly.push_back(V3(v));
  jp["polygon"] = std::move(poly);
  jp["support"] = p.support;
  jp["rms"] = R(p.rms, 1e-6);
  jp["fitted"] = p.fitted;
  return jp;
}

Json OpeningJson(const DetectedOpening& o) {
  Json jo;
  jo["id"] = o.id;
  jo["type"] = ToString(o.type);
  jo["host"] = o.host;
  Json cs = Json::array();
  for (const auto& c : o.corners) cs.push_back(V3(c));
  jo["corners"] = std::move(cs);
  if (o.type == OpeningType::kDoor) {
    jo["state"] = ToString(o.state);
    jo["opening_angle_deg"] =
        std::isfinite(o.opening_angle_deg) ? Json(R(o.opening_angle_deg, 0.01)) : Json(nullptr);
    jo["clear_width_m"] = R(o.clear_width_m);
    if (!o.hole_from.empty()) jo["hole_from"] = o.hole_from;
    if (!o.found_from.empty()) {
      jo["found_from"] = o.found_from;
    } else if (!o.state_from.empty()) {
      jo["state_from"] = o.state_from;
      Json own;
      own["state"] = ToString(o.own_state);
      own["opening_angle_deg"] = std::isfinite(o.own_opening_angle_deg)
                                     ? Json(R(o.own_opening_angle_deg, 0.01))
                                     : Json(nullptr);
      own["clear_width_m"] = R(o.own_clear_width_m);
      jo["own"] = std::move(own);
    }
  }
  jo["confidence"] = R(o.confidence, 1e-4);
  return jo;
}

}  // namespace

std::string Sm2Json(const Roi& roi, const std::string& room) {
  Json j;
  j["format"] = "mopad-sm2";
  j["version"] = kModelFormatVersion;
  j["room"] = room;
  j["floor_z"] = R(roi.floor_z);
  j["ceiling_z"] = R(roi.ceiling_z);
  Json vs = Json::array();
  for (const auto& v : roi.vertices) vs.push_back(V3(v));
  j["vertices"] = std::move(vs);
  Json es = Json::array();
  for (const auto& e : roi.edges)
    es.push_back({{"v", {e.v0, e.v1}}, {"faces", {e.face0, e.face1}}});
  j["edges"] = std::move(es);
  Json fs = Json::array();
  for (const auto& f : roi.faces) {
    Json jf;
    jf["kind"] = ToString(f.kind);
    jf["loop"] = f.loop;
    jf["holes"] = f.holes;
    jf["normal"] = N3(f.normal);
    jf["area"] = R(f.area);
    jf["structural"] = f.structural;
    jf["sensed_share"] = R(f.sensed_share, 1e-6);
    fs.push_back(std::move(jf));
  }
  j["faces"] = std::move(fs);
  j["face_adjacency"] = roi.face_adjacency;
  return j.dump(1);
}

std::string Sm3Json(const StructuralModel& m) {
  Json j;
  j["format"] = "mopad-sm3";
  j["version"] = kModelFormatVersion;
  j["room"] = m.room;
  j["floor_z"] = R(m.floor_z);
  j["ceiling_z"] = R(m.ceiling_z);
  Json ps = Json::array();
  for (const auto& p : m.patches) ps.push_back(PatchJson(p));
  j["patches"] = std::move(ps);
  Json adj = Json::array();
  for (const auto& [a, b] : m.adjacency) adj.push_back({a, b});
  j["adjacency"] = std::move(adj);
  return j.dump(1);
}

std::string Sm4Json(const Sm4Model& m) {
  Json j;
  j["format"] = "mopad-sm4";
  j["version"] = kModelFormatVersion;
  j["room"] = m.room;
  Json os = Json::array();
  for (const auto& o : m.openings) os.push_back(OpeningJson(o));
  j["openings"] = std::move(os);
  return j.dump(1);
}

namespace {

const Json& Field(const Json& j, const char* key, const std::string& where,
                  const std::string& ctx) {
  if (!j.is_object() || !j.contains(key)) throw InputError(where, ctx + key + ": missing field");
  return j.at(key);
}

std::string StringField(const Json& j, const char* key, const std::string& where,
                        const std::string& ctx) {
  const Json& v = Field(j, key, where, ctx);
  if (!v.is_string()) throw InputError(where, ctx + key + ": wrong type", v.dump(), "a string");
  return v.get<std::string>();
}

double NumberField(const Json& j, const char* key, const std::string& where,
                   const std::string& ctx) {
  const Json& v = Field(j, key, where, ctx);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(where, ctx + key + ": wrong type", v.dump(), "a finite number");
  return v.get<double>();
}

Json ParseJsonText(const std::string& text, const std::string& where) {
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, "not valid JSON", e.what());
  }
}

void CheckFormat(const Json& j, const char* format, const std::string& where) {
  if (StringField(j, "format", where, "") != format)
    throw InputError(where, "format: wrong file kind", j["format"].dump(),
                     std::string("\"") + format + "\"");
  const double version = NumberField(j, "version", where, "");
  if (version != kModelFormatVersion)
    throw InputError(where, "version: unsupported", j["version"].dump(),
                     std::to_string(kModelFormatVersion));
}

Vec3 PointField(const Json& p, const std::string& where, const std::string& ctx) {
  if (!p.is_array() || p.size() != 3)
    throw InputError(where, ctx + ": wrong shape", p.dump(), "[x, y, z]");
  Vec3 v;
  for (int a = 0; a < 3; ++a) {
    if (!p[a].is_number() || !std::isfinite(p[a].get<double>()))
      throw InputError(where, ctx + ": not a finite number", p[a].dump());
    v[a] = p[a].get<double>();
  }
  return v;
}

PatchClass ParsePatchClass(const std::string& c, const std::string& where, const std::string& ctx) {
  for (PatchClass k :
       {PatchClass::kWall, PatchClass::kFloor, PatchClass::kCeiling, PatchClass::kColumn})
    if (c == ToString(k)) return k;
  throw InputError(where, ctx + "class: unknown", c, "wall|floor|ceiling|column");
}

StructuralPatch ParsePatch(const Json& jp, const std::string& where, const std::string& ctx) {
  StructuralPatch p;
  p.id = StringField(jp, "id", where, ctx);
  p.patch_class = ParsePatchClass(StringField(jp, "class", where, ctx), where, ctx);
  const Json& plane = Field(jp, "plane", where, ctx);
  p.plane.n = PointField(Field(plane, "n", where, ctx + "plane."), where, ctx + "plane.n");
  p.plane.d = NumberField(plane, "d", where, ctx + "plane.");
  const Json& poly = Field(jp, "polygon", where, ctx);
  if (!poly.is_array() || poly.size() < 3)
    throw InputError(where, ctx + "polygon: wrong shape", poly.dump(), "3 or more [x, y, z]");
  for (std::size_t k = 0; k < poly.size(); ++k)
    p.polygon.push_back(PointField(poly[k], where, ctx + "polygon"));
  p.support = static_cast<int>(NumberField(jp, "support", where, ctx));
  p.rms = NumberField(jp, "rms", where, ctx);
  const Json& fitted = Field(jp, "fitted", where, ctx);
  if (!fitted.is_boolean())
    throw InputError(where, ctx + "fitted: wrong type", fitted.dump(), "true or false");
  p.fitted = fitted.get<bool>();
  return p;
}

DetectedOpening ParseOpening(const Json& jo, const std::string& where, const std::string& ctx) {
  DetectedOpening o;
  o.id = StringField(jo, "id", where, ctx);
  const std::string type = StringField(jo, "type", where, ctx);
  if (type == "door")
    o.type = OpeningType::kDoor;
  else if (type == "window")
    o.type = OpeningType::kWindow;
  else
    throw InputError(where, ctx + "type: unknown", type, "door|window");
  o.host = StringField(jo, "host", where, ctx);
  const Json& cs = Field(jo, "corners", where, ctx);
  if (!cs.is_array() || cs.size() != 4)
    throw InputError(where, ctx + "corners: wrong shape", cs.dump(), "4 points [x, y, z]");
  for (std::size_t k = 0; k < 4; ++k) {
    if (!cs[k].is_array() || cs[k].size() != 3)
      throw InputError(where, ctx + "corners: wrong shape", cs[k].dump(), "[x, y, z]");
    for (int a = 0; a < 3; ++a) {
      if (!cs[k][a].is_number() || !std::isfinite(cs[k][a].get<double>()))
        throw InputError(where, ctx + "corners: not a finite number", cs[k][a].dump());
      o.corners[k][a] = cs[k][a].get<double>();
    }
  }
  o.confidence = NumberField(jo, "confidence", where, ctx);
  if (o.type == OpeningType::kDoor) {
    // A door's reading: state, opening_angle_deg (null: unknown), clear_width_m.
    auto reading = [&](const Json& j, const std::string& c, DoorState& state, double& angle,
                       double& clear) {
      const std::string st = StringField(j, "state", where, c);
      const std::optional<DoorState> parsed = DoorStateFromString(st);
      if (!parsed) throw InputError(where, c + "state: unknown", st, "closed|semi_open|open");
      state = *parsed;
      const Json& a = Field(j, "opening_angle_deg", where, c);
      if (!a.is_null()) angle = NumberField(j, "opening_angle_deg", where, c);
      clear = NumberField(j, "clear_width_m", where, c);
    };
    reading(jo, ctx, o.state, o.opening_angle_deg, o.clear_width_m);
    if (jo.contains("hole_from")) o.hole_from = StringField(jo, "hole_from", where, ctx);
    if (jo.contains("found_from")) {
      o.found_from = StringField(jo, "found_from", where, ctx);
      o.state_from = o.found_from;
    } else if (jo.contains("state_from")) {
      o.state_from = StringField(jo, "state_from", where, ctx);
      const Json& own = Field(jo, "own", where, ctx);
      if (!own.is_object())
        throw InputError(where, ctx + "own: wrong type", own.dump(), "an object");
      reading(own, ctx + "own.", o.own_state, o.own_opening_angle_deg, o.own_clear_width_m);
    }
  }
  return o;
}

}  // namespace

StructuralModel ParseSm3(const std::string& text, const std::string& where) {
  const Json j = ParseJsonText(text, where);
  CheckFormat(j, "mopad-sm3", where);
  StructuralModel m;
  m.room = StringField(j, "room", where, "");
  m.floor_z = NumberField(j, "floor_z", where, "");
  m.ceiling_z = NumberField(j, "ceiling_z", where, "");
  const Json& ps = Field(j, "patches", where, "");
  if (!ps.is_array()) throw InputError(where, "patches: wrong type", "", "an array");
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string ctx = "patches[" + std::to_string(i) + "].";
    m.patches.push_back(ParsePatch(ps[i], where, ctx));
  }
  const Json& adj = Field(j, "adjacency", where, "");
  if (!adj.is_array()) throw InputError(where, "adjacency: wrong type", "", "an array");
  const int n = static_cast<int>(m.patches.size());
  for (const Json& pair : adj) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number_integer() ||
        !pair[1].is_number_integer() || pair[0].get<int>() < 0 || pair[0].get<int>() >= n ||
        pair[1].get<int>() < 0 || pair[1].get<int>() >= n)
      throw InputError(where, "adjacency: not a pair of patch indices", pair.dump(),
                       "[i, j] in [0, " + std::to_string(n) + ")");
    m.adjacency.emplace_back(pair[0].get<int>(), pair[1].get<int>());
  }
  return m;
}

StructuralModel ReadSm3(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return ParseSm3(text, path);
}

Sm4Model ParseSm4(const std::string& text, const std::string& where) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, "not valid JSON", e.what());
  }
  if (StringField(j, "format", where, "") != "mopad-sm4")
    throw InputError(where, "format: not an SM4 file", j["format"].dump(), "\"mopad-sm4\"");
  const double version = NumberField(j, "version", where, "");
  if (version != kModelFormatVersion)
    throw InputError(where, "version: unsupported", j["version"].dump(),
                     std::to_string(kModelFormatVersion));
  Sm4Model m;
  m.room = StringField(j, "room", where, "");
  const Json& os = Field(j, "openings", where, "");
  if (!os.is_array()) throw InputError(where, "openings: wrong type", "", "an array");
  for (std::size_t i = 0; i < os.size(); ++i) {
    const std::string ctx = "openings[" + std::to_string(i) + "].";
    m.openings.push_back(ParseOpening(os[i], where, ctx));
  }
  return m;
}

Sm4Model ReadSm4(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return ParseSm4(text, path);
}

namespace {

// The floor file's id of a room's floor, ceiling or column patch: column faces renumbered
// across the floor (`column_<N + offset>_face_<K>`, so a column keeps its faces' common prefix),
// anything else `<id>_<room number>` ("floor_2").
std::string FloorPatchId(const std::string& id, int room_number, int column_offset,
                         int* column_number) {
  const std::string prefix = "column_";
  const std::size_t face = id.find("_face_");
  if (id.rfind(prefix, 0) == 0 && face != std::string::npos && face > prefix.size()) {
    const std::string n = id.substr(prefix.size(), face - prefix.size());
    if (n.find_first_not_of("0123456789") == std::string::npos && n.size() < 9) {
      const int k = std::stoi(n);
      *column_number = std::max(*column_number, k);
      return prefix + std::to_string(k + column_offset) + id.substr(face);
    }
  }
  return id + "_" + std::to_string(room_number);
}

}  // namespace

std::string FloorSm3Json(const FloorModel& m) {
  Json j;
  j["format"] = "mopad-sm3";
  j["version"] = kModelFormatVersion;
  j["room"] = "floor";
  double floor_z = 0.0, ceiling_z = 0.0;
  for (std::size_t r = 0; r < m.rooms.size(); ++r) {
    floor_z = r == 0 ? m.rooms[r].floor_z : std::min(floor_z, m.rooms[r].floor_z);
    ceiling_z = r == 0 ? m.rooms[r].ceiling_z : std::max(ceiling_z, m.rooms[r].ceiling_z);
  }
  j["floor_z"] = R(floor_z);
  j["ceiling_z"] = R(ceiling_z);
  Json ps = Json::array();
  for (const FloorWall& w : m.walls) {
    StructuralPatch p;
    p.id = w.id;
    p.patch_class = PatchClass::kWall;
    p.plane = w.plane;
    p.polygon = w.polygon;
    p.fitted = !w.faces.empty();
    for (const WallFace& f : w.faces) {
      p.support += f.patch.support;
      p.rms = std::max(p.rms, f.patch.rms);
      p.fitted = p.fitted && f.patch.fitted;
    }
    Json jw = PatchJson(p);
    jw["thickness_m"] = w.TwoSided() ? Json(R(w.thickness)) : Json(nullptr);
    jw["known_side"] = w.TwoSided() || w.faces.empty() ? Json(nullptr) : Json(w.faces[0].room);
    Json faces = Json::array();
    for (const WallFace& f : w.faces)
      faces.push_back({{"room", f.room}, {"side", f.side}, {"patch", PatchJson(f.patch)}});
    jw["faces"] = std::move(faces);
    Json pairs = Json::array();
    for (const WallFacePair& q : w.pairs)
      pairs.push_back(
          {{"faces", {q.a, q.b}}, {"thickness_m", R(q.thickness)}, {"overlap_m", R(q.overlap)}});
    jw["pairs"] = std::move(pairs);
    ps.push_back(std::move(jw));
  }
  Json rooms = Json::array();
  int column_offset = 0;
  for (std::size_t r = 0; r < m.rooms.size(); ++r) {
    const StructuralModel& room = m.rooms[r];
    int columns = 0;
    for (const StructuralPatch& p : room.patches) {
      StructuralPatch q = p;
      q.id = FloorPatchId(p.id, static_cast<int>(r) + 1, column_offset, &columns);
      Json jp = PatchJson(q);
      jp["room"] = room.room;
      jp["room_patch"] = p.id;
      ps.push_back(std::move(jp));
    }
    column_offset += columns;
    rooms.push_back(
        {{"room", room.room}, {"floor_z", R(room.floor_z)}, {"ceiling_z", R(room.ceiling_z)}});
  }
  j["patches"] = std::move(ps);
  j["adjacency"] = Json::array();
  j["rooms"] = std::move(rooms);
  return j.dump(1);
}

std::string FloorSm4Json(const FloorModel& m) {
  Json j;
  j["format"] = "mopad-sm4";
  j["version"] = kModelFormatVersion;
  j["room"] = "floor";
  Json os = Json::array();
  for (const FloorOpening& o : m.openings) {
    Json jo = OpeningJson(o.opening);
    jo["rooms"] = o.rooms;
    Json sides = Json::array();
    for (std::size_t k = 0; k < o.sides.size() && k < o.rooms.size(); ++k)
      sides.push_back({{"room", o.rooms[k]}, {"opening", OpeningJson(o.sides[k])}});
    jo["sides"] = std::move(sides);
    os.push_back(std::move(jo));
  }
  j["openings"] = std::move(os);
  return j.dump(1);
}

namespace {

const Json& ArrayField(const Json& j, const char* key, const std::string& where,
                       const std::string& ctx) {
  const Json& v = Field(j, key, where, ctx);
  if (!v.is_array()) throw InputError(where, ctx + key + ": wrong type", "", "an array");
  return v;
}

}  // namespace

FloorModel ParseFloorModel(const std::string& sm3_text, const std::string& sm3_where,
                           const std::string& sm4_text, const std::string& sm4_where) {
  FloorModel m;
  {
    const std::string& where = sm3_where;
    const Json j = ParseJsonText(sm3_text, where);
    CheckFormat(j, "mopad-sm3", where);
    if (StringField(j, "room", where, "") != "floor" || !j.contains("rooms"))
      throw InputError(where, "not a floor model", "room " + j["room"].dump(),
                       "\"room\": \"floor\" and a \"rooms\" list");
    const Json& rooms = ArrayField(j, "rooms", where, "");
    for (std::size_t i = 0; i < rooms.size(); ++i) {
      const std::string ctx = "rooms[" + std::to_string(i) + "].";
      StructuralModel r;
      r.room = StringField(rooms[i], "room", where, ctx);
      r.floor_z = NumberField(rooms[i], "floor_z", where, ctx);
      r.ceiling_z = NumberField(rooms[i], "ceiling_z", where, ctx);
      m.rooms.push_back(std::move(r));
    }
    const Json& ps = ArrayField(j, "patches", where, "");
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const std::string ctx = "patches[" + std::to_string(i) + "].";
      const Json& jp = ps[i];
      StructuralPatch p = ParsePatch(jp, where, ctx);
      if (p.patch_class != PatchClass::kWall) {
        const std::string room = StringField(jp, "room", where, ctx);
        auto it = std::find_if(m.rooms.begin(), m.rooms.end(),
                               [&](const StructuralModel& r) { return r.room == room; });
        if (it == m.rooms.end())
          throw InputError(where, ctx + "room: not in rooms", "\"" + room + "\"", "a listed room");
        p.id = StringField(jp, "room_patch", where, ctx);
        it->patches.push_back(std::move(p));
        continue;
      }
      FloorWall w;
      w.id = p.id;
      w.plane = p.plane;
      w.polygon = p.polygon;
      const Json& faces = ArrayField(jp, "faces", where, ctx);
      if (faces.empty()) throw InputError(where, ctx + "faces: empty", "", "1 or more faces");
      for (std::size_t k = 0; k < faces.size(); ++k) {
        const std::string fctx = ctx + "faces[" + std::to_string(k) + "].";
        WallFace f;
        f.room = StringField(faces[k], "room", where, fctx);
        const double side = NumberField(faces[k], "side", where, fctx);
        if (side != 1 && side != -1)
          throw InputError(where, fctx + "side: unknown", faces[k]["side"].dump(), "1 or -1");
        f.side = static_cast<int>(side);
        f.patch = ParsePatch(Field(faces[k], "patch", where, fctx), where, fctx + "patch.");
        w.faces.push_back(std::move(f));
      }
      const Json& t = Field(jp, "thickness_m", where, ctx);
      if (!t.is_null()) w.thickness = NumberField(jp, "thickness_m", where, ctx);
      if (t.is_null() != (w.faces.size() == 1))
        throw InputError(where, ctx + "thickness_m: does not fit the faces", t.dump(),
                         "null for one face, a number for two or more");
      const Json& pairs = ArrayField(jp, "pairs", where, ctx);
      const int n = static_cast<int>(w.faces.size());
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        const std::string pctx = ctx + "pairs[" + std::to_string(k) + "].";
        const Json& ab = Field(pairs[k], "faces", where, pctx);
        if (!ab.is_array() || ab.size() != 2 || !ab[0].is_number_integer() ||
            !ab[1].is_number_integer() || ab[0].get<int>() < 0 || ab[0].get<int>() >= n ||
            ab[1].get<int>() < 0 || ab[1].get<int>() >= n)
          throw InputError(where, pctx + "faces: not a pair of face indices", ab.dump(),
                           "[i, j] in [0, " + std::to_string(n) + ")");
        w.pairs.push_back({ab[0].get<int>(), ab[1].get<int>(),
                           NumberField(pairs[k], "thickness_m", where, pctx),
                           NumberField(pairs[k], "overlap_m", where, pctx)});
      }
      m.walls.push_back(std::move(w));
    }
  }
  const std::string& where = sm4_where;
  const Json j = ParseJsonText(sm4_text, where);
  CheckFormat(j, "mopad-sm4", where);
  const Json& os = ArrayField(j, "openings", where, "");
  for (std::size_t i = 0; i < os.size(); ++i) {
    const std::string ctx = "openings[" + std::to_string(i) + "].";
    FloorOpening o;
    o.opening = ParseOpening(os[i], where, ctx);
    const Json& sides = ArrayField(os[i], "sides", where, ctx);
    if (sides.empty() || sides.size() > 2)
      throw InputError(where, ctx + "sides: wrong count", std::to_string(sides.size()), "1 or 2");
    for (std::size_t k = 0; k < sides.size(); ++k) {
      const std::string sctx = ctx + "sides[" + std::to_string(k) + "].";
      o.rooms.push_back(StringField(sides[k], "room", where, sctx));
      o.sides.push_back(
          ParseOpening(Field(sides[k], "opening", where, sctx), where, sctx + "opening."));
    }
    m.openings.push_back(std::move(o));
  }
  return m;
}

FloorModel ReadFloorModel(const std::string& dir) {
  auto read = [](const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot read the file");
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  const std::string p3 = (std::filesystem::path(dir) / "sm3.json").string();
  const std::string p4 = (std::filesystem::path(dir) / "sm4.json").string();
  return ParseFloorModel(read(p3), p3, read(p4), p4);
}

void WriteFloorModelFiles(const std::string& dir, const FloorModel& model) {
  const std::filesystem::path d(dir);
  io::WriteTextFile((d / "sm3.json").string(), FloorSm3Json(model));
  io::WriteTextFile((d / "sm4.json").string(), FloorSm4Json(model));
}

void WriteSm4Files(const std::string& dir, const Sm4Model& model,
                   const std::vector<std::pair<std::string, Orthoimage>>& images) {
  const std::filesystem::path d(dir);
  io::WriteTextFile((d / "sm4.json").string(), Sm4Json(model));
  if (images.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(d / "orthoimages", ec);
  if (ec) throw InputError((d / "orthoimages").string(), "cannot create the folder", ec.message());
  for (const auto& [id, image] : images)
    WriteOrthoimagePngs(image, (d / "orthoimages" / id).string());
}

void WriteDsm3Ply(const VoxelSpace& vs, const std::string& path) {
  io::PointCloud cloud;
  char buf[160];
  std::snprintf(buf, sizeof buf, "mopad_dsm3_voxel_size %.6f", vs.Size());
  cloud.comments.push_back(buf);
  std::snprintf(buf, sizeof buf, "mopad_dsm3_origin %.6f %.6f %.6f", vs.Origin().x(),
                vs.Origin().y(), vs.Origin().z());
  cloud.comments.push_back(buf);
  std::snprintf(buf, sizeof buf, "mopad_dsm3_dims %d %d %d", vs.Nx(), vs.Ny(), vs.Nz());
  cloud.comments.push_back(buf);
  for (int l = 0; l < kVoxelLabelCount; ++l)
    cloud.comments.push_back("mopad_dsm3_label " + std::to_string(l) + " " +
                             ToString(static_cast<VoxelLabel>(l)));
  io::ScalarField label{"scalar_label", io::PlyType::kUInt8, {}};
  io::ScalarField fi{"scalar_i", io::PlyType::kInt32, {}};
  io::ScalarField fj{"scalar_j", io::PlyType::kInt32, {}};
  io::ScalarField fk{"scalar_k", io::PlyType::kInt32, {}};
  for (int k = 0; k < vs.Nz(); ++k)
    for (int j = 0; j < vs.Ny(); ++j)
      for (int i = 0; i < vs.Nx(); ++i) {
        const std::size_t idx = vs.Index(i, j, k);
        const std::uint8_t fl = vs.Flags(idx);
        if (!(fl & (VoxelSpace::kInside | VoxelSpace::kStructural))) continue;
        cloud.points.push_back(vs.Centre(i, j, k).cast<float>());
        label.values.push_back(static_cast<double>(vs.Label(idx)));
        fi.values.push_back(i), fj.values.push_back(j), fk.values.push_back(k);
      }
  cloud.fields = {std::move(label), std::move(fi), std::move(fj), std::move(fk)};
  io::WritePly(path, cloud);
}

void WriteModelsGlb(const StructuralModel& sm3, const Sm4Model* sm4, const std::string& room,
                    const std::string& path, const Sm5Model* sm5) {
  io::GlbScene scene;
  scene.name = "robot model of room " + room;  // not the output path: same run, same bytes
  struct ClassStyle {
    PatchClass cls;
    const char* name;
    std::array<float, 4> colour;
  };
  const ClassStyle styles[] = {{PatchClass::kWall, "wall", {0.85f, 0.80f, 0.70f, 1.f}},
                               {PatchClass::kFloor, "floor", {0.45f, 0.50f, 0.55f, 1.f}},
                               {PatchClass::kCeiling, "ceiling", {0.95f, 0.95f, 0.95f, 1.f}},
                               {PatchClass::kColumn, "column", {0.70f, 0.35f, 0.30f, 1.f}}};
  for (const auto& st : styles) scene.materials.push_back({st.name, st.colour});
  const int door_material = static_cast<int>(scene.materials.size());
  scene.materials.push_back({"door", {0.55f, 0.35f, 0.20f, 1.f}});
  scene.materials.push_back({"window", {0.55f, 0.75f, 0.95f, 0.6f}});
  for (const auto& p : sm3.patches) {
    if (p.polygon.size() < 3) continue;
    int style = 0;
    for (int k = 0; k < 4; ++k)
      if (styles[k].cls == p.patch_class) style = k;
    // Triangulate in the patch's plane (u, v with u x v = n: CCW stays CCW).
    const Eigen::Vector3d n = p.plane.n.normalized();
    const Eigen::Vector3d u = (std::abs(n.z()) < 0.9 ? Eigen::Vector3d::UnitZ().cross(n)
                                                     : Eigen::Vector3d::UnitX().cross(n))
                                  .normalized();
    const Eigen::Vector3d v = n.cross(u);
    std::vector<Eigen::Vector2d> poly;
    for (const auto& q : p.polygon) poly.emplace_back(q.dot(u), q.dot(v));
    double area2 = 0.0;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const auto& a = poly[k];
      const auto& b = poly[(k + 1) % poly.size()];
      area2 += a.x() * b.y() - b.x() * a.y();
    }
    if (area2 < 0) continue;  // not CCW seen from the room: skip, never flip
    std::vector<Eigen::Vector3i> tris;
    try {
      tris = TriangulatePolygon(poly);
    } catch (const std::invalid_argument&) {
      continue;  // not simple
    }
    if (tris.empty()) continue;
    io::GlbMesh mesh;
    mesh.name = room + "/" + p.id;
    mesh.material = style;
    for (const auto& q : p.polygon) mesh.positions.push_back(q.cast<float>());
    for (const auto& t : tris)
      mesh.triangles.push_back({static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]),
                                static_cast<std::uint32_t>(t[2])});
    mesh.extras = {{"mopad", {{"id", mesh.name}, {"class", styles[style].name}, {"room", room}}}};
    scene.meshes.push_back(std::move(mesh));
  }
  if (sm4) {
    for (const auto& o : sm4->openings) {
      io::GlbMesh mesh;
      mesh.name = room + "/" + o.id;
      mesh.material = door_material + (o.type == OpeningType::kDoor ? 0 : 1);
      for (const auto& c : o.corners) mesh.positions.push_back(c.cast<float>());
      mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
      nlohmann::ordered_json m{
          {"id", mesh.name}, {"class", ToString(o.type)}, {"room", room}, {"host", o.host}};
      if (o.type == OpeningType::kDoor) {
        m["state"] = ToString(o.state);
        m["opening_angle_deg"] = std::isfinite(o.opening_angle_deg)
                                     ? nlohmann::ordered_json(o.opening_angle_deg)
                                     : nlohmann::ordered_json(nullptr);
      }
      mesh.extras = {{"mopad", m}};
      scene.meshes.push_back(std::move(mesh));
    }
  }
  if (sm5 != nullptr && !sm5->components.empty()) {
    const int material = static_cast<int>(scene.materials.size());
    scene.materials.push_back({"component", {0.90f, 0.20f, 0.15f, 1.f}});
    for (const DetectedComponent& c : sm5->components) {
      const StructuralPatch* host = nullptr;
      for (const auto& p : sm3.patches)
        if (p.id == c.host) host = &p;
      if (host == nullptr || host->polygon.size() < 3) continue;
      const PatchFrame f = PatchFrame::Of(*host);
      const Vec3 hu = 0.5 * c.size.x() * f.u, hv = 0.5 * c.size.y() * f.v;
      const Vec3 dn = c.size.z() * f.n;  // the host's normal into the room, as c.normal
      io::GlbMesh mesh;
      mesh.name = room + "/" + c.id;
      mesh.material = material;
      // Corners: bit 0 +u, bit 1 +v, bit 2 off the host (into the room).
      for (int k = 0; k < 8; ++k)
        mesh.positions.push_back((c.centre + ((k & 1) ? hu : Vec3(-hu)) +
                                  ((k & 2) ? hv : Vec3(-hv)) + ((k & 4) ? dn : Vec3::Zero()))
                                     .cast<float>());
      // Outward faces, counter-clockwise seen from outside (u x v = n for a PatchFrame).
      mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
      mesh.extras = {{"mopad",
                      {{"id", mesh.name},
                       {"class", c.class_name},
                       {"room", room},
                       {"host", c.host},
                       {"alpha", c.alpha},
                       {"found_by", ToString(c.found_by)}}}};
      scene.meshes.push_back(std::move(mesh));
    }
  }
  if (scene.meshes.empty()) throw InputError(path, "no model element could be triangulated");
  io::WriteGlb(scene, path);
}

}  // namespace mopad::modelling
