// The run-folder files `mopad eval` and `mopad export` read (a truncated or hostile file in a
// run folder): run.json (runfolder/run_record.h) and the models sm3.json, sm4.json, sm5.json and
// the floor model (modelling/model_io.h, sm5_io.h). Every reader gets the same bytes; each
// rejects what is not its format.
#include "fuzz/fuzz_input.h"
#include "modelling/model_io.h"
#include "modelling/sm5_io.h"
#include "runfolder/run_record.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mopad;
  const std::string text = fuzz::AsString(data, size);
  const std::string path = fuzz::AsFile(data, size, "run.json");
  fuzz::Run([&] { (void)runfolder::ReadRunJson(path); });
  fuzz::Run([&] { (void)modelling::ParseSm3(text, "sm3.json"); });
  fuzz::Run([&] { (void)modelling::ParseSm4(text, "sm4.json"); });
  fuzz::Run([&] { (void)modelling::ParseSm5(text, "sm5.json"); });
  return fuzz::Run(
      [&] { (void)modelling::ParseFloorModel(text, "floor/sm3.json", text, "floor/sm4.json"); });
}
