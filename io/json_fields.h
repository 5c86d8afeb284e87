#pragma once
// Field access in a parsed JSON file with one-line errors naming the file and the field:
// "PATH: error: FIELD: what; got X, expected Y" (mopad::InputError). The readers of the run
// folder's JSON files (run.json, the evaluator's model files) share it.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"
#include "common/frames.h"

namespace mopad::io {

struct JsonFields {
  std::string path;  ///< the file, named in every error

  [[noreturn]] void Fail(const std::string& field, const std::string& what,
                         const std::string& got = "", const std::string& expected = "") const {
    throw InputError(path, field + ": " + what, got, expected);
  }
  const nlohmann::json& Get(const nlohmann::json& j, const std::string& key,
                            const std::string& field) const {
    if (!j.is_object()) Fail(field, "not an object", j.type_name(), "an object");
    auto it = j.find(key);
    if (it == j.end()) Fail(field, "missing field");
    return *it;
  }
  /// A finite number.
  double Number(const nlohmann::json& j, const std::string& field) const {
    if (!j.is_number()) Fail(field, "not a number", j.dump(), "a number");
    const double x = j.get<double>();
    if (!std::isfinite(x)) Fail(field, "not finite", j.dump(), "a finite number");
    return x;
  }
  std::string String(const nlohmann::json& j, const std::string& field) const {
    if (!j.is_string()) Fail(field, "not a string", j.dump(), "a string");
    return j.get<std::string>();
  }
  /// [x, y, z] of finite numbers.
  Vec3 Vector3(const nlohmann::json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 3) Fail(field, "not a 3-vector", j.dump(), "[x, y, z]");
    return {Number(j[0], field + "[0]"), Number(j[1], field + "[1]"), Number(j[2], field + "[2]")};
  }
  /// "format" equal to `format` and an integer "version" equal to `version`.
  void Header(const nlohmann::json& j, const std::string& format, long version) const {
    const std::string f = String(Get(j, "format", "format"), "format");
    if (f != format) Fail("format", "wrong file format", "'" + f + "'", "'" + format + "'");
    const nlohmann::json& v = Get(j, "version", "version");
    if (!v.is_number_integer() || v.get<long>() != version)
      Fail("version", "unsupported version", v.dump(), std::to_string(version));
  }
};

}  // namespace mopad::io
