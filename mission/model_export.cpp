#include "mission/model_export.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"

namespace mopad::mission {

void WriteRunJson(const std::string& dir, const sim::SceneWorld& mw, const std::string& room,
                  std::uint64_t seed, const Pose3& X_WM) {
  nlohmann::ordered_json j;
  j["format"] = "mopad-room-run";
  j["version"] = 1;
  j["scene"] = mw.source;
  j["doors"] = mw.door_overrides;
  j["room"] = room;
  j["seed"] = seed;
  nlohmann::ordered_json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back(
        {X_WM.matrix()(r, 0), X_WM.matrix()(r, 1), X_WM.matrix()(r, 2), X_WM.matrix()(r, 3)});
  j["X_WM"] = m;
  j["files"] = {{"sm1", "sm1.ply"},
                {"sm2", "sm2.json"},
                {"sm3", "sm3.json"},
                {"sm4", "sm4.json"},
                {"dsm3", "dsm3.ply"}};
  const std::string path = (std::filesystem::path(dir) / "run.json").string();
  std::ofstream f(path);
  if (!f) throw InputError(path, "cannot write the file");
  f << j.dump(2) << "\n";
}

}  // namespace mopad::mission
