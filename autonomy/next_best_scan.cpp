#include "autonomy/next_best_scan.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <utility>

#include "common/error.h"

namespace mopad::autonomy {

void NextBestScanParams::Validate() const {
  ValidateParams(*this, "next_best_scan.");
  if (elevation_min_deg >= elevation_max_deg) {
    throw InputError("",
                     "parameter 'next_best_scan.elevation_min_deg' must be below elevation_max_deg",
                     std::to_string(elevation_min_deg), "< " + std::to_string(elevation_max_deg));
  }
  if (range_min >= range_max) {
    throw InputError("", "parameter 'next_best_scan.range_min' must be below range_max",
                     std::to_string(range_min), "< " + std::to_string(range_max));
  }
}

namespace {

struct Target {
  Vec3 p = Vec3::Zero();   // patch centroid, moved half a voxel into the room
  Vec3 n = Vec3::UnitZ();  // outward face normal
  double weight = 0.0;     // probability x area (x frontier factor), m^2
  double area = 0.0;       // unsensed area of the patch, m^2
  int face = -1;
  bool frontier = false;  // on a face without structural data
};

// The unsensed cells of the RoI's faces (the sensed ones with `of` = kSensed) grouped into
// square patches of about `patch_size`. Cells flagged in `exclude` (per face, per cell; null =
// none) are left out.
std::vector<Target> MakeTargets(const modelling::RoomModel& model, const NextBestScanParams& P,
                                double patch_size,
                                const std::vector<std::vector<std::uint8_t>>* exclude = nullptr,
                                modelling::FaceCell of = modelling::FaceCell::kUnsensed) {
  using modelling::FaceCell;
  const modelling::Roi& roi = model.GetRoi();
  const double half_voxel = 0.5 * model.Voxels().Size();
  std::vector<Target> targets;
  for (int fi = 0; fi < static_cast<int>(roi.faces.size()); ++fi) {
    const modelling::RoiFace& f = roi.faces[fi];
    const int k = std::max(1, static_cast<int>(std::lround(patch_size / f.cell)));
    const double prob = f.structural ? P.probability_structural : P.probability_unclassified;
    const double factor = f.structural ? 1.0 : P.frontier_factor;
    for (int pv = 0; pv < f.nv; pv += k) {
      for (int pu = 0; pu < f.nu; pu += k) {
        double area = 0.0;
        Vec3 c = Vec3::Zero();
        for (int iv = pv; iv < std::min(f.nv, pv + k); ++iv) {
          for (int iu = pu; iu < std::min(f.nu, pu + k); ++iu) {
            const std::size_t idx = static_cast<std::size_t>(iv) * f.nu + iu;
            if (f.cells[idx] != of) continue;
            if (exclude && (*exclude)[fi][idx]) continue;
            area += f.cell_area[idx];
            c += f.cell_area[idx] * f.CellCentre(iu, iv);
          }
        }
        if (area <= 0.0) continue;
        Target t;
        t.p = c / area - half_voxel * f.normal;
        t.n = f.normal;
        t.weight = area * prob * factor;
        t.area = area;
        t.face = fi;
        t.frontier = !f.structural;
        targets.push_back(t);
      }
    }
  }
  return targets;
}

// The visibility test of step c: range and elevation limits, incidence, free voxel line of
// sight. `d` = target - scanner centre.
// Returns the chance that the scan senses the patch's cells (0 = not visible).
struct Visibility {
  const modelling::VoxelSpace& vox;
  double range_min, range_max, sin_max, sin_min, cos_inc, stop_short;
  double cell, step;  // face cell (m), angular step (rad)
  // The geometric test alone, without the incidence limit and the point density: the patch
  // faces the scanner within its range and elevation limits, in a free line of sight.
  bool InView(const Vec3& sc, const Target& t) const {
    const Vec3 d = t.p - sc;
    const double r = d.norm();
    if (r < range_min || r > range_max) return false;
    const double sz = d.z() / r;
    if (sz > sin_max || sz < sin_min) return false;
    if (d.dot(t.n) <= 0.0) return false;
    return vox.SegmentFree(sc, t.p, stop_short);
  }
  double operator()(const Vec3& sc, const Target& t) const {
    const Vec3 d = t.p - sc;
    const double r = d.norm();
    if (r < range_min || r > range_max) return 0.0;
    const double sz = d.z() / r;
    if (sz > sin_max || sz < sin_min) return 0.0;
    const double cos_a = d.dot(t.n) / r;
    if (cos_a < cos_inc || cos_a <= 0.0) return 0.0;
    if (!vox.SegmentFree(sc, t.p, stop_short)) return 0.0;
    const double spacing = r * step;
    return std::min(1.0, cell / spacing) * std::min(1.0, cell * cos_a / spacing);
  }
};

Visibility VisibilityOf(const modelling::RoomModel& model, const NextBestScanParams& P,
                        double scan_step_deg) {
  return Visibility{model.Voxels(),
                    P.range_min,
                    P.range_max,
                    std::sin(DegToRad(P.elevation_max_deg)),
                    std::sin(DegToRad(P.elevation_min_deg)),
                    std::cos(DegToRad(P.max_incidence_deg)),
                    P.stop_short,
                    model.Params().face_cell,
                    DegToRad(scan_step_deg)};
}

// Plan distance from p to the RoI's walls and columns (the map may miss walls seen only at
// grazing angles from far away; the perimeter does not).
double BoundaryDistance(const modelling::Roi& roi, const Vec2& p) {
  double d = 1e300;
  auto loop = [&](const std::vector<Vec2>& poly) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], ab = poly[(i + 1) % poly.size()] - a;
      const double u = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-18), 0.0, 1.0);
      d = std::min(d, (p - (a + u * ab)).norm());
    }
  };
  loop(roi.perimeter);
  for (const auto& c : roi.columns) loop(c);
  return d;
}

std::pair<Vec2, Vec2> PlanBounds(const modelling::Roi& roi) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return {lo, hi};
}

// a. The grid cells a candidate may stand on (clearance of the robot radius in the map and
// from the RoI's walls and columns, inside the RoI) that are connected to the current pose (or
// the nearest such cell within 1 m): 1 = reachable.
std::vector<std::uint8_t> ReachableCells(const modelling::Roi& roi,
                                         const perception::OccupancyGrid& map,
                                         const perception::DistanceField& df,
                                         const Pose2& current_M, const Vec2& lo, const Vec2& hi,
                                         const NextBestScanParams& P) {
  const int W = map.Width(), H = map.Height();
  std::vector<std::uint8_t> passable(static_cast<std::size_t>(W) * H, 0), reach(passable.size(), 0);
  tbb::parallel_for(0, H, [&](int j) {
    for (int i = 0; i < W; ++i) {
      const perception::Cell c{i, j};
      const Vec2 p = map.CentreOf(c);
      if (p.x() < lo.x() || p.y() < lo.y() || p.x() > hi.x() || p.y() > hi.y()) continue;
      passable[map.Index(c)] = df.ClearanceOfCell(c) >= P.robot_radius && roi.ContainsPlan(p) &&
                                       BoundaryDistance(roi, p) >= P.robot_radius
                                   ? 1
                                   : 0;
    }
  });
  // Seed: the current cell, or the nearest passable cell within 1 m.
  const perception::Cell c0 = map.CellOf(Vec2(current_M.x, current_M.y));
  int seed = -1;
  double seed_d = 1e300;
  const int rad = static_cast<int>(std::ceil(1.0 / map.Resolution()));
  for (int dj = -rad; dj <= rad; ++dj) {
    for (int di = -rad; di <= rad; ++di) {
      const perception::Cell c{c0.i + di, c0.j + dj};
      if (!map.Contains(c) || !passable[map.Index(c)]) continue;
      const double d = std::hypot(di, dj);
      if (d < seed_d) {
        seed_d = d;
        seed = static_cast<int>(map.Index(c));
      }
    }
  }
  if (seed < 0) return reach;
  std::deque<int> queue{seed};
  reach[seed] = 1;
  while (!queue.empty()) {
    const int idx = queue.front();
    queue.pop_front();
    const int i = idx % W, j = idx / W;
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const int ni = i + di, nj = j + dj;
        if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= W || nj >= H) continue;
        const int n = nj * W + ni;
        if (passable[n] && !reach[n]) {
          reach[n] = 1;
          queue.push_back(n);
        }
      }
    }
  }
  return reach;
}

// a. The candidate grid (candidate_spacing) inside the RoI: safe (clearance of robot_radius +
// safety_margin) and reachable ones into out.candidates, the others counted.
void AddCandidates(const modelling::Roi& roi, const perception::OccupancyGrid& map,
                   const perception::DistanceField& df, const std::vector<std::uint8_t>& reach,
                   const Vec2& lo, const Vec2& hi, const NextBestScanParams& P, NbsResult& out) {
  const double s = P.candidate_spacing;
  for (double y = std::ceil(lo.y() / s) * s; y <= hi.y(); y += s) {
    for (double x = std::ceil(lo.x() / s) * s; x <= hi.x(); x += s) {
      const Vec2 p(x, y);
      if (!roi.ContainsPlan(p)) continue;
      const perception::Cell c = map.CellOf(p);
      const double clearance = std::min(df.Clearance(p), BoundaryDistance(roi, p));
      if (!map.Contains(c) || clearance < P.robot_radius + P.safety_margin) {
        ++out.rejected_unsafe;
        continue;
      }
      if (!reach[map.Index(c)]) {
        ++out.rejected_unreachable;
        continue;
      }
      NbsCandidate cand;
      cand.position = p;
      out.candidates.push_back(cand);
    }
  }
}

// c/d. Certainty of every face and of the RoI for every candidate (its gain); the expected
// overlap from the sensed patches `known` and the unsensed `targets` (their area x sensing
// chance; a frontier patch x the structure behind it, as the gain), and the gain scaled by
// overlap / min_overlap where the overlap falls short.
void EvaluateCandidates(const std::vector<Target>& targets, const std::vector<Target>& known,
                        const Visibility& visible, double zs, std::size_t faces,
                        const NextBestScanParams& P, std::vector<NbsCandidate>& candidates) {
  tbb::parallel_for(std::size_t{0}, candidates.size(), [&](std::size_t ci) {
    NbsCandidate& cand = candidates[ci];
    const Vec3 sc(cand.position.x(), cand.position.y(), zs);
    std::vector<double>& fg = cand.face_certainty;
    fg.assign(faces, 0.0);
    double frontier = 0.0, fresh = 0.0, seen = 0.0;
    for (const Target& t : known) seen += t.area * visible(sc, t);
    for (const Target& t : targets) {
      const double chance = visible(sc, t);
      if (chance <= 0.0) continue;
      fresh += t.frontier ? t.area * P.frontier_factor : t.area * chance;
      if (t.weight <= 0.0) continue;
      // A frontier patch reveals what lies behind it in proportion to how squarely it is seen
      // (not how densely: what lies behind is seen from elsewhere).
      const Vec3 d = t.p - sc;
      const double certainty = t.frontier ? t.weight * d.dot(t.n) / d.norm() : t.weight * chance;
      fg[t.face] += certainty;
      if (t.frontier) frontier += certainty;
      ++cand.visible_patches;
    }
    double g = 0.0;
    for (double v : fg) g += v;  // fixed order
    cand.expected_overlap = seen + fresh > 0.0 ? seen / (seen + fresh) : 0.0;
    const double scale = P.min_overlap > 0.0 && cand.expected_overlap < P.min_overlap
                             ? cand.expected_overlap / P.min_overlap
                             : 1.0;
    for (double& v : fg) v *= scale;
    cand.gain = g * scale;
    cand.frontier_gain = frontier * scale;
  });
}

}  // namespace

// e. Near-ties: the candidates within `tolerance` x the largest gain G of it. Among them, those
// whose frontier gain is within tolerance x G of the largest frontier gain F there (frontier
// differences smaller than the estimate's own error are ties too); of those the largest
// gain, then the nearest to the current pose, then grid order. -1 when none has a gain.
int ChooseNextBestScan(const std::vector<NbsCandidate>& candidates, const Vec2& cur,
                       double tolerance) {
  double best = 0.0;
  for (const NbsCandidate& c : candidates) best = std::max(best, c.gain);
  if (!(best > 0.0)) return -1;
  const double slack = tolerance * best;
  auto tied = [&](const NbsCandidate& c) { return c.gain > 0.0 && c.gain >= best - slack; };
  double frontier = 0.0;
  for (const NbsCandidate& c : candidates) {
    if (tied(c)) frontier = std::max(frontier, c.frontier_gain);
  }
  int chosen = -1;
  for (std::size_t ci = 0; ci < candidates.size(); ++ci) {
    const NbsCandidate& a = candidates[ci];
    if (!tied(a) || a.frontier_gain < frontier - slack) continue;
    if (chosen >= 0) {
      const NbsCandidate& b = candidates[chosen];
      if (a.gain < b.gain) continue;
      if (a.gain == b.gain && (a.position - cur).norm() >= (b.position - cur).norm()) continue;
    }
    chosen = static_cast<int>(ci);
  }
  return chosen;
}

NbsResult NextBestScan(const modelling::RoomModel& model, const perception::OccupancyGrid& map,
                       const Pose2& current_M, double scan_step_deg, const NextBestScanParams& P) {
  P.Validate();
  if (!(scan_step_deg > 0.0 && scan_step_deg <= 10.0))
    throw InputError("", "next best scan: scan step must be in (0, 10] deg",
                     std::to_string(scan_step_deg), "(0, 10]");
  NbsResult out;
  out.goal = current_M;
  const modelling::Roi& roi = model.GetRoi();
  if (roi.empty() || model.Voxels().empty()) {
    out.message = "no next best scan: the room model is empty";
    return out;
  }
  // a. Safe and reachable candidates.
  const perception::DistanceField df(map, P.unknown_is_obstacle);
  const auto [lo, hi] = PlanBounds(roi);
  const std::vector<std::uint8_t> reach = ReachableCells(roi, map, df, current_M, lo, hi, P);
  AddCandidates(roi, map, df, reach, lo, hi, P, out);
  // b. Targets with their membership probabilities.
  std::vector<Target> targets = MakeTargets(model, P, P.patch_size);
  const double zs = model.FloorZ() + P.mast_height;
  const Visibility visible = VisibilityOf(model, P, scan_step_deg);
  // Patches the earlier scan positions should already have sensed are discounted.
  if (P.revisit_factor < 1.0) {
    const std::vector<Pose3>& scans = model.ScanPoses();
    tbb::parallel_for(std::size_t{0}, targets.size(), [&](std::size_t ti) {
      Target& t = targets[ti];
      for (const Pose3& X : scans) {
        t.weight *= 1.0 - (1.0 - P.revisit_factor) * visible(X.translation(), t);
      }
    });
  }
  // c/d/e. The sensed patches only for the expected overlap, twice as coarse (a share, not
  // a map of what is seen).
  const std::vector<Target> known =
      P.min_overlap > 0.0
          ? MakeTargets(model, P, 2.0 * P.patch_size, nullptr, modelling::FaceCell::kSensed)
          : std::vector<Target>{};
  EvaluateCandidates(targets, known, visible, zs, roi.faces.size(), P, out.candidates);
  const std::size_t nc = out.candidates.size();
  out.chosen = ChooseNextBestScan(out.candidates, Vec2(current_M.x, current_M.y), P.tie_tolerance);
  char buf[320];
  if (out.chosen < 0) {
    std::snprintf(
        buf, sizeof(buf),
        "no next best scan: %zu candidates (%d unsafe, %d unreachable), %zu target patches, "
        "none with a gain",
        nc, out.rejected_unsafe, out.rejected_unreachable, targets.size());
    out.message = buf;
    return out;
  }
  const NbsCandidate& best = out.candidates[out.chosen];
  out.found = true;
  out.goal = Pose2{best.position.x(), best.position.y(), current_M.yaw};
  out.expected_gain = best.gain;
  std::snprintf(buf, sizeof(buf),
                "next best scan at (%.2f, %.2f): expected gain %.2f m2, expected overlap %.2f, "
                "%d of %zu patches visible; %zu candidates (%d unsafe, %d unreachable)",
                best.position.x(), best.position.y(), best.gain, best.expected_overlap,
                best.visible_patches,
                targets.size(), nc, out.rejected_unsafe, out.rejected_unreachable);
  out.message = buf;
  return out;
}

HiddenArea EstimateHiddenArea(const modelling::RoomModel& model,
                              const perception::OccupancyGrid& map, const Pose2& current_M,
                              const NextBestScanParams& P,
                              const modelling::OrthoPoints* no_return) {
  P.Validate();
  HiddenArea out;
  const modelling::Roi& roi = model.GetRoi();
  if (roi.empty() || model.Voxels().empty()) return out;
  const perception::DistanceField df(map, P.unknown_is_obstacle);
  const auto [lo, hi] = PlanBounds(roi);
  const std::vector<std::uint8_t> reach = ReachableCells(roi, map, df, current_M, lo, hi, P);
  // Scanner centres: the lattice points of reachable map cells, and the scans taken.
  const double zs = model.FloorZ() + P.mast_height;
  const double s = P.observability_spacing;
  std::vector<Vec3> centres;
  for (double y = std::ceil(lo.y() / s) * s; y <= hi.y(); y += s) {
    for (double x = std::ceil(lo.x() / s) * s; x <= hi.x(); x += s) {
      const perception::Cell c = map.CellOf(Vec2(x, y));
      if (map.Contains(c) && reach[map.Index(c)]) centres.emplace_back(x, y, zs);
    }
  }
  for (const Pose3& X : model.ScanPoses()) centres.push_back(X.translation());
  out.positions = static_cast<int>(centres.size());
  // Unsensed cells with clutter standing within stop_short in front of them (a closed door's
  // leaf, a radiator): the line of sight ignores voxels that near a target, the points do not.
  const std::size_t nf = roi.faces.size();
  std::vector<std::vector<std::uint8_t>> covered(nf);
  const std::vector<Eigen::Vector3f>& points = model.Points();
  const std::vector<modelling::PointLabel>& labels = model.Labels();
  tbb::parallel_for(std::size_t{0}, nf, [&](std::size_t fi) {
    const modelling::RoiFace& f = roi.faces[fi];
    covered[fi].assign(f.cells.size(), 0);
    if (!f.structural) return;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (labels[i] != modelling::PointLabel::kClutter) continue;
      const Vec3 p = points[i].cast<double>();
      const double depth = (f.origin - p).dot(f.normal);
      if (depth <= 0.0 || depth > P.stop_short) continue;
      const int c = f.CellIndexOf(p);
      if (c >= 0 && f.cells[c] == modelling::FaceCell::kUnsensed) covered[fi][c] = 1;
    }
  });
  // Unsensed wall cells a ray without a return passed (beyond the minimum range: a window to
  // the outside, a doorway to far space) are openings, not structure: flagged 2.
  if (no_return != nullptr) {
    const std::vector<Pose3>& scans = model.ScanPoses();
    const std::size_t nr =
        std::min(no_return->no_return_dirs.size(), no_return->no_return_scan.size());
    for (std::size_t i = 0; i < nr; ++i) {  // serial: each ray flags at most one cell
      const std::size_t si = no_return->no_return_scan[i];
      if (si >= scans.size()) continue;
      const Vec3 o = scans[si].translation();
      const Vec3 d = no_return->no_return_dirs[i].cast<double>();
      double best_t = 1e300;
      int best_f = -1, best_c = -1;
      for (std::size_t fi = 0; fi < nf; ++fi) {
        const modelling::RoiFace& f = roi.faces[fi];
        if (f.kind != modelling::FaceKind::kWall) continue;
        const double dn = d.dot(f.normal);
        if (dn <= 1e-9) continue;
        const double t = (f.origin - o).dot(f.normal) / dn;
        if (t < P.range_min || t >= best_t) continue;
        const int c = f.CellIndexOf(o + t * d);
        if (c < 0 || f.cells[c] == modelling::FaceCell::kOff) continue;
        best_t = t;
        best_f = static_cast<int>(fi);
        best_c = c;
      }
      if (best_f >= 0 && roi.faces[best_f].cells[best_c] == modelling::FaceCell::kUnsensed &&
          !covered[best_f][best_c])
        covered[best_f][best_c] = 2;
    }
  }
  for (std::size_t fi = 0; fi < nf; ++fi) {  // fixed order
    const modelling::RoiFace& f = roi.faces[fi];
    for (std::size_t c = 0; c < f.cells.size(); ++c) {
      if (covered[fi][c] == 1) out.covered_area += f.cell_area[c];
      if (covered[fi][c] == 2) out.seen_through_area += f.cell_area[c];
    }
  }
  out.area = out.covered_area + out.seen_through_area;
  // The other unsensed patches of structural faces (a frontier face is unknown, not hidden).
  std::vector<Target> patches = MakeTargets(model, P, P.observability_patch, &covered);
  patches.erase(
      std::remove_if(patches.begin(), patches.end(), [](const Target& t) { return t.frontier; }),
      patches.end());
  const Visibility visible = VisibilityOf(model, P, 1.0);
  std::vector<std::uint8_t> hidden(patches.size(), 0);
  // A patch is hidden when no centre sees it: the answer does not depend on the order the
  // centres are tried in. Neighbouring patches (in face order) are mostly seen from the same
  // centre, so the one that saw the last patch is tried first: a visible patch then mostly
  // costs one line of sight, a hidden one all of them in any order.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, patches.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::size_t last = 0;
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        if (!centres.empty() && visible.InView(centres[last], patches[i])) continue;
                        bool seen = false;
                        for (std::size_t k = 0; k < centres.size() && !seen; ++k)
                          if (k != last && visible.InView(centres[k], patches[i])) {
                            seen = true;
                            last = k;
                          }
                        if (!seen) hidden[i] = 1;
                      }
                    });
  for (std::size_t i = 0; i < patches.size(); ++i) {  // fixed order
    if (hidden[i]) {
      out.area += patches[i].area;
      ++out.patches;
    }
  }
  return out;
}

}  // namespace mopad::autonomy
