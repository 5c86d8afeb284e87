#pragma once
// glTF 2.0 (.gltf with external or embedded buffers, .glb) through tinygltf 2.7 (Debian).
// What it reads: every triangle primitive (TRIANGLES; strips and fans converted; points and
// lines skipped) instanced by every node of the default scene (`scene`, else scenes[0], else all
// root nodes), flattened to the world frame through the node TRS/matrix hierarchy and then
// mopad::ZupFromYup(); morph targets at their node/mesh weights; sparse accessors applied;
// KHR_texture_transform applied to the UVs; KHR_mesh_quantization's integer attributes;
// materials (base colour factor and texture, metallic, roughness, KHR_materials_transmission,
// doubleSided, extras.nir_reflectance); textures decoded to RGBA8.
// Semantics per node: `extras.mopad {id, class, subclass, room}` (our generator), inherited by
// descendants; else the nearest self-or-ancestor whose name is an assimp-converted IFC name
// `Ifc<Class>_<Name>_<GlobalId>` (not IfcMappedItem) gives class, id and subclass.
// Skins and animations are ignored (the bind pose as placed by the node transforms).
// Draco (KHR_draco_mesh_compression): Debian's tinygltf cannot decode it; such files go through
// assimp when LoadOptions::allow_assimp_fallback (losing node extras), else are rejected.
// Every rejection: mopad::InputError, one line `path: error: what; got X, expected Y`.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenes/scene.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {

/// Loads a .gltf/.glb file (read as GLB if named .glb or starting with the GLB magic) and
/// validates it (ValidateScene). Throws InputError.
Scene LoadGltf(const std::string& path, const LoadOptions& options = {});

/// KHR_texture_transform on one textureInfo: uv' = T(offset) R(rotation) S(scale) uv, where R
/// turns the UVs by `rotation` radians counter-clockwise as seen in the image (v pointing down),
/// i.e. u' = cos*u + sin*v, v' = -sin*u + cos*v: the extension's worked example (offset [0, 1],
/// rotation pi/2, scale 0.5 selects the lower-left quadrant turned clockwise) pins the sign.
struct UvTransform {
  Eigen::Vector2d offset{0.0, 0.0};
  double rotation = 0.0;  ///< rad
  Eigen::Vector2d scale{1.0, 1.0};

  Eigen::Vector2f Apply(const Eigen::Vector2f& uv) const;
  bool IsIdentity() const;
};

/// Decodes a PNG/JPEG/BMP/TGA image (tinygltf's stb_image) into an RGBA8 texture, top row first;
/// 16-bit images are reduced to 8 bits. Returns false and sets `error` if it cannot.
bool DecodeImageRgba8(const std::uint8_t* bytes, std::size_t size, Texture* out,
                      std::string* error);

}  // namespace mopad::scenes
