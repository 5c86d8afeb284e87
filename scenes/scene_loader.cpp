#include "scenes/scene_loader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>

#include "common/error.h"
#include "scenes/assimp_loader.h"
#include "scenes/gltf_loader.h"

namespace mopad::scenes {

Scene LoadScene(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(path, "cannot open file", "no such file", "an existing scene file");
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") return LoadGltf(path, options);
  constexpr std::array<std::string_view, 6> kAssimp{".obj", ".ply", ".fbx", ".dae", ".stl", ".ifc"};
  if (std::find(kAssimp.begin(), kAssimp.end(), ext) != kAssimp.end())
    return LoadWithAssimp(path, options);
  throw InputError(path, "unsupported file extension", ext.empty() ? "none" : "'" + ext + "'",
                   ".gltf, .glb, .obj, .ply, .fbx, .dae, .stl or .ifc");
}

}  // namespace mopad::scenes
