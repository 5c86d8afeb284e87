#include "scenes/assimp_loader.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Core>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/child_reader.h"
#include "scenes/gltf_loader.h"
#include "scenes/ifc4_loader.h"
#include "scenes/mesh_validation.h"

namespace mopad::scenes {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string Upper(std::string_view v) {
  std::string s(v);
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}

std::string OneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open file", "unreadable", "a readable file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// --- STEP (ISO 10303-21) scraps: just enough to read an IFC unit assignment. ---

// The body "IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.)" of entity instance `#id = ...;` or "".
std::string_view EntityBody(std::string_view text, unsigned long id) {
  std::string key(1, '#');  // not "#" + to_string(): GCC 12 warns falsely (-Wrestrict)
  key += std::to_string(id);
  for (std::size_t pos = text.find(key); pos != std::string_view::npos;
       pos = text.find(key, pos + 1)) {
    std::size_t i = pos + key.size();
    if (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) continue;  // #140
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i >= text.size() || text[i] != '=') continue;  // a reference, not the definition
    ++i;
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    // Up to the ';' that ends the instance, skipping quoted strings ('' is an escaped quote).
    bool quoted = false;
    for (std::size_t j = i; j < text.size(); ++j) {
      if (text[j] == '\'')
        quoted = !quoted;
      else if (text[j] == ';' && !quoted)
        return text.substr(i, j - i);
    }
    return {};
  }
  return {};
}

std::string EntityName(std::string_view body) {
  std::size_t n = 0;
  while (n < body.size() && (std::isalnum(static_cast<unsigned char>(body[n])) || body[n] == '_'))
    ++n;
  return Upper(body.substr(0, n));
}

// "#12" references in order of appearance.
std::vector<unsigned long> References(std::string_view s) {
  std::vector<unsigned long> refs;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '#') continue;
    std::size_t j = i + 1;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i + 1) refs.push_back(std::stoul(std::string(s.substr(i + 1, j - i - 1))));
    i = j - 1;
  }
  return refs;
}

double SiPrefixScale(std::string_view body) {
  static const std::pair<const char*, double> kPrefixes[] = {
      {".EXA.", 1e18},  {".PETA.", 1e15},  {".TERA.", 1e12},   {".GIGA.", 1e9},
      {".MEGA.", 1e6},  {".KILO.", 1e3},   {".HECTO.", 1e2},   {".DECA.", 1e1},
      {".DECI.", 1e-1}, {".CENTI.", 1e-2}, {".MILLI.", 1e-3},  {".MICRO.", 1e-6},
      {".NANO.", 1e-9}, {".PICO.", 1e-12}, {".FEMTO.", 1e-15}, {".ATTO.", 1e-18}};
  const std::string up = Upper(body);
  for (const auto& [name, scale] : kPrefixes)
    if (up.find(name) != std::string::npos) return scale;
  return 1.0;
}

std::string Truncate(std::string_view s) {
  return std::string(s.substr(0, 120)) + (s.size() > 120 ? "..." : "");
}

}  // namespace

std::string IfcSchemaOf(std::string_view step_text) {
  // The HEADER section is tiny; never scan the DATA section (a string could mention anything).
  std::size_t end = step_text.find("DATA;");
  const std::string header = Upper(step_text.substr(0, std::min(end, std::size_t{65536})));
  const std::size_t pos = header.find("FILE_SCHEMA");
  if (pos == std::string::npos) return "";
  const std::size_t open = header.find('\'', pos);
  if (open == std::string::npos) return "";
  const std::size_t close = header.find('\'', open + 1);
  if (close == std::string::npos) return "";
  return header.substr(open + 1, close - open - 1);
}

double IfcUnappliedLengthScale(std::string_view text, const std::string& where) {
  // Find the instance "#n= IFCUNITASSIGNMENT((#a,#b,...));" (the project's units).
  std::size_t pos = std::string_view::npos;
  for (std::size_t p = text.find("IFCUNITASSIGNMENT"); p != std::string_view::npos;
       p = text.find("IFCUNITASSIGNMENT", p + 1)) {
    // Must be the entity of an instance: preceded (after spaces) by '='.
    std::size_t b = p;
    while (b > 0 && std::isspace(static_cast<unsigned char>(text[b - 1]))) --b;
    if (b > 0 && text[b - 1] == '=') {
      pos = p;
      break;
    }
  }
  if (pos == std::string_view::npos) return 1.0;
  const std::size_t semi = text.find(';', pos);
  const std::string_view assignment =
      text.substr(pos, semi == std::string_view::npos ? std::string_view::npos : semi - pos);
  for (unsigned long ref : References(assignment)) {
    const std::string_view unit = EntityBody(text, ref);
    if (Upper(unit).find(".LENGTHUNIT.") == std::string::npos) continue;
    const std::string name = EntityName(unit);
    if (name == "IFCSIUNIT") return 1.0;  // assimp applies SI prefixes itself
    if (name != "IFCCONVERSIONBASEDUNIT")
      throw InputError(where, "unsupported IFC length unit entity", Truncate(unit),
                       "IFCSIUNIT or IFCCONVERSIONBASEDUNIT");
    // IFCCONVERSIONBASEDUNIT(#dims, .LENGTHUNIT., 'FOOT', #measure_with_unit)
    const std::vector<unsigned long> refs = References(unit);
    const std::string_view mwu = refs.empty() ? std::string_view{} : EntityBody(text, refs.back());
    if (EntityName(mwu) != "IFCMEASUREWITHUNIT")
      throw InputError(where, "cannot read the IFC conversion-based length unit", Truncate(unit),
                       "IFCCONVERSIONBASEDUNIT(#d,.LENGTHUNIT.,'NAME',#IFCMEASUREWITHUNIT)");
    // IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(0.3048),#si_unit): the value is the first number
    // after the innermost '(' (or directly after the first '(' if untyped).
    std::size_t open = mwu.find('(');
    const std::size_t inner = mwu.find('(', open + 1);
    const std::size_t comma = mwu.find(',', open + 1);
    if (inner != std::string_view::npos && (comma == std::string_view::npos || inner < comma))
      open = inner;
    const std::string number(mwu.substr(open + 1, 40));
    char* end = nullptr;
    const double value = std::strtod(number.c_str(), &end);
    const std::vector<unsigned long> mwu_refs = References(mwu);
    const std::string_view si =
        mwu_refs.empty() ? std::string_view{} : EntityBody(text, mwu_refs.back());
    if (end == number.c_str() || !std::isfinite(value) || value <= 0.0 ||
        EntityName(si) != "IFCSIUNIT")
      throw InputError(where, "cannot read the IFC length conversion factor", Truncate(mwu),
                       "IFCMEASUREWITHUNIT(IFCLENGTHMEASURE(factor),#IFCSIUNIT)");
    return value * SiPrefixScale(si);
  }
  return 1.0;
}

std::string IfcClassFromNodeName(std::string_view name) {
  if (name.size() < 4 || name.substr(0, 3) != "Ifc" ||
      !std::isupper(static_cast<unsigned char>(name[3])))
    return "";
  const std::string_view token = name.substr(0, name.find('_'));
  for (char c : token)
    if (!std::isalnum(static_cast<unsigned char>(c))) return "";
  return std::string(token);
}

namespace {

class AssimpSceneBuilder {
 public:
  AssimpSceneBuilder(const aiScene& ai, const std::string& path, const Eigen::Matrix4d& fix)
      : ai_(ai), path_(path), fix_(fix) {}

  Scene Build() {
    Scene scene;
    scene.source = path_;
    scene_ = &scene;
    for (unsigned i = 0; i < ai_.mNumMaterials; ++i) {
      uv_channel_.push_back(0);
      scene.materials.push_back(ConvertMaterial(i));
    }
    struct Frame {
      const aiNode* node;
      Eigen::Matrix4d parent;
      std::string path;
      const aiNode* ifc;  // nearest self-or-ancestor IFC element node
    };
    std::vector<Frame> stack{{ai_.mRootNode, fix_, "", nullptr}};
    while (!stack.empty()) {
      Frame f = std::move(stack.back());
      stack.pop_back();
      const aiNode* n = f.node;
      if (n == nullptr) continue;
      if (++visited_ > kMaxNodes)
        throw InputError(path_, "node hierarchy too large or cyclic",
                         "more than " + std::to_string(kMaxNodes) + " nodes", "a tree");
      Eigen::Matrix4d local;
      const aiMatrix4x4& m = n->mTransformation;
      local << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2,
          m.d3, m.d4;
      const Eigen::Matrix4d world = f.parent * local;
      const std::string name = n->mName.C_Str();
      const std::string node_path = f.path.empty() ? name : f.path + "/" + name;
      const aiNode* ifc = f.ifc;
      if (const std::string cls = IfcClassFromNodeName(name);
          !cls.empty() && cls != "IfcMappedItem")
        ifc = n;
      for (unsigned i = 0; i < n->mNumMeshes; ++i) AddMesh(n->mMeshes[i], world, node_path, ifc);
      for (unsigned c = n->mNumChildren; c-- > 0;)
        stack.push_back({n->mChildren[c], world, node_path, ifc});
    }
    return scene;
  }

 private:
  static constexpr std::size_t kMaxNodes = 10'000'000;

  void AddMesh(unsigned mesh_index, const Eigen::Matrix4d& world, const std::string& node_path,
               const aiNode* ifc) {
    if (mesh_index >= ai_.mNumMeshes)
      throw InputError(path_, "node '" + node_path + "' mesh index out of range",
                       std::to_string(mesh_index), "< " + std::to_string(ai_.mNumMeshes));
    const aiMesh* mesh = ai_.mMeshes[mesh_index];
    MeshPart part;
    part.name = node_path;
    if (ifc != nullptr) {
      part.element_id = ifc->mName.C_Str();
      part.subclass = IfcClassFromNodeName(part.element_id);
      part.element_class = FromIfcClass(part.subclass);
    }
    part.material =
        mesh->mMaterialIndex < ai_.mNumMaterials ? static_cast<int>(mesh->mMaterialIndex) : -1;
    const Eigen::Matrix3d r = world.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = world.topRightCorner<3, 1>();
    part.positions.resize(mesh->mNumVertices);
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D& v = mesh->mVertices[i];
      part.positions[i] = (r * Eigen::Vector3d(v.x, v.y, v.z) + t).cast<float>();
    }
    const unsigned channel = part.material >= 0 ? uv_channel_[part.material] : 0;
    if (channel < AI_MAX_NUMBER_OF_TEXTURECOORDS && mesh->mTextureCoords[channel] != nullptr) {
      part.uvs.resize(mesh->mNumVertices);
      for (unsigned i = 0; i < mesh->mNumVertices; ++i)
        part.uvs[i] = {mesh->mTextureCoords[channel][i].x, mesh->mTextureCoords[channel][i].y};
    }
    const bool flip = r.determinant() < 0.0;  // mirrored: keep CCW = front
    part.triangles.reserve(mesh->mNumFaces);
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines (Triangulate did the polygons)
      Eigen::Vector3i tri;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices)
          throw InputError(
              path_, "mesh '" + std::string(mesh->mName.C_Str()) + "' face index out of range",
              std::to_string(face.mIndices[k]), "< " + std::to_string(mesh->mNumVertices));
        tri[k] = static_cast<int>(face.mIndices[k]);
      }
      if (flip) std::swap(tri[1], tri[2]);
      part.triangles.push_back(tri);
    }
    scene_->parts.push_back(std::move(part));
  }

  Material ConvertMaterial(unsigned index) {
    const aiMaterial* am = ai_.mMaterials[index];
    Material m;
    aiString name;
    if (am->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
    aiColor4D c;
    if (am->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS ||
        am->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
      m.base_color = Eigen::Vector4f(c.r, c.g, c.b, c.a).cwiseMax(0.0f).cwiseMin(1.0f);
    float opacity = 1.0f;
    if (am->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && std::isfinite(opacity))
      m.base_color[3] = std::clamp(opacity, 0.0f, 1.0f) * m.base_color[3];
    float f = 0.0f;
    if (am->Get(AI_MATKEY_METALLIC_FACTOR, f) == AI_SUCCESS && std::isfinite(f))
      m.metallic = std::clamp(f, 0.0f, 1.0f);
    if (am->Get(AI_MATKEY_ROUGHNESS_FACTOR, f) == AI_SUCCESS && std::isfinite(f))
      m.roughness = std::clamp(f, 0.0f, 1.0f);
    if (am->Get(AI_MATKEY_TRANSMISSION_FACTOR, f) == AI_SUCCESS && std::isfinite(f))
      m.transmission = std::clamp(f, 0.0f, 1.0f);
    else if (m.base_color[3] < 1.0f)
      m.transmission = 1.0f - m.base_color[3];  // IFC glass: only a transparency is given
    int two_sided = 1;
    if (am->Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) m.double_sided = two_sided != 0;
    aiString tex_path;
    unsigned uv_index = 0;
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      if (am->GetTextureCount(type) == 0) continue;
      if (am->GetTexture(type, 0, &tex_path, nullptr, &uv_index) != AI_SUCCESS) continue;
      m.base_color_texture = SceneTexture(tex_path.C_Str(), "material '" + m.name + "'");
      uv_channel_[index] = uv_index;
      break;
    }
    return m;
  }

  int SceneTexture(const std::string& ref, const std::string& what) {
    if (auto it = texture_map_.find(ref); it != texture_map_.end()) return it->second;
    Texture tex;
    tex.name = ref;
    std::string error;
    bool ok = false;
    if (const aiTexture* emb = ai_.GetEmbeddedTexture(ref.c_str())) {
      if (emb->mHeight == 0) {  // compressed (PNG/JPEG) bytes, mWidth of them
        ok = DecodeImageRgba8(reinterpret_cast<const std::uint8_t*>(emb->pcData), emb->mWidth, &tex,
                              &error);
      } else {  // raw BGRA texels
        tex.width = static_cast<int>(emb->mWidth);
        tex.height = static_cast<int>(emb->mHeight);
        const std::size_t n = static_cast<std::size_t>(emb->mWidth) * emb->mHeight;
        tex.rgba.resize(n * 4);
        for (std::size_t i = 0; i < n; ++i) {
          const aiTexel& t = emb->pcData[i];
          tex.rgba[4 * i] = t.r;
          tex.rgba[4 * i + 1] = t.g;
          tex.rgba[4 * i + 2] = t.b;
          tex.rgba[4 * i + 3] = t.a;
        }
        ok = true;
      }
    } else {
      const std::filesystem::path file =
          std::filesystem::path(path_).parent_path() / std::filesystem::path(ref);
      std::error_code ec;
      if (!std::filesystem::is_regular_file(file, ec)) {
        error = "file " + file.string() + " not found";
      } else {
        const std::string bytes = ReadWholeFile(file.string());
        ok = DecodeImageRgba8(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                              &tex, &error);
      }
    }
    if (!ok)
      throw InputError(path_, what + " texture '" + ref + "' could not be loaded", error,
                       "a readable PNG or JPEG image");
    scene_->textures.push_back(std::move(tex));
    const int index = static_cast<int>(scene_->textures.size()) - 1;
    texture_map_[ref] = index;
    return index;
  }

  const aiScene& ai_;
  const std::string& path_;
  Eigen::Matrix4d fix_;
  Scene* scene_ = nullptr;
  std::vector<unsigned> uv_channel_;  // per material: UV set of its base colour texture
  std::map<std::string, int> texture_map_;
  std::size_t visited_ = 0;
};

}  // namespace

Scene LoadWithAssimp(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(path, "cannot open file", "no such file", "an existing scene file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "cannot open file", "not a regular file", "a scene file");
  const std::string ext = Lower(std::filesystem::path(path).extension().string());

  double unit_scale = 1.0;
  if (ext == ".ifc") {
    const std::string text = ReadWholeFile(path);
    const std::string schema = IfcSchemaOf(text);
    if (schema.empty())
      throw InputError(path, "not an IFC STEP file (no FILE_SCHEMA in its header)", "",
                       "ISO-10303-21 with FILE_SCHEMA(('IFC2X3'))");
    // assimp 5.2.5 reads IFC 2x3 only and segfaults on some IFC4 files: IFC4 goes to
    // IfcPlusPlus (scenes/ifc4_loader.h).
    if (schema.rfind("IFC4", 0) == 0) return LoadIfc4(path, options);
    if (schema.rfind("IFC2X", 0) != 0)
      throw InputError(path, "unsupported IFC schema", schema, "IFC2X3 or IFC4");
    unit_scale = IfcUnappliedLengthScale(text, path);
  }

  const auto read = [&] {
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_IFC_SKIP_SPACE_REPRESENTATIONS,
                             !options.import_ifc_spaces);
    importer.SetPropertyBool(AI_CONFIG_FBX_CONVERT_TO_M, true);  // FBX centimetres -> metres
    // No PreTransformVertices: it merges meshes and drops the node names IFC classes live in.
    // FlipUVs: assimp keeps UVs with a bottom-left origin; ours (and glTF's) is top-left.
    const unsigned flags =
        aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_FlipUVs;
    const aiScene* ai = importer.ReadFile(path, flags);
    if (ai == nullptr)
      throw InputError(path, "assimp cannot read the file",
                       "\"" + OneLine(importer.GetErrorString()) + "\"",
                       "a valid " + (ext.empty() ? std::string("scene") : ext.substr(1)) + " file");
    if ((ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || ai->mRootNode == nullptr)
      throw InputError(path, "assimp returned an incomplete scene", "", "a scene with meshes");

    bool y_up = ext != ".stl";
    if (options.up_axis == UpAxis::kY) y_up = true;
    if (options.up_axis == UpAxis::kZ) y_up = false;
    Eigen::Matrix4d fix = Eigen::Matrix4d::Identity();
    if (y_up) fix.topLeftCorner<3, 3>() = ZupFromYup();
    fix.topLeftCorner<3, 3>() *= unit_scale;

    AssimpSceneBuilder builder(*ai, path, fix);
    return builder.Build();
  };
  // assimp's IFC 2x3 reader segfaults on some hostile files (found by fuzzing,
  // docs/reliability.md): it runs in a child process, as the IFC4 reader does.
  Scene scene = ext == ".ifc" ? ReadSceneInChild(path, "the IFC 2x3 reader (assimp)",
                                                 "an IFC 2x3 file it can read", read)
                              : read();
  ValidateScene(&scene, options.drop_degenerate_triangles);
  return scene;
}

}  // namespace mopad::scenes
