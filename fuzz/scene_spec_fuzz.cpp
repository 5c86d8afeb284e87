// `mopad scene generate SPEC`: the scene spec YAML parsed and validated (scenes/scene_spec.h),
// then generated when it is accepted (a spec that passes validation must generate).
#include "fuzz/fuzz_input.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return mopad::fuzz::Run([&] {
    const mopad::scenes::SceneSpec spec =
        mopad::scenes::ParseSceneSpec(mopad::fuzz::AsString(data, size), "fuzz.yaml");
    (void)mopad::scenes::Generate(spec);
  });
}
