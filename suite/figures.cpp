#include "suite/figures.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include <yaml-cpp/yaml.h>

#include "autonomy/floor_scan.h"
#include "runfolder/layout.h"
#include "scenes/ground_truth.h"
#include "suite/reachable_rooms.h"

namespace mopad::suite {

namespace {

namespace fs = std::filesystem;
using Getter = std::function<std::optional<double>(const CaseFiles&)>;

struct FigureDef {
  FigureInfo info;
  Getter get;
};

Getter Summary(const std::string& path) {
  return [path](const CaseFiles& f) { return NumberAt(f.summary, path); };
}
Getter Eval(const std::string& path) {
  return [path](const CaseFiles& f) { return NumberAt(f.eval, path); };
}
// a / b, none when either is missing or b is 0.
Getter Ratio(Getter a, Getter b) {
  return [a, b](const CaseFiles& f) -> std::optional<double> {
    auto x = a(f), y = b(f);
    if (!x || !y || *y == 0.0) return std::nullopt;
    return *x / *y;
  };
}
// The first of two sources that gives a number.
Getter Either(Getter a, Getter b) {
  return [a, b](const CaseFiles& f) { return a(f) ? a(f) : b(f); };
}

// Truth rooms the run modelled: summary.json's rooms with a truth room and status "scanned".
std::set<std::string> ModelledRooms(const CaseFiles& f) {
  std::set<std::string> out;
  if (!f.summary.is_object() || !f.summary.contains("rooms") || !f.summary["rooms"].is_array())
    return out;
  for (const auto& r : f.summary["rooms"])
    if (r.is_object() && r.value("status", "") == "scanned" && !r.value("room", "").empty())
      out.insert(r.value("room", ""));
  return out;
}

const std::vector<FigureDef>& Defs() {
  static const std::vector<FigureDef> defs = {
      {{"rooms_reachable", "none", "", "reachable"},
       [](const CaseFiles& f) -> std::optional<double> {
         if (!f.rooms_reachable) return std::nullopt;
         return *f.rooms_reachable;
       }},
      {{"rooms_modelled", "higher", "", "modelled"},
       [](const CaseFiles& f) -> std::optional<double> {
         if (!f.summary.is_object()) return std::nullopt;
         return static_cast<double>(ModelledRooms(f).size());
       }},
      {{"rooms_missed", "lower", "", "missed"},
       [](const CaseFiles& f) -> std::optional<double> {
         if (!f.rooms_reachable || !f.summary.is_object()) return std::nullopt;
         const double got = static_cast<double>(ModelledRooms(f).size());
         return std::max(0.0, *f.rooms_reachable - got);
       }},
      {{"scans", "none", "", "scans"}, Summary("mission.scans")},
      {{"structural_scans", "lower", "", "struct. scans"},
       [](const CaseFiles& f) -> std::optional<double> {
         auto a = NumberAt(f.summary, "mission.scans");
         auto b = NumberAt(f.summary, "mission.detail_scans");
         if (!a) return std::nullopt;
         return *a - b.value_or(0.0);
       }},
      {{"contacts", "lower", "", "contacts"}, Summary("mission.contacts")},
      {{"localisation_max_m", "lower", "m", "loc. max"}, Summary("mission.localisation_max_m")},
      {{"localisation_rms_m", "lower", "m", "loc. RMS"}, Summary("mission.localisation_rms_m")},
      {{"coverage_min", "higher", "", "coverage min"},
       Eval("summary.mission.coverage_of_observable_min")},
      {{"walls_tp", "higher", "", "walls TP"}, Eval("summary.detection.wall.tp")},
      {{"walls_fp", "lower", "", "walls FP"}, Eval("summary.detection.wall.fp")},
      {{"walls_fn", "lower", "", "walls FN"}, Eval("summary.detection.wall.fn")},
      {{"floors_tp", "higher", "", "floors TP"}, Eval("summary.detection.floor.tp")},
      {{"ceilings_tp", "higher", "", "ceilings TP"}, Eval("summary.detection.ceiling.tp")},
      {{"wall_precision", "higher", "", "wall P"},
       Ratio(Eval("summary.detection.wall.tp"),
             [](const CaseFiles& f) -> std::optional<double> {
               auto tp = NumberAt(f.eval, "summary.detection.wall.tp");
               auto fp = NumberAt(f.eval, "summary.detection.wall.fp");
               if (!tp || !fp) return std::nullopt;
               return *tp + *fp;
             })},
      {{"wall_recall", "higher", "", "wall R"},
       Ratio(Eval("summary.detection.wall.tp"), Eval("summary.detection.wall.n_truth"))},
      {{"d_v_mean", "lower", "m", "d_v"}, Eval("summary.d_v.mean")},
      {{"d_h_mean", "lower", "m", "d_h"}, Eval("summary.d_h.mean")},
      {{"d_v_max", "lower", "m", "d_v max"}, Eval("summary.d_v.max")},
      {{"d_h_max", "lower", "m", "d_h max"}, Eval("summary.d_h.max")},
      {{"phi_mean_deg", "lower", "deg", "phi"}, Eval("summary.phi_deg.mean")},
      {{"phi_max_deg", "lower", "deg", "phi max"}, Eval("summary.phi_deg.max")},
      {{"floor_d_h_mean", "lower", "m", "floor d_h"},
       Either(Eval("summary.floor.d_h.mean"), Eval("summary.d_h.mean"))},
      {{"floor_alignment_max_m", "lower", "m", "alignment max"},
       Eval("summary.floor.room_alignment_m.max")},
      {{"sm4_precision", "higher", "", "SM4 P"}, Eval("summary.openings.precision")},
      {{"sm4_recall", "higher", "", "SM4 R"}, Eval("summary.openings.recall")},
      {{"sm4_fn_max_m2", "lower", "m2", "fn max"}, Eval("summary.openings.fn_max_m2")},
      {{"sm4_fp_max_m2", "lower", "m2", "fp max"}, Eval("summary.openings.fp_max_m2")},
      {{"sm4_e_abs_mean_m2", "lower", "m2", "e_abs"}, Eval("summary.openings.e_abs_m2.mean")},
      {{"sm4_e_r_mean", "lower", "", "e_r"}, Eval("summary.openings.e_r.mean")},
      {{"sm4_door_states_right", "higher", "", "door states"},
       Ratio(Eval("summary.openings.door_states.right"),
             Eval("summary.openings.door_states.doors"))},
      {{"sm5_tp_rate", "higher", "", "SM5 TP"}, Eval("summary.components.all.tp_share")},
      {{"sm5_fn_rate", "lower", "", "SM5 FN"}, Eval("summary.components.all.fn_share")},
      {{"sm5_fp_rate", "lower", "", "SM5 FP"}, Eval("summary.components.all.fp_share")},
      {{"sm5_h_error_mean_m", "lower", "m", "SM5 h err"},
       Eval("summary.components.centre_error_m.horizontal.mean")},
      {{"sm5_v_error_mean_m", "lower", "m", "SM5 v err"},
       Eval("summary.components.centre_error_m.vertical.mean")},
      {{"sim_time_s", "none", "s", "sim time"}, Summary("mission.sim_time_s")},
  };
  return defs;
}

// The per-class SM5 fields (evaluation.json summary.components.classes[]) and their direction.
const std::vector<std::pair<std::string, std::string>> kClassFields = {
    {"n", "none"},         {"tp_share", "higher"}, {"fn_share", "lower"},
    {"fp_share", "lower"}, {"tp_alpha_above_0_9_share", "none"}, {"tp_alpha_0_5_share", "none"}};

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

}  // namespace

const std::vector<FigureInfo>& MainFigures() {
  static const std::vector<FigureInfo> infos = [] {
    std::vector<FigureInfo> v;
    for (const auto& d : Defs()) v.push_back(d.info);
    return v;
  }();
  return infos;
}

FigureInfo InfoOf(const std::string& name) {
  for (const auto& d : Defs())
    if (d.info.name == name) return d.info;
  if (name.rfind("sm5_class.", 0) == 0)
    for (const auto& [field, better] : kClassFields)
      if (name.size() > field.size() && name.compare(name.size() - field.size(), field.size(), field) == 0)
        return {name, better, "", field};
  return {name, "none", "", name};
}

std::optional<double> NumberAt(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* at = &j;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (at->is_object()) {
      auto it = at->find(part);
      if (it == at->end()) return std::nullopt;
      at = &*it;
    } else if (at->is_array() && !part.empty() &&
               part.find_first_not_of("0123456789") == std::string::npos) {
      const std::size_t k = std::stoul(part);
      if (k >= at->size()) return std::nullopt;
      at = &(*at)[k];
    } else {
      return std::nullopt;
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (at->is_boolean()) return at->get<bool>() ? 1.0 : 0.0;
  if (at->is_number()) return at->get<double>();
  return std::nullopt;
}

CaseFiles ReadCaseFiles(const std::string& dir, const std::string& truth_path) {
  CaseFiles f;
  f.summary = ReadJson(runfolder::Join(dir, runfolder::kSummary));
  f.eval = ReadJson(runfolder::Join(runfolder::Join(dir, runfolder::kEvalDir), "evaluation.json"));
  std::error_code ec;
  if (truth_path.empty() || !fs::is_regular_file(truth_path, ec) || !f.summary.is_object())
    return f;
  // The start room: the first room of the run; the passable width: the run's own setting.
  std::string start;
  if (f.summary.contains("rooms") && f.summary["rooms"].is_array() && !f.summary["rooms"].empty())
    start = f.summary["rooms"][0].value("room", "");
  double min_clear = autonomy::FloorScanParams{}.min_clear_width;
  try {
    const YAML::Node eff = YAML::LoadFile(runfolder::Join(dir, runfolder::kEffectiveConfig));
    if (eff["floor"] && eff["floor"]["min_clear_width"])
      min_clear = eff["floor"]["min_clear_width"].as<double>();
  } catch (const YAML::Exception&) {
  }
  try {
    const scenes::GroundTruth truth = scenes::ReadGroundTruth(truth_path);
    f.rooms_reachable = static_cast<int>(ReachableRooms(truth, start, min_clear).size());
  } catch (const std::exception&) {
  }
  return f;
}

Figures ExtractFigures(const CaseFiles& f, const std::vector<std::string>& paths) {
  Figures out;
  for (const auto& d : Defs())
    if (auto v = d.get(f)) out[d.info.name] = *v;
  if (f.eval.is_object()) {
    const nlohmann::json* classes = nullptr;
    if (f.eval.contains("summary") && f.eval["summary"].contains("components"))
      if (auto it = f.eval["summary"]["components"].find("classes");
          it != f.eval["summary"]["components"].end() && it->is_array())
        classes = &*it;
    if (classes)
      for (const auto& c : *classes)
        for (const auto& [field, better] : kClassFields)
          if (c.is_object() && c.contains(field) && c[field].is_number())
            out["sm5_class." + c.value("class", "?") + "." + field] = c[field].get<double>();
  }
  for (const std::string& p : paths) {
    std::optional<double> v;
    if (p.rfind("summary.", 0) == 0) v = NumberAt(f.summary, p.substr(8));
    if (p.rfind("eval.", 0) == 0) v = NumberAt(f.eval, p.substr(5));
    if (v) out[p] = *v;
  }
  return out;
}

}  // namespace mopad::suite
