#pragma once
// Self-contained HTML report of a run: summary tables, a plan-view SVG of the scene (rooms,
// doors coloured by state, windows, service components, furniture) with the scan positions and
// a plan-view slice of the scanned points, one coverage-against-scans plot per room, and the
// run folder's wall orthoimages and 3D model (report/report_walls.h, report_viewer.h). No
// external files, scripts or fonts.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "scenes/ground_truth.h"

namespace mopad::report {

struct ReportScan {
  std::string name;
  bool door = false;                                   ///< a door scan (drawn in its own colour)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world, m
  std::vector<Eigen::Vector2f> plan_points;            ///< world x, y of a subsample, m
};

struct ReportTable {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string note;  ///< a line under the table; empty: none
};

/// A room's coverage after each of its room-loop scans, as shares in [0, 1].
struct ReportCoverage {
  std::string room;
  std::vector<double> robot;      ///< the robot's estimate (sensed share of structural area)
  std::vector<double> evaluator;  ///< the truth's share of observable area; empty: not scored
};

struct ReportInput {
  std::string title;
  std::string subtitle;
  const scenes::GroundTruth* truth = nullptr;  ///< plan drawn from it when set
  std::vector<ReportTable> tables;
  std::vector<ReportScan> scans;
  std::vector<Eigen::Vector2d> path;  ///< world x, y of the robot's true path, m
  /// Dynamic Traversal Tree edges (world, m): parent room's first scan -> door -> child's.
  struct TreeEdge {
    Eigen::Vector2d from, via, to;
    std::string label;
  };
  std::vector<TreeEdge> tree_edges;
  std::vector<ReportCoverage> coverage;  ///< one plot per room, in visit order
  double coverage_threshold = 0.0;       ///< the stopping rule's epsilon1; 0: no line
};

/// Plan-view SVG (also embedded in the HTML). Empty string if there is nothing to draw.
std::string PlanSvg(const ReportInput& input);
/// `s` with &, <, > and " escaped for HTML text and attribute values.
std::string HtmlEscape(const std::string& s);
/// One room's coverage against scans (x: scan 1..N, y: share 0..1) as an inline SVG: the robot's
/// estimate as a solid line with one <circle class='robot'> per scan, the evaluator's as a
/// dashed line with <circle class='evaluator'>, and `threshold` (> 0) as a horizontal line.
std::string CoveragePlotSvg(const ReportCoverage& c, double threshold);
/// The pooled model scores of `mopad eval` (evaluation.json's summary) as a report table: SM3
/// detection, d_v, d_h, Phi, ISPRS, DSM3, floorplan, and SM4 openings when scored.
ReportTable ModelScoresTable(const nlohmann::ordered_json& summary);
void WriteHtmlReport(const ReportInput& input, const std::string& path);
/// The same tables as GitHub-flavoured Markdown (for CI summaries).
void WriteMarkdownReport(const ReportInput& input, const std::string& path);

}  // namespace mopad::report
