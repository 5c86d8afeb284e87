#include "evaluation/metrics_openings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>

#include "common/error.h"
#include "common/statistics.h"
#include "evaluation/json_number.h"

namespace mopad::evaluation {
namespace {

using nlohmann::json;
constexpr double kPi = 3.14159265358979323846;

void Check(const OpeningRecord& r, const std::string& side, std::size_t i) {
  const std::string what = side + " opening " + std::to_string(i) + " '" + r.id + "'";
  if (r.corners.size() != 4)
    throw InputError("", what + ": needs 4 corners", std::to_string(r.corners.size()), "4");
  for (const auto& c : r.corners)
    if (!c.allFinite()) throw InputError("", what + ": corner not finite");
  if (!r.normal.allFinite() || r.normal.norm() < 1e-12)
    throw InputError("", what + ": normal zero or not finite");
  if (r.type != "door" && r.type != "window")
    throw InputError("", what + ": unknown type", "'" + r.type + "'", "door|window");
  if (!r.state.empty() && !DoorStateFromString(r.state))
    throw InputError("", what + ": unknown state", "'" + r.state + "'", "closed|semi_open|open");
}

int StateIndex(const std::string& s) {
  for (int i = 0; i < 3; ++i)
    if (s == kDoorStateNames[i]) return i;
  return -1;
}

Patch AsPatch(const OpeningRecord& r) {
  Patch p;
  p.id = r.id;
  p.polygon = r.corners;
  p.normal = r.normal;
  return p;
}

}  // namespace

OpeningEvaluation EvaluateOpenings(const std::vector<OpeningRecord>& model,
                                   const std::vector<OpeningRecord>& truth,
                                   const OpeningMatchParams& params) {
  ValidateParams(params, "openings_match.");
  for (std::size_t i = 0; i < model.size(); ++i) Check(model[i], "model", i);
  for (std::size_t j = 0; j < truth.size(); ++j) Check(truth[j], "truth", j);
  OpeningEvaluation e;
  e.truth_count = static_cast<int>(truth.size());
  e.model_count = static_cast<int>(model.size());
  std::vector<double> model_area(model.size()), truth_area(truth.size());
  for (std::size_t i = 0; i < model.size(); ++i) model_area[i] = PolygonArea3d(model[i].corners);
  for (std::size_t j = 0; j < truth.size(); ++j) truth_area[j] = PolygonArea3d(truth[j].corners);
  // Candidate pairs with their overlap in the truth's plane.
  const double cos_max = std::cos(params.max_normal_angle_deg * kPi / 180.0);
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;  // (-overlap, j, i)
  for (std::size_t j = 0; j < truth.size(); ++j) {
    const PlaneFrame f = PlaneFrame::Of(AsPatch(truth[j]));
    std::vector<Vec2> t2;
    for (const auto& c : truth[j].corners) t2.push_back(f.To2d(c));
    for (std::size_t i = 0; i < model.size(); ++i) {
      if (model[i].normal.normalized().dot(f.n) < cos_max) continue;
      Vec3 centroid = Vec3::Zero();
      for (const auto& c : model[i].corners) centroid += c / 4.0;
      if (std::abs(f.SignedDistance(centroid)) > params.max_plane_distance) continue;
      std::vector<Vec2> m2;
      for (const auto& c : model[i].corners) m2.push_back(f.To2d(c));
      const double overlap = IntersectionArea(m2, t2);
      if (overlap > 1e-9) pairs.emplace_back(-overlap, j, i);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> match_of_truth(truth.size(), -1), match_of_model(model.size(), -1);
  std::vector<double> overlap_of_truth(truth.size(), 0.0);
  for (const auto& [neg, j, i] : pairs) {
    if (match_of_truth[j] >= 0 || match_of_model[i] >= 0) continue;
    match_of_truth[j] = static_cast<int>(i), match_of_model[i] = static_cast<int>(j);
    overlap_of_truth[j] = -neg;
  }
  std::vector<double> angle_errors;
  for (std::size_t j = 0; j < truth.size(); ++j) {
    const OpeningRecord& t = truth[j];
    OpeningRow r;
    r.truth_id = t.id, r.truth_type = t.type, r.truth_area = truth_area[j];
    r.truth_state = t.state, r.truth_angle_deg = t.angle_deg;
    const int mi = match_of_truth[j];
    if (mi >= 0) {
      const OpeningRecord& m = model[mi];
      ++e.matched;
      if (m.type == t.type) ++e.type_right;
      r.model_id = m.id, r.model_type = m.type, r.model_area = model_area[mi];
      r.model_state = m.state, r.model_angle_deg = m.angle_deg;
      r.tp = std::min({overlap_of_truth[j], r.truth_area, r.model_area});
      r.fp = std::max(0.0, r.model_area - r.tp);
      r.fn = std::max(0.0, r.truth_area - r.tp);
    } else {
      ++e.missed;
      r.fn = r.truth_area;
    }
    r.e_abs = r.fp + r.fn;
    r.e_r = r.tp + r.fn > 0 ? r.e_abs / (r.tp + r.fn) : 0.0;
    if (t.type == "door") {
      const int ts = StateIndex(t.state);
      if (ts >= 0) {
        ++e.doors;
        const int ms = (mi >= 0 && r.model_type == "door") ? StateIndex(r.model_state) : -1;
        ++e.state_confusion[ts][ms >= 0 ? ms : 3];
        if (ms == ts) ++e.door_state_right;
      }
      if (mi >= 0 && r.model_type == "door" && std::isfinite(r.model_angle_deg) &&
          std::isfinite(r.truth_angle_deg)) {
        r.angle_error_deg = std::abs(r.model_angle_deg - r.truth_angle_deg);
        e.angle_error.Add(r.angle_error_deg);
        angle_errors.push_back(r.angle_error_deg);
      }
    }
    e.rows.push_back(r);
  }
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (match_of_model[i] >= 0) continue;
    ++e.false_openings;
    OpeningRow r;
    r.model_id = model[i].id, r.model_type = model[i].type, r.model_area = model_area[i];
    r.model_state = model[i].state, r.model_angle_deg = model[i].angle_deg;
    r.fp = r.model_area;
    r.e_abs = r.fp;
    e.rows.push_back(r);
  }
  for (const OpeningRow& r : e.rows) {
    e.tp += r.tp, e.fp += r.fp, e.fn += r.fn;
    e.e_abs.Add(r.e_abs);
    if (!r.truth_id.empty()) e.e_r.Add(r.e_r);
    e.fn_max = std::max(e.fn_max, r.fn);
    e.fp_max = std::max(e.fp_max, r.fp);
  }
  e.precision = e.tp + e.fp > 0 ? e.tp / (e.tp + e.fp) : 1.0;
  e.recall = e.tp + e.fn > 0 ? e.tp / (e.tp + e.fn) : 1.0;
  if (!angle_errors.empty()) e.angle_error_median = Median(std::move(angle_errors));
  return e;
}

OpeningEvaluation PoolOpenings(const std::vector<OpeningEvaluation>& parts) {
  OpeningEvaluation e;
  std::vector<double> angle_errors;
  for (const OpeningEvaluation& p : parts) {
    e.rows.insert(e.rows.end(), p.rows.begin(), p.rows.end());
    e.truth_count += p.truth_count, e.model_count += p.model_count, e.matched += p.matched;
    e.missed += p.missed, e.false_openings += p.false_openings, e.type_right += p.type_right;
    e.doors += p.doors, e.door_state_right += p.door_state_right;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 4; ++k) e.state_confusion[i][k] += p.state_confusion[i][k];
  }
  for (const OpeningRow& r : e.rows) {
    e.tp += r.tp, e.fp += r.fp, e.fn += r.fn;
    e.e_abs.Add(r.e_abs);
    if (!r.truth_id.empty()) e.e_r.Add(r.e_r);
    e.fn_max = std::max(e.fn_max, r.fn);
    e.fp_max = std::max(e.fp_max, r.fp);
    if (std::isfinite(r.angle_error_deg)) {
      e.angle_error.Add(r.angle_error_deg);
      angle_errors.push_back(r.angle_error_deg);
    }
  }
  e.precision = e.tp + e.fp > 0 ? e.tp / (e.tp + e.fp) : 1.0;
  e.recall = e.tp + e.fn > 0 ? e.tp / (e.tp + e.fn) : 1.0;
  if (!angle_errors.empty()) e.angle_error_median = Median(std::move(angle_errors));
  return e;
}

std::vector<OpeningRecord> TruthOpenings(const scenes::GroundTruth& truth,
                                         const std::string& room) {
  if (truth.FindRoom(room) == nullptr) {
    std::string ids;
    for (const auto& x : truth.rooms) ids += (ids.empty() ? "" : ", ") + x.id;
    throw InputError("truth", "unknown room", "'" + room + "'", "one of " + ids);
  }
  std::vector<OpeningRecord> out;
  for (const auto& o : truth.openings) {
    for (const auto& host : o.host_walls) {
      const scenes::StructuralElement* w = truth.FindElement(host);
      if (w == nullptr || w->element_class != scenes::ElementClass::kWall) continue;
      if (std::find(w->rooms.begin(), w->rooms.end(), room) == w->rooms.end()) continue;
      const Vec3 u = w->u_axis.normalized();
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      for (const auto& c : o.corners) {
        const double cu = u.dot(c - w->origin), cv = c.z() - w->origin.z();
        u0 = std::min(u0, cu), u1 = std::max(u1, cu), v0 = std::min(v0, cv), v1 = std::max(v1, cv);
      }
      u0 = std::max(u0, 0.0), u1 = std::min(u1, w->length);
      v0 = std::max(v0, 0.0), v1 = std::min(v1, w->height);
      if (!(u1 > u0 && v1 > v0)) continue;
      OpeningRecord r;
      r.id = o.id;
      r.type = o.type == scenes::OpeningType::kDoor ? "door" : "window";
      r.host = host;
      r.normal = w->normal.normalized();
      const Vec3 z = Vec3::UnitZ();
      r.corners = {w->origin + u0 * u + v0 * z, w->origin + u1 * u + v0 * z,
                   w->origin + u1 * u + v1 * z, w->origin + u0 * u + v1 * z};
      // CCW seen from the normal.
      const Vec3 nw = (r.corners[1] - r.corners[0]).cross(r.corners[3] - r.corners[0]);
      if (nw.dot(r.normal) < 0) std::reverse(r.corners.begin(), r.corners.end());
      if (o.type == scenes::OpeningType::kDoor) {
        r.state = std::string(scenes::ToString(o.state));
        r.angle_deg = o.opening_angle * 180.0 / kPi;
      }
      out.push_back(std::move(r));
      break;  // one host wall per room
    }
  }
  return out;
}

std::vector<OpeningRecord> ModelOpenings(const modelling::Sm4Model& sm4, const Pose3& X_WM) {
  std::vector<OpeningRecord> out;
  for (const auto& o : sm4.openings) {
    OpeningRecord r;
    r.id = o.id;
    r.type = modelling::ToString(o.type);
    r.host = o.host;
    for (const auto& c : o.corners) r.corners.push_back(X_WM * c);
    r.normal = (r.corners[1] - r.corners[0]).cross(r.corners[3] - r.corners[0]);
    if (o.type == modelling::OpeningType::kDoor) {
      r.state = modelling::ToString(o.state);
      r.angle_deg = o.opening_angle_deg;
    }
    out.push_back(std::move(r));
  }
  return out;
}

json ToJson(const OpeningEvaluation& e) {
  auto stats = [](const ErrorStats& s) {
    return json{{"n", s.n}, {"mean", Num(s.mean)}, {"max", Num(s.max)}};
  };
  json rows = json::array();
  for (const auto& r : e.rows)
    rows.push_back({{"truth_id", r.truth_id},
                    {"model_id", r.model_id},
                    {"truth_type", r.truth_type},
                    {"model_type", r.model_type},
                    {"truth_area_m2", Num(r.truth_area)},
                    {"model_area_m2", Num(r.model_area)},
                    {"tp_m2", Num(r.tp)},
                    {"fp_m2", Num(r.fp)},
                    {"fn_m2", Num(r.fn)},
                    {"e_abs_m2", Num(r.e_abs)},
                    {"e_r", Num(r.e_r)},
                    {"truth_state", r.truth_state},
                    {"model_state", r.model_state},
                    {"truth_angle_deg", Num(r.truth_angle_deg)},
                    {"model_angle_deg", Num(r.model_angle_deg)},
                    {"angle_error_deg", Num(r.angle_error_deg)}});
  json matrix = json::array();
  for (const auto& row : e.state_confusion) matrix.push_back(row);
  return {{"truth_openings", e.truth_count},
          {"model_openings", e.model_count},
          {"matched", e.matched},
          {"missed", e.missed},
          {"false_openings", e.false_openings},
          {"type_right", e.type_right},
          {"tp_m2", Num(e.tp)},
          {"fp_m2", Num(e.fp)},
          {"fn_m2", Num(e.fn)},
          {"precision", Num(e.precision)},
          {"recall", Num(e.recall)},
          {"e_abs_m2", stats(e.e_abs)},
          {"e_r", stats(e.e_r)},
          {"fn_max_m2", Num(e.fn_max)},
          {"fp_max_m2", Num(e.fp_max)},
          {"door_states",
           {{"rows", {"closed", "semi_open", "open"}},
            {"columns", {"closed", "semi_open", "open", "missed"}},
            {"matrix", matrix},
            {"doors", e.doors},
            {"right", e.door_state_right}}},
          {"angle_error_deg",
           {{"n", e.angle_error.n},
            {"mean", Num(e.angle_error.mean)},
            {"median", Num(e.angle_error_median)},
            {"max", Num(e.angle_error.max)}}},
          {"openings", rows}};
}

std::string MarkdownOpeningsTable(const OpeningEvaluation& e) {
  auto f = [](const char* fmt, double x) {
    if (!std::isfinite(x)) return std::string("-");
    char b[64];
    std::snprintf(b, sizeof b, fmt, x);
    return std::string(b);
  };
  std::string s;
  s += "| truth | recognised | missed | false | Precision | Recall | e_abs mean / max (m²) | "
       "e_r mean / max | fn max (m²) | fp max (m²) | door states right | angle error mean / "
       "median / max (deg) |\n";
  s += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  s += "| " + std::to_string(e.truth_count) + " | " + std::to_string(e.model_count) + " | " +
       std::to_string(e.missed) + " | " + std::to_string(e.false_openings) + " | " +
       f("%.4f", e.precision) + " | " + f("%.4f", e.recall) + " | " + f("%.4f", e.e_abs.mean) +
       " / " + f("%.4f", e.e_abs.max) + " | " + f("%.4f", e.e_r.mean) + " / " +
       f("%.4f", e.e_r.max) + " | " + f("%.4f", e.fn_max) + " | " + f("%.4f", e.fp_max) + " | " +
       std::to_string(e.door_state_right) + "/" + std::to_string(e.doors) + " | " +
       (e.angle_error.n > 0
            ? f("%.2f", e.angle_error.mean) + " / " + f("%.2f", e.angle_error_median) + " / " +
                  f("%.2f", e.angle_error.max)
            : std::string("-")) +
       " |\n\n";
  s += "| door state (truth \\ recognised) | closed | semi_open | open | missed |\n";
  s += "|---|---|---|---|---|\n";
  for (int i = 0; i < 3; ++i) {
    s += std::string("| ") + kDoorStateNames[i];
    for (int k = 0; k < 4; ++k) s += " | " + std::to_string(e.state_confusion[i][k]);
    s += " |\n";
  }
  s +=
      "\n| truth | recognised | type | area truth / recognised (m²) | tp | fp | fn | e_abs | e_r | "
      "state truth / recognised | lambda truth / recognised (deg) |\n";
  s += "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : e.rows) {
    const std::string type = r.truth_type.empty()           ? r.model_type
                             : r.model_type.empty()         ? r.truth_type
                             : r.truth_type == r.model_type ? r.truth_type
                                                            : r.truth_type + " / " + r.model_type;
    s += "| " + (r.truth_id.empty() ? "-" : r.truth_id) + " | " +
         (r.model_id.empty() ? "-" : r.model_id) + " | " + type + " | " + f("%.3f", r.truth_area) +
         " / " + f("%.3f", r.model_area) + " | " + f("%.3f", r.tp) + " | " + f("%.3f", r.fp) +
         " | " + f("%.3f", r.fn) + " | " + f("%.3f", r.e_abs) + " | " + f("%.3f", r.e_r) + " | " +
         (r.truth_state.empty() ? "-" : r.truth_state) + " / " +
         (r.model_state.empty() ? "-" : r.model_state) + " | " + f("%.1f", r.truth_angle_deg) +
         " / " + f("%.1f", r.model_angle_deg) + " |\n";
  }
  return s;
}

}  // namespace mopad::evaluation
