// `mopad run --config FILE`: FloorMissionParams loaded from YAML and validated as the CLI does
// (common/params.h: unknown keys, types, bounds, every nested struct's own Validate()).
#include "common/params.h"
#include "fuzz/fuzz_input.h"
#include "mission/floor_job.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return mopad::fuzz::Run([&] {
    const YAML::Node node = mopad::LoadYamlString(mopad::fuzz::AsString(data, size), "fuzz.yaml");
    const auto params = mopad::LoadParams<mopad::mission::FloorMissionParams>(node, "fuzz.yaml");
    mopad::ValidateParams(params, "room.");
  });
}
