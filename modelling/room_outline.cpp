// The per-scan outline of the ceiling view (RoomModel::TraceOutline): per azimuth column, the
// ceiling seen contiguously from the scanner up to the wall that stops it; the union of these
// outlines is the perimeter (room_perimeter.cpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

using detail::kColumnMask;
using detail::kGapBit;
using detail::Plan;

namespace {

// One azimuth column after its walk: the vertex of its walk, if it accepted a point (has).
struct OutlineColumn {
  bool has = false;
  Vec2 vertex = Vec2::Zero();
};

// The walk down one azimuth column: the points [begin, end) of `points` (top row first) with
// their column tags, of a scan from `origin` whose shortest return is `min_range`. Ceiling points
// (and small things hanging just below it) continue the walk; the first point well below the
// ceiling that is not closer than the ceiling seen so far (a wall, a lintel, a column) ends it.
// The ceiling is the room's (Roi::CeilingAt: level, or sloped under a roof).
// Returns the plan distance from the scanner of the farthest accepted point, `vertex` (negative
// when none was accepted).
double WalkColumn(const std::vector<Eigen::Vector3f>& points,
                  const std::vector<std::uint32_t>& tags, std::size_t begin, std::size_t end,
                  const Vec3& origin, double min_range, const Roi& roi,
                  const RoomModelParams& params, Vec2& vertex) {
  const CeilingOutlineParams& P = params.outline;
  const double tol = params.ceiling_tolerance;
  const double hang = P.hang_depth;
  const Vec2 o = origin.head<2>();
  double best_rho = -1.0, last_rho = 0.0;
  vertex = Vec2::Zero();
  bool any = false, on_ceiling = false, last_near = false;
  for (std::size_t k = begin; k < end; ++k) {
    const Eigen::Vector3f& p = points[k];
    const Vec2 q = Plan(p);
    const double rho = (q - o).norm();
    // Under a sloped ceiling (an attic's roof) the ceiling over the point is the slope's there:
    // the walk goes on down the roof to the wall under it.
    const double dz = roi.CeilingAt(q) - p.z();
    const bool ceiling_like = std::abs(dz) <= tol || (dz > 0 && dz <= hang);
    // Rows without return before this point: what they looked at is unknown. After a wall
    // top (or before anything was seen) it is typically the rest of a wall too close to
    // return (a lintel over a door beside the scanner), and the next return is the next
    // room's ceiling: the walk ends. On the ceiling a gap is a dropout, unless the last
    // ceiling return was itself near the minimum range (a low ceiling beside a door wall).
    // A gap before a column's first return, when that return is ceiling at the scan's
    // shortest range, is the ceiling inside the scanner's minimum range (a low ceiling right
    // above the scanner), not a wall too close to return.
    const double range = (p.cast<double>() - origin).norm();
    const bool near = range < P.near_range;
    const bool ceiling_above =
        !any && std::abs(dz) <= tol && range <= min_range + P.min_range_slack;
    if ((tags[k] & kGapBit) && ceiling_like && !ceiling_above && (!any || !on_ceiling || last_near))
      break;
    if (ceiling_like) {
      last_near = near;
      if (rho > best_rho) {
        best_rho = rho;
        vertex = q;
      }
      on_ceiling = std::abs(dz) <= tol;
      if (on_ceiling) last_rho = std::max(last_rho, rho);
      any = true;
      continue;
    }
    if (dz > 0 && rho < last_rho - P.occluder_margin) continue;  // an occluder before the ceiling
    // A wall right beside the scanner: the first return, above the scanner and below the
    // ceiling. A first return above the ceiling is beyond this room (the next room's higher
    // ceiling seen under a lintel too close to return): it ends the walk without a vertex.
    if (!any && p.z() > origin.z() && dz > 0) {
      vertex = q;
      best_rho = rho;
    }
    break;
  }
  return best_rho;
}

// Where the ceiling's reach jumps by more than `step` between neighbouring azimuths (the end of a
// wall, a door jamb, a re-entrant corner seen past its edge), the straight edge between the two
// vertices would claim the unseen shadow behind the nearer one: the outline steps radially
// instead, at the nearer reach on the farther azimuth. Along a smooth wall the step costs a
// sliver of one azimuth step's width. `o`: the scanner's plan position.
std::vector<Vec2> StepAroundShadows(const std::vector<Vec2>& outline, const Vec2& o, double step) {
  const std::size_t m = outline.size();
  std::vector<Vec2> stepped;
  stepped.reserve(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    const Vec2& a = outline[k];
    const Vec2& b = outline[(k + 1) % m];
    stepped.push_back(a);
    const double ra = (a - o).norm(), rb = (b - o).norm();
    if (std::abs(ra - rb) <= step) continue;
    stepped.push_back(ra < rb ? o + (b - o) * (ra / rb) : o + (a - o) * (rb / ra));
  }
  return stepped;
}

}  // namespace

void RoomModel::TraceOutline(ScanRecord& rec) const {
  // Per azimuth column, the walk down from the top row (WalkColumn): the farthest accepted
  // point is the outline vertex of that azimuth. The blind cone above the scanner lies inside.
  const Vec2 o = rec.origin.head<2>();
  rec.outline.clear();
  std::vector<OutlineColumn> cols(rec.columns);
  std::size_t i = rec.begin;
  while (i < rec.end) {
    const std::uint32_t col = column_index_[i] & kColumnMask;
    std::size_t j = i;
    while (j < rec.end && (column_index_[j] & kColumnMask) == col) ++j;
    Vec2 vertex;
    const double best_rho =
        WalkColumn(points_, column_index_, i, j, rec.origin, rec.min_range, roi_, params_, vertex);
    if (col < cols.size() && best_rho > 0.0) cols[col] = {true, vertex};
    i = j;
  }
  // Columns without a vertex are bridged by the edge between their neighbours' vertices. Such a
  // column shows no ceiling beyond the minimum range: without any return, something inside the
  // range stopped it (a wall's end right beside the scanner); with returns but none accepted,
  // its upper rays returned nothing (a lintel or a beam inside the range, or nothing at all)
  // before what lies past them, or its first return lay above the ceiling. Where the bridge
  // passes beyond that range, it would claim space the column does not show, so those columns
  // keep to the scanner's surroundings instead and the other scans' outlines claim what lies
  // beyond (a wall ending 1.55 m from a scanner under the beam that continues its line,
  // `RoomModel.AWallEndingUnderABeamBesideTheScannerStaysOutOfTheOutline`). A wall along the
  // scanner closer than the minimum range is bridged by its own far parts.
  std::vector<std::uint32_t> with;
  for (std::uint32_t c = 0; c < rec.columns; ++c)
    if (cols[c].has) with.push_back(c);
  const double reach = rec.min_range + params_.outline.min_range_slack;
  auto direction = [&](std::uint32_t c) {
    const double a = rec.azimuth_min + rec.azimuth_step * static_cast<double>(c);
    return Vec2((rec.R_MS * Vec3(std::cos(a), std::sin(a), 0.0)).head<2>().normalized());
  };
  for (std::size_t k = 0; k < with.size(); ++k) {
    const std::uint32_t a = with[k], b = with[(k + 1) % with.size()];
    rec.outline.push_back(cols[a].vertex);
    const std::uint32_t n_between = (b + rec.columns - a - 1) % rec.columns;
    if (with.size() < 2 || n_between == 0) continue;
    const Vec2 A = cols[a].vertex, AB = cols[b].vertex - A;
    bool beyond = false;
    for (std::uint32_t m = 1; m <= n_between && !beyond; ++m) {
      const std::uint32_t c = (a + m) % rec.columns;
      // Where the column's ray meets the bridge A-B (none: taken as beyond).
      const Vec2 d = direction(c), w = A - o;
      const double den = d.x() * AB.y() - d.y() * AB.x();
      const double t = std::abs(den) > 1e-12 ? (w.x() * AB.y() - w.y() * AB.x()) / den : -1.0;
      const double u = std::abs(den) > 1e-12 ? (w.x() * d.y() - w.y() * d.x()) / den : -1.0;
      beyond = !(t > 0.0 && u >= -1e-9 && u <= 1.0 + 1e-9 && t <= reach);
    }
    if (!beyond) continue;
    for (std::uint32_t m = 1; m <= n_between; ++m) {
      const std::uint32_t c = (a + m) % rec.columns;
      rec.outline.push_back(o + params_.outline.blind_radius * direction(c));
    }
  }
  if (rec.outline.size() < 3) return;
  rec.outline = StepAroundShadows(rec.outline, o, params_.outline.shadow_step);
}

}  // namespace mopad::modelling
