#pragma once
// Binary glTF 2.0 (.glb) of triangle meshes with per-node semantics: the robot's models (and
// later the semantic export). Written directly (JSON chunk + binary chunk): tinygltf reads scene
// files and stays on the truth side. Z-up data: one root node carries the Z-up -> Y-up rotation
// (quaternion [-0.7071068, 0, 0, 0.7071068], glTF's x, y, z, w); positions stay in the model's
// frame (metres) inside it. One child node per mesh, named, with its `extras`. Materials are
// glTF PBR metallic-roughness (base colour, metallic 0, roughness 1; alpha blend when alpha < 1).
// Deterministic: the same scene gives the same bytes.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mopad::io {

struct GlbMaterial {
  std::string name;
  std::array<float, 4> base_color{0.8f, 0.8f, 0.8f, 1.0f};  ///< linear RGBA, [0, 1]
};

struct GlbMesh {
  std::string name;                                     ///< node and mesh name
  int material = 0;                                     ///< index into GlbScene::materials
  std::vector<Eigen::Vector3f> positions;               ///< m, Z-up model frame
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside
  nlohmann::ordered_json extras = nlohmann::ordered_json::object();  ///< the node's extras
};

struct GlbScene {
  std::string name;  ///< the glTF scene's name
  std::vector<GlbMaterial> materials;
  std::vector<GlbMesh> meshes;
};

/// Writes `scene` to `path`. Throws InputError for a mesh with no triangles, an index out of
/// range, a non-finite position or a material index out of range, and when the file cannot be
/// written.
void WriteGlb(const GlbScene& scene, const std::string& path);

}  // namespace mopad::io
