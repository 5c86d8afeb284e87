#include "suite/scoreboard.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common/format.h"
#include "suite/figures.h"

namespace mopad::suite {

namespace {

// The per-case table's figure columns.
const std::vector<std::string> kCaseColumns = {
    "rooms_modelled", "rooms_reachable", "wall_precision", "wall_recall", "d_h_mean",
    "sm4_precision",  "sm4_recall",      "sm5_tp_rate",    "localisation_max_m", "contacts",
    "scans"};
const std::vector<std::string> kSm3 = {"walls_tp", "walls_fp", "walls_fn",   "floors_tp",
                                       "ceilings_tp", "d_v_mean", "d_h_mean", "d_v_max",
                                       "d_h_max",  "phi_mean_deg", "phi_max_deg"};
const std::vector<std::string> kSm4 = {"sm4_precision",     "sm4_recall",   "sm4_fn_max_m2",
                                       "sm4_fp_max_m2",     "sm4_e_abs_mean_m2", "sm4_e_r_mean",
                                       "sm4_door_states_right"};

// Shown scale and unit of a figure: lengths in cm, shares in %.
struct Shown {
  double scale;
  std::string unit;
  int digits;
};
Shown ShownOf(const std::string& fig) {
  const FigureInfo i = InfoOf(fig);
  if (i.unit == "m") return {100.0, "cm", 2};
  if (fig.find("precision") != std::string::npos || fig.find("recall") != std::string::npos ||
      fig.find("rate") != std::string::npos || fig.find("share") != std::string::npos ||
      fig == "coverage_min" || fig == "sm4_door_states_right")
    return {100.0, "%", 1};
  if (i.unit == "m2" || i.unit == "deg") return {1.0, i.unit, 3};
  if (fig == "sm4_e_r_mean") return {1.0, "", 3};
  return {1.0, i.unit, 1};
}
std::string Title(const std::string& fig) {
  const Shown s = ShownOf(fig);
  const std::string label = InfoOf(fig).label;
  return s.unit.empty() ? label : label + " (" + s.unit + ")";
}
std::string Value(const std::string& fig, double v) {
  const Shown s = ShownOf(fig);
  if (s.unit.empty() && v == std::floor(v)) return FormatFixed(v, 0);
  return FormatFixed(v * s.scale, s.digits);
}

struct Table {
  std::string title;
  std::vector<std::string> head;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::vector<std::string>> links;  ///< per row: href of the first cell ("" = none)
};

std::string Markdown(const Table& t) {
  if (t.rows.empty()) return "";
  auto cell = [](std::string s) {
    std::string o;
    for (char c : s) o += c == '|' ? std::string("\\|") : std::string(1, c);
    return o;
  };
  std::string out = "## " + t.title + "\n\n|";
  for (const auto& h : t.head) out.append(" ").append(cell(h)).append(" |");
  out += "\n|";
  for (std::size_t i = 0; i < t.head.size(); ++i) out += i == 0 ? "---|" : "---:|";
  out += "\n";
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    out += "|";
    for (std::size_t c = 0; c < t.rows[r].size(); ++c) {
      std::string v = cell(t.rows[r][c]);
      if (c == 0 && r < t.links.size() && !t.links[r].empty() && !t.links[r][0].empty())
        v = "[" + v + "](" + t.links[r][0] + ")";
      out += " " + v + " |";
    }
    out += "\n";
  }
  return out + "\n";
}

std::string Html(const Table& t) {
  if (t.rows.empty()) return "";
  std::string out = "<h2>" + XmlEscape(t.title) + "</h2>\n<table>\n<tr>";
  for (const auto& h : t.head) out += "<th>" + XmlEscape(h) + "</th>";
  out += "</tr>\n";
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    out += "<tr>";
    for (std::size_t c = 0; c < t.rows[r].size(); ++c) {
      std::string v = XmlEscape(t.rows[r][c]);
      if (c == 0 && r < t.links.size() && !t.links[r].empty() && !t.links[r][0].empty())
        v = "<a href=\"" + XmlEscape(t.links[r][0]) + "\">" + v + "</a>";
      const bool verdict = c == 1 && t.head.size() > 1 && t.head[1] == "verdict";
      out += verdict ? "<td class=\"" + XmlEscape(t.rows[r][c]) + "\">" + v + "</td>"
                     : "<td>" + v + "</td>";
    }
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

const PooledFigure* Find(const SuiteSummary& s, const std::string& g, const std::string& f) {
  for (const auto& p : s.pooled)
    if (p.group == g && p.figure == f) return &p;
  return nullptr;
}
std::string MeanSd(const SuiteSummary& s, const std::string& g, const std::string& f) {
  const PooledFigure* p = Find(s, g, f);
  if (p == nullptr) return "-";
  std::string v = Value(f, p->mean);
  if (p->n > 1) v += " ± " + Value(f, p->sd);
  return v;
}

std::vector<Table> Tables(const Manifest& m, const std::vector<CaseResult>& cases,
                          const SuiteSummary& s) {
  std::vector<Table> out;
  const std::vector<std::string> groups = Groups(cases);
  // Per case.
  Table t{"Cases", {"case", "verdict"}, {}, {}};
  for (const auto& f : kCaseColumns) t.head.push_back(Title(f));
  t.head.push_back("message");
  for (const auto& c : cases) {
    std::vector<std::string> row{c.id, c.verdict};
    for (const auto& f : kCaseColumns) {
      auto it = c.figures.find(f);
      row.push_back(it == c.figures.end() ? "-" : Value(f, it->second));
    }
    row.push_back(c.message);
    t.rows.push_back(row);
    t.links.push_back({c.dir + "/report.html"});
  }
  out.push_back(t);
  auto pooled_table = [&](const std::string& title, const std::vector<std::string>& figs) {
    Table p{title, {"group", "n"}, {}, {}};
    for (const auto& f : figs) p.head.push_back(Title(f));
    for (const auto& g : groups) {
      bool any = false;
      for (const auto& f : figs) any |= Find(s, g, f) != nullptr;
      if (!any) continue;
      int n = 0;
      for (const auto& c : cases) n += c.group == g && !c.figures.empty();
      std::vector<std::string> row{g, std::to_string(n)};
      for (const auto& f : figs) row.push_back(MeanSd(s, g, f));
      p.rows.push_back(row);
    }
    return p;
  };
  out.push_back(pooled_table("Groups: mean ± sd over seeds", kCaseColumns));
  out.push_back(pooled_table("SM3: structural elements (mean ± sd over seeds)", kSm3));
  out.push_back(pooled_table("SM4: openings (mean ± sd over seeds)", kSm4));
  // The paper's Table 3: per class, each group.
  for (const auto& g : groups) {
    std::set<std::string> classes;
    for (const auto& p : s.pooled)
      if (p.group == g && p.figure.rfind("sm5_class.", 0) == 0) {
        const std::string rest = p.figure.substr(10);
        classes.insert(rest.substr(0, rest.rfind('.')));
      }
    if (classes.empty()) continue;
    Table c{"SM5: building service components, " + g + " (the paper's Table 3; mean ± sd over seeds)",
            {"class", "N", "TP (%)", "FN (%)", "FP (%)", "TP with α>0.9 (%)", "TP with α=0.5 (%)"},
            {},
            {}};
    for (const std::string& cl : classes) {
      const std::string k = "sm5_class." + cl + ".";
      c.rows.push_back({cl, MeanSd(s, g, k + "n"), MeanSd(s, g, k + "tp_share"),
                        MeanSd(s, g, k + "fn_share"), MeanSd(s, g, k + "fp_share"),
                        MeanSd(s, g, k + "tp_alpha_above_0_9_share"),
                        MeanSd(s, g, k + "tp_alpha_0_5_share")});
    }
    c.rows.push_back({"all", "", MeanSd(s, g, "sm5_tp_rate"), MeanSd(s, g, "sm5_fn_rate"),
                      MeanSd(s, g, "sm5_fp_rate"), "", ""});
    out.push_back(c);
  }
  Table pc{"Pooled checks", {"group", "check", "value", "bound", "result"}, {}, {}};
  for (const auto& p : s.pooled_checks)
    pc.rows.push_back({p.group, p.check, p.value ? FormatShortest(*p.value) : "null",
                       p.bound ? FormatShortest(*p.bound) : "null", p.passed ? "pass" : "FAIL"});
  out.push_back(pc);
  (void)m;
  return out;
}

std::string TotalsLine(const SuiteSummary& s) {
  std::string t = std::to_string(s.totals.at("cases")) + " cases:";
  for (const char* v : kVerdicts) t.append(" ").append(std::to_string(s.totals.at(v))).append(" ").append(v).append(",");
  t.pop_back();
  return t + (s.all_passed ? " — PASS" : " — FAIL");
}

// One strip plot per main figure: a row per group, a dot per case (SVG, self-contained).
std::string Distributions(const std::vector<CaseResult>& cases) {
  const std::vector<std::string> groups = Groups(cases);
  std::string out = "<h2>Distributions</h2>\n";
  const double w = 640, row_h = 22, left = 220;
  for (const auto& fi : MainFigures()) {
    std::vector<double> all;
    for (const auto& c : cases)
      if (auto it = c.figures.find(fi.name); it != c.figures.end()) all.push_back(it->second);
    if (all.empty()) continue;
    const Shown sh = ShownOf(fi.name);
    double lo = *std::min_element(all.begin(), all.end()) * sh.scale;
    double hi = *std::max_element(all.begin(), all.end()) * sh.scale;
    if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
    const double h = row_h * groups.size() + 30;
    out += "<figure><figcaption>" + XmlEscape(Title(fi.name)) + " (better: " + fi.better +
           ")</figcaption>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
           FormatFixed(w, 0) + "\" height=\"" + FormatFixed(h, 0) + "\">\n";
    auto x_of = [&](double v) { return left + (v - lo) / (hi - lo) * (w - left - 20); };
    for (std::size_t gi = 0; gi < groups.size(); ++gi) {
      const double y = row_h * gi + row_h / 2;
      out += "<text x=\"4\" y=\"" + FormatFixed(y + 4, 1) + "\" font-size=\"11\">" +
             XmlEscape(groups[gi]) + "</text>\n<line x1=\"" + FormatFixed(left, 1) + "\" x2=\"" +
             FormatFixed(w - 20, 1) + "\" y1=\"" + FormatFixed(y, 1) + "\" y2=\"" +
             FormatFixed(y, 1) + "\" stroke=\"#ddd\"/>\n";
      for (const auto& c : cases) {
        if (c.group != groups[gi]) continue;
        auto it = c.figures.find(fi.name);
        if (it == c.figures.end()) continue;
        out += "<circle cx=\"" + FormatFixed(x_of(it->second * sh.scale), 1) + "\" cy=\"" +
               FormatFixed(y, 1) + "\" r=\"4\" fill=\"" +
               (c.verdict == "passed" ? "#2a7" : "#d43") + "\" fill-opacity=\"0.7\"><title>" +
               XmlEscape(c.id) + ": " + Value(fi.name, it->second) + "</title></circle>\n";
      }
    }
    const double yb = row_h * groups.size() + 18;
    out += "<text x=\"" + FormatFixed(left, 1) + "\" y=\"" + FormatFixed(yb, 1) +
           "\" font-size=\"11\">" + FormatFixed(lo, sh.digits) + "</text><text x=\"" +
           FormatFixed(w - 20, 1) + "\" y=\"" + FormatFixed(yb, 1) +
           "\" font-size=\"11\" text-anchor=\"end\">" + FormatFixed(hi, sh.digits) +
           "</text>\n</svg></figure>\n";
  }
  return out;
}

}  // namespace

std::string ScoreboardMarkdown(const Manifest& m, const std::vector<CaseResult>& cases,
                               const SuiteSummary& s) {
  std::string out = "# Suite " + m.name + "\n\nManifest: `" + m.path + "`. " + TotalsLine(s) +
                    "\n\n";
  for (const Table& t : Tables(m, cases, s)) out += Markdown(t);
  return out;
}

std::string ScoreboardHtml(const Manifest& m, const std::vector<CaseResult>& cases,
                           const SuiteSummary& s) {
  std::string out =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Suite " + XmlEscape(m.name) +
      "</title>\n<style>body{font-family:sans-serif;margin:1em 2em}table{border-collapse:"
      "collapse;font-size:13px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
      "td:first-child,th:first-child{text-align:left}.passed{background:#dfd}.failed{background:"
      "#fdd}.error,.timeout,.crashed{background:#fd9}figure{margin:1em 0}</style></head><body>\n"
      "<h1>Suite " + XmlEscape(m.name) + "</h1>\n<p>Manifest: <code>" + XmlEscape(m.path) +
      "</code>. " + XmlEscape(TotalsLine(s)) + "</p>\n";
  for (const Table& t : Tables(m, cases, s)) out += Html(t);
  out += Distributions(cases);
  return out + "</body></html>\n";
}

}  // namespace mopad::suite
