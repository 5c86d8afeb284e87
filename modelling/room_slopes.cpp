// Sloped ceilings of a room (RoomModel::DetectSlopes): an attic's roof seen from below. The top
// surface of the working cloud (its highest point per plan cell) is, inside a room, its
// ceiling; where neighbourhoods of that surface fit tilted planes that join into one large
// enough, that plane is a sloped ceiling (docs/room-scanning.md, step 2).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <vector>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

namespace {

// Least-squares plane z = a x + b y + c through `pts` (about their mean): false when they
// span no plane. rms: of the z residuals.
bool FitHeightPlane(const std::vector<Vec3>& pts, Eigen::Vector3d* abc, double* rms) {
  if (pts.size() < 3) return false;
  Vec3 mean = Vec3::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector2d q = (p - mean).head<2>();
    A += q * q.transpose();
    b += q * (p.z() - mean.z());
  }
  if (A.determinant() < 1e-12 * std::max(1.0, A.trace() * A.trace())) return false;
  const Eigen::Vector2d g = A.ldlt().solve(b);
  *abc = Eigen::Vector3d(g.x(), g.y(), mean.z() - g.dot(mean.head<2>()));
  double ss = 0.0;
  for (const auto& p : pts) {
    const double r = p.z() - (abc->x() * p.x() + abc->y() * p.y() + abc->z());
    ss += r * r;
  }
  *rms = std::sqrt(ss / static_cast<double>(pts.size()));
  return true;
}

// The plane z = a x + b y + c as a ceiling plane facing down.
CeilingPlane FromHeight(const Eigen::Vector3d& abc) {
  CeilingPlane p;
  const Vec3 n = Vec3(abc.x(), abc.y(), -1.0).normalized();
  p.n = n;
  p.c = n.dot(Vec3(0.0, 0.0, abc.z()));
  return p;
}

using Cell = std::pair<std::int64_t, std::int64_t>;
struct CellHash {
  std::size_t operator()(const Cell& c) const {
    return std::hash<std::int64_t>()(c.first * 73856093 ^ c.second * 19349663);
  }
};
// Per plan cell, the highest point. Unordered: every pass over it either looks cells up or
// gathers into ordered containers (the seeds join in key order), so its order is never seen.
using TopSurface = std::unordered_map<Cell, Vec3, CellHash>;

// The top surface of `points`: per plan cell, the highest point at least min_height over the
// floor.
TopSurface TopOf(const std::vector<Eigen::Vector3f>& points, double floor_z,
                 const SlopedCeilingParams& P) {
  TopSurface top;
  for (const auto& p : points) {
    if (p.z() < floor_z + P.min_height) continue;
    const Cell key(static_cast<std::int64_t>(std::floor(p.x() / P.cell)),
                   static_cast<std::int64_t>(std::floor(p.y() / P.cell)));
    auto [it, inserted] = top.try_emplace(key, p.cast<double>());
    if (!inserted && p.z() > it->second.z()) it->second = p.cast<double>();
  }
  return top;
}

// Each cell's local plane z = a x + b y + c over its 3 x 3 neighbourhood (at least 6 points),
// where it fits within local_rms and is tilted between min_tilt_deg and max_tilt_deg.
std::map<Cell, Eigen::Vector3d> LocalPlanes(const TopSurface& top, const SlopedCeilingParams& P) {
  const double tan_lo = std::tan(DegToRad(P.min_tilt_deg));
  const double tan_hi = std::tan(DegToRad(P.max_tilt_deg));
  std::map<Cell, Eigen::Vector3d> local;
  for (const auto& [k, p] : top) {
    std::vector<Vec3> nb;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const auto it = top.find({k.first + dx, k.second + dy});
        if (it != top.end()) nb.push_back(it->second);
      }
    Eigen::Vector3d abc;
    double rms = 0.0;
    if (nb.size() < 6 || !FitHeightPlane(nb, &abc, &rms) || rms > P.local_rms) continue;
    const double slope = std::hypot(abc.x(), abc.y());
    if (slope >= tan_lo && slope <= tan_hi) local.emplace(k, abc);
  }
  return local;
}

// Neighbouring cells whose local planes agree (normal within max_turn_deg, the top point within
// tolerance of the seed's plane) joined, seeds in key order: each join's top points.
std::vector<std::vector<Vec3>> JoinCells(const TopSurface& top,
                                         const std::map<Cell, Eigen::Vector3d>& local,
                                         const SlopedCeilingParams& P) {
  const double cos_turn = std::cos(DegToRad(P.max_turn_deg));
  std::map<Cell, int> region;
  std::vector<std::vector<Vec3>> members;
  for (const auto& [seed, abc] : local) {
    if (region.count(seed)) continue;
    const CeilingPlane sp = FromHeight(abc);
    const int id = static_cast<int>(members.size());
    members.emplace_back();
    std::vector<Cell> queue{seed};
    region[seed] = id;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Cell k = queue[q];
      members[id].push_back(top.at(k));
      for (const auto& d : {std::pair<int, int>{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const Cell m{k.first + d.first, k.second + d.second};
        const auto it = local.find(m);
        if (it == local.end() || region.count(m)) continue;
        if (FromHeight(it->second).n.dot(sp.n) < cos_turn) continue;
        if (std::abs(sp.n.dot(top.at(m)) - sp.c) > P.tolerance) continue;
        region[m] = id;
        queue.push_back(m);
      }
    }
  }
  return members;
}

// One plane may have grown from several seeds (each seed's local plane drifts from the whole):
// joins whose points lie on a kept join's plane are merged into it, largest first. The merged
// joins of at least min_area and min_width, refit and still tilted and flat, are the slopes.
std::vector<CeilingPlane> MergeJoins(const std::vector<std::vector<Vec3>>& members,
                                     const SlopedCeilingParams& P) {
  const double cos_turn = std::cos(DegToRad(P.max_turn_deg));
  std::vector<std::size_t> order(members.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return members[a].size() > members[b].size();
  });
  std::vector<std::vector<Vec3>> kept;
  std::vector<Eigen::Vector3d> kept_abc;
  for (std::size_t i : order) {
    const std::vector<Vec3>& pts = members[i];
    Eigen::Vector3d abc;
    double rms = 0.0;
    if (pts.size() < 3 || !FitHeightPlane(pts, &abc, &rms)) continue;
    const CeilingPlane plane = FromHeight(abc);
    bool merged = false;
    for (std::size_t k = 0; k < kept.size() && !merged; ++k) {
      const CeilingPlane other = FromHeight(kept_abc[k]);
      if (other.n.dot(plane.n) < cos_turn) continue;
      double mean = 0.0;
      for (const auto& p : pts) mean += other.n.dot(p) - other.c;
      if (std::abs(mean / static_cast<double>(pts.size())) > P.tolerance) continue;
      kept[k].insert(kept[k].end(), pts.begin(), pts.end());
      FitHeightPlane(kept[k], &kept_abc[k], &rms);
      merged = true;
    }
    if (!merged) {
      kept.push_back(pts);
      kept_abc.push_back(abc);
    }
  }
  const double tan_lo = std::tan(DegToRad(P.min_tilt_deg));
  const double tan_hi = std::tan(DegToRad(P.max_tilt_deg));
  std::vector<CeilingPlane> found;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    if (static_cast<double>(kept[k].size()) * P.cell * P.cell < P.min_area) continue;
    Eigen::Vector3d abc;
    double rms = 0.0;
    if (!FitHeightPlane(kept[k], &abc, &rms)) continue;
    const CeilingPlane plane = FromHeight(abc);
    const double slope = std::hypot(abc.x(), abc.y());
    if (slope < tan_lo || slope > tan_hi || rms * std::abs(plane.n.z()) > P.tolerance) continue;
    // Its width along its level lines (across the gradient (a, b)).
    const Eigen::Vector2d along = Eigen::Vector2d(-abc.y(), abc.x()) / slope;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : kept[k]) {
      lo = std::min(lo, along.dot(p.head<2>()));
      hi = std::max(hi, along.dot(p.head<2>()));
    }
    if (hi - lo + P.cell < P.min_width) continue;
    found.push_back(plane);
  }
  return found;
}

// With a sloped ceiling, the level one is a ceiling only where at least min_area of the top
// surface lies at its height and on none of the slopes (not a ridge beam, not the slopes' own
// band through that height).
bool LevelIsCeiling(const TopSurface& top, const std::vector<CeilingPlane>& slopes,
                    double ceiling_z, double ceiling_tolerance, const SlopedCeilingParams& P) {
  double on_level = 0.0;
  for (const auto& [k, p] : top) {
    if (std::abs(p.z() - ceiling_z) > ceiling_tolerance) continue;
    bool on_slope = false;
    for (const auto& s : slopes) on_slope = on_slope || std::abs(s.n.dot(p) - s.c) <= P.tolerance;
    if (!on_slope) on_level += P.cell * P.cell;
  }
  return on_level >= P.min_area;
}

}  // namespace

bool RoomModel::DetectSlopes() {
  const SlopedCeilingParams& P = params_.slopes;
  std::vector<CeilingPlane> found;
  bool level = true;
  if (P.min_area > 0.0) {
    const TopSurface top = TopOf(work_points_, roi_.floor_z, P);
    found = MergeJoins(JoinCells(top, LocalPlanes(top, P), P), P);
    if (!found.empty())
      level = LevelIsCeiling(top, found, roi_.ceiling_z, params_.ceiling_tolerance, P);
  }
  bool moved = found.size() != roi_.slopes.size() || level != roi_.level_ceiling;
  for (std::size_t i = 0; i < found.size() && !moved; ++i)
    moved = found[i].n.dot(roi_.slopes[i].n) < std::cos(DegToRad(0.5)) ||
            std::abs(found[i].c - roi_.slopes[i].c) > params_.outline.retrace_change;
  roi_.slopes = std::move(found);
  roi_.level_ceiling = level;
  return moved;
}

}  // namespace mopad::modelling
