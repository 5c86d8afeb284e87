#include "evaluation/model_files.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/error.h"
#include "evaluation/metrics_voxels.h"
#include "io/json_fields.h"

namespace mopad::evaluation {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::string ReadWholeFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

json ParseJsonFile(const std::string& path) {
  const std::string text = ReadWholeFile(path);
  try {
    return json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond double (406)
    throw InputError(path, std::string("malformed JSON: ") + e.what());
  }
}

// The model files' fields (io::JsonFields), their header at the model format version.
struct Reader : io::JsonFields {
  void Header(const json& j, const std::string& format) const {
    JsonFields::Header(j, format, kModelFormatVersion);
  }
};

bool ParseClass(const std::string& name, SurfaceClass* cls) {
  for (SurfaceClass c : AllSurfaceClasses())
    if (name == SurfaceClassName(c)) {
      *cls = c;
      return true;
    }
  return false;
}

}  // namespace

std::vector<Patch> Sm3Model::Patches() const {
  std::vector<Patch> out;
  out.reserve(patches.size());
  for (const auto& p : patches) out.push_back(p.patch);
  return out;
}

Sm3Model ReadSm3(const std::string& path) {
  const Reader r{{path}};
  const json j = ParseJsonFile(path);
  r.Header(j, "mopad-sm3");
  Sm3Model m;
  m.room = r.String(r.Get(j, "room", "room"), "room");
  m.floor_z = r.Number(r.Get(j, "floor_z", "floor_z"), "floor_z");
  m.ceiling_z = r.Number(r.Get(j, "ceiling_z", "ceiling_z"), "ceiling_z");
  const json& patches = r.Get(j, "patches", "patches");
  if (!patches.is_array()) r.Fail("patches", "not an array", patches.type_name(), "an array");
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const std::string f = "patches[" + std::to_string(i) + "]";
    const json& pj = patches[i];
    Sm3Patch p;
    p.patch.id = r.String(r.Get(pj, "id", f + ".id"), f + ".id");
    const std::string cls = r.String(r.Get(pj, "class", f + ".class"), f + ".class");
    if (!ParseClass(cls, &p.patch.cls))
      r.Fail(f + ".class", "unknown class", "'" + cls + "'", "wall|floor|ceiling|column");
    const json& plane = r.Get(pj, "plane", f + ".plane");
    p.plane_n = r.Vector3(r.Get(plane, "n", f + ".plane.n"), f + ".plane.n");
    p.plane_d = r.Number(r.Get(plane, "d", f + ".plane.d"), f + ".plane.d");
    const double nn = p.plane_n.norm();
    if (nn < 1e-9) r.Fail(f + ".plane.n", "zero normal");
    p.plane_n /= nn;
    p.plane_d /= nn;
    p.patch.normal = p.plane_n;
    const json& poly = r.Get(pj, "polygon", f + ".polygon");
    if (!poly.is_array() || poly.size() < 3)
      r.Fail(f + ".polygon", "not a polygon", poly.dump().substr(0, 80), "at least 3 vertices");
    for (std::size_t k = 0; k < poly.size(); ++k)
      p.patch.polygon.push_back(r.Vector3(poly[k], f + ".polygon[" + std::to_string(k) + "]"));
    if (auto it = pj.find("support"); it != pj.end())
      p.support = static_cast<long>(r.Number(*it, f + ".support"));
    if (auto it = pj.find("rms"); it != pj.end()) p.rms = r.Number(*it, f + ".rms");
    if (auto it = pj.find("fitted"); it != pj.end()) {
      if (!it->is_boolean()) r.Fail(f + ".fitted", "not a boolean", it->dump(), "true|false");
      p.fitted = it->get<bool>();
    }
    m.patches.push_back(std::move(p));
  }
  if (auto it = j.find("adjacency"); it != j.end()) {
    if (!it->is_array()) r.Fail("adjacency", "not an array", it->type_name(), "[[i, j], ...]");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& a = (*it)[i];
      const std::string f = "adjacency[" + std::to_string(i) + "]";
      if (!a.is_array() || a.size() != 2 || !a[0].is_number_integer() || !a[1].is_number_integer())
        r.Fail(f, "not an index pair", a.dump(), "[i, j]");
      const int x = a[0].get<int>(), y = a[1].get<int>();
      const int n = static_cast<int>(m.patches.size());
      if (x < 0 || y < 0 || x >= n || y >= n)
        r.Fail(f, "patch index out of range", a.dump(), "0.." + std::to_string(n - 1));
      m.adjacency.push_back({x, y});
    }
  }
  return m;
}

namespace {

enum class PlyType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

bool ParsePlyType(const std::string& s, PlyType* t, int* size) {
  static const std::map<std::string, std::pair<PlyType, int>> kTypes = {
      {"char", {PlyType::kI8, 1}},    {"int8", {PlyType::kI8, 1}},
      {"uchar", {PlyType::kU8, 1}},   {"uint8", {PlyType::kU8, 1}},
      {"short", {PlyType::kI16, 2}},  {"int16", {PlyType::kI16, 2}},
      {"ushort", {PlyType::kU16, 2}}, {"uint16", {PlyType::kU16, 2}},
      {"int", {PlyType::kI32, 4}},    {"int32", {PlyType::kI32, 4}},
      {"uint", {PlyType::kU32, 4}},   {"uint32", {PlyType::kU32, 4}},
      {"float", {PlyType::kF32, 4}},  {"float32", {PlyType::kF32, 4}},
      {"double", {PlyType::kF64, 8}}, {"float64", {PlyType::kF64, 8}}};
  auto it = kTypes.find(s);
  if (it == kTypes.end()) return false;
  *t = it->second.first;
  *size = it->second.second;
  return true;
}

double ReadBinary(const char* p, PlyType t) {
  switch (t) {
    case PlyType::kI8: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case PlyType::kU8: {
      std::uint8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case PlyType::kI16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case PlyType::kU16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case PlyType::kI32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PlyType::kU32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PlyType::kF32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PlyType::kF64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
  return 0.0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kF32;
  int size = 4;
  int offset = 0;
};

// What dsm3.ply's header says: the vertex layout, the grid and the label names.
struct Dsm3Header {
  std::string format;
  long n_vertex = -1;
  std::vector<PlyProperty> props;
  int record = 0;        // bytes per binary vertex
  std::size_t body = 0;  // offset of the vertex data
  bool have_size = false, have_origin = false, have_dims = false;
  VoxelGrid grid;
  std::map<int, std::uint8_t> file_to_label;  // file value -> VoxelLabel
};

using Dsm3Fail = std::function<void(const std::string&, const std::string&, const std::string&)>;

// One "comment mopad_dsm3_*" line of the header (other comments are ignored).
void ReadDsm3Comment(std::istringstream& ls, const std::string& line, Dsm3Header& h,
                     const Dsm3Fail& fail) {
  std::string key;
  ls >> key;
  if (key == "mopad_dsm3_voxel_size") {
    if (!(ls >> h.grid.voxel_size) || !(h.grid.voxel_size > 0.0) ||
        !std::isfinite(h.grid.voxel_size))
      fail("mopad_dsm3_voxel_size: bad value", line, "a positive size in metres");
    h.have_size = true;
  } else if (key == "mopad_dsm3_origin") {
    if (!(ls >> h.grid.origin.x() >> h.grid.origin.y() >> h.grid.origin.z()) ||
        !h.grid.origin.allFinite())
      fail("mopad_dsm3_origin: bad value", line, "X Y Z");
    h.have_origin = true;
  } else if (key == "mopad_dsm3_dims") {
    auto& d = h.grid.dims;
    if (!(ls >> d[0] >> d[1] >> d[2]) || d[0] <= 0 || d[1] <= 0 || d[2] <= 0)
      fail("mopad_dsm3_dims: bad value", line, "NX NY NZ > 0");
    h.have_dims = true;
  } else if (key == "mopad_dsm3_label") {
    int value = -1;
    std::string name;
    if (!(ls >> value >> name) || value < 0 || value > 255)
      fail("mopad_dsm3_label: bad entry", line, "VALUE NAME");
    const auto& names = Dsm3LabelNames();
    int code = -1;
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) code = static_cast<int>(c);
    if (code < 0)
      fail("mopad_dsm3_label: unknown label name", "'" + name + "'",
           "unseen|empty|structure|occluded_structure|clutter|opening");
    h.file_to_label[value] = static_cast<std::uint8_t>(code);
  }
}

// The header up to end_header, every required comment and element checked.
Dsm3Header ReadDsm3Header(const std::string& data, const Dsm3Fail& fail) {
  Dsm3Header h;
  const std::size_t header_end = data.find("end_header");
  if (data.rfind("ply", 0) != 0 || header_end == std::string::npos)
    fail("not a PLY file (no 'ply' magic or no 'end_header')", "", "");
  h.body = data.find('\n', header_end);
  if (h.body == std::string::npos) fail("truncated header", "", "");
  ++h.body;
  std::istringstream header(data.substr(0, header_end));
  std::string line;
  bool in_vertex = false;
  int line_no = 0;
  while (std::getline(header, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    const std::string where = "header line " + std::to_string(line_no);
    if (kw == "format") {
      ls >> h.format;
    } else if (kw == "element") {
      std::string name;
      long n = -1;
      ls >> name >> n;
      in_vertex = name == "vertex";
      if (in_vertex) {
        if (n < 0) fail(where + ": bad vertex count", line, "");
        h.n_vertex = n;
      } else if (n != 0) {
        fail(where + ": unexpected element", "'" + name + "'", "only 'vertex'");
      }
    } else if (kw == "property") {
      if (!in_vertex) continue;
      std::string type, name;
      ls >> type >> name;
      if (type == "list") fail(where + ": list property in the vertex element", line, "");
      PlyProperty p;
      p.name = name;
      if (!ParsePlyType(type, &p.type, &p.size))
        fail(where + ": unknown property type", "'" + type + "'", "");
      p.offset = h.record;
      h.record += p.size;
      h.props.push_back(p);
    } else if (kw == "comment") {
      ReadDsm3Comment(ls, line, h, fail);
    }
  }
  if (!h.have_size) fail("missing header comment mopad_dsm3_voxel_size", "", "");
  if (!h.have_origin) fail("missing header comment mopad_dsm3_origin", "", "");
  if (!h.have_dims) fail("missing header comment mopad_dsm3_dims", "", "");
  if (h.file_to_label.empty()) fail("missing header comments mopad_dsm3_label", "", "");
  if (h.n_vertex < 0) fail("missing 'element vertex N'", "", "");
  if (h.format != "ascii" && h.format != "binary_little_endian")
    fail("unsupported PLY format", "'" + h.format + "'", "binary_little_endian or ascii");
  return h;
}

// Index in h.props of the property `name`.
int PropertyIndex(const Dsm3Header& h, const std::string& name, const Dsm3Fail& fail) {
  for (std::size_t q = 0; q < h.props.size(); ++q)
    if (h.props[q].name == name) return static_cast<int>(q);
  fail("missing vertex property '" + name + "'", "", "");
  return 0;  // unreachable: fail throws
}

}  // namespace

Dsm3Voxels ReadDsm3(const std::string& path) {
  const std::string data = ReadWholeFile(path);
  const Dsm3Fail fail = [&](const std::string& what, const std::string& got,
                            const std::string& expected) {
    throw InputError(path, what, got, expected);
  };
  const Dsm3Header h = ReadDsm3Header(data, fail);
  const bool ascii = h.format == "ascii";
  const int idx_l = PropertyIndex(h, "scalar_label", fail);
  const int idx_i = PropertyIndex(h, "scalar_i", fail);
  const int idx_j = PropertyIndex(h, "scalar_j", fail);
  const int idx_k = PropertyIndex(h, "scalar_k", fail);
  Dsm3Voxels out;
  out.grid = h.grid;
  const std::size_t n = static_cast<std::size_t>(h.n_vertex);
  const std::size_t record = static_cast<std::size_t>(h.record);
  out.ijk.resize(n);
  out.labels.resize(n);
  std::vector<double> values(h.props.size());
  std::istringstream ascii_body;
  if (ascii)
    ascii_body.str(data.substr(h.body));
  else if (data.size() - h.body < n * record)
    fail("truncated vertex data", std::to_string(data.size() - h.body) + " bytes",
         std::to_string(n * record) + " bytes for " + std::to_string(n) + " voxels");
  const auto& d = out.grid.dims;
  for (std::size_t v = 0; v < n; ++v) {
    if (ascii) {
      for (auto& x : values)
        if (!(ascii_body >> x))
          fail("truncated vertex data", "voxel " + std::to_string(v),
               std::to_string(n) + " voxels");
    } else {
      const char* rec = data.data() + h.body + v * record;
      for (std::size_t q = 0; q < h.props.size(); ++q)
        values[q] = ReadBinary(rec + h.props[q].offset, h.props[q].type);
    }
    const std::array<int, 3> ijk{static_cast<int>(values[idx_i]), static_cast<int>(values[idx_j]),
                                 static_cast<int>(values[idx_k])};
    for (int a = 0; a < 3; ++a)
      if (ijk[a] < 0 || ijk[a] >= d[a])
        fail("voxel " + std::to_string(v) + ": grid index outside the grid",
             std::to_string(ijk[0]) + " " + std::to_string(ijk[1]) + " " + std::to_string(ijk[2]),
             "0 <= i,j,k < " + std::to_string(d[0]) + " " + std::to_string(d[1]) + " " +
                 std::to_string(d[2]));
    const int lv = static_cast<int>(values[idx_l]);
    auto it = h.file_to_label.find(lv);
    if (it == h.file_to_label.end())
      fail("voxel " + std::to_string(v) + ": label value not declared in the header",
           std::to_string(lv), "");
    out.ijk[v] = ijk;
    out.labels[v] = it->second;
  }
  return out;
}

std::vector<Vec3> ReadTumPositions(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path, "cannot open file");
  std::vector<Vec3> out;
  std::string line;
  int line_no = 0;
  while (std::getline(f, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    double v[8];
    for (double& x : v)
      if (!(ls >> x) || !std::isfinite(x))
        throw InputError(path + ":" + std::to_string(line_no), "malformed TUM pose line",
                         "'" + line + "'", "t x y z qx qy qz qw");
    out.emplace_back(v[1], v[2], v[3]);
  }
  return out;
}

}  // namespace mopad::evaluation
