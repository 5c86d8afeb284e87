#include "mission/floor_model_job.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "common/error.h"
#include "modelling/model_io.h"

namespace mopad::mission {

bool WriteFloorModel(autonomy::FloorScanResult& mission, const modelling::FloorModelParams& params,
                     const std::string& dir,
                     const std::function<void(const std::string&)>& progress) {
  std::vector<modelling::StructuralModel> sm3;
  std::vector<modelling::Sm4Model> sm4;
  for (const autonomy::FloorRoom& r : mission.rooms) {
    if (!r.error.empty()) continue;
    sm3.push_back(r.sm3);
    sm4.push_back(r.sm4);
  }
  const std::filesystem::path floor = std::filesystem::path(dir) / "floor";
  if (sm3.empty()) {
    if (progress) progress("floor model not written: no room was modelled");
    return false;
  }
  try {
    const modelling::FloorModel model = modelling::BuildFloorModel(sm3, sm4, params);
    std::error_code ec;
    std::filesystem::create_directories(floor, ec);
    if (ec) throw InputError(floor.string(), "cannot create the folder", ec.message());
    modelling::WriteFloorModelFiles(floor.string(), model);
    const std::vector<std::string> changed = modelling::ShareDoors(model, sm4);
    for (autonomy::FloorRoom& r : mission.rooms) {
      if (!r.error.empty() ||
          std::find(changed.begin(), changed.end(), r.sm4.room) == changed.end())
        continue;
      for (const modelling::Sm4Model& m : sm4)
        if (m.room == r.sm4.room) r.sm4 = m;
    }
    return true;
  } catch (const InputError& e) {
    // A half-written floor/ would be read by the exports and the evaluator as the floor's model.
    std::error_code ec;
    std::filesystem::remove_all(floor, ec);
    if (progress) progress(std::string("floor model not written: ") + e.what());
    return false;
  }
}

}  // namespace mopad::mission
