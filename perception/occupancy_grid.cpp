#include "perception/occupancy_grid.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <unordered_map>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/format.h"
#include "io/image_codec.h"

namespace mopad::perception {

namespace {

double Logit(double p) { return std::log(p / (1.0 - p)); }

/// Bresenham's line between two cells (inclusive), calling f(cell) in order from a to b.
template <class F>
void TraceLine(Cell a, const Cell& b, F&& f) {
  const int dx = std::abs(b.i - a.i), dy = -std::abs(b.j - a.j);
  const int sx = a.i < b.i ? 1 : -1, sy = a.j < b.j ? 1 : -1;
  int err = dx + dy;
  while (true) {
    f(a);
    if (a == b) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      a.i += sx;
    }
    if (e2 <= dx) {
      err += dx;
      a.j += sy;
    }
  }
}

}  // namespace

void OccupancyGridParams::Validate() const {
  ValidateParams(*this, "occupancy_grid.");
  if (obstacle_z_max <= obstacle_z_min) {
    throw InputError("", "parameter 'occupancy_grid.obstacle_z_max' must exceed obstacle_z_min",
                     std::to_string(obstacle_z_max), "> " + std::to_string(obstacle_z_min));
  }
  if (log_odds_max <= Logit(occupied_thresh) || log_odds_min >= Logit(free_thresh)) {
    throw InputError("", "occupancy_grid log-odds clamps cannot reach the thresholds",
                     "[" + std::to_string(log_odds_min) + ", " + std::to_string(log_odds_max) + "]",
                     "log_odds_max > logit(occupied_thresh) and log_odds_min < logit(free_thresh)");
  }
}

// --- OccupancyGrid ----------------------------------------------------------------------------

OccupancyGrid::OccupancyGrid(const OccupancyGridParams& params, const Vec2& origin, int width,
                             int height)
    : params_(params), origin_(origin), width_(width), height_(height) {
  params_.Validate();
  if (width <= 0 || height <= 0 || static_cast<double>(width) * height > 4e8) {
    throw InputError("", "occupancy grid size out of range",
                     std::to_string(width) + " x " + std::to_string(height),
                     "positive, at most 4e8 cells");
  }
  if (!origin.allFinite()) throw InputError("", "occupancy grid origin must be finite");
  l_occ_ = static_cast<float>(Logit(params_.occupied_thresh));
  l_free_ = static_cast<float>(Logit(params_.free_thresh));
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  log_odds_.assign(n, 0.0f);
  return_dx_.assign(n, 0.0f);
  return_dy_.assign(n, 0.0f);
  return_n_.assign(n, 0);
  cloud_obstacle_.assign(n, 0);
  return_xx_.assign(n, 0.0f);
  return_xy_.assign(n, 0.0f);
  return_yy_.assign(n, 0.0f);
  const Vec2 q = origin_ / params_.resolution;
  const Vec2 r(std::round(q.x()), std::round(q.y()));
  on_lattice_ = (q - r).cwiseAbs().maxCoeff() <= 1e-6 && r.cwiseAbs().maxCoeff() < 1e9;
  if (on_lattice_) lattice_ = {static_cast<int>(r.x()), static_cast<int>(r.y())};
}

OccupancyGrid OccupancyGrid::Covering(const OccupancyGridParams& params,
                                      const std::vector<Eigen::Vector3d>& points_M, double margin) {
  Vec2 lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (const auto& p : points_M) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  if (!lo.allFinite()) throw InputError("", "cannot size an occupancy grid from no points");
  return Covering(params, lo, hi, margin);
}

OccupancyGrid OccupancyGrid::Covering(const OccupancyGridParams& params, const Vec2& lo,
                                      const Vec2& hi, double margin) {
  if (!lo.allFinite() || !hi.allFinite() || (lo.array() > hi.array()).any() ||
      !std::isfinite(margin))
    throw InputError("", "cannot size an occupancy grid from an empty or non-finite box");
  const double r = params.resolution;
  // Snap the origin to a multiple of the resolution so maps of the same site line up.
  const Vec2 origin((std::floor((lo.x() - margin) / r)) * r,
                    (std::floor((lo.y() - margin) / r)) * r);
  const int w = static_cast<int>(std::ceil((hi.x() + margin - origin.x()) / r)) + 1;
  const int h = static_cast<int>(std::ceil((hi.y() + margin - origin.y()) / r)) + 1;
  return OccupancyGrid(params, origin, w, h);
}

Cell OccupancyGrid::CellOf(const Vec2& p) const {
  // On the lattice, the global cell less the origin's: every grid of the site (and
  // CloudEvidence) puts a point on a cell boundary into the same cell.
  if (on_lattice_)
    return {static_cast<int>(std::floor(p.x() / params_.resolution)) - lattice_.i,
            static_cast<int>(std::floor(p.y() / params_.resolution)) - lattice_.j};
  return {static_cast<int>(std::floor((p.x() - origin_.x()) / params_.resolution)),
          static_cast<int>(std::floor((p.y() - origin_.y()) / params_.resolution))};
}

Vec2 OccupancyGrid::CentreOf(const Cell& c) const {
  return origin_ + params_.resolution * Vec2(c.i + 0.5, c.j + 0.5);
}

void OccupancyGrid::Add(const Cell& c, double delta) {
  float& l = log_odds_[Index(c)];
  l = static_cast<float>(
      std::clamp(static_cast<double>(l) + delta, params_.log_odds_min, params_.log_odds_max));
}

void OccupancyGrid::AddReturn(const Cell& c, const Vec2& p) {
  const std::size_t k = Index(c);
  const Vec2 d = p - CentreOf(c);
  return_dx_[k] += static_cast<float>(d.x());
  return_dy_[k] += static_cast<float>(d.y());
  return_xx_[k] += static_cast<float>(d.x() * d.x());
  return_xy_[k] += static_cast<float>(d.x() * d.y());
  return_yy_[k] += static_cast<float>(d.y() * d.y());
  ++return_n_[k];
}

OccupancyGrid::ReturnSegment OccupancyGrid::ObstacleSegment(const Cell& c) const {
  ReturnSegment seg;
  seg.centre = ObstaclePosition(c);
  const std::size_t k = Index(c);
  const double n = return_n_[k];
  if (n < 3) return seg;
  const double mx = return_dx_[k] / n, my = return_dy_[k] / n;
  const double sxx = return_xx_[k] / n - mx * mx, sxy = return_xy_[k] / n - mx * my,
               syy = return_yy_[k] / n - my * my;
  // Principal axes of the 2x2 covariance.
  const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
  const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double l1 = 0.5 * tr + disc, l2 = std::max(0.0, 0.5 * tr - disc);
  if (!(l1 > 0.0) || l2 > kLineLikeRatio * l1) return seg;
  Vec2 dir =
      std::abs(sxy) > 1e-12 ? Vec2(l1 - syy, sxy) : (sxx >= syy ? Vec2::UnitX() : Vec2::UnitY());
  seg.direction = dir.normalized();
  // Uniform spread along a segment of length L has variance L^2 / 12.
  // A wall crosses the whole cell, however sparse the returns in it.
  seg.half_length =
      std::clamp(std::sqrt(3.0 * l1), 0.5 * params_.resolution, 0.75 * params_.resolution);
  return seg;
}

Vec2 OccupancyGrid::ObstaclePosition(const Cell& c) const {
  const std::size_t k = Index(c);
  const Vec2 centre = CentreOf(c);
  if (return_n_[k] == 0) return centre;
  return centre + Vec2(return_dx_[k], return_dy_[k]) / static_cast<double>(return_n_[k]);
}

CloudEvidence OccupancyGrid::Evidence(const OccupancyGridParams& params,
                                      const std::vector<Eigen::Vector3d>& points_M,
                                      const Eigen::Vector3d* origin_M) {
  params.Validate();
  CloudEvidence e;
  const double res = params.resolution;
  e.resolution = res;
  auto key = [](long i, long j) { return (static_cast<std::int64_t>(j) << 32) ^ (i & 0xffffffffL); };
  auto cell_of = [res](double x) { return static_cast<int>(std::floor(x / res)); };
  std::unordered_map<std::int64_t, std::size_t> at;
  for (const auto& p : points_M) {
    if (!p.allFinite()) continue;
    e.lo = e.lo.cwiseMin(p.head<2>());
    e.hi = e.hi.cwiseMax(p.head<2>());
    const bool band = p.z() >= params.obstacle_z_min && p.z() <= params.obstacle_z_max;
    if (!band && std::abs(p.z()) > params.floor_z_max) continue;
    const int i = cell_of(p.x()), j = cell_of(p.y());
    const auto [it, fresh] = at.try_emplace(key(i, j), e.cells.size());
    if (fresh) e.cells.push_back({i, j});
    CloudEvidence::PointCell& c = e.cells[it->second];
    if (band) {
      const float q[3] = {static_cast<float>(p.x()), static_cast<float>(p.y()),
                          static_cast<float>(p.z())};
      if (c.band == 0 || q[2] < c.lo[2]) std::copy(q, q + 3, c.lo);
      if (c.band == 0 || q[2] > c.hi[2]) std::copy(q, q + 3, c.hi);
      ++c.band;
      const double dx = p.x() - (i + 0.5) * res, dy = p.y() - (j + 0.5) * res;
      c.dx += static_cast<float>(dx);
      c.dy += static_cast<float>(dy);
      c.xx += static_cast<float>(dx * dx);
      c.xy += static_cast<float>(dx * dy);
      c.yy += static_cast<float>(dy * dy);
    } else {
      ++c.floor;
    }
  }
  std::sort(e.cells.begin(), e.cells.end(), [](const auto& a, const auto& b) {
    return a.j != b.j ? a.j < b.j : a.i < b.i;
  });
  if (!origin_M || !origin_M->allFinite() || params.ray_clear_z_max <= 0.0) return e;
  // Rays: per azimuth bin, the plan-range intervals [r0, r1] the beams clear.
  const Eigen::Vector3d& o = *origin_M;
  const double cap = params.ray_clear_z_max;
  const double bin = params.ray_bin_deg * kPi / 180.0;
  const int bins = static_cast<int>(std::ceil(2.0 * kPi / bin));
  std::vector<std::vector<std::pair<float, float>>> spans(static_cast<std::size_t>(bins));
  for (const auto& p : points_M) {
    if (!p.allFinite() || p.z() > params.obstacle_z_max || p.z() >= cap) continue;
    const Vec2 d = p.head<2>() - o.head<2>();
    const double r = d.norm();
    if (r < 2.0 * res) continue;
    // The part of the beam below `cap`: from parameter t0 (where it descends through cap) on.
    const double t0 = o.z() <= cap ? 0.0 : (o.z() - cap) / (o.z() - p.z());
    const double r0 = t0 * r, r1 = r - res;
    if (r1 <= r0) continue;
    double a = std::atan2(d.y(), d.x());
    if (a < 0.0) a += 2.0 * kPi;
    const int b = std::min(bins - 1, static_cast<int>(a / bin));
    spans[static_cast<std::size_t>(b)].emplace_back(static_cast<float>(r0), static_cast<float>(r1));
  }
  std::vector<std::int64_t> crossed;
  for (int b = 0; b < bins; ++b) {
    auto& s = spans[static_cast<std::size_t>(b)];
    if (s.empty()) continue;
    std::sort(s.begin(), s.end());
    const double a = (b + 0.5) * bin;
    const Vec2 u(std::cos(a), std::sin(a));
    auto trace = [&](double r0, double r1) {
      std::int64_t last = 0;
      bool any = false;
      for (double r = r0; r <= r1; r += 0.5 * res) {
        const Vec2 q = o.head<2>() + r * u;
        const std::int64_t k = key(cell_of(q.x()), cell_of(q.y()));
        if (any && k == last) continue;
        crossed.push_back(k);
        last = k;
        any = true;
      }
    };
    double lo = s[0].first, hi = s[0].second;
    for (std::size_t k = 1; k < s.size(); ++k) {
      if (s[k].first <= hi + res) {
        hi = std::max<double>(hi, s[k].second);
      } else {
        trace(lo, hi);
        lo = s[k].first, hi = s[k].second;
      }
    }
    trace(lo, hi);
  }
  std::sort(crossed.begin(), crossed.end());
  crossed.erase(std::unique(crossed.begin(), crossed.end()), crossed.end());
  e.crossed.reserve(crossed.size());
  for (const std::int64_t k : crossed)
    e.crossed.emplace_back(static_cast<int>(static_cast<std::int32_t>(k & 0xffffffffL)),
                           static_cast<int>(k >> 32));
  return e;
}

Cell OccupancyGrid::LatticeOffset(double resolution, const Vec2& origin, const char* what) const {
  const double r = params_.resolution;
  const Vec2 q = origin / r;
  const Vec2 n(std::round(q.x()), std::round(q.y()));
  if (std::abs(resolution - r) > 1e-12 * r || (q - n).cwiseAbs().maxCoeff() > 1e-6 ||
      n.cwiseAbs().maxCoeff() >= 1e9)
    throw InputError("", std::string(what) + " does not share the grid's cell lattice",
                     FormatNumbers("resolution %.6g m, origin (%.6g, %.6g)", resolution,
                                   origin.x(), origin.y()),
                     FormatNumbers("resolution %.6g m, origin a multiple of it", r));
  return {static_cast<int>(n.x()), static_cast<int>(n.y())};
}

void OccupancyGrid::InsertPoints(const std::vector<Eigen::Vector3d>& points_M) {
  InsertPoints(Evidence(params_, points_M));
}

void OccupancyGrid::InsertPoints(const CloudEvidence& e) {
  const Cell o = LatticeOffset(e.resolution, origin_, "the grid's origin");
  // One observation per cell and batch, however dense the scan.
  for (const CloudEvidence::PointCell& pc : e.cells) {
    const Cell c{pc.i - o.i, pc.j - o.j};
    if (!Contains(c)) continue;
    const std::size_t k = Index(c);
    if (pc.transient) {  // what was there is gone: its floor, if any, is what remains
      if (pc.floor > 0 && !(cloud_obstacle_[k] & 1)) Add(c, params_.cloud_log_odds_floor);
      continue;
    }
    if (pc.band > 0) {
      return_dx_[k] += pc.dx;
      return_dy_[k] += pc.dy;
      return_xx_[k] += pc.xx;
      return_xy_[k] += pc.xy;
      return_yy_[k] += pc.yy;
      return_n_[k] += pc.band;
      cloud_obstacle_[k] |= 2;
    }
    if (pc.band >= static_cast<std::uint32_t>(params_.min_points_per_cell)) {
      // Band beats floor: a thin obstacle (a door leaf) shares its cell with floor returns,
      // and another scan that saw it edge-on saw only that floor.
      if (!(cloud_obstacle_[k] & 1) && log_odds_[k] < 0.0f) log_odds_[k] = 0.0f;
      Add(c, params_.cloud_log_odds_hit);
      cloud_obstacle_[k] |= 1;
    } else if (pc.band == 0 && pc.floor > 0 && !(cloud_obstacle_[k] & 1)) {
      Add(c, params_.cloud_log_odds_floor);
    }
  }
}

void OccupancyGrid::InsertRays(const Eigen::Vector3d& o,
                               const std::vector<Eigen::Vector3d>& points_M) {
  if (!o.allFinite() || params_.ray_clear_z_max <= 0.0) return;
  InsertRays(Evidence(params_, points_M, &o));
}

void OccupancyGrid::InsertRays(const CloudEvidence& e) {
  const Cell o = LatticeOffset(e.resolution, origin_, "the grid's origin");
  for (const auto& [gi, gj] : e.crossed) {
    const Cell c{gi - o.i, gj - o.j};
    if (!Contains(c) || cloud_obstacle_[Index(c)]) continue;
    Add(c, params_.cloud_log_odds_floor);
  }
}

void OccupancyGrid::Compose(const OccupancyGrid& base, const OccupancyGrid& evidence,
                            const Vec2& lo, const Vec2& hi) {
  if (base.width_ != width_ || base.height_ != height_ || base.origin_ != origin_ ||
      base.params_.resolution != params_.resolution)
    throw InputError("", "occupancy grid Compose: the base grid's geometry differs");
  const Cell me = LatticeOffset(params_.resolution, origin_, "the grid's origin");
  const Cell ev = LatticeOffset(evidence.params_.resolution, evidence.origin_, "the evidence grid");
  const Cell a = CellOf(lo), b = CellOf(hi);
  for (int j = std::max(0, a.j); j <= std::min(height_ - 1, b.j); ++j) {
    for (int i = std::max(0, a.i); i <= std::min(width_ - 1, b.i); ++i) {
      const std::size_t k = Index({i, j});
      CopyCell(base, k, k);
      const Cell ce{i + me.i - ev.i, j + me.j - ev.j};
      if (!evidence.Contains(ce)) continue;
      const std::size_t q = evidence.Index(ce);
      double e = evidence.log_odds_[q];
      if (!params_.lrf_clears_cloud_obstacles && (cloud_obstacle_[k] & 1)) e = std::max(e, 0.0);
      log_odds_[k] = static_cast<float>(std::clamp(static_cast<double>(log_odds_[k]) + e,
                                                   params_.log_odds_min, params_.log_odds_max));
      return_dx_[k] += evidence.return_dx_[q];
      return_dy_[k] += evidence.return_dy_[q];
      return_xx_[k] += evidence.return_xx_[q];
      return_xy_[k] += evidence.return_xy_[q];
      return_yy_[k] += evidence.return_yy_[q];
      return_n_[k] += evidence.return_n_[q];
    }
  }
}

void OccupancyGrid::CopyCell(const OccupancyGrid& from, std::size_t k, std::size_t q) {
  log_odds_[q] = from.log_odds_[k];
  return_dx_[q] = from.return_dx_[k];
  return_dy_[q] = from.return_dy_[k];
  return_xx_[q] = from.return_xx_[k];
  return_xy_[q] = from.return_xy_[k];
  return_yy_[q] = from.return_yy_[k];
  return_n_[q] = from.return_n_[k];
  cloud_obstacle_[q] = from.cloud_obstacle_[k];
}

OccupancyGrid OccupancyGrid::Resized(const Vec2& lo, const Vec2& hi) const {
  OccupancyGrid out = Covering(params_, lo, hi, 0.0);
  const Cell me = LatticeOffset(params_.resolution, origin_, "the grid's origin");
  const Cell to = out.LatticeOffset(params_.resolution, out.origin_, "the resized grid");
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i) {
      const Cell c{i + me.i - to.i, j + me.j - to.j};
      if (!out.Contains(c)) continue;
      out.CopyCell(*this, Index({i, j}), out.Index(c));
    }
  }
  return out;
}

void OccupancyGrid::InsertScan(const interfaces::LrfScan& scan, const Pose2& X_MB,
                               double max_range) {
  const Pose3 X_ML = X_MB.To3d() * scan.X_BL;
  const Eigen::Vector3d o = X_ML.translation();
  const Cell origin_cell = CellOf(o.head<2>());
  const double range_cap = std::max(0.0, static_cast<double>(scan.range_max));
  for (std::size_t k = 0; k < scan.ranges.size(); ++k) {
    const double r = scan.ranges[k];
    if (!std::isfinite(r) || r < scan.range_min) continue;
    const bool beyond = r > max_range && r < scan.range_max;
    const bool hit = r < scan.range_max && !beyond;
    if (!hit && !beyond && !params_.clear_on_no_return) continue;
    const double a = scan.angle_min + scan.angle_increment * static_cast<double>(k);
    const double len = hit ? r : (beyond ? max_range : range_cap);
    const Eigen::Vector3d p = X_ML * Eigen::Vector3d(len * std::cos(a), len * std::sin(a), 0.0);
    const Cell end = CellOf(p.head<2>());
    TraceLine(origin_cell, end, [&](const Cell& c) {
      if (!Contains(c)) return;
      if (c == end && hit) {
        Add(c, params_.log_odds_hit);
        AddReturn(c, p.head<2>());
      } else if (!(c == end) &&
                 (params_.lrf_clears_cloud_obstacles || !(cloud_obstacle_[Index(c)] & 1))) {
        Add(c, params_.log_odds_miss);
      }
    });
  }
}

void OccupancyGrid::SetState(const Cell& c, CellState state) {
  if (!Contains(c)) return;
  float& l = log_odds_[Index(c)];
  switch (state) {
    case CellState::kOccupied:
      l = static_cast<float>(params_.log_odds_max);
      break;
    case CellState::kFree:
      l = static_cast<float>(params_.log_odds_min);
      break;
    case CellState::kUnknown:
      l = 0.0f;
      break;
  }
}

void OccupancyGrid::FillBox(const Vec2& lo, const Vec2& hi, CellState state) {
  const Cell a = CellOf(lo), b = CellOf(hi);
  for (int j = std::max(0, a.j); j <= std::min(height_ - 1, b.j); ++j) {
    for (int i = std::max(0, a.i); i <= std::min(width_ - 1, b.i); ++i) {
      const Vec2 c = CentreOf({i, j});
      if ((c.array() >= lo.array()).all() && (c.array() <= hi.array()).all()) {
        SetState({i, j}, state);
      }
    }
  }
}

CellState OccupancyGrid::State(const Cell& c) const {
  if (!Contains(c)) return CellState::kUnknown;
  const float l = log_odds_[Index(c)];
  if (l > l_occ_) return CellState::kOccupied;
  if (l < l_free_) return CellState::kFree;
  return CellState::kUnknown;
}

int OccupancyGrid::Count(CellState state) const {
  int n = 0;
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) n += State(Cell{i, j}) == state ? 1 : 0;
  return n;
}

OccupancyGrid OccupancyGrid::Inflated(double radius, bool unknown_is_obstacle) const {
  const DistanceField field(*this, unknown_is_obstacle);
  OccupancyGrid out = *this;
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i) {
      const CellState s = State(Cell{i, j});
      if (s == CellState::kOccupied) continue;
      if (s == CellState::kUnknown && !unknown_is_obstacle) continue;
      if (field.ClearanceOfCell(Cell{i, j}) < radius) out.SetState({i, j}, CellState::kOccupied);
    }
  }
  return out;
}

OccupancyGrid OccupancyGrid::Refined(int factor) const {
  if (factor < 1 || factor > 8)
    throw InputError("", "grid refinement factor out of range", std::to_string(factor), "[1, 8]");
  OccupancyGridParams p = params_;
  p.resolution = params_.resolution / factor;
  OccupancyGrid out(p, origin_, width_ * factor, height_ * factor);
  auto mark = [&](const Vec2& x) {
    const Cell s = out.CellOf(x);
    if (out.Contains(s)) out.SetState(s, CellState::kOccupied);
  };
  std::vector<Vec2> covered;  // obstacle points, marked after every free sub-cell is set
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i) {
      const Cell c{i, j};
      const CellState st = State(c);
      if (st == CellState::kUnknown) continue;
      const std::size_t k = Index(c);
      const bool solid = st == CellState::kOccupied && return_n_[k] == 0;
      for (int dj = 0; dj < factor; ++dj)
        for (int di = 0; di < factor; ++di)
          out.SetState({i * factor + di, j * factor + dj},
                       solid ? CellState::kOccupied : CellState::kFree);
      if (st != CellState::kOccupied || solid) continue;
      const ReturnSegment seg = ObstacleSegment(c);
      const double step = 0.5 * p.resolution;
      if (seg.half_length > 0.0) {
        const int n = static_cast<int>(std::ceil(seg.half_length / step));
        for (int t = -n; t <= n; ++t)
          covered.push_back(seg.centre + seg.direction * (seg.half_length * t / n));
        continue;
      }
      // Not line-like (a corner, an edge seen end-on): the sub-cells within sqrt(3) standard
      // deviations of the returns' mean (the half length of a uniform spread).
      const double m = return_n_[k];
      const double mx = return_dx_[k] / m, my = return_dy_[k] / m;
      const double var = std::max(0.0, return_xx_[k] / m - mx * mx + return_yy_[k] / m - my * my);
      const double r = std::sqrt(3.0 * var);
      const int n = static_cast<int>(std::ceil(r / step));
      for (int v = -n; v <= n; ++v)
        for (int u = -n; u <= n; ++u)
          if (std::hypot(u * step, v * step) <= r + 1e-12)
            covered.push_back(seg.centre + Vec2(u * step, v * step));
    }
  }
  for (const Vec2& x : covered) mark(x);
  return out;
}

// --- DistanceField ----------------------------------------------------------------------------

DistanceField::DistanceField(const OccupancyGrid& grid, bool unknown_is_obstacle,
                             double max_distance)
    : origin_(grid.Origin()),
      resolution_(grid.Resolution()),
      width_(grid.Width()),
      height_(grid.Height()),
      max_distance_(max_distance) {
  cv::Mat src(height_, width_, CV_8U);
  free_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), 0);
  bool any_obstacle = false;
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i) {
      const CellState s = grid.State(Cell{i, j});
      const bool obstacle =
          s == CellState::kOccupied || (unknown_is_obstacle && s == CellState::kUnknown);
      src.at<std::uint8_t>(j, i) = obstacle ? 0 : 255;
      free_[grid.Index({i, j})] = obstacle ? 0 : 1;
      any_obstacle |= obstacle;
    }
  }
  centre_distance_.assign(free_.size(), static_cast<float>(max_distance));
  nearest_.assign(free_.size(), std::numeric_limits<std::uint32_t>::max());
  if (!any_obstacle) return;
  // Nearest obstacle cell of every cell (Voronoi labels; the 5x5 mask picks the nearest cell
  // up to rare ties), then the segment of its returns.
  {
    cv::Mat approx, labels;
    cv::distanceTransform(src, approx, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
    std::vector<std::uint32_t> label_segment;
    for (int j = 0; j < height_; ++j) {
      for (int i = 0; i < width_; ++i) {
        if (src.at<std::uint8_t>(j, i) != 0) continue;
        const auto l = static_cast<std::size_t>(labels.at<int>(j, i));
        if (label_segment.size() <= l)
          label_segment.resize(l + 1, std::numeric_limits<std::uint32_t>::max());
        label_segment[l] = static_cast<std::uint32_t>(segments_.size());
        segments_.push_back(grid.ObstacleSegment(Cell{i, j}));
      }
    }
    for (int j = 0; j < height_; ++j) {
      for (int i = 0; i < width_; ++i) {
        const auto l = static_cast<std::size_t>(labels.at<int>(j, i));
        if (l < label_segment.size())
          nearest_[static_cast<std::size_t>(j) * width_ + i] = label_segment[l];
      }
    }
  }
  cv::Mat dist;
  cv::distanceTransform(src, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i) {
      const double d = static_cast<double>(dist.at<float>(j, i)) * resolution_;
      centre_distance_[static_cast<std::size_t>(j) * width_ + i] =
          static_cast<float>(std::min(d, max_distance));
    }
  }
}

Cell DistanceField::CellOf(const Vec2& p) const {
  return {static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_)),
          static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_))};
}

double DistanceField::ClearanceOfCell(const Cell& c) const {
  if (c.i < 0 || c.j < 0 || c.i >= width_ || c.j >= height_) return 0.0;
  const std::size_t k = static_cast<std::size_t>(c.j) * width_ + c.i;
  if (!free_[k]) return 0.0;
  return std::max(0.0, static_cast<double>(centre_distance_[k]) - 0.5 * resolution_);
}

double DistanceField::Clearance(const Vec2& p) const { return ClearanceOfCell(CellOf(p)); }

bool DistanceField::IsFree(const Vec2& p, double radius) const {
  const Cell c = CellOf(p);
  if (c.i < 0 || c.j < 0 || c.i >= width_ || c.j >= height_) return false;
  if (!free_[static_cast<std::size_t>(c.j) * width_ + c.i]) return false;
  return ClearanceOfCell(c) >= radius;
}

double DistanceField::CentreDistance(const Vec2& p, double outside) const {
  const double u = (p.x() - origin_.x()) / resolution_ - 0.5;
  const double v = (p.y() - origin_.y()) / resolution_ - 0.5;
  if (!(u > -0.5 && v > -0.5 && u < width_ - 0.5 && v < height_ - 0.5)) return outside;
  const int i0 = std::clamp(static_cast<int>(std::floor(u)), 0, width_ - 1);
  const int j0 = std::clamp(static_cast<int>(std::floor(v)), 0, height_ - 1);
  const int i1 = std::min(i0 + 1, width_ - 1), j1 = std::min(j0 + 1, height_ - 1);
  const double fu = std::clamp(u - i0, 0.0, 1.0), fv = std::clamp(v - j0, 0.0, 1.0);
  auto at = [&](int i, int j) {
    return static_cast<double>(centre_distance_[static_cast<std::size_t>(j) * width_ + i]);
  };
  return (1 - fv) * ((1 - fu) * at(i0, j0) + fu * at(i1, j0)) +
         fv * ((1 - fu) * at(i0, j1) + fu * at(i1, j1));
}

double DistanceField::ObstacleDistance(const Vec2& p, double outside) const {
  const Cell c = CellOf(p);
  if (c.i < 0 || c.j < 0 || c.i >= width_ || c.j >= height_) return outside;
  const Nearest n = NearestReturn(p);
  return n.found ? n.distance : max_distance_;
}

DistanceField::Nearest DistanceField::NearestReturn(const Vec2& p) const {
  Nearest out;
  const Cell c = CellOf(p);
  if (c.i < 0 || c.j < 0 || c.i >= width_ || c.j >= height_) return out;
  // The nearest-cell labels are exact only up to ties and to where in its cell p lies: take
  // the best of the segments labelled in the 3x3 neighbourhood.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t seen[9];
  int n_seen = 0;
  double best = max_distance_;
  for (int dj = -1; dj <= 1; ++dj) {
    for (int di = -1; di <= 1; ++di) {
      const int i = c.i + di, j = c.j + dj;
      if (i < 0 || j < 0 || i >= width_ || j >= height_) continue;
      const std::uint32_t n = nearest_[static_cast<std::size_t>(j) * width_ + i];
      if (n == kNone || std::find(seen, seen + n_seen, n) != seen + n_seen) continue;
      seen[n_seen++] = n;
      const auto& seg = segments_[n];
      const Vec2 v = p - seg.centre;
      const double along = std::clamp(seg.direction.dot(v), -seg.half_length, seg.half_length);
      const Vec2 r = v - along * seg.direction;  // from the segment's nearest point to p
      const double d = r.norm();
      if (d >= best) continue;
      best = d;
      out.found = true;
      out.distance = d;
      out.normal = d > 1e-12 ? Vec2(r / d) : Vec2(-seg.direction.y(), seg.direction.x());
      out.surface_normal =
          seg.half_length > 0.0 ? Vec2(-seg.direction.y(), seg.direction.x()) : Vec2::Zero();
    }
  }
  return out;
}

// --- map_server I/O ---------------------------------------------------------------------------

void WriteMap(const OccupancyGrid& grid, const std::string& yaml_path) {
  namespace fs = std::filesystem;
  const fs::path yaml(yaml_path);
  fs::path png = yaml;
  png.replace_extension(".png");
  cv::Mat img(grid.Height(), grid.Width(), CV_8U);
  for (int j = 0; j < grid.Height(); ++j) {
    for (int i = 0; i < grid.Width(); ++i) {
      std::uint8_t v = 205;
      switch (grid.State(Cell{i, j})) {
        case CellState::kFree:
          v = 254;
          break;
        case CellState::kOccupied:
          v = 0;
          break;
        case CellState::kUnknown:
          v = 205;
          break;
      }
      img.at<std::uint8_t>(grid.Height() - 1 - j, i) = v;  // top row = highest y
    }
  }
  std::string encoded;
  try {
    encoded = io::EncodePng({img.data, img.cols, img.rows, 1, 8, img.step});
  } catch (const std::exception& e) {
    throw InputError(png.string(), "cannot write map image", e.what());
  }
  WriteWholeFile(png.string(), encoded);
  std::ostringstream out;
  const auto& p = grid.Params();
  out << std::setprecision(17);
  out << "image: " << png.filename().string() << "\n"
      << "mode: trinary\n"
      << "resolution: " << grid.Resolution() << "\n"
      << "origin: [" << grid.Origin().x() << ", " << grid.Origin().y() << ", 0.0]\n"
      << "negate: 0\n"
      << "occupied_thresh: " << p.occupied_thresh << "\n"
      << "free_thresh: " << p.free_thresh << "\n";
  WriteWholeFile(yaml.string(), out.str());
}

OccupancyGrid ReadMap(const std::string& yaml_path, const OccupancyGridParams& params) {
  namespace fs = std::filesystem;
  const YAML::Node root = LoadYamlFile(yaml_path);
  if (!root.IsMap()) throw InputError(YamlWhere(yaml_path, root), "map YAML must be a map");
  RejectUnknownKeys(
      root, {"image", "mode", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"},
      yaml_path, "");
  auto need = [&](const char* key) {
    const YAML::Node n = root[key];
    if (!n) throw InputError(yaml_path, std::string("map YAML lacks '") + key + "'");
    return n;
  };
  auto number = [&](const char* key) {
    const YAML::Node n = need(key);
    try {
      return n.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(YamlWhere(yaml_path, n), std::string("wrong type for '") + key + "'",
                       n.IsScalar() ? "'" + n.Scalar() + "'" : "not a scalar", "a number");
    }
  };
  OccupancyGridParams p = params;
  p.resolution = number("resolution");
  p.occupied_thresh = number("occupied_thresh");
  p.free_thresh = number("free_thresh");
  const double negate = number("negate");
  if (negate != 0.0 && negate != 1.0) {
    throw InputError(YamlWhere(yaml_path, root["negate"]), "'negate' must be 0 or 1",
                     std::to_string(negate), "0 or 1");
  }
  if (root["mode"]) {
    const std::string mode = root["mode"].as<std::string>("");
    if (mode != "trinary" && mode != "scale") {
      throw InputError(YamlWhere(yaml_path, root["mode"]), "unsupported map mode", mode,
                       "trinary or scale");
    }
  }
  const YAML::Node origin = need("origin");
  if (!origin.IsSequence() || origin.size() != 3) {
    throw InputError(YamlWhere(yaml_path, origin), "'origin' must be [x, y, yaw]", "",
                     "a sequence of 3 numbers");
  }
  double o[3];
  for (int k = 0; k < 3; ++k) {
    try {
      o[k] = origin[k].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(YamlWhere(yaml_path, origin), "'origin' must hold numbers");
    }
  }
  if (o[2] != 0.0) {
    throw InputError(YamlWhere(yaml_path, origin), "rotated maps are not supported",
                     std::to_string(o[2]), "origin yaw 0");
  }
  try {
    p.Validate();
  } catch (const InputError& e) {
    throw InputError(yaml_path + ": " + e.what());
  }
  const YAML::Node image = need("image");
  fs::path png(image.as<std::string>(""));
  if (png.empty()) throw InputError(YamlWhere(yaml_path, image), "'image' must be a file name");
  if (png.is_relative()) png = fs::path(yaml_path).parent_path() / png;
  const io::Image8 img = io::ReadImage8(png.string(), 1);
  if (img.empty()) {
    throw InputError(YamlWhere(yaml_path, image), "cannot read map image", png.string(),
                     "a readable PNG/PGM");
  }
  OccupancyGrid grid(p, Vec2(o[0], o[1]), img.width, img.height);
  for (int r = 0; r < img.height; ++r) {
    for (int i = 0; i < img.width; ++i) {
      const double v = img.pixels[static_cast<std::size_t>(r) * img.width + i];
      const double occ = negate != 0.0 ? v / 255.0 : (255.0 - v) / 255.0;
      const Cell c{i, img.height - 1 - r};
      if (occ > p.occupied_thresh) {
        grid.SetState(c, CellState::kOccupied);
      } else if (occ < p.free_thresh) {
        grid.SetState(c, CellState::kFree);
      }
    }
  }
  return grid;
}

}  // namespace mopad::perception
