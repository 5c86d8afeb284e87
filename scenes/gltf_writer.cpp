#include "scenes/gltf_writer.h"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"

namespace mopad::scenes {
namespace {

std::uint32_t Crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void PutU32Be(std::vector<std::uint8_t>* out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out->push_back(static_cast<std::uint8_t>(v >> s));
}

void PutChunk(std::vector<std::uint8_t>* out, const char type[4],
              const std::vector<std::uint8_t>& data) {
  PutU32Be(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out->size();
  out->insert(out->end(), type, type + 4);
  out->insert(out->end(), data.begin(), data.end());
  PutU32Be(out, Crc32(out->data() + start, out->size() - start));
}

tinygltf::Value Str(const std::string& s) { return tinygltf::Value(s); }

// Appends `n` bytes to buffer 0 (4-byte aligned) as a new buffer view; returns its index.
int AddView(const void* bytes, std::size_t n, int target, tinygltf::Model* m) {
  std::vector<unsigned char>& data = m->buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = data.size();
  v.byteLength = n;
  v.target = target;
  const auto* p = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), p, p + n);
  m->bufferViews.push_back(v);
  return static_cast<int>(m->bufferViews.size()) - 1;
}

// Textures: one PNG image, sampler and texture each.
void AddTextures(const Scene& scene, tinygltf::Model* m) {
  for (const Texture& t : scene.textures) {
    const std::vector<std::uint8_t> png = EncodePng(t);
    tinygltf::Image img;
    img.name = t.name;
    img.mimeType = "image/png";
    img.bufferView = AddView(png.data(), png.size(), 0, m);
    m->images.push_back(img);
    tinygltf::Sampler s;
    s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    s.wrapS = s.wrapT =
        t.repeat ? TINYGLTF_TEXTURE_WRAP_REPEAT : TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    m->samplers.push_back(s);
    tinygltf::Texture tex;
    tex.name = t.name;
    tex.source = static_cast<int>(m->images.size()) - 1;
    tex.sampler = static_cast<int>(m->samplers.size()) - 1;
    m->textures.push_back(tex);
  }
}

// PBR metallic-roughness material; sets *transmission_used when it uses
// KHR_materials_transmission. The NIR reflectance goes to extras.
tinygltf::Material ToGltfMaterial(const Material& mat, const Scene& scene,
                                  bool* transmission_used) {
  tinygltf::Material g;
  g.name = mat.name;
  g.pbrMetallicRoughness.baseColorFactor = {mat.base_color[0], mat.base_color[1], mat.base_color[2],
                                            mat.base_color[3]};
  g.pbrMetallicRoughness.metallicFactor = mat.metallic;
  g.pbrMetallicRoughness.roughnessFactor = mat.roughness;
  if (mat.base_color_texture >= 0) {
    if (mat.base_color_texture >= static_cast<int>(scene.textures.size()))
      throw std::invalid_argument("WriteGlb: material '" + mat.name + "' texture out of range");
    g.pbrMetallicRoughness.baseColorTexture.index = mat.base_color_texture;
  }
  g.doubleSided = mat.double_sided;
  if (mat.transmission > 0.0f) {
    tinygltf::Value::Object ext;
    ext["transmissionFactor"] = tinygltf::Value(static_cast<double>(mat.transmission));
    g.extensions["KHR_materials_transmission"] = tinygltf::Value(ext);
    *transmission_used = true;
  }
  if (mat.nir_reflectance >= 0.0f) {
    tinygltf::Value::Object extras;
    extras["nir_reflectance"] = tinygltf::Value(static_cast<double>(mat.nir_reflectance));
    g.extras = tinygltf::Value(extras);
  }
  return g;
}

// Per-axis min and max of the part's positions (glTF requires them on POSITION); throws on a
// non-finite vertex.
void PositionBounds(const MeshPart& part, std::vector<double>* lo, std::vector<double>* hi) {
  const std::size_t nv = part.positions.size();
  for (std::size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) {
      const double v = part.positions[i][k];
      if (!std::isfinite(v))
        throw std::invalid_argument("WriteGlb: part '" + part.name + "' has a non-finite vertex");
      (*lo)[k] = i == 0 ? v : std::min((*lo)[k], v);
      (*hi)[k] = i == 0 ? v : std::max((*hi)[k], v);
    }
}

int AddPositions(const MeshPart& part, const std::vector<double>& lo, const std::vector<double>& hi,
                 tinygltf::Model* m) {
  const std::size_t nv = part.positions.size();
  const int view =
      AddView(part.positions.data(), nv * 3 * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER, m);
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = TINYGLTF_TYPE_VEC3;
  a.count = nv;
  a.minValues = lo;
  a.maxValues = hi;
  m->accessors.push_back(a);
  return static_cast<int>(m->accessors.size()) - 1;
}

// TEXCOORD_0: the part's uvs, or zeros for a textured part without them.
int AddTexcoords(const MeshPart& part, tinygltf::Model* m) {
  const std::size_t nv = part.positions.size();
  std::vector<float> uv(nv * 2, 0.0f);
  if (!part.uvs.empty()) {
    if (part.uvs.size() != nv)
      throw std::invalid_argument("WriteGlb: part '" + part.name + "' uv count mismatch");
    for (std::size_t i = 0; i < nv; ++i) {
      uv[2 * i] = part.uvs[i].x();
      uv[2 * i + 1] = part.uvs[i].y();
    }
  }
  const int view = AddView(uv.data(), uv.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER, m);
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = TINYGLTF_TYPE_VEC2;
  a.count = nv;
  m->accessors.push_back(a);
  return static_cast<int>(m->accessors.size()) - 1;
}

// Triangle indices, 16-bit when the part has at most 65535 vertices, else 32-bit.
int AddIndices(const MeshPart& part, tinygltf::Model* m) {
  const std::size_t nv = part.positions.size();
  const bool small = nv <= 65535;
  std::vector<std::uint16_t> i16;
  std::vector<std::uint32_t> i32;
  for (const auto& t : part.triangles)
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || static_cast<std::size_t>(t[k]) >= nv)
        throw std::invalid_argument("WriteGlb: part '" + part.name + "' index out of range");
      if (small)
        i16.push_back(static_cast<std::uint16_t>(t[k]));
      else
        i32.push_back(static_cast<std::uint32_t>(t[k]));
    }
  const int view =
      small ? AddView(i16.data(), i16.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, m)
            : AddView(i32.data(), i32.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, m);
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType =
      small ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  a.type = TINYGLTF_TYPE_SCALAR;
  a.count = part.triangles.size() * 3;
  m->accessors.push_back(a);
  return static_cast<int>(m->accessors.size()) - 1;
}

// One mesh and one node per part, the node a child of the root (node 0) carrying the part's
// labels in extras.mopad (id, class, subclass, room).
void AddPartNode(const MeshPart& part, int material, bool textured, const std::vector<double>& lo,
                 const std::vector<double>& hi, tinygltf::Model* m) {
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = material;
  prim.attributes["POSITION"] = AddPositions(part, lo, hi, m);
  if (!part.uvs.empty() || textured) prim.attributes["TEXCOORD_0"] = AddTexcoords(part, m);
  prim.indices = AddIndices(part, m);
  tinygltf::Mesh mesh;
  mesh.name = part.name;
  mesh.primitives.push_back(prim);
  m->meshes.push_back(mesh);

  tinygltf::Node node;
  node.name = part.name;
  node.mesh = static_cast<int>(m->meshes.size()) - 1;
  tinygltf::Value::Object mopad;
  mopad["id"] = Str(part.element_id);
  mopad["class"] = Str(std::string(ToString(part.element_class)));
  mopad["subclass"] = Str(part.subclass);
  mopad["room"] = Str(part.room);
  tinygltf::Value::Object extras;
  extras["mopad"] = tinygltf::Value(mopad);
  node.extras = tinygltf::Value(extras);
  m->nodes.push_back(node);
  m->nodes[0].children.push_back(static_cast<int>(m->nodes.size()) - 1);
}

}  // namespace

std::vector<std::uint8_t> EncodePng(const Texture& t) {
  if (t.width <= 0 || t.height <= 0 ||
      t.rgba.size() != static_cast<std::size_t>(t.width) * t.height * 4)
    throw std::invalid_argument("EncodePng: texture '" + t.name + "' has inconsistent size");
  bool opaque = true;
  for (std::size_t i = 3; i < t.rgba.size(); i += 4) opaque = opaque && t.rgba[i] == 255;
  const int channels = opaque ? 3 : 4;
  // Raw scanlines, filter type 0.
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<std::size_t>(t.height) * (1 + t.width * channels));
  for (int y = 0; y < t.height; ++y) {
    raw.push_back(0);
    for (int x = 0; x < t.width; ++x)
      for (int c = 0; c < channels; ++c)
        raw.push_back(t.rgba[(static_cast<std::size_t>(y) * t.width + x) * 4 + c]);
  }
  // zlib stream of stored deflate blocks (RFC 1950/1951).
  std::vector<std::uint8_t> z{0x78, 0x01};
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    z.push_back(pos + n == raw.size() ? 1 : 0);
    z.push_back(static_cast<std::uint8_t>(n & 0xFF));
    z.push_back(static_cast<std::uint8_t>(n >> 8));
    z.push_back(static_cast<std::uint8_t>(~n & 0xFF));
    z.push_back(static_cast<std::uint8_t>((~n >> 8) & 0xFF));
    z.insert(z.end(), raw.begin() + static_cast<long>(pos),
             raw.begin() + static_cast<long>(pos + n));
    pos += n;
  } while (pos < raw.size());
  std::uint32_t s1 = 1, s2 = 0;
  for (std::uint8_t b : raw) {
    s1 = (s1 + b) % 65521;
    s2 = (s2 + s1) % 65521;
  }
  PutU32Be(&z, (s2 << 16) | s1);

  std::vector<std::uint8_t> png{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  PutU32Be(&ihdr, static_cast<std::uint32_t>(t.width));
  PutU32Be(&ihdr, static_cast<std::uint32_t>(t.height));
  ihdr.insert(ihdr.end(), {8, static_cast<std::uint8_t>(opaque ? 2 : 6), 0, 0, 0});
  PutChunk(&png, "IHDR", ihdr);
  PutChunk(&png, "IDAT", z);
  PutChunk(&png, "IEND", {});
  return png;
}

void WriteGlb(const Scene& scene, const std::string& path) {
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "OpenMoPAD scene writer";
  m.buffers.emplace_back();
  AddTextures(scene, &m);

  // Materials (plus a default grey one for parts without a material).
  bool transmission_used = false;
  for (const Material& mat : scene.materials)
    m.materials.push_back(ToGltfMaterial(mat, scene, &transmission_used));
  int default_material = -1;

  tinygltf::Node root;
  root.name = "world_zup";
  root.rotation = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};  // mopad::YupFromZup()
  m.nodes.push_back(root);

  for (const MeshPart& part : scene.parts) {
    if (part.triangles.empty()) continue;
    std::vector<double> lo(3, 0.0), hi(3, 0.0);
    PositionBounds(part, &lo, &hi);
    int material = part.material;
    if (material >= static_cast<int>(scene.materials.size()))
      throw std::invalid_argument("WriteGlb: part '" + part.name + "' material out of range");
    if (material < 0) {
      if (default_material < 0) {
        Material grey;
        grey.name = "default";
        m.materials.push_back(ToGltfMaterial(grey, scene, &transmission_used));
        default_material = static_cast<int>(m.materials.size()) - 1;
      }
      material = default_material;
    }
    const bool textured = material < static_cast<int>(scene.materials.size()) &&
                          scene.materials[material].base_color_texture >= 0;
    AddPartNode(part, material, textured, lo, hi, &m);
  }
  std::vector<unsigned char>& data = m.buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  if (transmission_used) m.extensionsUsed.push_back("KHR_materials_transmission");

  tinygltf::Scene s;
  s.name = scene.source.empty() ? "scene" : scene.source;
  s.nodes = {0};
  m.scenes.push_back(s);
  m.defaultScene = 0;

  tinygltf::TinyGLTF writer;
  AtomicFile file(path);
  if (!writer.WriteGltfSceneToFile(&m, file.TempPath(), /*embedImages=*/true,
                                   /*embedBuffers=*/true, /*prettyPrint=*/false,
                                   /*writeBinary=*/true)) {
    throw InputError(path, "cannot write glTF binary");
  }
  file.Commit();
}

}  // namespace mopad::scenes
