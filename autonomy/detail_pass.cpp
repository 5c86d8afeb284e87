#include "autonomy/detail_pass.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/format.h"

namespace mopad::autonomy {
namespace {

constexpr double kMinCosElevation = 0.05;  // keeps the density finite straight overhead

// Points per m^2 one scan with angular step `step` puts on a surface at range r, incidence
// cos_a and scanner elevation cos_e (each ray covers step^2 cos(e) sr).
double AnalyticDensity(double r, double cos_a, double cos_e, double step) {
  return cos_a / (r * r * step * step * std::max(cos_e, kMinCosElevation));
}

}  // namespace

double DetailCell::Spacing() const {
  return density > 0.0 ? 1.0 / std::sqrt(density) : std::numeric_limits<double>::infinity();
}

std::vector<DetailSurface> DetailSurfacesOf(const modelling::Roi& roi) {
  std::vector<DetailSurface> out;
  int wall = 0, column = 0;
  for (const modelling::RoiFace& f : roi.faces) {
    if (f.kind == modelling::FaceKind::kFloor) continue;
    DetailSurface s;
    if (f.kind == modelling::FaceKind::kCeiling)
      s.name = "ceiling";
    else if (f.kind == modelling::FaceKind::kWall)
      s.name = "wall_" + std::to_string(++wall);
    else
      s.name = "column_face_" + std::to_string(++column);
    s.origin = f.origin;
    s.u = f.u_axis;
    s.v = f.v_axis;
    s.n = -f.normal;  // RoI normals point away from the room
    s.width = f.nu * f.cell;
    s.height = f.nv * f.cell;
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<DetailCell> AnalyseDetailCells(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<std::uint16_t>& scan_index,
                                           const DetailScans& scans,
                                           const std::vector<DetailSurface>& surfaces,
                                           const DetailPassParams& params) {
  if (points.size() != scan_index.size())
    throw InputError("AnalyseDetailCells", "points and scan indices differ in number",
                     std::to_string(points.size()), std::to_string(scan_index.size()));
  if (scans.origins.size() != scans.step_rad.size())
    throw InputError("AnalyseDetailCells", "scan origins and steps differ in number",
                     std::to_string(scans.origins.size()), std::to_string(scans.step_rad.size()));
  const std::size_t S = scans.origins.size();
  const double cell = params.cell;
  struct Grid {
    int nu = 0, nv = 0;
    std::vector<int> counts;  // (iv * nu + iu) * S + scan
  };
  std::vector<Grid> grids(surfaces.size());
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    grids[k].nu = std::max(0, static_cast<int>(std::ceil(surfaces[k].width / cell - 1e-9)));
    grids[k].nv = std::max(0, static_cast<int>(std::ceil(surfaces[k].height / cell - 1e-9)));
    grids[k].counts.assign(static_cast<std::size_t>(grids[k].nu) * grids[k].nv * S, 0);
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t scan = scan_index[i];
    if (scan >= S)
      throw InputError("AnalyseDetailCells", "point scan index out of range", std::to_string(scan),
                       "< " + std::to_string(S));
    const Vec3 p = points[i].cast<double>();
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      const DetailSurface& s = surfaces[k];
      const Vec3 d = p - s.origin;
      if (std::abs(s.n.dot(d)) > params.band) continue;
      const double pu = s.u.dot(d), pv = s.v.dot(d);
      if (pu < 0.0 || pv < 0.0 || pu >= s.width || pv >= s.height) continue;
      const int iu = std::min(grids[k].nu - 1, static_cast<int>(pu / cell));
      const int iv = std::min(grids[k].nv - 1, static_cast<int>(pv / cell));
      ++grids[k].counts[(static_cast<std::size_t>(iv) * grids[k].nu + iu) * S + scan];
    }
  }
  const double max_inc = DegToRad(params.max_incidence_deg);
  std::vector<DetailCell> cells;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    const DetailSurface& s = surfaces[k];
    const Grid& g = grids[k];
    for (int iv = 0; iv < g.nv; ++iv)
      for (int iu = 0; iu < g.nu; ++iu) {
        DetailCell c;
        c.surface = static_cast<int>(k);
        const double w = std::min(cell, s.width - iu * cell),
                     h = std::min(cell, s.height - iv * cell);
        c.area = w * h;
        c.centre = s.origin + (iu * cell + 0.5 * w) * s.u + (iv * cell + 0.5 * h) * s.v;
        c.incidence = 0.5 * kPi;
        bool seen = false;
        for (std::size_t scan = 0; scan < S; ++scan) {
          if (g.counts[(static_cast<std::size_t>(iv) * g.nu + iu) * S + scan] < params.min_points)
            continue;
          const Vec3 d = c.centre - scans.origins[scan];
          const double r = d.norm();
          if (r <= 1e-6) continue;
          const double cos_a = -s.n.dot(d) / r;
          if (cos_a <= 0.0) continue;  // seen from behind: the points are not this face's
          seen = true;
          c.density += AnalyticDensity(r, cos_a, d.head<2>().norm() / r, scans.step_rad[scan]);
          c.incidence = std::min(c.incidence, std::acos(std::min(1.0, cos_a)));
        }
        if (!seen) continue;
        c.deficient = c.Spacing() > params.max_spacing || c.incidence > max_inc;
        cells.push_back(c);
      }
  }
  return cells;
}

DetailPlan PlanDetailScan(const std::vector<DetailCell>& cells,
                          const std::vector<DetailSurface>& surfaces,
                          const std::vector<DetailCandidate>& candidates, const DetailView& view,
                          const DetailPassParams& params, const DetailScans& taken,
                          const LineOfSight& visible) {
  DetailPlan plan;
  std::vector<int> deficient;
  for (int i = 0; i < static_cast<int>(cells.size()); ++i)
    if (cells[i].deficient) {
      deficient.push_back(i);
      plan.deficient_area += cells[i].area;
    }
  if (plan.deficient_area < params.min_gain_area || params.max_scans == 0) {
    plan.message = FormatNumbers(
        "detail: %.2f m2 of SE too sparse or grazing, %.0f cells (< %.2f m2: none planned)",
        plan.deficient_area, static_cast<double>(deficient.size()), params.min_gain_area);
    return plan;
  }
  const double max_inc = DegToRad(params.max_incidence_deg);
  const double max_density_needed = 1.0 / (params.max_spacing * params.max_spacing);
  double best_rate = -1.0;
  // Visibility is shared by candidates at the same base (they differ in step only).
  std::vector<std::int8_t> vis_cache;
  Vec2 cached_base(std::numeric_limits<double>::quiet_NaN(), 0.0);
  for (int ci = 0; ci < static_cast<int>(candidates.size()); ++ci) {
    const DetailCandidate& cand = candidates[ci];
    bool repeat = false;
    for (std::size_t k = 0; k < taken.origins.size() && k < taken.step_rad.size(); ++k)
      repeat = repeat || ((taken.origins[k].head<2>() - cand.base).norm() < params.same_place &&
                          cand.step_rad >= taken.step_rad[k] * (1.0 - 1e-9));
    if (repeat) continue;
    if (!(cand.base == cached_base)) {
      vis_cache.assign(deficient.size(), -1);
      cached_base = cand.base;
    }
    const Vec3 sc(cand.base.x(), cand.base.y(), cand.scanner_z);
    double gain = 0.0;
    for (std::size_t j = 0; j < deficient.size(); ++j) {
      const DetailCell& c = cells[deficient[j]];
      const Vec3 d = c.centre - sc;
      const double r = d.norm();
      if (r < view.range_min || r > view.range_max) continue;
      const double el = std::asin(std::clamp(d.z() / r, -1.0, 1.0));
      if (el < view.elevation_min || el > view.elevation_max) continue;
      const double cos_a = -surfaces[c.surface].n.dot(d) / r;
      if (cos_a <= 0.0) continue;
      const double density =
          c.density + AnalyticDensity(r, cos_a, d.head<2>().norm() / r, cand.step_rad);
      const double inc = std::min(c.incidence, std::acos(std::min(1.0, cos_a)));
      if (density < max_density_needed || inc > max_inc) continue;
      if (visible) {
        if (vis_cache[j] < 0) vis_cache[j] = visible(sc, c.centre) ? 1 : 0;
        if (vis_cache[j] == 0) continue;
      }
      gain += c.area;
    }
    if (gain < params.min_gain_area || gain <= 0.0) continue;
    const double scan_s =
        view.ref_step_rad > 0.0
            ? view.seconds_at_ref * std::pow(view.ref_step_rad / cand.step_rad, 2.0)
            : 0.0;
    const double cost = params.scan_overhead + scan_s +
                        params.route_factor * cand.drive_distance / params.drive_speed;
    const double rate = gain / std::max(cost, 1e-6);
    const bool better = rate > best_rate * (1.0 + 1e-9) ||
                        (rate >= best_rate * (1.0 - 1e-9) && plan.chosen >= 0 &&
                         cand.drive_distance < candidates[plan.chosen].drive_distance - 1e-9);
    if (better) {
      best_rate = rate;
      plan.found = true;
      plan.chosen = ci;
      plan.gain_area = gain;
      plan.cost_seconds = cost;
    }
  }
  if (!plan.found) {
    plan.message = FormatNumbers(
        "detail: %.2f m2 of SE too sparse or grazing, %.0f cells; no candidate fixes %.2f m2",
        plan.deficient_area, static_cast<double>(deficient.size()), params.min_gain_area);
    return plan;
  }
  const DetailCandidate& c = candidates[plan.chosen];
  plan.message = FormatNumbers("detail: %.2f m2 of SE too sparse or grazing (%.0f cells); ",
                               plan.deficient_area, static_cast<double>(deficient.size())) +
                 FormatNumbers("scan at (%.2f, %.2f) m, step %.3f deg, ", c.base.x(), c.base.y(),
                               RadToDeg(c.step_rad)) +
                 FormatNumbers("%.2f m away, fixes %.2f m2 for ~%.0f s", c.drive_distance,
                               plan.gain_area, plan.cost_seconds);
  return plan;
}

}  // namespace mopad::autonomy
