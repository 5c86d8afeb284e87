#include "scenes/gltf_loader.h"

// Debian's libtinygltf is a compiled library: include the declarations only (no
// TINYGLTF_IMPLEMENTATION); the header then pulls in neither nlohmann-json nor stb.
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/assimp_loader.h"
#include "scenes/mesh_validation.h"

namespace mopad::scenes {
namespace {

namespace tg = tinygltf;

constexpr char kDraco[] = "KHR_draco_mesh_compression";
constexpr char kTextureTransform[] = "KHR_texture_transform";
constexpr char kQuantization[] = "KHR_mesh_quantization";
constexpr char kTransmission[] = "KHR_materials_transmission";
// An accessor without a bufferView (sparse or all-zero) costs memory without file bytes to back
// it; cap it so a hostile `count` cannot exhaust memory (2^24 elements: 16.7 M vertices, far
// past any building). Accessors with a bufferView are bounded by their bytes.
constexpr std::size_t kMaxUnbackedElements = std::size_t{1} << 24;

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// tinygltf joins several messages with newlines; InputError needs one line.
std::string OneLine(const std::string& s) {
  std::string out;
  bool pending_sep = false;
  for (char c : s) {
    if (c == '\n' || c == '\r') {
      pending_sep = !out.empty();
      continue;
    }
    if (pending_sep) {
      out += "; ";
      pending_sep = false;
    }
    out += c;
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out;
}

int ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not glTF 2.0 component types
  }
}

int NumComponents(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;  // matrices: never a vertex attribute we read
  }
}

// One component at `p` (possibly unaligned), as a double; normalised integers per glTF 3.11.
double ReadComponent(const std::uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      std::uint8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

std::uint32_t ReadUnsigned(const std::uint8_t* p, int size) {
  if (size == 1) return *p;
  if (size == 2) {
    std::uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

bool IsIndexComponentType(int t) {
  return t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// tinygltf Image (8 or 16 bit, 1-4 channels) -> RGBA8.
bool ImageToTexture(const tg::Image& img, Texture* out, std::string* error) {
  const int comp = img.component;
  const int bytes = img.bits == 16 ? 2 : (img.bits == 8 ? 1 : 0);
  if (img.width <= 0 || img.height <= 0 || comp < 1 || comp > 4 || bytes == 0) {
    *error = "image has no decoded pixels (size " + std::to_string(img.width) + "x" +
             std::to_string(img.height) + ", " + std::to_string(comp) + " channels, " +
             std::to_string(img.bits) + " bits)";
    return false;
  }
  const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
  if (img.image.size() != n * comp * bytes) {
    *error = "image pixel buffer has " + std::to_string(img.image.size()) + " bytes, expected " +
             std::to_string(n * comp * bytes);
    return false;
  }
  out->width = img.width;
  out->height = img.height;
  out->rgba.resize(n * 4);
  // For 16-bit little-endian channels keep the high byte.
  auto channel = [&](std::size_t pixel, int c) -> std::uint8_t {
    return img.image[(pixel * comp + c) * bytes + (bytes - 1)];
  };
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t* d = &out->rgba[i * 4];
    if (comp <= 2) {
      d[0] = d[1] = d[2] = channel(i, 0);
      d[3] = comp == 2 ? channel(i, 1) : 255;
    } else {
      d[0] = channel(i, 0);
      d[1] = channel(i, 1);
      d[2] = channel(i, 2);
      d[3] = comp == 4 ? channel(i, 3) : 255;
    }
  }
  return true;
}

// The semantic label a node hands down to its subtree.
struct Semantic {
  std::string id;
  ElementClass element_class = ElementClass::kUnknown;
  std::string subclass;
  std::string room;
};

// A primitive in its mesh's frame, before instancing.
struct LocalPrimitive {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2f> uvs;
  std::vector<Eigen::Vector3i> triangles;
  int material = -1;
};

class GltfSceneBuilder {
 public:
  GltfSceneBuilder(const tg::Model& model, const std::string& path, const LoadOptions& options,
                   std::string warnings)
      : model_(model), path_(path), options_(options), warnings_(std::move(warnings)) {}

  Scene Build() {
    Scene scene;
    scene.source = path_;
    scene_ = &scene;
    for (std::size_t m = 0; m < model_.materials.size(); ++m)
      scene.materials.push_back(ConvertMaterial(static_cast<int>(m)));

    const std::vector<int> roots = SceneRoots();
    std::vector<std::vector<int>> children(model_.nodes.size());
    for (std::size_t i = 0; i < model_.nodes.size(); ++i) children[i] = model_.nodes[i].children;
    CheckNodeForest(path_, children, roots);

    Eigen::Matrix4d fix = Eigen::Matrix4d::Identity();
    if (options_.up_axis != UpAxis::kZ) fix.topLeftCorner<3, 3>() = ZupFromYup();

    // Iterative depth-first walk: the forest check above guarantees termination, and no
    // recursion means no stack overflow on deep (or hostile) hierarchies.
    struct Frame {
      int node;
      Eigen::Matrix4d parent;
      int mopad;  // index into semantics, -1 = none
      int ifc;
    };
    std::vector<Semantic> semantics;
    std::vector<Frame> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, fix, -1, -1});
    while (!stack.empty()) {
      const Frame f = stack.back();
      stack.pop_back();
      const tg::Node& node = model_.nodes[f.node];
      const Eigen::Matrix4d world = f.parent * LocalMatrix(f.node);
      int mopad = f.mopad;
      int ifc = f.ifc;
      Semantic s;
      if (ReadMopadExtras(f.node, &s)) {
        semantics.push_back(std::move(s));
        mopad = static_cast<int>(semantics.size()) - 1;
      } else if (const std::string cls = IfcClassFromNodeName(node.name);
                 !cls.empty() && cls != "IfcMappedItem") {
        s.id = node.name;
        s.element_class = FromIfcClass(cls);
        s.subclass = cls;
        semantics.push_back(std::move(s));
        ifc = static_cast<int>(semantics.size()) - 1;
      }
      if (node.mesh != -1) {
        const int label = mopad >= 0 ? mopad : ifc;
        Instance(f.node, world, label >= 0 ? &semantics[label] : nullptr);
      }
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
        stack.push_back({*it, world, mopad, ifc});
    }
    return scene;
  }

 private:
  [[noreturn]] void Fail(const std::string& what, const std::string& got = "",
                         const std::string& expected = "") const {
    throw InputError(path_, what, got, expected);
  }

  static std::string Range(std::size_t n) {
    return n == 0 ? "none (the array is empty)" : "0.." + std::to_string(n - 1);
  }

  std::vector<int> SceneRoots() const {
    const int num_scenes = static_cast<int>(model_.scenes.size());
    if (model_.defaultScene >= num_scenes)
      Fail("default scene index out of range", std::to_string(model_.defaultScene),
           Range(model_.scenes.size()));
    if (model_.defaultScene >= 0) return model_.scenes[model_.defaultScene].nodes;
    if (num_scenes > 0) return model_.scenes[0].nodes;
    if (model_.nodes.empty()) Fail("file has no scene and no nodes", "", "at least one node");
    // No scene: instance every root node (nodes nobody lists as a child).
    std::vector<char> is_child(model_.nodes.size(), 0);
    for (const tg::Node& n : model_.nodes)
      for (int c : n.children)
        if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[c] = 1;
    std::vector<int> roots;
    for (std::size_t i = 0; i < is_child.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
    return roots;  // empty only if every node is a child: CheckNodeForest reports the cycle
  }

  Eigen::Matrix4d LocalMatrix(int index) const {
    const tg::Node& n = model_.nodes[index];
    const std::string what = "node " + std::to_string(index) + " '" + n.name + "'";
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    const bool has_trs = !n.translation.empty() || !n.rotation.empty() || !n.scale.empty();
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16)
        Fail(what + " matrix has the wrong size", std::to_string(n.matrix.size()), "16");
      if (has_trs) Fail(what + " has both matrix and TRS", "", "one or the other");
      for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = n.matrix[i];  // column-major
      if (std::abs(m(3, 0)) > 1e-9 || std::abs(m(3, 1)) > 1e-9 || std::abs(m(3, 2)) > 1e-9 ||
          std::abs(m(3, 3) - 1.0) > 1e-9)
        Fail(what + " matrix is not affine",
             "last row (" + std::to_string(m(3, 0)) + ", " + std::to_string(m(3, 1)) + ", " +
                 std::to_string(m(3, 2)) + ", " + std::to_string(m(3, 3)) + ")",
             "(0, 0, 0, 1)");
    } else {
      if (!n.translation.empty() && n.translation.size() != 3)
        Fail(what + " translation has the wrong size", std::to_string(n.translation.size()), "3");
      if (!n.rotation.empty() && n.rotation.size() != 4)
        Fail(what + " rotation has the wrong size", std::to_string(n.rotation.size()), "4");
      if (!n.scale.empty() && n.scale.size() != 3)
        Fail(what + " scale has the wrong size", std::to_string(n.scale.size()), "3");
      Eigen::Affine3d t = Eigen::Affine3d::Identity();
      if (!n.translation.empty())
        t.translate(Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]));
      if (!n.rotation.empty()) {
        // glTF stores (x, y, z, w); Eigen's constructor takes (w, x, y, z).
        Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        const double norm = q.norm();
        if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
          Fail(what + " rotation is not a unit quaternion", "norm " + std::to_string(norm), "1");
        t.rotate(q.normalized());
      }
      if (!n.scale.empty()) t.scale(Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]));
      m = t.matrix();
    }
    if (!m.allFinite()) Fail(what + " transform is not finite", "", "finite numbers");
    return m;
  }

  // extras.mopad {id, class, subclass, room}, written by our generator.
  bool ReadMopadExtras(int index, Semantic* s) const {
    const tg::Node& n = model_.nodes[index];
    if (!n.extras.IsObject() || !n.extras.Has("mopad")) return false;
    const std::string what = "node " + std::to_string(index) + " '" + n.name + "' extras.mopad";
    const tg::Value& m = n.extras.Get("mopad");
    if (!m.IsObject()) Fail(what + " is not an object", "", "{id, class, subclass, room}");
    auto field = [&](const char* key) -> std::string {
      if (!m.Has(key)) return "";
      const tg::Value& v = m.Get(key);
      if (!v.IsString()) Fail(what + "." + key + " is not a string", "", "a string");
      return v.Get<std::string>();
    };
    s->id = field("id");
    s->subclass = field("subclass");
    s->room = field("room");
    const std::string cls = field("class");
    if (!cls.empty() && !ParseElementClass(cls, &s->element_class))
      Fail(what + ".class is not a known element class", "'" + cls + "'",
           "a name such as wall, floor, ceiling, door_leaf, service_component");
    return true;
  }

  const tg::Accessor& AccessorAt(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
      Fail(what + " accessor index out of range", std::to_string(index),
           Range(model_.accessors.size()));
    return model_.accessors[index];
  }

  struct View {
    const std::uint8_t* data;
    std::size_t length;
    std::size_t stride;  // 0 = tightly packed
  };

  View CheckedView(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(model_.bufferViews.size()))
      Fail(what + " bufferView index out of range", std::to_string(index),
           Range(model_.bufferViews.size()));
    const tg::BufferView& bv = model_.bufferViews[index];
    const std::string name = "bufferView " + std::to_string(index);
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(model_.buffers.size()))
      Fail(name + " buffer index out of range", std::to_string(bv.buffer),
           Range(model_.buffers.size()));
    const std::vector<unsigned char>& data = model_.buffers[bv.buffer].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
      Fail(name + " runs past the end of buffer " + std::to_string(bv.buffer),
           "byteOffset " + std::to_string(bv.byteOffset) + " + byteLength " +
               std::to_string(bv.byteLength),
           "at most " + std::to_string(data.size()) + " bytes");
    return {data.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
  }

  // Reads an accessor into doubles (count * components), bounds-checked, sparse applied.
  std::vector<double> ReadAccessor(int index, const std::string& what) const {
    const tg::Accessor& a = AccessorAt(index, what);
    const std::string name = what + " accessor " + std::to_string(index);
    const int nc = NumComponents(a.type);
    if (nc == 0)
      Fail(name + " has an unsupported type", std::to_string(a.type), "SCALAR or VEC2..4");
    const int cs = ComponentSize(a.componentType);
    if (cs == 0)
      Fail(name + " has an invalid componentType", std::to_string(a.componentType),
           "5120, 5121, 5122, 5123, 5125 or 5126");
    if (a.bufferView < 0 && a.count > kMaxUnbackedElements)
      Fail(name + " without a bufferView has too large a count", std::to_string(a.count),
           "at most " + std::to_string(kMaxUnbackedElements));
    const std::size_t elem = static_cast<std::size_t>(nc) * cs;
    std::vector<double> out(a.count * nc, 0.0);  // no bufferView: zeros (glTF 3.6.2.3)
    if (a.bufferView >= 0 && a.count > 0) {
      const View v = CheckedView(a.bufferView, name);
      const std::size_t stride = v.stride ? v.stride : elem;
      if (stride < elem)
        Fail(name + " byteStride is smaller than one element", std::to_string(stride),
             "at least " + std::to_string(elem));
      // Last byte read = byteOffset + (count - 1) * stride + elem; test without overflow.
      if (a.byteOffset > v.length || elem > v.length - a.byteOffset ||
          (a.count - 1) > (v.length - a.byteOffset - elem) / stride)
        Fail(name + " runs past the end of bufferView " + std::to_string(a.bufferView),
             "byteOffset " + std::to_string(a.byteOffset) + ", count " + std::to_string(a.count) +
                 ", stride " + std::to_string(stride),
             "within byteLength " + std::to_string(v.length));
      const std::uint8_t* base = v.data + a.byteOffset;
      for (std::size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < nc; ++c)
          out[i * nc + c] =
              ReadComponent(base + i * stride + c * cs, a.componentType, a.normalized);
    }
    if (a.sparse.isSparse) ApplySparse(a, name, nc, cs, &out);
    return out;
  }

  // tinygltf parses accessor.sparse but leaves it to the application (glTF 3.6.2.3).
  void ApplySparse(const tg::Accessor& a, const std::string& name, int nc, int cs,
                   std::vector<double>* out) const {
    const int sc = a.sparse.count;
    if (sc < 1 || static_cast<std::size_t>(sc) > a.count)
      Fail(name + " sparse count out of range", std::to_string(sc),
           "1.." + std::to_string(a.count));
    const int ict = a.sparse.indices.componentType;
    if (!IsIndexComponentType(ict))
      Fail(name + " sparse indices have an invalid componentType", std::to_string(ict),
           "5121, 5123 or 5125");
    const int ics = ComponentSize(ict);
    const std::size_t elem = static_cast<std::size_t>(nc) * cs;
    const View iv = CheckedView(a.sparse.indices.bufferView, name + " sparse indices");
    const View vv = CheckedView(a.sparse.values.bufferView, name + " sparse values");
    const long long ioff = a.sparse.indices.byteOffset;
    const long long voff = a.sparse.values.byteOffset;
    const std::size_t count = static_cast<std::size_t>(sc);
    if (ioff < 0 || static_cast<std::size_t>(ioff) > iv.length ||
        count * ics > iv.length - static_cast<std::size_t>(ioff))
      Fail(name + " sparse indices run past their bufferView",
           "byteOffset " + std::to_string(ioff) + " + " + std::to_string(count * ics) + " bytes",
           "within " + std::to_string(iv.length));
    if (voff < 0 || static_cast<std::size_t>(voff) > vv.length ||
        count * elem > vv.length - static_cast<std::size_t>(voff))
      Fail(name + " sparse values run past their bufferView",
           "byteOffset " + std::to_string(voff) + " + " + std::to_string(count * elem) + " bytes",
           "within " + std::to_string(vv.length));
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t idx = ReadUnsigned(iv.data + ioff + i * ics, ics);
      if (idx >= a.count)
        Fail(name + " sparse index out of range", std::to_string(idx),
             "0.." + std::to_string(a.count - 1));
      for (int c = 0; c < nc; ++c)
        (*out)[idx * nc + c] =
            ReadComponent(vv.data + voff + i * elem + c * cs, a.componentType, a.normalized);
    }
  }

  // KHR_texture_transform of a textureInfo; `tex_coord` gets its texCoord override.
  UvTransform ReadUvTransform(const tg::TextureInfo& info, int* tex_coord,
                              const std::string& what) const {
    UvTransform t;
    auto it = info.extensions.find(kTextureTransform);
    if (it == info.extensions.end() || !it->second.IsObject()) return t;
    const tg::Value& v = it->second;
    auto vec2 = [&](const char* key, Eigen::Vector2d* out) {
      if (!v.Has(key)) return;
      const tg::Value& a = v.Get(key);
      if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
        Fail(what + " KHR_texture_transform." + key + " is not two numbers", "", "[x, y]");
      *out = {a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble()};
    };
    vec2("offset", &t.offset);
    vec2("scale", &t.scale);
    if (v.Has("rotation")) {
      if (!v.Get("rotation").IsNumber())
        Fail(what + " KHR_texture_transform.rotation is not a number", "", "radians");
      t.rotation = v.Get("rotation").GetNumberAsDouble();
    }
    if (v.Has("texCoord") && v.Get("texCoord").IsNumber())
      *tex_coord = v.Get("texCoord").GetNumberAsInt();
    if (!t.offset.allFinite() || !t.scale.allFinite() || !std::isfinite(t.rotation))
      Fail(what + " KHR_texture_transform is not finite", "", "finite numbers");
    return t;
  }

  int SceneTexture(int gltf_texture, const std::string& what) {
    if (auto it = texture_map_.find(gltf_texture); it != texture_map_.end()) return it->second;
    if (gltf_texture < 0 || gltf_texture >= static_cast<int>(model_.textures.size()))
      Fail(what + " texture index out of range", std::to_string(gltf_texture),
           Range(model_.textures.size()));
    const tg::Texture& gt = model_.textures[gltf_texture];
    if (gt.source < 0) {  // e.g. only an extension source (KTX2, WebP) we cannot decode
      texture_map_[gltf_texture] = -1;
      return -1;
    }
    if (gt.source >= static_cast<int>(model_.images.size()))
      Fail("texture " + std::to_string(gltf_texture) + " image index out of range",
           std::to_string(gt.source), Range(model_.images.size()));
    const tg::Image& img = model_.images[gt.source];
    Texture tex;
    tex.name = !img.name.empty() ? img.name
               : (!img.uri.empty() && img.uri.rfind("data:", 0) != 0)
                   ? img.uri
                   : "image_" + std::to_string(gt.source);
    std::string error;
    if (!ImageToTexture(img, &tex, &error))
      Fail("image " + std::to_string(gt.source) + " '" + tex.name + "' could not be decoded",
           error + (warnings_.empty() ? "" : " (tinygltf: " + warnings_ + ")"),
           "a PNG or JPEG image");
    if (gt.sampler >= 0) {
      if (gt.sampler >= static_cast<int>(model_.samplers.size()))
        Fail("texture " + std::to_string(gltf_texture) + " sampler index out of range",
             std::to_string(gt.sampler), Range(model_.samplers.size()));
      const tg::Sampler& s = model_.samplers[gt.sampler];
      // One wrap flag in Texture: clamp only when both directions clamp.
      tex.repeat = !(s.wrapS == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE &&
                     s.wrapT == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE);
    }
    scene_->textures.push_back(std::move(tex));
    const int index = static_cast<int>(scene_->textures.size()) - 1;
    texture_map_[gltf_texture] = index;
    return index;
  }

  Material ConvertMaterial(int index) {
    const tg::Material& gm = model_.materials[index];
    const std::string what = "material " + std::to_string(index) + " '" + gm.name + "'";
    Material m;
    m.name = gm.name;
    const auto& pbr = gm.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4)
      for (int i = 0; i < 4; ++i)
        m.base_color[i] = static_cast<float>(std::clamp(pbr.baseColorFactor[i], 0.0, 1.0));
    m.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
    m.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
    if (!m.base_color.allFinite() || !std::isfinite(m.metallic) || !std::isfinite(m.roughness))
      Fail(what + " has non-finite factors", "", "numbers in [0, 1]");
    m.double_sided = gm.doubleSided;
    if (pbr.baseColorTexture.index >= 0)
      m.base_color_texture = SceneTexture(pbr.baseColorTexture.index, what);
    if (auto it = gm.extensions.find(kTransmission);
        it != gm.extensions.end() && it->second.IsObject()) {
      if (it->second.Has("transmissionFactor") && it->second.Get("transmissionFactor").IsNumber())
        m.transmission = static_cast<float>(
            std::clamp(it->second.Get("transmissionFactor").GetNumberAsDouble(), 0.0, 1.0));
    } else if (gm.alphaMode == "BLEND") {
      // No transmission given: a blended, partly transparent surface (how IFC glass arrives
      // through assimp's exporter) lets the rest through.
      m.transmission = 1.0f - m.base_color[3];
    }
    if (gm.extras.IsObject() && gm.extras.Has("nir_reflectance")) {
      const tg::Value& v = gm.extras.Get("nir_reflectance");
      const double r = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!v.IsNumber() || !(r >= 0.0 && r <= 1.0))
        Fail(what + " extras.nir_reflectance is not a reflectance", "", "a number in [0, 1]");
      m.nir_reflectance = static_cast<float>(r);
    }
    return m;
  }

  std::vector<LocalPrimitive> ReadMesh(int mesh_index, const std::vector<double>& weights) const {
    const tg::Mesh& mesh = model_.meshes[mesh_index];
    std::vector<LocalPrimitive> result;
    const bool quantized = Contains(model_.extensionsUsed, kQuantization);
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tg::Primitive& p = mesh.primitives[k];
      const std::string what =
          "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(k);
      const int mode = p.mode == -1 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode < 0 || mode > TINYGLTF_MODE_TRIANGLE_FAN)
        Fail(what + " has an invalid mode", std::to_string(mode), "0..6");
      if (p.material < -1 || p.material >= static_cast<int>(model_.materials.size()))
        Fail(what + " material index out of range", std::to_string(p.material),
             Range(model_.materials.size()));
      // Every referenced accessor must exist, even those we do not read (morph targets).
      for (const auto& target : p.targets)
        for (const auto& [attr, acc] : target) AccessorAt(acc, what + " target " + attr);
      auto pos_it = p.attributes.find("POSITION");
      if (mode < TINYGLTF_MODE_TRIANGLES || pos_it == p.attributes.end())
        continue;  // points and lines have no area; no POSITION: not rendered (glTF 3.7.2.1)
      const tg::Accessor& pa = AccessorAt(pos_it->second, what + " POSITION");
      for (const auto& [attr, acc] : p.attributes) {
        const tg::Accessor& aa = AccessorAt(acc, what + " " + attr);
        if (aa.count != pa.count)
          Fail(what + " attribute " + attr + " count differs from POSITION",
               std::to_string(aa.count), std::to_string(pa.count));
      }
      if (pa.type != TINYGLTF_TYPE_VEC3 ||
          (pa.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !quantized))
        Fail(what + " POSITION accessor has the wrong format",
             "type " + std::to_string(pa.type) + ", componentType " +
                 std::to_string(pa.componentType),
             "VEC3 FLOAT (or KHR_mesh_quantization)");
      const std::vector<double> pos = ReadAccessor(pos_it->second, what + " POSITION");
      const std::size_t nv = pa.count;
      LocalPrimitive lp;
      lp.material = p.material;
      lp.positions.resize(nv);
      for (std::size_t i = 0; i < nv; ++i)
        lp.positions[i] = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
      ApplyMorphTargets(p, weights, what, &lp.positions);

      std::vector<std::uint32_t> idx;
      if (p.indices >= 0) {
        const tg::Accessor& ia = AccessorAt(p.indices, what + " indices");
        if (ia.type != TINYGLTF_TYPE_SCALAR || !IsIndexComponentType(ia.componentType))
          Fail(what + " indices accessor has the wrong format",
               "type " + std::to_string(ia.type) + ", componentType " +
                   std::to_string(ia.componentType),
               "SCALAR of 5121, 5123 or 5125");
        const std::vector<double> raw = ReadAccessor(p.indices, what + " indices");
        idx.resize(raw.size());
        for (std::size_t i = 0; i < raw.size(); ++i) {
          if (raw[i] >= static_cast<double>(nv))
            Fail(what + " index " + std::to_string(i) + " out of range",
                 std::to_string(static_cast<std::uint64_t>(raw[i])), Range(nv));
          idx[i] = static_cast<std::uint32_t>(raw[i]);
        }
      } else {
        idx.resize(nv);
        for (std::size_t i = 0; i < nv; ++i) idx[i] = static_cast<std::uint32_t>(i);
      }
      auto tri = [&](std::size_t a, std::size_t b, std::size_t c) {
        lp.triangles.emplace_back(static_cast<int>(idx[a]), static_cast<int>(idx[b]),
                                  static_cast<int>(idx[c]));
      };
      const std::size_t ni = idx.size();
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (std::size_t i = 0; i + 2 < ni; i += 3) tri(i, i + 1, i + 2);
      } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // glTF 3.7.2.1 strip ordering
        for (std::size_t i = 0; i + 2 < ni; ++i) tri(i, i + 1 + i % 2, i + 2 - i % 2);
      } else {  // fan
        for (std::size_t i = 0; i + 2 < ni; ++i) tri(i + 1, i + 2, 0);
      }
      ReadUvs(p, what, nv, &lp.uvs);
      result.push_back(std::move(lp));
    }
    return result;
  }

  void ApplyMorphTargets(const tg::Primitive& p, const std::vector<double>& weights,
                         const std::string& what, std::vector<Eigen::Vector3d>* pos) const {
    if (p.targets.empty() || weights.empty()) return;  // default weights are 0
    if (weights.size() != p.targets.size())
      Fail(what + " morph weights count differs from its targets", std::to_string(weights.size()),
           std::to_string(p.targets.size()));
    for (std::size_t t = 0; t < p.targets.size(); ++t) {
      auto it = p.targets[t].find("POSITION");
      if (weights[t] == 0.0 || it == p.targets[t].end()) continue;
      const std::string name = what + " target " + std::to_string(t) + " POSITION";
      const tg::Accessor& ta = AccessorAt(it->second, name);
      if (ta.type != TINYGLTF_TYPE_VEC3 || ta.count != pos->size())
        Fail(name + " has the wrong format",
             "type " + std::to_string(ta.type) + ", count " + std::to_string(ta.count),
             "VEC3, count " + std::to_string(pos->size()));
      const std::vector<double> d = ReadAccessor(it->second, name);
      for (std::size_t i = 0; i < pos->size(); ++i)
        (*pos)[i] += weights[t] * Eigen::Vector3d(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
    }
  }

  // UVs of the base colour texture's set, with its KHR_texture_transform applied; without a
  // texture, TEXCOORD_0 as is.
  void ReadUvs(const tg::Primitive& p, const std::string& what, std::size_t nv,
               std::vector<Eigen::Vector2f>* uvs) const {
    int set = 0;
    UvTransform transform;
    if (p.material >= 0) {
      const tg::TextureInfo& info =
          model_.materials[p.material].pbrMetallicRoughness.baseColorTexture;
      if (info.index >= 0) {
        set = info.texCoord;
        transform = ReadUvTransform(info, &set, "material " + std::to_string(p.material));
      }
    }
    auto it = p.attributes.find("TEXCOORD_" + std::to_string(set));
    if (it == p.attributes.end()) return;
    const std::string name = what + " TEXCOORD_" + std::to_string(set);
    const tg::Accessor& ua = AccessorAt(it->second, name);
    if (ua.type != TINYGLTF_TYPE_VEC2)
      Fail(name + " accessor has the wrong type", std::to_string(ua.type), "VEC2");
    const std::vector<double> raw = ReadAccessor(it->second, name);
    uvs->resize(nv);
    const bool identity = transform.IsIdentity();
    for (std::size_t i = 0; i < nv; ++i) {
      const Eigen::Vector2f uv(static_cast<float>(raw[2 * i]), static_cast<float>(raw[2 * i + 1]));
      (*uvs)[i] = identity ? uv : transform.Apply(uv);
    }
  }

  void Instance(int node_index, const Eigen::Matrix4d& world, const Semantic* label) {
    const tg::Node& node = model_.nodes[node_index];
    if (node.mesh < 0 || node.mesh >= static_cast<int>(model_.meshes.size()))
      Fail("node " + std::to_string(node_index) + " mesh index out of range",
           std::to_string(node.mesh), Range(model_.meshes.size()));
    // Instances of one mesh share its decoded primitives unless the node sets its own morph
    // weights.
    std::vector<LocalPrimitive> own;
    const std::vector<LocalPrimitive>* prims;
    if (!node.weights.empty()) {
      own = ReadMesh(node.mesh, node.weights);
      prims = &own;
    } else {
      auto it = mesh_cache_.find(node.mesh);
      if (it == mesh_cache_.end())
        it = mesh_cache_.emplace(node.mesh, ReadMesh(node.mesh, model_.meshes[node.mesh].weights))
                 .first;
      prims = &it->second;
    }
    // A mirroring transform turns counter-clockwise into clockwise: swap to keep CCW = front.
    const bool flip = world.topLeftCorner<3, 3>().determinant() < 0.0;
    for (const LocalPrimitive& lp : *prims) {
      MeshPart part;
      part.name = node.name.empty() ? "node_" + std::to_string(node_index) : node.name;
      if (label) {
        part.element_id = label->id;
        part.element_class = label->element_class;
        part.subclass = label->subclass;
        part.room = label->room;
      }
      part.material = lp.material;
      part.positions.reserve(lp.positions.size());
      for (const Eigen::Vector3d& p : lp.positions)
        part.positions.push_back(
            (world.topLeftCorner<3, 3>() * p + world.topRightCorner<3, 1>()).cast<float>());
      part.uvs = lp.uvs;
      part.triangles = lp.triangles;
      if (flip)
        for (Eigen::Vector3i& t : part.triangles) std::swap(t[1], t[2]);
      scene_->parts.push_back(std::move(part));
    }
  }

 private:
  const tg::Model& model_;
  const std::string& path_;
  const LoadOptions& options_;
  const std::string warnings_;  // tinygltf's, quoted when an image is missing
  Scene* scene_ = nullptr;
  std::map<int, int> texture_map_;
  std::map<int, std::vector<LocalPrimitive>> mesh_cache_;
};

bool StartsWithGlbMagic(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  char magic[4] = {};
  f.read(magic, 4);
  return f.gcount() == 4 && std::memcmp(magic, "glTF", 4) == 0;
}

// Required extensions we can honour: the ones we apply, and material extensions whose other
// parameters only shade (they never change geometry).
bool SupportedRequiredExtension(const std::string& e) {
  return e == kTextureTransform || e == kQuantization || e == kDraco ||
         e == "KHR_lights_punctual" || e.rfind("KHR_materials_", 0) == 0;
}

bool AnyPrimitiveUsesDraco(const tg::Model& model) {
  for (const tg::Mesh& m : model.meshes)
    for (const tg::Primitive& p : m.primitives)
      if (p.extensions.count(kDraco)) return true;
  return false;
}

}  // namespace

Eigen::Vector2f UvTransform::Apply(const Eigen::Vector2f& uv) const {
  const double c = std::cos(rotation), s = std::sin(rotation);
  const double u = scale.x() * uv.x(), v = scale.y() * uv.y();
  return {static_cast<float>(c * u + s * v + offset.x()),
          static_cast<float>(-s * u + c * v + offset.y())};
}

bool UvTransform::IsIdentity() const {
  return offset.isZero(0.0) && rotation == 0.0 && scale == Eigen::Vector2d(1.0, 1.0);
}

bool DecodeImageRgba8(const std::uint8_t* bytes, std::size_t size, Texture* out,
                      std::string* error) {
  if (bytes == nullptr || size == 0 || size > static_cast<std::size_t>(INT_MAX)) {
    *error = "image data is empty or too large (" + std::to_string(size) + " bytes)";
    return false;
  }
  tg::Image img;
  std::string err, warn;
  // nullptr options = tinygltf's default: channels expanded to RGBA.
  if (!tg::LoadImageData(&img, 0, &err, &warn, 0, 0, bytes, static_cast<int>(size), nullptr)) {
    *error = OneLine(err.empty() ? "cannot decode image" : err);
    return false;
  }
  return ImageToTexture(img, out, error);
}

Scene LoadGltf(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(path, "cannot open file", "no such file", "an existing .gltf or .glb file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "cannot open file", "not a regular file", "a .gltf or .glb file");

  tg::TinyGLTF loader;
  tg::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    // A .gltf holding GLB bytes is read as GLB; a .glb is always read as GLB (so a bad magic
    // is reported as such, not as broken JSON).
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    ok = (ext == ".glb" || StartsWithGlbMagic(path))
             ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
             : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {  // allocation failures on absurd byteLengths, json
    ok = false;
    err = e.what();
  }
  // tinygltf parses extensionsUsed/Required before the accessors, so they are known even when
  // it fails on a Draco file's accessors ("accessor[0] invalid bufferView").
  const bool draco =
      Contains(model.extensionsRequired, kDraco) ||
      (Contains(model.extensionsUsed, kDraco) && (!ok || AnyPrimitiveUsesDraco(model)));
  if (draco) {
    if (!options.allow_assimp_fallback)
      throw InputError(path,
                       "Draco-compressed meshes (KHR_draco_mesh_compression) cannot be decoded "
                       "by tinygltf and the assimp fallback is off",
                       "allow_assimp_fallback = false", "true, or an uncompressed glTF");
    return LoadWithAssimp(path, options);
  }
  if (!ok)
    throw InputError(path, "tinygltf cannot read the file",
                     "\"" + OneLine(err.empty() ? warn : err) + "\"", "a valid glTF 2.0 asset");
  for (const std::string& e : model.extensionsRequired)
    if (!SupportedRequiredExtension(e))
      throw InputError(path, "unsupported required glTF extension", e,
                       "KHR_texture_transform, KHR_mesh_quantization, KHR_draco_mesh_compression, "
                       "KHR_materials_*, KHR_lights_punctual");

  Scene scene = GltfSceneBuilder(model, path, options, OneLine(warn)).Build();
  ValidateScene(&scene, options.drop_degenerate_triangles);
  return scene;
}

}  // namespace mopad::scenes
