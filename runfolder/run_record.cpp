#include "runfolder/run_record.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "io/json_fields.h"
#include "io/text_file.h"
#include "runfolder/layout.h"

namespace mopad::runfolder {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kVersion = 1;
const std::string kFormat = "mopad-room-run";

using Reader = io::JsonFields;

Pose3 ReadPose(const Reader& r, const json& X) {
  if (!X.is_array() || X.size() != 4) r.Fail("X_WM", "not a 4x4 matrix", X.dump(), "4 rows of 4");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i) {
    if (!X[i].is_array() || X[i].size() != 4)
      r.Fail("X_WM", "not a 4x4 matrix", X.dump(), "4 rows of 4");
    for (int k = 0; k < 4; ++k)
      m(i, k) = r.Number(X[i][k], "X_WM[" + std::to_string(i) + "][" + std::to_string(k) + "]");
  }
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-5 ||
      R.determinant() < 0.0 || m.row(3).cwiseAbs().sum() != 1.0 || m(3, 3) != 1.0)
    r.Fail("X_WM", "not a rigid transform", "", "a rotation, a translation and a last row 0 0 0 1");
  Pose3 X_WM = Pose3::Identity();
  X_WM.linear() = R;
  X_WM.translation() = m.block<3, 1>(0, 3);
  return X_WM;
}

}  // namespace

std::string RunJsonText(const RunRecord& record) {
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["scene"] = record.scene;
  j["doors"] = record.doors;
  j["room"] = record.room;
  j["seed"] = record.seed;
  nlohmann::ordered_json m = nlohmann::json::array();
  const Eigen::Matrix4d& X = record.X_WM.matrix();
  for (int r = 0; r < 4; ++r) m.push_back({X(r, 0), X(r, 1), X(r, 2), X(r, 3)});
  j["X_WM"] = m;
  j["files"] = {{"sm1", kSm1}, {"sm2", kSm2}, {"sm3", kSm3}, {"sm4", kSm4}, {"dsm3", kDsm3}};
  return j.dump(2);
}

void WriteRunJson(const std::string& dir, const RunRecord& record) {
  io::WriteTextFile(Join(dir, kRunJson), RunJsonText(record));
}

RunRecord ReadRunJson(const std::string& path) {
  const Reader r{path};
  const std::string text = io::ReadTextFile(path);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond double (406)
    throw InputError(path, std::string("malformed JSON: ") + e.what());
  }
  r.Header(j, kFormat, kVersion);
  RunRecord info;
  info.dir = fs::path(path).parent_path().string();
  if (info.dir.empty()) info.dir = ".";
  info.scene = r.String(r.Get(j, "scene", "scene"), "scene");
  if (auto it = j.find("doors"); it != j.end() && !it->is_null()) {
    if (!it->is_array()) r.Fail("doors", "not an array", it->dump(), "[\"ID=DEG\", ...]");
    for (std::size_t i = 0; i < it->size(); ++i)
      info.doors.push_back(r.String((*it)[i], "doors[" + std::to_string(i) + "]"));
  }
  info.room = r.String(r.Get(j, "room", "room"), "room");
  if (info.room.empty()) r.Fail("room", "empty room id");
  if (auto it = j.find("seed"); it != j.end()) {
    if (!it->is_number_integer()) r.Fail("seed", "not an integer", it->dump(), "an integer");
    info.seed = it->get<std::uint64_t>();
  }
  info.X_WM = ReadPose(r, r.Get(j, "X_WM", "X_WM"));
  const json& files = r.Get(j, "files", "files");
  if (!files.is_object()) r.Fail("files", "not an object", files.dump(), "an object");
  auto resolve = [&](const char* key) -> std::string {
    auto it = files.find(key);
    if (it == files.end() || it->is_null()) return "";
    const std::string name = r.String(*it, std::string("files.") + key);
    if (name.empty()) return "";
    const fs::path p(name);
    return p.is_absolute() ? p.string() : (fs::path(info.dir) / p).string();
  };
  info.sm1 = resolve("sm1");
  info.sm2 = resolve("sm2");
  info.sm3 = resolve("sm3");
  info.sm4 = resolve("sm4");
  info.dsm3 = resolve("dsm3");
  return info;
}

}  // namespace mopad::runfolder
