#include "report/report.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "common/polygon.h"
#include "report/report_viewer.h"
#include "report/report_walls.h"

namespace mopad::report {

std::string HtmlEscape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

namespace {

std::string Escape(const std::string& s) { return HtmlEscape(s); }

const char* DoorColour(scenes::DoorState s) {
  switch (s) {
    case scenes::DoorState::kOpen:
      return "#2e9d3a";
    case scenes::DoorState::kSemiOpen:
      return "#e69500";
    case scenes::DoorState::kClosed:
      return "#c62828";
  }
  return "#000";
}

// Maps world (x, y) to SVG pixels (y down).
struct PlanView {
  double min_x, max_y, scale;
  std::string P(double x, double y) const {
    return FormatFixed((x - min_x) * scale + 20, 1) + "," +
           FormatFixed((max_y - y) * scale + 20, 1);
  }
  double X(double x) const { return (x - min_x) * scale + 20; }
  double Y(double y) const { return (max_y - y) * scale + 20; }
};

// A point well inside a (possibly non-convex) room: the vertex mean if it is inside, else the
// inside point of a coarse grid nearest to it.
Eigen::Vector2d LabelPoint(const std::vector<Eigen::Vector2d>& poly) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  if (poly.empty()) return c;
  Eigen::AlignedBox2d box;
  for (const auto& p : poly) {
    c += p;
    box.extend(p);
  }
  c /= static_cast<double>(poly.size());
  if (PointInPolygon(c, poly)) return c;
  Eigen::Vector2d best = c;
  double best_d = 1e18;
  for (int i = 1; i < 40; ++i)
    for (int j = 1; j < 40; ++j) {
      const Eigen::Vector2d p =
          box.min() + Eigen::Vector2d(box.sizes().x() * i / 40.0, box.sizes().y() * j / 40.0);
      if (PointInPolygon(p, poly) && (p - c).squaredNorm() < best_d) {
        best_d = (p - c).squaredNorm();
        best = p;
      }
    }
  return best;
}

}  // namespace

std::string PlanSvg(const ReportInput& in) {
  Eigen::AlignedBox2d box;
  if (in.truth)
    for (const auto& r : in.truth->rooms)
      for (const auto& p : r.polygon) box.extend(p);
  for (const auto& s : in.scans) {
    box.extend(s.position.head<2>());
    for (const auto& p : s.plan_points) box.extend(p.cast<double>());
  }
  if (box.isEmpty()) return "";
  const double width_px = 900.0;
  const double scale = width_px / std::max(1e-6, box.sizes().x());
  const PlanView v{box.min().x(), box.max().y(), scale};
  const double h_px = box.sizes().y() * scale + 40;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << FormatFixed(width_px + 40, 1)
    << "' height='" << FormatFixed(h_px, 1) << "' viewBox='0 0 " << FormatFixed(width_px + 40, 1)
    << " " << FormatFixed(h_px, 1) << "' font-family='sans-serif' font-size='12'>\n";
  if (in.truth) {
    for (const auto& r : in.truth->rooms) {
      s << "<polygon fill='#f3f1ea' stroke='#333' stroke-width='2' points='";
      for (const auto& p : r.polygon) s << v.P(p.x(), p.y()) << " ";
      s << "'/>\n";
    }
    for (const auto& e : in.truth->elements) {
      if (e.element_class != scenes::ElementClass::kColumn) continue;
      for (const auto& poly : e.polygons) {
        if (poly.size() < 2) continue;
        s << "<line stroke='#555' stroke-width='3' x1='" << FormatFixed(v.X(poly[0].x()), 1)
          << "' y1='" << FormatFixed(v.Y(poly[0].y()), 1) << "' x2='"
          << FormatFixed(v.X(poly[1].x()), 1) << "' y2='" << FormatFixed(v.Y(poly[1].y()), 1)
          << "'/>\n";
      }
    }
    for (const auto& f : in.truth->furniture) {
      s << "<g transform='translate(" << v.P(f.centre.x(), f.centre.y()) << ") rotate("
        << FormatFixed(-f.yaw * 180.0 / 3.14159265358979, 1)
        << ")'><rect fill='#bbb' fill-opacity='0.6' x='" << FormatFixed(-f.size.x() * scale / 2, 1)
        << "' y='" << FormatFixed(-f.size.y() * scale / 2, 1) << "' width='"
        << FormatFixed(f.size.x() * scale, 1) << "' height='" << FormatFixed(f.size.y() * scale, 1)
        << "'/></g>\n";
    }
    for (const auto& o : in.truth->openings) {
      if (o.corners.size() < 2) continue;
      // The opening's plan extent: the two corners farthest apart in plan view.
      std::size_t a = 0, b = 1;
      for (std::size_t i = 0; i < o.corners.size(); ++i)
        for (std::size_t j = i + 1; j < o.corners.size(); ++j)
          if ((o.corners[i] - o.corners[j]).head<2>().norm() >
              (o.corners[a] - o.corners[b]).head<2>().norm()) {
            a = i;
            b = j;
          }
      const bool door = o.type == scenes::OpeningType::kDoor;
      s << "<line stroke='" << (door ? DoorColour(o.state) : "#1e88e5") << "' stroke-width='"
        << (door ? 6 : 4) << "' x1='" << FormatFixed(v.X(o.corners[a].x()), 1) << "' y1='"
        << FormatFixed(v.Y(o.corners[a].y()), 1) << "' x2='"
        << FormatFixed(v.X(o.corners[b].x()), 1) << "' y2='"
        << FormatFixed(v.Y(o.corners[b].y()), 1) << "'><title>" << Escape(o.id) << " ("
        << (door ? std::string(scenes::ToString(o.state)) : std::string("window"))
        << ")</title></line>\n";
    }
    for (const auto& b : in.truth->service_components) {
      s << "<circle r='3' fill='#8e24aa' cx='" << FormatFixed(v.X(b.centre.x()), 1) << "' cy='"
        << FormatFixed(v.Y(b.centre.y()), 1) << "'><title>" << Escape(b.id + " " + b.bsc_class)
        << "</title></circle>\n";
    }
  }
  for (const auto& sc : in.scans) {
    // One 1-pixel square per SVG pixel the scan's points fall in (sorted, so deterministic).
    std::vector<std::pair<long, long>> px;
    px.reserve(sc.plan_points.size());
    for (const auto& p : sc.plan_points)
      px.emplace_back(std::lround(std::floor(v.X(p.x()))), std::lround(std::floor(v.Y(p.y()))));
    std::sort(px.begin(), px.end());
    px.erase(std::unique(px.begin(), px.end()), px.end());
    if (px.empty()) continue;
    s << "<path class='scan-points' fill='#1565c0' fill-opacity='0.35' d='";
    for (const auto& [x, y] : px) s << "M" << x << " " << y << "h1v1h-1z";
    s << "'/>\n";
  }
  if (in.path.size() >= 2) {
    s << "<polyline fill='none' stroke='#e65100' stroke-width='1.5' stroke-opacity='0.8' "
         "points='";
    for (const auto& p : in.path) s << v.P(p.x(), p.y()) << " ";
    s << "'><title>the robot's true path</title></polyline>\n";
  }
  for (const auto& e : in.tree_edges) {
    s << "<polyline fill='none' stroke='#2e7d32' stroke-width='3' stroke-dasharray='8 4' "
         "points='"
      << v.P(e.from.x(), e.from.y()) << " " << v.P(e.via.x(), e.via.y()) << " "
      << v.P(e.to.x(), e.to.y()) << "'><title>" << Escape(e.label) << "</title></polyline>\n";
  }
  for (const auto& sc : in.scans) {
    const double x = v.X(sc.position.x()), y = v.Y(sc.position.y());
    s << "<g stroke='" << (sc.door ? "#2e7d32" : "#000") << "' stroke-width='2'><line x1='"
      << FormatFixed(x - 6, 1) << "' y1='" << FormatFixed(y - 6, 1) << "' x2='"
      << FormatFixed(x + 6, 1) << "' y2='" << FormatFixed(y + 6, 1) << "'/><line x1='"
      << FormatFixed(x - 6, 1) << "' y1='" << FormatFixed(y + 6, 1) << "' x2='"
      << FormatFixed(x + 6, 1) << "' y2='" << FormatFixed(y - 6, 1) << "'/></g><text x='"
      << FormatFixed(x + 8, 1) << "' y='" << FormatFixed(y - 8, 1) << "'>" << Escape(sc.name)
      << "</text>\n";
  }
  if (in.truth)
    for (const auto& r : in.truth->rooms) {
      const Eigen::Vector2d c = LabelPoint(r.polygon);
      s << "<text font-weight='bold' x='" << FormatFixed(v.X(c.x()), 1) << "' y='"
        << FormatFixed(v.Y(c.y()), 1) << "'>" << Escape(r.id) << "</text>\n";
    }
  s << "</svg>\n";
  return s.str();
}

std::string CoveragePlotSvg(const ReportCoverage& c, double threshold) {
  // Plot area in pixels: x from 40 to 300, y from 170 (share 0) to 20 (share 1).
  const double x0 = 40, x1 = 300, y0 = 170, y1 = 20;
  const std::size_t n = std::max(c.robot.size(), c.evaluator.size());
  const double last = std::max<double>(2.0, static_cast<double>(n));
  auto X = [&](std::size_t k) { return x0 + (x1 - x0) * (static_cast<double>(k) / (last - 1)); };
  auto Y = [&](double share) { return y0 + (y1 - y0) * std::clamp(share, 0.0, 1.0); };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' class='coverage' width='320' height='205' "
       "viewBox='0 0 320 205' font-family='sans-serif' font-size='11'><title>"
    << Escape(c.room) << ": coverage after each scan</title>\n";
  for (int i = 0; i <= 4; ++i) {
    const double y = Y(0.25 * i);
    s << "<line stroke='#ddd' x1='" << x0 << "' x2='" << x1 << "' y1='" << FormatFixed(y, 1)
      << "' y2='" << FormatFixed(y, 1) << "'/><text text-anchor='end' x='" << x0 - 4 << "' y='"
      << FormatFixed(y + 4, 1) << "'>" << FormatFixed(0.25 * i, 2) << "</text>\n";
  }
  for (std::size_t k = 0; k < n; ++k)
    s << "<text text-anchor='middle' x='" << FormatFixed(X(k), 1) << "' y='" << y0 + 14 << "'>"
      << k + 1 << "</text>";
  s << "<text text-anchor='middle' x='" << (x0 + x1) / 2 << "' y='" << y0 + 30 << "'>scan</text>\n";
  if (threshold > 0)
    s << "<line class='threshold' stroke='#c62828' stroke-dasharray='2 3' x1='" << x0 << "' x2='"
      << x1 << "' y1='" << FormatFixed(Y(threshold), 1) << "' y2='" << FormatFixed(Y(threshold), 1)
      << "'><title>stopping threshold epsilon1 = " << FormatFixed(threshold, 3)
      << "</title></line>\n";
  auto series = [&](const std::vector<double>& v, const char* cls, const char* colour,
                    const char* dash) {
    if (v.empty()) return;
    s << "<polyline fill='none' stroke='" << colour << "' stroke-width='2'" << dash << " points='";
    for (std::size_t k = 0; k < v.size(); ++k)
      s << FormatFixed(X(k), 1) << "," << FormatFixed(Y(v[k]), 1) << " ";
    s << "'/>";
    for (std::size_t k = 0; k < v.size(); ++k)
      s << "<circle class='" << cls << "' r='3' fill='" << colour << "' cx='"
        << FormatFixed(X(k), 1) << "' cy='" << FormatFixed(Y(v[k]), 1) << "'><title>scan " << k + 1
        << ": " << FormatFixed(v[k], 3) << "</title></circle>";
    s << "\n";
  };
  series(c.evaluator, "evaluator", "#6d6d6d", " stroke-dasharray='5 3'");
  series(c.robot, "robot", "#1565c0", "");
  s << "<text font-weight='bold' x='" << x0 << "' y='12'>" << Escape(c.room) << "</text></svg>\n";
  return s.str();
}

void WriteHtmlReport(const ReportInput& in, const std::string& path) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><title>" << Escape(in.title)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em;color:#222}"
    << "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 10px;"
    << "text-align:right}th{background:#eee}td:first-child{text-align:left}"
    << ".legend span{display:inline-block;margin-right:1.5em}"
    << "figure.wall{display:inline-block;margin:0 1em 1em 0}figcaption{font-size:small}"
    << "svg.coverage{margin-right:1em}</style></head><body>\n";
  h << "<h1>" << Escape(in.title) << "</h1>\n<p>" << Escape(in.subtitle) << "</p>\n";
  const std::string svg = PlanSvg(in);
  if (!svg.empty()) {
    h << "<h2>Plan view</h2>\n<p class='legend'><span style='color:#2e9d3a'>&#9632; open door"
      << "</span><span style='color:#e69500'>&#9632; semi-open door</span><span "
      << "style='color:#c62828'>&#9632; closed door</span><span style='color:#1e88e5'>&#9632; "
      << "window</span><span style='color:#8e24aa'>&#9679; service component</span><span>&#10005;"
      << " scan position</span></p>\n"
      << svg;
  }
  if (!in.coverage.empty()) {
    bool scored = false;
    for (const auto& c : in.coverage) scored = scored || !c.evaluator.empty();
    h << "<h2>Coverage against scans</h2>\n<p class='legend'><span style='color:#1565c0'>&#9679; "
      << "the robot's estimate (sensed share of the structural area it modelled)</span>";
    if (scored)
      h << "<span style='color:#6d6d6d'>&#9679; the evaluator's (share of the truly observable "
        << "area)</span>";
    if (in.coverage_threshold > 0)
      h << "<span style='color:#c62828'>- - stopping threshold epsilon1 = "
        << FormatFixed(in.coverage_threshold, 2) << "</span>";
    h << "</p>\n<div class='plots'>\n";
    for (const auto& c : in.coverage) h << CoveragePlotSvg(c, in.coverage_threshold);
    h << "</div>\n";
  }
  const std::string run_dir = std::filesystem::path(path).parent_path().string();
  // The wall orthoimages and the 3D view of the model files beside the report (a run folder).
  h << WallImagesHtml(run_dir);
  h << ModelViewerHtml(run_dir, in.truth);
  for (const auto& t : in.tables) {
    h << "<h2>" << Escape(t.title) << "</h2>\n<table><tr>";
    for (const auto& c : t.header) h << "<th>" << Escape(c) << "</th>";
    h << "</tr>\n";
    for (const auto& r : t.rows) {
      h << "<tr>";
      for (const auto& c : r) h << "<td>" << Escape(c) << "</td>";
      h << "</tr>\n";
    }
    h << "</table>\n";
    if (!t.note.empty()) h << "<p>" << Escape(t.note) << "</p>\n";
  }
  h << "</body></html>\n";
  WriteWholeFile(path, h.str());
}

void WriteMarkdownReport(const ReportInput& in, const std::string& path) {
  std::ostringstream m;
  m << "# " << in.title << "\n\n" << in.subtitle << "\n";
  for (const auto& t : in.tables) {
    m << "\n## " << t.title << "\n\n|";
    for (const auto& c : t.header) m << " " << c << " |";
    m << "\n|";
    for (std::size_t i = 0; i < t.header.size(); ++i) m << (i == 0 ? " --- |" : " ---: |");
    m << "\n";
    for (const auto& r : t.rows) {
      m << "|";
      for (const auto& c : r) m << " " << c << " |";
      m << "\n";
    }
    if (!t.note.empty()) m << "\n" << t.note << "\n";
  }
  WriteWholeFile(path, m.str());
}

ReportTable ModelScoresTable(const nlohmann::ordered_json& summary) {
  ReportTable t{
      "Models against the truth (mopad eval, eval/evaluation.md)", {"figure", "value"}, {}, ""};
  int tp = 0, n = 0, fp = 0;
  for (const auto& [cls, d] : summary.at("detection").items())
    tp += d.at("tp").get<int>(), n += d.at("n_truth").get<int>(), fp += d.at("fp").get<int>();
  auto num = [](const nlohmann::ordered_json& v, double scale, int digits) {
    return v.is_number() ? FormatNumbers(("%." + std::to_string(digits) + "f").c_str(),
                                         scale * v.get<double>())
                         : std::string("-");
  };
  auto pair = [&](const char* key, double scale, int digits) {
    return num(summary[key]["mean"], scale, digits) + " / " +
           num(summary[key]["max"], scale, digits);
  };
  t.rows = {
      {"structural elements detected (walls, floors, ceilings, columns)",
       std::to_string(tp) + " / " + std::to_string(n) + ", " + std::to_string(fp) +
           " false positives"},
      {"d_v mean / max (cm)", pair("d_v", 100, 2)},
      {"d_h mean / max (cm)", pair("d_h", 100, 2)},
      {"Phi mean / max (deg)", pair("phi_deg", 1, 4)},
      {"ISPRS completeness / correctness at " + num(summary["isprs_buffer"], 100, 0) + " cm",
       num(summary["isprs_completeness"], 1, 4) + " / " + num(summary["isprs_correctness"], 1, 4)},
      {"DSM3 structure IoU", num(summary["dsm3_structure_iou"], 1, 4)},
      {"floorplan mean room IoU", num(summary["floorplan_mean_iou"], 1, 4)}};
  const auto& o = summary["openings"];
  if (o.is_object()) {
    t.rows.push_back({"SM4 openings: precision / recall of areas",
                      num(o["precision"], 1, 4) + " / " + num(o["recall"], 1, 4)});
    t.rows.push_back({"SM4 openings: matched / truth, false",
                      std::to_string(o["matched"].get<int>()) + " / " +
                          std::to_string(o["matched"].get<int>() + o["missed"].get<int>()) + ", " +
                          std::to_string(o["false_openings"].get<int>())});
    t.rows.push_back({"SM4 e_abs mean / max (m2), e_r mean / max",
                      num(o["e_abs_m2"]["mean"], 1, 3) + " / " + num(o["e_abs_m2"]["max"], 1, 3) +
                          ", " + num(o["e_r"]["mean"], 1, 3) + " / " + num(o["e_r"]["max"], 1, 3)});
    t.rows.push_back({"SM4 door states right; angle error median / max (deg)",
                      std::to_string(o["door_states"]["right"].get<int>()) + " / " +
                          std::to_string(o["door_states"]["doors"].get<int>()) + "; " +
                          num(o["angle_error_deg"]["median"], 1, 2) + " / " +
                          num(o["angle_error_deg"]["max"], 1, 2)});
  }
  return t;
}

}  // namespace mopad::report
