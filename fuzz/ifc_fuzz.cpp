// `mopad scene import FILE.ifc`: the IFC (ISO 10303-21 STEP text) import, IFC 2x3 through
// assimp, IFC4 through IfcPlusPlus (scenes/bim_import.h); and the property-set reader that
// `mopad eval --model` uses (scenes::ReadIfcProperties, STEP text only).
#include "fuzz/fuzz_input.h"
#include "scenes/bim_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mopad::fuzz::AsFile(data, size, "model.ifc");
  mopad::fuzz::Run([&] { (void)mopad::scenes::ReadIfcProperties(path); });
  return mopad::fuzz::Run([&] { (void)mopad::scenes::ImportBim(path); });
}
