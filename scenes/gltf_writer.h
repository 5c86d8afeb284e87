#pragma once
// Writes a Scene as a binary glTF 2.0 file (.glb) with exact per-triangle semantics
// (docs/scene-format.md): one root node carrying the Z-up -> Y-up rotation (quaternion
// [-0.7071068, 0, 0, 0.7071068], mopad::YupFromZup()) and one child node per MeshPart whose
// `extras` hold {"mopad": {"id", "class", "subclass", "room"}}. Positions stay in the world
// frame (metres) inside the root. Materials are glTF PBR metallic-roughness; glass uses
// KHR_materials_transmission; `nir_reflectance` goes to material extras; textures are embedded
// as PNG. The output is byte-deterministic: the same Scene gives the same bytes.

#include <cstdint>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace mopad::scenes {

/// Writes `scene` to `path` (.glb). Throws InputError if the file cannot be written and
/// std::invalid_argument for scenes with out-of-range indices or non-finite positions.
void WriteGlb(const Scene& scene, const std::string& path);

/// Encodes an RGBA8 texture as PNG (uncompressed deflate blocks; RGB when fully opaque).
/// Deterministic and dependency-free.
std::vector<std::uint8_t> EncodePng(const Texture& texture);

}  // namespace mopad::scenes
