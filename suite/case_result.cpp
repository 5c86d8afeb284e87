#include "suite/case_result.h"

#include "common/error.h"

namespace mopad::suite {

namespace {

nlohmann::ordered_json Num(const std::optional<double>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
}

std::optional<double> OptNum(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  return std::nullopt;
}

}  // namespace

CheckOutcome ToOutcome(const CheckResult& r) {
  CheckOutcome o;
  o.check = r.check->text;
  o.figure = r.check->figure;
  o.op = r.check->op;
  o.bound = r.bound;
  o.value = r.value;
  o.passed = r.passed;
  return o;
}

nlohmann::ordered_json ToJson(const CheckOutcome& c) {
  nlohmann::ordered_json j;
  if (!c.group.empty()) j["group"] = c.group;
  if (!c.stat.empty()) j["stat"] = c.stat;
  j["check"] = c.check;
  j["figure"] = c.figure;
  j["op"] = c.op;
  j["bound"] = Num(c.bound);
  j["value"] = Num(c.value);
  j["passed"] = c.passed;
  return j;
}

nlohmann::ordered_json ToJson(const CaseResult& r) {
  nlohmann::ordered_json j;
  j["id"] = r.id;
  j["group"] = r.group;
  j["scene"] = r.scene;
  j["seed"] = r.seed;
  j["config"] = r.config;
  j["sweep"] = nlohmann::ordered_json::object();
  for (const auto& [k, v] : r.sweep) j["sweep"][k] = v;
  j["verdict"] = r.verdict;
  j["message"] = r.message;
  j["checks"] = nlohmann::ordered_json::array();
  for (const auto& c : r.checks) j["checks"].push_back(ToJson(c));
  j["figures"] = nlohmann::ordered_json::object();
  for (const auto& [k, v] : r.figures) j["figures"][k] = v;
  j["dir"] = r.dir;
  j["wall_s"] = r.wall_s;
  j["peak_rss_mb"] = r.peak_rss_mb;
  j["bytes_written"] = r.bytes_written;
  return j;
}

CaseResult CaseResultFromJson(const nlohmann::json& j, const std::string& where) {
  try {
    CaseResult r;
    r.id = j.at("id").get<std::string>();
    r.group = j.at("group").get<std::string>();
    r.scene = j.at("scene").get<std::string>();
    r.seed = j.at("seed").get<std::uint64_t>();
    r.config = j.at("config").get<std::string>();
    for (const auto& [k, v] : j.at("sweep").items()) r.sweep.emplace_back(k, v.get<std::string>());
    r.verdict = j.at("verdict").get<std::string>();
    r.message = j.at("message").get<std::string>();
    for (const auto& c : j.at("checks")) {
      CheckOutcome o;
      o.check = c.at("check").get<std::string>();
      o.figure = c.at("figure").get<std::string>();
      o.op = c.at("op").get<std::string>();
      o.bound = OptNum(c.at("bound"));
      o.value = OptNum(c.at("value"));
      o.passed = c.at("passed").get<bool>();
      r.checks.push_back(o);
    }
    for (const auto& [k, v] : j.at("figures").items()) r.figures[k] = v.get<double>();
    r.dir = j.at("dir").get<std::string>();
    r.wall_s = j.at("wall_s").get<double>();
    r.peak_rss_mb = j.at("peak_rss_mb").get<double>();
    r.bytes_written = j.at("bytes_written").get<std::uint64_t>();
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, std::string("bad case result: ") + e.what());
  }
}

}  // namespace mopad::suite
