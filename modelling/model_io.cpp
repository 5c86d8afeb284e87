#include "modelling/model_io.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

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
  for (const auto& p : m.patches) {
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
    ps.push_back(std::move(jp));
  }
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
  for (const auto& o : m.openings) {
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
    }
    jo["confidence"] = R(o.confidence, 1e-4);
    os.push_back(std::move(jo));
  }
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
    const Json& jp = ps[i];
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
    m.patches.push_back(std::move(p));
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
    const Json& jo = os[i];
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
      const std::string state = StringField(jo, "state", where, ctx);
      if (state == "closed")
        o.state = DoorState::kClosed;
      else if (state == "semi_open")
        o.state = DoorState::kSemiOpen;
      else if (state == "open")
        o.state = DoorState::kOpen;
      else
        throw InputError(where, ctx + "state: unknown", state, "closed|semi_open|open");
      const Json& a = Field(jo, "opening_angle_deg", where, ctx);
      if (!a.is_null()) o.opening_angle_deg = NumberField(jo, "opening_angle_deg", where, ctx);
      o.clear_width_m = NumberField(jo, "clear_width_m", where, ctx);
    }
    m.openings.push_back(std::move(o));
  }
  return m;
}

Sm4Model ReadSm4(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return ParseSm4(text, path);
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
                    const std::string& path) {
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
  if (scene.meshes.empty()) throw InputError(path, "no model element could be triangulated");
  io::WriteGlb(scene, path);
}

}  // namespace mopad::modelling
