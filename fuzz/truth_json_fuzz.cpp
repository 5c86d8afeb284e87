// scene.truth.json (the ground-truth sidecar every scene folder carries): ReadGroundTruth, as
// `mopad eval`, `mopad run --scene` and `mopad scene validate` read it.
#include "fuzz/fuzz_input.h"
#include "scenes/ground_truth.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mopad::fuzz::AsFile(data, size, "scene.truth.json");
  return mopad::fuzz::Run([&] { (void)mopad::scenes::ReadGroundTruth(path); });
}
