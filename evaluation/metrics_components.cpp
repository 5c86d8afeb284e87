#include "evaluation/metrics_components.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "common/error.h"
#include "common/format.h"
#include "common/statistics.h"

namespace mopad::evaluation {
namespace {

// Horizontal and vertical unit axes of a host plane with normal n (see the file comment).
std::pair<Vec3, Vec3> PlaneAxes(const Vec3& normal) {
  const Vec3 n = normal.normalized();
  if (std::abs(n.z()) > 0.9) return {Vec3::UnitX(), Vec3::UnitY()};
  const Vec3 h = n.cross(Vec3::UnitZ()).normalized();
  return {h, h.cross(n).normalized().dot(Vec3::UnitZ()) >= 0 ? h.cross(n).normalized()
                                                             : -h.cross(n).normalized()};
}

void Stats(ComponentEvaluation& e) {
  e.horizontal_stats = {};
  e.vertical_stats = {};
  for (double x : e.horizontal) e.horizontal_stats.Add(x);
  for (double x : e.vertical) e.vertical_stats.Add(x);
  // No matched pair: 0, as the mean and max of an empty ErrorStats.
  e.horizontal_median = e.horizontal.empty() ? 0.0 : Median(e.horizontal);
  e.vertical_median = e.vertical.empty() ? 0.0 : Median(e.vertical);
}

void Check(const ComponentRecord& r, const char* side) {
  if (!r.centre.allFinite() || !r.normal.allFinite() || r.normal.norm() < 1e-9)
    throw InputError("", std::string(side) + " component '" + r.id + "' has a bad centre or normal",
                     "non-finite", "finite centre and non-zero normal");
}

}  // namespace

ComponentEvaluation EvaluateComponents(const std::vector<ComponentRecord>& model,
                                       const std::vector<ComponentRecord>& truth,
                                       const ComponentMatchParams& params) {
  ValidateParams(params, "eval.components.");
  for (const auto& r : model) Check(r, "recognised");
  for (const auto& r : truth) Check(r, "truth");
  std::vector<std::tuple<double, std::size_t, std::size_t>> cand;
  for (std::size_t t = 0; t < truth.size(); ++t)
    for (std::size_t m = 0; m < model.size(); ++m) {
      if (truth[t].class_name != model[m].class_name) continue;
      const double d = (truth[t].centre - model[m].centre).norm();
      if (d <= params.max_centre_distance) cand.emplace_back(d, t, m);
    }
  std::sort(cand.begin(), cand.end());
  std::vector<int> t_of_m(model.size(), -1), m_of_t(truth.size(), -1);
  for (const auto& [d, t, m] : cand)
    if (m_of_t[t] < 0 && t_of_m[m] < 0)
      m_of_t[t] = static_cast<int>(m), t_of_m[m] = static_cast<int>(t);
  ComponentEvaluation e;
  std::map<std::string, ComponentClassRow> rows;
  for (const auto& t : truth) rows[t.class_name].n++;
  for (std::size_t t = 0; t < truth.size(); ++t) {
    ComponentClassRow& row = rows[truth[t].class_name];
    ComponentPair p;
    p.truth_id = truth[t].id;
    p.truth_class = truth[t].class_name;
    if (m_of_t[t] < 0) {
      row.fn++;
      e.pairs.push_back(p);
      continue;
    }
    const ComponentRecord& m = model[static_cast<std::size_t>(m_of_t[t])];
    row.tp++;
    if (m.alpha > 0.9) row.tp_alpha_high++;
    if (std::abs(m.alpha - 0.5) < 1e-6) row.tp_alpha_half++;
    const auto [h, v] = PlaneAxes(truth[t].normal);
    const Vec3 d = m.centre - truth[t].centre;
    p.model_id = m.id, p.model_class = m.class_name, p.found_by = m.found_by, p.alpha = m.alpha;
    p.horizontal = std::abs(d.dot(h));
    p.vertical = std::abs(d.dot(v));
    e.horizontal.push_back(p.horizontal);
    e.vertical.push_back(p.vertical);
    e.pairs.push_back(p);
  }
  for (std::size_t m = 0; m < model.size(); ++m) {
    if (t_of_m[m] >= 0) continue;
    rows[model[m].class_name].fp++;
    ComponentPair p;
    p.model_id = model[m].id, p.model_class = model[m].class_name;
    p.found_by = model[m].found_by, p.alpha = model[m].alpha;
    e.pairs.push_back(p);
  }
  e.total.class_name = "all";
  for (auto& [name, row] : rows) {
    row.class_name = name;
    e.classes.push_back(row);
    e.total.n += row.n, e.total.tp += row.tp, e.total.fn += row.fn, e.total.fp += row.fp;
    e.total.tp_alpha_high += row.tp_alpha_high, e.total.tp_alpha_half += row.tp_alpha_half;
  }
  Stats(e);
  return e;
}

ComponentEvaluation PoolComponents(const std::vector<ComponentEvaluation>& parts) {
  ComponentEvaluation e;
  std::map<std::string, ComponentClassRow> rows;
  for (const auto& p : parts) {
    for (const auto& r : p.classes) {
      ComponentClassRow& x = rows[r.class_name];
      x.class_name = r.class_name;
      x.n += r.n, x.tp += r.tp, x.fn += r.fn, x.fp += r.fp;
      x.tp_alpha_high += r.tp_alpha_high, x.tp_alpha_half += r.tp_alpha_half;
    }
    e.pairs.insert(e.pairs.end(), p.pairs.begin(), p.pairs.end());
    e.horizontal.insert(e.horizontal.end(), p.horizontal.begin(), p.horizontal.end());
    e.vertical.insert(e.vertical.end(), p.vertical.begin(), p.vertical.end());
  }
  e.total.class_name = "all";
  for (const auto& [name, r] : rows) {
    e.classes.push_back(r);
    e.total.n += r.n, e.total.tp += r.tp, e.total.fn += r.fn, e.total.fp += r.fp;
    e.total.tp_alpha_high += r.tp_alpha_high, e.total.tp_alpha_half += r.tp_alpha_half;
  }
  Stats(e);
  return e;
}

std::vector<ComponentRecord> TruthComponents(const scenes::GroundTruth& truth,
                                             const std::string& room) {
  if (!truth.FindRoom(room)) throw InputError("", "unknown room", "'" + room + "'", "a truth room");
  std::vector<ComponentRecord> out;
  for (const auto& c : truth.service_components) {
    if (c.room != room) continue;
    ComponentRecord r;
    r.id = c.id, r.class_name = c.bsc_class, r.host = c.host;
    r.centre = c.centre, r.normal = c.normal;
    out.push_back(r);
  }
  return out;
}

std::vector<ComponentRecord> ModelComponents(const modelling::Sm5Model& sm5, const Pose3& X_WM) {
  std::vector<ComponentRecord> out;
  for (const auto& c : sm5.components) {
    ComponentRecord r;
    r.id = c.id, r.class_name = c.class_name, r.host = c.host;
    r.centre = X_WM * c.centre;
    r.normal = X_WM.linear() * c.normal;
    r.alpha = c.alpha;
    r.found_by = modelling::ToString(c.found_by);
    out.push_back(r);
  }
  return out;
}

namespace {

nlohmann::json RowJson(const ComponentClassRow& r) {
  const double tp = r.tp > 0 ? r.tp : 1;
  return {{"class", r.class_name},
          {"n", r.n},
          {"tp", r.tp},
          {"fn", r.fn},
          {"fp", r.fp},
          {"tp_share", r.Share(r.tp)},
          {"fn_share", r.Share(r.fn)},
          {"fp_share", r.Share(r.fp)},
          {"tp_alpha_above_0_9_share", r.tp > 0 ? r.tp_alpha_high / tp : 0.0},
          {"tp_alpha_0_5_share", r.tp > 0 ? r.tp_alpha_half / tp : 0.0}};
}

}  // namespace

nlohmann::json ToJson(const ComponentEvaluation& e) {
  nlohmann::json j;
  j["all"] = RowJson(e.total);
  nlohmann::json cls = nlohmann::json::array();
  for (const auto& r : e.classes) cls.push_back(RowJson(r));
  j["classes"] = cls;
  j["centre_error_m"] = {{"horizontal",
                          {{"mean", e.horizontal_stats.mean},
                           {"median", e.horizontal_median},
                           {"max", e.horizontal_stats.max}}},
                         {"vertical",
                          {{"mean", e.vertical_stats.mean},
                           {"median", e.vertical_median},
                           {"max", e.vertical_stats.max}}}};
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& p : e.pairs)
    pairs.push_back({{"truth_id", p.truth_id},
                     {"model_id", p.model_id},
                     {"truth_class", p.truth_class},
                     {"model_class", p.model_class},
                     {"found_by", p.found_by},
                     {"alpha", p.alpha},
                     {"horizontal_m", p.horizontal},
                     {"vertical_m", p.vertical}});
  j["pairs"] = pairs;
  return j;
}

ComponentTableText ComponentsTable(const ComponentEvaluation& e) {
  ComponentTableText t;
  t.header = {"class",       "N", "TP %", "FN %", "FP %", "TP alpha > 0.9 %", "TP alpha = 0.5 %",
              "TP / FN / FP"};
  auto line = [&](const ComponentClassRow& r) {
    const double tp = r.tp > 0 ? r.tp : 1;
    t.rows.push_back(
        {r.class_name, std::to_string(r.n), FormatFixed(100 * r.Share(r.tp), 1),
         FormatFixed(100 * r.Share(r.fn), 1), FormatFixed(100 * r.Share(r.fp), 1),
         FormatFixed(r.tp > 0 ? 100 * r.tp_alpha_high / tp : 0.0, 1),
         FormatFixed(r.tp > 0 ? 100 * r.tp_alpha_half / tp : 0.0, 1),
         std::to_string(r.tp) + " / " + std::to_string(r.fn) + " / " + std::to_string(r.fp)});
  };
  for (const auto& r : e.classes) line(r);
  line(e.total);
  t.centre_errors = "Centre error on the host plane (mm): horizontal mean " +
                    FormatFixed(1000 * e.horizontal_stats.mean, 2) + ", median " +
                    FormatFixed(1000 * e.horizontal_median, 2) + ", max " +
                    FormatFixed(1000 * e.horizontal_stats.max, 2) + "; vertical mean " +
                    FormatFixed(1000 * e.vertical_stats.mean, 2) + ", median " +
                    FormatFixed(1000 * e.vertical_median, 2) + ", max " +
                    FormatFixed(1000 * e.vertical_stats.max, 2) + " (" +
                    std::to_string(e.horizontal.size()) + " true positives)";
  return t;
}

std::string MarkdownComponentsTable(const ComponentEvaluation& e) {
  const ComponentTableText t = ComponentsTable(e);
  std::ostringstream md;
  md << "|";
  for (const auto& h : t.header) md << " " << h << " |";
  md << "\n|";
  for (std::size_t i = 0; i < t.header.size(); ++i) md << "---|";
  md << "\n";
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    md << "|";
    for (std::size_t j = 0; j < t.rows[i].size(); ++j)
      md << " " << (j == 0 && i + 1 == t.rows.size() ? "**" + t.rows[i][j] + "**" : t.rows[i][j])
         << " |";
    md << "\n";
  }
  md << "\n" << t.centre_errors << "\n";
  return md.str();
}

}  // namespace mopad::evaluation
