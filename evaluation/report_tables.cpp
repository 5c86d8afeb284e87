#include "evaluation/report_tables.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/format.h"
#include "evaluation/json_number.h"

namespace mopad::evaluation {
namespace {

using nlohmann::json;

json NumVec(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(Num(x));
  return a;
}

json ToJson(const PrecisionRecall& s) {
  return {{"tp", s.tp},
          {"n_predicted", s.n_predicted},
          {"n_truth", s.n_truth},
          {"precision", Num(s.precision)},
          {"recall", Num(s.recall)},
          {"f1", Num(s.f1)}};
}

json ToJson(const IsprsCurve& c) {
  return {{"reference_area", Num(c.reference_area)},
          {"source_area", Num(c.source_area)},
          {"completeness", NumVec(c.completeness)},
          {"correctness", NumVec(c.correctness)},
          {"accuracy", Num(c.accuracy)},
          {"accuracy_samples", c.accuracy_samples}};
}

// Class name for the ISPRS table/plot rows: index kNumSurfaceClasses is "all".
std::string RowName(int ci) {
  return ci < kNumSurfaceClasses ? SurfaceClassName(static_cast<SurfaceClass>(ci)) : "all";
}

}  // namespace

nlohmann::json ToJson(const ErrorStats& s) {
  return {{"n", s.n}, {"mean", Num(s.mean)}, {"max", Num(s.max)}};
}

nlohmann::json ToJson(const PatchEvaluation& e) {
  json classes = json::object();
  for (SurfaceClass c : AllSurfaceClasses()) {
    const int ci = static_cast<int>(c);
    const ClassDetection& d = e.detection[ci];
    const ClassAccuracy& a = e.accuracy[ci];
    classes[SurfaceClassName(c)] = {{"n_truth", d.n_truth},
                                    {"n_model", d.n_model},
                                    {"tp", d.tp},
                                    {"fp", d.fp},
                                    {"fn", d.fn},
                                    {"recall", Num(d.Recall())},
                                    {"precision", Num(d.Precision())},
                                    {"d_v", ToJson(a.d_v)},
                                    {"d_h", ToJson(a.d_h)},
                                    {"phi_deg", ToJson(a.phi_deg)}};
  }
  json pairs = json::array();
  for (const PatchPair& p : e.pairs) {
    pairs.push_back({{"model", p.model_id},
                     {"truth", p.truth_id},
                     {"class", SurfaceClassName(p.cls)},
                     {"iou", Num(p.iou)},
                     {"plane_distance", Num(p.plane_distance)},
                     {"phi_deg", Num(p.phi_deg)},
                     {"d_v", ToJson(p.d_v)},
                     {"d_h", ToJson(p.d_h)},
                     {"unpaired_edges", p.unpaired_edges}});
  }
  return {{"classes", classes},
          {"d_v", ToJson(e.d_v)},
          {"d_h", ToJson(e.d_h)},
          {"phi_deg", ToJson(e.phi_deg)},
          {"pairs", pairs},
          {"false_positives", e.unmatched_model_ids},
          {"false_negatives", e.unmatched_truth_ids}};
}

nlohmann::json ToJson(const IsprsResult& r) {
  json classes = json::object();
  for (SurfaceClass c : AllSurfaceClasses()) {
    classes[SurfaceClassName(c)] = ToJson(r.per_class[static_cast<int>(c)]);
  }
  json refp = json::array(), srcp = json::array();
  for (const auto& v : r.reference_patch_completeness) refp.push_back(NumVec(v));
  for (const auto& v : r.source_patch_correctness) srcp.push_back(NumVec(v));
  return {{"buffers", NumVec(r.buffers)},
          {"cutoff", Num(r.cutoff)},
          {"classes", classes},
          {"all", ToJson(r.all)},
          {"reference_patch_completeness", refp},
          {"source_patch_correctness", srcp}};
}

nlohmann::json ToJson(const FloorplanResult& r) {
  json pairs = json::array();
  for (const RoomPair& p : r.room_pairs) {
    pairs.push_back({{"predicted", p.predicted_id},
                     {"truth", p.truth_id},
                     {"iou", Num(p.iou)},
                     {"true_positive", p.true_positive}});
  }
  json corners = json::array();
  for (const CornerScore& c : r.corners) {
    json j = ToJson(c.score);
    j["threshold"] = c.threshold;
    corners.push_back(j);
  }
  return {{"room_pairs", pairs},
          {"truth_room_iou", NumVec(r.truth_room_iou)},
          {"mean_truth_iou", Num(r.mean_truth_iou)},
          {"rooms", ToJson(r.rooms)},
          {"corners", corners},
          {"angles", ToJson(r.angles)}};
}

nlohmann::json ToJson(const ConfusionMatrix& m) {
  json rows = json::array();
  const size_t k = m.labels.size();
  for (size_t t = 0; t < k; ++t) {
    json row = json::array();
    for (size_t p = 0; p < k; ++p) row.push_back(m.counts[t * k + p]);
    rows.push_back(row);
  }
  return {{"labels", m.labels},         {"counts", rows},
          {"total", m.total},           {"accuracy", Num(m.accuracy)},
          {"iou", NumVec(m.iou)},       {"precision", NumVec(m.precision)},
          {"recall", NumVec(m.recall)}, {"mean_iou", Num(m.mean_iou)}};
}

// ---------------------------------------------------------------------------------------------
std::string MarkdownPatchTable(const PatchEvaluation& e) {
  std::ostringstream s;
  s << "| class | N | TP | FP | FN | TP % | d_v mean (cm) | d_v max (cm) | d_h mean (cm) "
       "| d_h max (cm) | Φ mean (°) | Φ max (°) |\n"
    << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  auto stat = [](const ErrorStats& st, double scale, int digits) {
    return st.n > 0
               ? FormatFixed(st.mean * scale, digits) + " | " + FormatFixed(st.max * scale, digits)
               : std::string("- | -");
  };
  int n = 0, tp = 0, fp = 0, fn = 0;
  for (SurfaceClass c : AllSurfaceClasses()) {
    const int ci = static_cast<int>(c);
    const ClassDetection& d = e.detection[ci];
    const ClassAccuracy& a = e.accuracy[ci];
    n += d.n_truth;
    tp += d.tp;
    fp += d.fp;
    fn += d.fn;
    s << "| " << SurfaceClassName(c) << " | " << d.n_truth << " | " << d.tp << " | " << d.fp
      << " | " << d.fn << " | " << FormatFixed(100.0 * d.Recall(), 1) << " | "
      << stat(a.d_v, 100.0, 2) << " | " << stat(a.d_h, 100.0, 2) << " | " << stat(a.phi_deg, 1.0, 3)
      << " |\n";
  }
  s << "| overall | " << n << " | " << tp << " | " << fp << " | " << fn << " | "
    << FormatFixed(n > 0 ? 100.0 * tp / n : NAN, 1) << " | " << stat(e.d_v, 100.0, 2) << " | "
    << stat(e.d_h, 100.0, 2) << " | " << stat(e.phi_deg, 1.0, 3) << " |\n";
  return s.str();
}

std::string MarkdownIsprsTable(const IsprsResult& r, double buffer) {
  const int k = r.BufferIndex(buffer);
  const std::string b = r.buffers.empty() ? "?" : FormatFixed(r.buffers[k] * 100.0, 0);
  std::ostringstream s;
  s << "| class | reference area (m²) | source area (m²) | completeness @" << b
    << " cm | correctness @" << b << " cm | accuracy (cm, r = " << FormatFixed(r.cutoff * 100.0, 0)
    << " cm) |\n|---|---:|---:|---:|---:|---:|\n";
  for (int ci = 0; ci <= kNumSurfaceClasses; ++ci) {
    const IsprsCurve& c = ci < kNumSurfaceClasses ? r.per_class[ci] : r.all;
    if (c.reference_area <= 0.0 && c.source_area <= 0.0) continue;
    s << "| " << RowName(ci) << " | " << FormatFixed(c.reference_area, 2) << " | "
      << FormatFixed(c.source_area, 2) << " | "
      << FormatFixed(r.buffers.empty() ? NAN : c.completeness[k], 4) << " | "
      << FormatFixed(r.buffers.empty() ? NAN : c.correctness[k], 4) << " | "
      << FormatFixed(c.accuracy * 100.0, 2) << " |\n";
  }
  return s.str();
}

std::string MarkdownFloorplanTable(const FloorplanResult& r) {
  std::ostringstream s;
  s << "| metric | TP | predicted | truth | precision | recall | F1 |\n"
    << "|---|---:|---:|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& name, const PrecisionRecall& p) {
    s << "| " << name << " | " << p.tp << " | " << p.n_predicted << " | " << p.n_truth << " | "
      << FormatFixed(p.precision, 3) << " | " << FormatFixed(p.recall, 3) << " | "
      << FormatFixed(p.f1, 3) << " |\n";
  };
  row("rooms (IoU > 0.5)", r.rooms);
  for (const CornerScore& c : r.corners)
    row("corners @" + FormatFixed(c.threshold * 100.0, 0) + " cm", c.score);
  row("angles (≤ 5°)", r.angles);
  s << "\nMean room IoU over truth rooms: " << FormatFixed(r.mean_truth_iou, 4) << "\n";
  return s.str();
}

std::string MarkdownConfusionTable(const ConfusionMatrix& m) {
  std::ostringstream s;
  const size_t k = m.labels.size();
  s << "| truth \\ predicted |";
  for (const std::string& l : m.labels) s << " " << l << " |";
  s << " IoU | precision | recall |\n|---|";
  for (size_t i = 0; i < k + 3; ++i) s << "---:|";
  s << "\n";
  for (size_t t = 0; t < k; ++t) {
    s << "| " << m.labels[t] << " |";
    for (size_t p = 0; p < k; ++p) s << " " << m.counts[t * k + p] << " |";
    s << " " << FormatFixed(m.iou[t], 4) << " | " << FormatFixed(m.precision[t], 4) << " | "
      << FormatFixed(m.recall[t], 4) << " |\n";
  }
  s << "\nAccuracy: " << FormatFixed(m.accuracy, 4) << " over " << m.total
    << " elements; mean IoU: " << FormatFixed(m.mean_iou, 4) << "\n";
  return s.str();
}

// ---------------------------------------------------------------------------------------------
std::string IsprsSvgPlot(const IsprsResult& r, const std::string& title) {
  // Plot area in pixels; x = buffer (cm), y = share [0, 1].
  const double W = 520, H = 320, L = 55, R = 130, T = 30, B = 45;
  const double pw = W - L - R, ph = H - T - B;
  const double xmax = r.buffers.empty() ? 1.0 : std::max(1e-9, r.buffers.back() * 100.0);
  auto X = [&](double b_cm) { return L + pw * b_cm / xmax; };
  auto Y = [&](double v) { return T + ph * (1.0 - v); };
  static const char* kColors[] = {"#1f77b4", "#2ca02c", "#d62728", "#9467bd", "#000000"};
  std::string esc;
  for (char c : title) {
    if (c == '<')
      esc += "&lt;";
    else if (c == '>')
      esc += "&gt;";
    else if (c == '&')
      esc += "&amp;";
    else
      esc += c;
  }
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n"
    << "<rect width=\"" << W << "\" height=\"" << H << "\" fill=\"white\"/>\n"
    << "<text x=\"" << L << "\" y=\"18\" font-size=\"13\">" << esc << "</text>\n";
  // Axes, grid and ticks.
  for (int i = 0; i <= 5; ++i) {
    const double v = i / 5.0;
    s << "<line x1=\"" << L << "\" y1=\"" << FormatFixed(Y(v), 1) << "\" x2=\"" << L + pw
      << "\" y2=\"" << FormatFixed(Y(v), 1) << "\" stroke=\"#ddd\"/>\n"
      << "<text x=\"" << L - 6 << "\" y=\"" << FormatFixed(Y(v) + 4, 1) << "\" text-anchor=\"end\">"
      << FormatFixed(v, 1) << "</text>\n";
  }
  const int xticks = 5;
  for (int i = 0; i <= xticks; ++i) {
    const double b = xmax * i / xticks;
    s << "<text x=\"" << FormatFixed(X(b), 1) << "\" y=\"" << T + ph + 16
      << "\" text-anchor=\"middle\">" << FormatFixed(b, 0) << "</text>\n";
  }
  s << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << pw << "\" height=\"" << ph
    << "\" fill=\"none\" stroke=\"#333\"/>\n"
    << "<text x=\"" << L + pw / 2 << "\" y=\"" << H - 8
    << "\" text-anchor=\"middle\">buffer b (cm)</text>\n"
    << "<text x=\"14\" y=\"" << T + ph / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 "
    << T + ph / 2 << ")\">share of area</text>\n";
  int legend = 0;
  for (int ci = 0; ci <= kNumSurfaceClasses; ++ci) {
    const IsprsCurve& c = ci < kNumSurfaceClasses ? r.per_class[ci] : r.all;
    if (c.reference_area <= 0.0 && c.source_area <= 0.0) continue;
    const char* color = kColors[ci];
    for (int kind = 0; kind < 2; ++kind) {
      const std::vector<double>& v = kind == 0 ? c.completeness : c.correctness;
      std::string pts;
      for (size_t k = 0; k < r.buffers.size(); ++k) {
        if (!std::isfinite(v[k])) continue;
        pts += FormatFixed(X(r.buffers[k] * 100.0), 1) + "," + FormatFixed(Y(v[k]), 1) + " ";
      }
      if (pts.empty()) continue;
      pts.pop_back();
      s << "<polyline fill=\"none\" stroke=\"" << color << "\" stroke-width=\"1.5\""
        << (kind == 1 ? " stroke-dasharray=\"5,3\"" : "") << " points=\"" << pts << "\"/>\n";
    }
    const double ly = T + 10 + 16 * legend++;
    s << "<line x1=\"" << L + pw + 10 << "\" y1=\"" << ly << "\" x2=\"" << L + pw + 30 << "\" y2=\""
      << ly << "\" stroke=\"" << color << "\" stroke-width=\"2\"/>\n"
      << "<text x=\"" << L + pw + 35 << "\" y=\"" << ly + 4 << "\">" << RowName(ci) << "</text>\n";
  }
  const double ly = T + 10 + 16 * legend + 8;
  s << "<text x=\"" << L + pw + 10 << "\" y=\"" << ly << "\">solid: completeness</text>\n"
    << "<text x=\"" << L + pw + 10 << "\" y=\"" << ly + 14 << "\">dashed: correctness</text>\n"
    << "</svg>\n";
  return s.str();
}

}  // namespace mopad::evaluation
