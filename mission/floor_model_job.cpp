#include "mission/floor_model_job.h"

#include <filesystem>
#include <system_error>

#include "common/error.h"
#include "modelling/model_io.h"

namespace mopad::mission {

modelling::FloorModel WriteFloorModel(const autonomy::FloorScanResult& mission,
                                      const modelling::FloorModelParams& params,
                                      const std::string& dir) {
  std::vector<modelling::StructuralModel> sm3;
  std::vector<modelling::Sm4Model> sm4;
  for (const autonomy::FloorRoom& r : mission.rooms) {
    if (!r.error.empty()) continue;
    sm3.push_back(r.sm3);
    sm4.push_back(r.sm4);
  }
  const modelling::FloorModel model = modelling::BuildFloorModel(sm3, sm4, params);
  const std::filesystem::path floor = std::filesystem::path(dir) / "floor";
  std::error_code ec;
  std::filesystem::create_directories(floor, ec);
  if (ec) throw InputError(floor.string(), "cannot create the folder", ec.message());
  modelling::WriteFloorModelFiles(floor.string(), model);
  return model;
}

}  // namespace mopad::mission
