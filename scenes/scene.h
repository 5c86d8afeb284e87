#pragma once
// In-memory scene: triangle geometry in the world frame (Z-up, metres), materials, textures and
// the semantic label of every triangle. Loaders (glTF, assimp) produce it; the generator builds
// it; the simulator ray-casts it. It is ground truth: the robot's libraries never see it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "scenes/element_class.h"

namespace mopad::scenes {

/// An RGBA8 image, row-major, top row first (glTF UV (0,0) is the top-left corner).
struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< width * height * 4 bytes
  bool repeat = true;              ///< wrap mode (false: clamp to edge)
};

struct Material {
  std::string name;
  Eigen::Vector4f base_color{0.8f, 0.8f, 0.8f, 1.0f};  ///< linear RGBA factor, [0, 1]
  int base_color_texture = -1;                         ///< index into Scene::textures, -1 = none
  float metallic = 0.0f;                               ///< [0, 1]
  float roughness = 1.0f;     ///< [0, 1]; low roughness + metallic = specular (scanner dropouts)
  float transmission = 0.0f;  ///< [0, 1], probability a laser ray passes (glass); glTF
                              ///< KHR_materials_transmission
  float nir_reflectance = -1.0f;  ///< [0, 1] at the scanner's wavelength; < 0 = derive from colour
  bool double_sided = true;
};

/// One glTF primitive instanced by one node, flattened to the world frame.
struct MeshPart {
  std::string name;        ///< node name (glTF) or node path (assimp)
  std::string element_id;  ///< truth id ("wall_R1_2", IFC GlobalId-based name); "" if none
  ElementClass element_class = ElementClass::kUnknown;
  std::string subclass;  ///< BSC class ("socket_x1"), furniture type, or the IFC entity name
  std::string room;      ///< room id for generated scenes; "" if unknown
  int material = -1;     ///< index into Scene::materials, -1 = default grey
  std::vector<Eigen::Vector3f> positions;  ///< world frame, Z-up, metres
  std::vector<Eigen::Vector2f> uvs;        ///< empty, or one per position (transforms applied)
  std::vector<Eigen::Vector3i> triangles;  ///< indices into positions, CCW = front
};

struct Scene {
  std::string source;  ///< file it was loaded from, for messages
  std::vector<MeshPart> parts;
  std::vector<Material> materials;
  std::vector<Texture> textures;

  std::size_t TriangleCount() const;
  Eigen::AlignedBox3d Bounds() const;
};

}  // namespace mopad::scenes
