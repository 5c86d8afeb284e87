#include "exports/run_folder.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/rng.h"
#include "modelling/model_io.h"
#include "runfolder/layout.h"
#include "runfolder/run_record.h"

namespace mopad::exports {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string ReadText(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path.string(), "cannot read the file");
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

Json ParseJson(const std::string& text, const std::string& where) {
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, "not valid JSON", e.what());
  }
}

const Json& Need(const Json& j, const char* key, const std::string& where, const std::string& ctx) {
  if (!j.is_object() || !j.contains(key)) throw InputError(where, ctx + key + ": missing field");
  return j.at(key);
}

double Number(const Json& v, const std::string& where, const std::string& name) {
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(where, name + ": wrong type", v.dump(), "a finite number");
  return v.get<double>();
}

std::string Text(const Json& v, const std::string& where, const std::string& name) {
  if (!v.is_string()) throw InputError(where, name + ": wrong type", v.dump(), "a string");
  return v.get<std::string>();
}

Eigen::Vector3d Vector(const Json& v, const std::string& where, const std::string& name,
                       std::size_t min_size = 3) {
  if (!v.is_array() || v.size() < min_size || v.size() > 3)
    throw InputError(where, name + ": wrong shape", v.dump(), "[x, y, z]");
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < v.size(); ++a) out[a] = Number(v[a], where, name);
  return out;
}

// X_WM of the room's run.json; none when the room has no run.json.
std::optional<Eigen::Isometry3d> ReadXwm(const fs::path& room_dir) {
  const std::string path = runfolder::Join(room_dir.string(), runfolder::kRunJson);
  if (!fs::exists(path)) return std::nullopt;
  return runfolder::ReadRunJson(path).X_WM;
}

std::vector<double> ReadScanTimes(const fs::path& scans_json) {
  std::vector<double> times;
  if (!fs::exists(scans_json)) return times;
  const std::string where = scans_json.string();
  const Json j = ParseJson(ReadText(scans_json), where);
  const Json& scans = Need(j, "scans", where, "");
  if (!scans.is_array()) throw InputError(where, "scans: wrong type", "", "an array");
  for (const Json& s : scans) {
    const int index = static_cast<int>(Number(Need(s, "index", where, "scans[]."), where, "index"));
    if (index < 0 || index > 65535) throw InputError(where, "scans[].index out of range");
    if (times.size() <= static_cast<std::size_t>(index)) times.resize(index + 1, 0.0);
    times[index] = Number(Need(s, "sim_time", where, "scans[]."), where, "sim_time");
  }
  return times;
}

// Reads the model files of `dir`; `key` accumulates a hash of their bytes.
ModelSet ReadModelSet(const fs::path& dir, const std::string& id, std::uint64_t& key) {
  ModelSet s;
  s.id = id;
  s.dir = dir.string();
  auto absorb = [&key](const std::string& text) {
    key = DeriveKey(key, HashName(text));
    return text;
  };
  const std::string sm3_text = absorb(ReadText(dir / runfolder::kSm3));
  s.sm3 = modelling::ParseSm3(sm3_text, (dir / runfolder::kSm3).string());
  for (const Json& p : ParseJson(sm3_text, (dir / runfolder::kSm3).string()).value("patches", Json()))
    if (p.is_object() && p.contains("thickness_m") && p["thickness_m"].is_number() &&
        p.contains("id") && p["id"].is_string())
      s.wall_thickness[p["id"].get<std::string>()] = p["thickness_m"].get<double>();
  if (fs::exists(dir / runfolder::kSm4))
    s.sm4 = modelling::ParseSm4(absorb(ReadText(dir / runfolder::kSm4)), (dir / runfolder::kSm4).string());
  if (fs::exists(dir / runfolder::kSm5))
    s.sm5 = ParseSm5(absorb(ReadText(dir / runfolder::kSm5)), (dir / runfolder::kSm5).string());
  if (fs::exists(dir / runfolder::kSm1)) s.sm1_path = (dir / runfolder::kSm1).string();
  s.scan_times = ReadScanTimes(dir / runfolder::kScansLog);
  return s;
}

}  // namespace

Sm5Model ParseSm5(const std::string& text, const std::string& where) {
  const Json j = ParseJson(text, where);
  if (Text(Need(j, "format", where, ""), where, "format") != "mopad-sm5")
    throw InputError(where, "format: not an SM5 file", j["format"].dump(), "\"mopad-sm5\"");
  if (Number(Need(j, "version", where, ""), where, "version") != 1)
    throw InputError(where, "version: unsupported", j["version"].dump(), "1");
  Sm5Model m;
  m.room = Text(Need(j, "room", where, ""), where, "room");
  const Json& cs = Need(j, "components", where, "");
  if (!cs.is_array()) throw InputError(where, "components: wrong type", "", "an array");
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const std::string ctx = "components[" + std::to_string(i) + "].";
    const Json& jc = cs[i];
    ServiceComponent c;
    c.id = Text(Need(jc, "id", where, ctx), where, ctx + "id");
    c.class_name = Text(Need(jc, "class", where, ctx), where, ctx + "class");
    if (jc.contains("host") && !jc.at("host").is_null())
      c.host = Text(jc.at("host"), where, ctx + "host");
    c.centre = Vector(Need(jc, "centre", where, ctx), where, ctx + "centre");
    c.normal = Vector(Need(jc, "normal", where, ctx), where, ctx + "normal");
    if (c.normal.norm() < 1e-9) throw InputError(where, ctx + "normal: zero vector");
    c.normal.normalize();
    c.size = Vector(Need(jc, "size", where, ctx), where, ctx + "size", 2);
    c.alpha = Number(Need(jc, "alpha", where, ctx), where, ctx + "alpha");
    if (jc.contains("found_by") && !jc.at("found_by").is_null())
      c.found_by = Text(jc.at("found_by"), where, ctx + "found_by");
    m.components.push_back(std::move(c));
  }
  return m;
}

RunFolder ReadRunFolder(const std::string& dir) {
  const fs::path root(dir);
  if (!fs::is_directory(root)) throw InputError(dir, "not a folder");
  RunFolder run;
  run.dir = dir;
  std::uint64_t key = HashName("mopad-exports/1");
  std::vector<std::pair<std::string, fs::path>> room_dirs;
  for (const std::string& room : runfolder::RoomFolders(dir, runfolder::kSm3)) {
    const fs::path path(room);
    if (path == root) {  // one room's folder: its id is its model's
      const std::string sm3 = runfolder::Join(room, runfolder::kSm3);
      room_dirs.emplace_back(modelling::ParseSm3(ReadText(sm3), sm3).room, path);
    } else {
      room_dirs.emplace_back(path.filename().string(), path);
    }
  }
  std::sort(room_dirs.begin(), room_dirs.end());
  if (room_dirs.empty() && !fs::exists(root / runfolder::kFloorDir / runfolder::kSm3))
    throw InputError(dir, "no model to export", "no rooms/<ID>/sm3.json or floor/sm3.json",
                     "a run folder of `mopad run` or `mopad room`");
  std::optional<Eigen::Isometry3d> X_WM_first;
  for (const auto& [id, path] : room_dirs) {
    ModelSet s = ReadModelSet(path, id, key);
    const auto X_WM = ReadXwm(path);
    if (X_WM && !X_WM_first) X_WM_first = X_WM;
    if (X_WM && X_WM_first) {
      s.X_EM = X_WM_first->inverse() * *X_WM;
      if (!s.X_EM.isApprox(Eigen::Isometry3d::Identity(), 1e-12)) run.placed_by_run_json = true;
    }
    run.rooms.push_back(std::move(s));
  }
  run.X_WE = X_WM_first;
  if (fs::exists(root / runfolder::kFloorDir / runfolder::kSm3))
    run.floor = ReadModelSet(root / runfolder::kFloorDir, "floor", key);
  run.content_key = std::to_string(key);
  return run;
}

}  // namespace mopad::exports
