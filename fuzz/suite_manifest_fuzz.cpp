// `mopad suite run MANIFEST`: the suite manifest YAML (suite/manifest.h, ParseManifest).
#include "fuzz/fuzz_input.h"
#include "suite/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return mopad::fuzz::Run(
      [&] { (void)mopad::suite::ParseManifest(mopad::fuzz::AsString(data, size), "fuzz.yaml"); });
}
