#include "io/glb_writer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "common/atomic_file.h"
#include "common/error.h"

namespace mopad::io {
namespace {

using Json = nlohmann::ordered_json;

void Append(std::vector<std::uint8_t>& bin, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  bin.insert(bin.end(), p, p + bytes);
}

void PadTo4(std::vector<std::uint8_t>& bytes, std::uint8_t fill) {
  while (bytes.size() % 4 != 0) bytes.push_back(fill);
}

void PutU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
}

}  // namespace

void WriteGlb(const GlbScene& scene, const std::string& path) {
  Json materials = Json::array();
  for (const GlbMaterial& m : scene.materials) {
    Json jm;
    jm["name"] = m.name;
    jm["pbrMetallicRoughness"] = {
        {"baseColorFactor", {m.base_color[0], m.base_color[1], m.base_color[2], m.base_color[3]}},
        {"metallicFactor", 0.0},
        {"roughnessFactor", 1.0}};
    if (m.base_color[3] < 1.0f) jm["alphaMode"] = "BLEND";
    jm["doubleSided"] = true;
    materials.push_back(std::move(jm));
  }
  std::vector<std::uint8_t> bin;
  Json buffer_views = Json::array(), accessors = Json::array(), meshes = Json::array();
  Json nodes = Json::array();
  Json root_children = Json::array();
  nodes.push_back(Json::object());  // the root, filled below
  for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const GlbMesh& mesh = scene.meshes[mi];
    const std::string where = path + ": mesh '" + mesh.name + "'";
    if (mesh.triangles.empty()) throw InputError(where, "has no triangles");
    if (mesh.material < 0 || mesh.material >= static_cast<int>(scene.materials.size()))
      throw InputError(where, "material index out of range", std::to_string(mesh.material),
                       "[0, " + std::to_string(scene.materials.size()) + ")");
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
    Eigen::Vector3f hi = -lo;
    for (const auto& p : mesh.positions) {
      if (!p.allFinite()) throw InputError(where, "non-finite position");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    for (const auto& t : mesh.triangles)
      for (std::uint32_t v : t)
        if (v >= mesh.positions.size())
          throw InputError(where, "vertex index out of range", std::to_string(v),
                           "< " + std::to_string(mesh.positions.size()));
    // Positions, then indices, each in its own 4-byte aligned buffer view.
    const std::size_t pos_offset = bin.size();
    for (const auto& p : mesh.positions) Append(bin, p.data(), 3 * sizeof(float));
    const std::size_t pos_bytes = bin.size() - pos_offset;
    PadTo4(bin, 0);
    const std::size_t idx_offset = bin.size();
    for (const auto& t : mesh.triangles) Append(bin, t.data(), 3 * sizeof(std::uint32_t));
    const std::size_t idx_bytes = bin.size() - idx_offset;
    PadTo4(bin, 0);
    const int bv = static_cast<int>(buffer_views.size());
    buffer_views.push_back(
        {{"buffer", 0}, {"byteOffset", pos_offset}, {"byteLength", pos_bytes}, {"target", 34962}});
    buffer_views.push_back(
        {{"buffer", 0}, {"byteOffset", idx_offset}, {"byteLength", idx_bytes}, {"target", 34963}});
    const int acc = static_cast<int>(accessors.size());
    accessors.push_back({{"bufferView", bv},
                         {"componentType", 5126},
                         {"count", mesh.positions.size()},
                         {"type", "VEC3"},
                         {"min", {lo.x(), lo.y(), lo.z()}},
                         {"max", {hi.x(), hi.y(), hi.z()}}});
    accessors.push_back({{"bufferView", bv + 1},
                         {"componentType", 5125},
                         {"count", 3 * mesh.triangles.size()},
                         {"type", "SCALAR"}});
    meshes.push_back({{"name", mesh.name},
                      {"primitives",
                       {{{"attributes", {{"POSITION", acc}}},
                         {"indices", acc + 1},
                         {"material", mesh.material}}}}});
    Json node{{"name", mesh.name}, {"mesh", static_cast<int>(mi)}};
    if (!mesh.extras.empty()) node["extras"] = mesh.extras;
    root_children.push_back(static_cast<int>(nodes.size()));
    nodes.push_back(std::move(node));
  }
  nodes[0] = {{"name", "z_up_to_y_up"},
              {"rotation", {-0.7071068, 0.0, 0.0, 0.7071068}},
              {"children", root_children}};
  Json gltf;
  gltf["asset"] = {{"generator", "OpenMoPAD io::WriteGlb"}, {"version", "2.0"}};
  gltf["scene"] = 0;
  gltf["scenes"] = {{{"name", scene.name}, {"nodes", {0}}}};
  gltf["nodes"] = nodes;
  if (!meshes.empty()) {
    gltf["meshes"] = meshes;
    gltf["materials"] = materials;
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = buffer_views;
    gltf["buffers"] = {{{"byteLength", bin.size()}}};
  }
  const std::string text = gltf.dump();
  std::vector<std::uint8_t> json(text.begin(), text.end());
  PadTo4(json, ' ');
  std::vector<std::uint8_t> out;
  PutU32(out, 0x46546C67u);  // "glTF"
  PutU32(out, 2u);
  const std::size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
  PutU32(out, static_cast<std::uint32_t>(total));
  PutU32(out, static_cast<std::uint32_t>(json.size()));
  PutU32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  if (!bin.empty()) {
    PutU32(out, static_cast<std::uint32_t>(bin.size()));
    PutU32(out, 0x004E4942u);  // "BIN\0"
    out.insert(out.end(), bin.begin(), bin.end());
  }
  WriteWholeFile(path, std::string(out.begin(), out.end()));
}

}  // namespace mopad::io
