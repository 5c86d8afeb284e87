#include "modelling/sm5_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "io/text_file.h"

namespace mopad::modelling {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kSm5FormatVersion = 1;

double R(double v, double q = 1e-4) { return std::round(v / q) * q; }
Json V3(const Vec3& v, double q = 1e-4) {
  return Json::array({R(v.x(), q), R(v.y(), q), R(v.z(), q)});
}

const Json& Field(const Json& j, const char* key, const std::string& where,
                  const std::string& ctx) {
  if (!j.is_object() || !j.contains(key))
    throw InputError(where, ctx + key + ": missing", "", "a value");
  return j.at(key);
}

std::string Str(const Json& j, const char* key, const std::string& where, const std::string& ctx) {
  const Json& f = Field(j, key, where, ctx);
  if (!f.is_string()) throw InputError(where, ctx + key + ": wrong type", f.dump(), "a string");
  return f.get<std::string>();
}

double Num(const Json& j, const char* key, const std::string& where, const std::string& ctx) {
  const Json& f = Field(j, key, where, ctx);
  if (!f.is_number() || !std::isfinite(f.get<double>()))
    throw InputError(where, ctx + key + ": wrong type", f.dump(), "a finite number");
  return f.get<double>();
}

Vec3 Xyz(const Json& j, const char* key, const std::string& where, const std::string& ctx) {
  const Json& f = Field(j, key, where, ctx);
  if (!f.is_array() || f.size() != 3)
    throw InputError(where, ctx + key + ": wrong type", f.dump(), "3 finite numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!f[static_cast<std::size_t>(i)].is_number() ||
        !std::isfinite(f[static_cast<std::size_t>(i)].get<double>()))
      throw InputError(where, ctx + key + ": wrong type", f.dump(), "3 finite numbers");
    v[i] = f[static_cast<std::size_t>(i)].get<double>();
  }
  return v;
}

}  // namespace

std::string Sm5Json(const Sm5Model& m) {
  Json j;
  j["format"] = "mopad-sm5";
  j["version"] = kSm5FormatVersion;
  j["room"] = m.room;
  Json cs = Json::array();
  for (const auto& c : m.components) {
    Json jc;
    jc["id"] = c.id;
    jc["class"] = c.class_name;
    jc["host"] = c.host;
    jc["centre"] = V3(c.centre);
    jc["normal"] = V3(c.normal, 1e-6);
    jc["size"] = V3(c.size);
    jc["alpha"] = R(c.alpha);
    jc["found_by"] = ToString(c.found_by);
    cs.push_back(std::move(jc));
  }
  j["components"] = std::move(cs);
  return j.dump(1);
}

Sm5Model ParseSm5(const std::string& text, const std::string& where) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, "not valid JSON", e.what());
  }
  if (Str(j, "format", where, "") != "mopad-sm5")
    throw InputError(where, "format: not an SM5 file", j["format"].dump(), "\"mopad-sm5\"");
  if (Num(j, "version", where, "") != kSm5FormatVersion)
    throw InputError(where, "version: unsupported", j["version"].dump(),
                     std::to_string(kSm5FormatVersion));
  Sm5Model m;
  m.room = Str(j, "room", where, "");
  const Json& cs = Field(j, "components", where, "");
  if (!cs.is_array()) throw InputError(where, "components: wrong type", "", "an array");
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const std::string ctx = "components[" + std::to_string(i) + "].";
    DetectedComponent c;
    c.id = Str(cs[i], "id", where, ctx);
    c.class_name = Str(cs[i], "class", where, ctx);
    c.host = Str(cs[i], "host", where, ctx);
    c.centre = Xyz(cs[i], "centre", where, ctx);
    c.normal = Xyz(cs[i], "normal", where, ctx);
    c.size = Xyz(cs[i], "size", where, ctx);
    c.alpha = Num(cs[i], "alpha", where, ctx);
    if (c.alpha < 0.0 || c.alpha > 1.0)
      throw InputError(where, ctx + "alpha: out of range", std::to_string(c.alpha), "[0, 1]");
    const std::string by = Str(cs[i], "found_by", where, ctx);
    if (by == "colour+depth")
      c.found_by = FoundBy::kColourAndDepth;
    else if (by == "colour")
      c.found_by = FoundBy::kColour;
    else if (by == "depth")
      c.found_by = FoundBy::kDepth;
    else
      throw InputError(where, ctx + "found_by: unknown", by, "colour+depth|colour|depth");
    m.components.push_back(std::move(c));
  }
  return m;
}

Sm5Model ReadSm5(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot read the file");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return ParseSm5(text, path);
}

void WriteSm5File(const std::string& dir, const Sm5Model& model) {
  io::WriteTextFile((std::filesystem::path(dir) / "sm5.json").string(), Sm5Json(model));
}

}  // namespace mopad::modelling
