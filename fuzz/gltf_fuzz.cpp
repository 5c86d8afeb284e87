// A .glb/.gltf scene (`mopad scene info|validate`, `--scene`): LoadGltf reads GLB when the
// input starts with the GLB magic, else glTF JSON, and validates the mesh (scenes/gltf_loader.h).
#include "fuzz/fuzz_input.h"
#include "scenes/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mopad::fuzz::AsFile(data, size, "scene.gltf");
  return mopad::fuzz::Run([&] { (void)mopad::scenes::LoadGltf(path); });
}
