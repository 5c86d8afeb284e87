#include "evaluation/coverage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "io/scan_io.h"

namespace mopad::evaluation {
namespace {

using Json = nlohmann::ordered_json;

double Round(double x, double scale) { return std::round(x * scale) / scale; }

Json FiguresJson(const CoverageFigures& f) {
  Json j;
  j["name"] = f.name;
  j["total_area_m2"] = Round(f.total_area, 1e6);
  j["observable_area_m2"] = Round(f.observable_area, 1e6);
  j["sensed_area_m2"] = Round(f.sensed_area, 1e6);
  j["sensed_observable_area_m2"] = Round(f.sensed_observable_area, 1e6);
  j["share_of_observable"] = Round(f.ShareOfObservable(), 1e6);
  j["share_of_total"] = Round(f.ShareOfTotal(), 1e6);
  return j;
}

}  // namespace

std::vector<std::uint8_t> SensedCells(const StructuralSurfaces& surfaces,
                                      std::span<const Eigen::Vector3f> p_M, const Pose3& X_WM,
                                      const CoverageParams& params,
                                      std::uint64_t* points_on_cells) {
  ValidateParams(params, "coverage.");
  std::vector<std::atomic<std::uint8_t>> flags(surfaces.cells.size());
  for (auto& f : flags) f.store(0, std::memory_order_relaxed);
  std::atomic<std::uint64_t> on{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, p_M.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::uint64_t local = 0;
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        const Eigen::Vector3d p = X_WM * p_M[i].cast<double>();
                        const std::int32_t c = surfaces.FindCell(p, params.distance_tolerance);
                        if (c < 0) continue;
                        ++local;
                        flags[c].store(1, std::memory_order_relaxed);
                      }
                      on.fetch_add(local, std::memory_order_relaxed);
                    });
  std::vector<std::uint8_t> out(flags.size());
  for (std::size_t k = 0; k < flags.size(); ++k) out[k] = flags[k].load(std::memory_order_relaxed);
  if (points_on_cells) *points_on_cells = on.load();
  return out;
}

CoverageReport SummariseCoverage(const StructuralSurfaces& surfaces,
                                 const std::vector<std::uint8_t>& observable,
                                 const std::vector<std::uint8_t>& sensed) {
  const std::size_t n = surfaces.cells.size();
  if (!observable.empty() && observable.size() != n) {
    throw InputError("", "observable flags do not match the surface cells",
                     std::to_string(observable.size()), std::to_string(n));
  }
  if (sensed.size() != n) {
    throw InputError("", "sensed flags do not match the surface cells",
                     std::to_string(sensed.size()), std::to_string(n));
  }
  CoverageReport rep;
  rep.room.name = surfaces.room;
  rep.per_element.resize(surfaces.elements.size());
  for (std::size_t e = 0; e < surfaces.elements.size(); ++e)
    rep.per_element[e].name = surfaces.elements[e].id;
  const scenes::ElementClass classes[] = {scenes::ElementClass::kWall, scenes::ElementClass::kFloor,
                                          scenes::ElementClass::kCeiling,
                                          scenes::ElementClass::kColumn};
  std::vector<CoverageFigures> per_class(4);
  std::vector<bool> present(4, false);
  for (int c = 0; c < 4; ++c) per_class[c].name = std::string(scenes::ToString(classes[c]));
  for (std::size_t k = 0; k < n; ++k) {
    const SurfaceCell& cell = surfaces.cells[k];
    int ci = 0;
    while (ci < 4 && classes[ci] != cell.element_class) ++ci;
    const bool obs = observable.empty() || observable[k];
    const bool sen = sensed[k] != 0;
    for (CoverageFigures* f :
         {&rep.room, &rep.per_element[cell.element], ci < 4 ? &per_class[ci] : nullptr}) {
      if (!f) continue;
      f->total_area += cell.area;
      if (obs) f->observable_area += cell.area;
      if (sen) f->sensed_area += cell.area;
      if (sen && obs) f->sensed_observable_area += cell.area;
    }
    if (ci < 4) present[ci] = true;
  }
  for (int c = 0; c < 4; ++c)
    if (present[c]) rep.per_class.push_back(per_class[c]);
  return rep;
}

CoverageReport ComputeCoverage(const StructuralSurfaces& surfaces,
                               const std::vector<std::uint8_t>& observable,
                               std::span<const Eigen::Vector3f> p_M, const Pose3& X_WM,
                               const CoverageParams& params) {
  std::uint64_t on = 0;
  const std::vector<std::uint8_t> sensed = SensedCells(surfaces, p_M, X_WM, params, &on);
  CoverageReport rep = SummariseCoverage(surfaces, observable, sensed);
  rep.points = p_M.size();
  rep.points_on_cells = on;
  return rep;
}

CoverageReport ComputeCoverageFromPly(const StructuralSurfaces& surfaces,
                                      const std::vector<std::uint8_t>& observable,
                                      const std::string& ply_path, const Pose3& X_WM,
                                      const CoverageParams& params) {
  const io::PointCloud cloud = io::ReadPly(ply_path);
  return ComputeCoverage(surfaces, observable, cloud.points, X_WM, params);
}

nlohmann::ordered_json CoverageJson(const CoverageReport& report) {
  Json j;
  j["room"] = FiguresJson(report.room);
  j["per_class"] = Json::array();
  for (const auto& f : report.per_class) j["per_class"].push_back(FiguresJson(f));
  j["per_element"] = Json::array();
  for (const auto& f : report.per_element) j["per_element"].push_back(FiguresJson(f));
  j["points"] = report.points;
  j["points_on_cells"] = report.points_on_cells;
  return j;
}

std::string CoverageToJson(const CoverageReport& report) {
  return CoverageJson(report).dump(2) + "\n";
}

}  // namespace mopad::evaluation
