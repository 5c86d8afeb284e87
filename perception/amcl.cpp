#include "perception/amcl.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "common/error.h"
#include "common/rng.h"

namespace mopad::perception {

Pose2 Compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, WrapAngle(a.yaw + b.yaw)};
}

Pose2 Inverse(const Pose2& a) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, WrapAngle(-a.yaw)};
}

void AmclParams::Validate() const {
  ValidateParams(*this, "amcl.");
  if (min_particles > max_particles) {
    throw InputError("", "parameter 'amcl.min_particles' exceeds max_particles",
                     std::to_string(min_particles), "<= " + std::to_string(max_particles));
  }
  if (refine_normal_radius > refine_normal_max_radius) {
    throw InputError("", "parameter 'amcl.refine_normal_radius' exceeds refine_normal_max_radius",
                     std::to_string(refine_normal_radius),
                     "<= " + std::to_string(refine_normal_max_radius));
  }
  if (z_hit + z_rand > 1.0 + 1e-9) {
    throw InputError("", "amcl mixture weights z_hit + z_rand exceed 1",
                     std::to_string(z_hit + z_rand), "<= 1");
  }
}

const char* ToString(LocalisationStatus s) {
  switch (s) {
    case LocalisationStatus::kNotInitialised:
      return "not_initialised";
    case LocalisationStatus::kLocalised:
      return "localised";
    case LocalisationStatus::kUncertain:
      return "uncertain";
    case LocalisationStatus::kLost:
      return "lost";
    case LocalisationStatus::kRelocalising:
      return "relocalising";
  }
  return "?";
}

namespace {

constexpr double kSqrt2Pi = 2.5066282746310002;
// Beams per task of the refinement's matching (a 1080-beam sweep in a few tasks).
constexpr std::size_t kRefineBeamsPerTask = 256;

/// Low-variance (systematic) resampling (Probabilistic Robotics Table 4.4): `m` indices drawn
/// with one uniform offset `u0` in [0, 1).
std::vector<std::size_t> LowVariance(const std::vector<Particle>& p, std::size_t m, double u0) {
  std::vector<std::size_t> out;
  out.reserve(m);
  const double step = 1.0 / static_cast<double>(m);
  double c = p[0].weight;
  std::size_t i = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double u = (u0 + static_cast<double>(k)) * step;
    while (u > c && i + 1 < p.size()) c += p[++i].weight;
    out.push_back(i);
  }
  return out;
}

struct PoseMean {
  double x = 0, y = 0, yaw = 0;
};

}  // namespace

struct Amcl::Impl {
  DistanceField likelihood;          // occupied cells only
  std::vector<std::uint8_t> mapped;  // per cell: 1 = known (free or occupied)
  Vec2 origin;
  int width = 0, height = 0;
  std::vector<Vec2> free_centres;      // cells for uniform sampling
  std::vector<Vec2> search_positions;  // lattice of the global search
  bool pending_search = false;
  double resolution;
  Pose2 last_odom;
  bool have_last_odom = false;
  bool force_next = false;
  bool relocalising = false;
  int bad_count = 0;
  std::uint64_t update_index = 0;
  std::uint64_t reloc_updates = 0;
  double w_slow = 0.0, w_fast = 0.0;

  // True if p lies in a known (free or occupied) cell of the map.
  bool Known(const Vec2& p) const {
    const int i = static_cast<int>(std::floor((p.x() - origin.x()) / resolution));
    const int j = static_cast<int>(std::floor((p.y() - origin.y()) / resolution));
    return i >= 0 && j >= 0 && i < width && j < height &&
           mapped[static_cast<std::size_t>(j) * width + i];
  }

  Impl(const OccupancyGrid& map, const AmclParams& p)
      : likelihood(map, false, p.likelihood_max_dist),
        origin(map.Origin()),
        width(map.Width()),
        height(map.Height()),
        resolution(map.Resolution()) {
    mapped.assign(static_cast<std::size_t>(width) * height, 0);
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i)
        mapped[static_cast<std::size_t>(j) * width + i] = map.State({i, j}) != CellState::kUnknown;
    const DistanceField clearance(map, true);
    for (int j = 0; j < map.Height(); ++j) {
      for (int i = 0; i < map.Width(); ++i) {
        const Vec2 c = map.CentreOf({i, j});
        if (clearance.IsFree(c, p.global_min_clearance)) free_centres.push_back(c);
      }
    }
    const double step = std::max(p.global_search_step, map.Resolution());
    const Vec2 o = map.Origin();
    const Vec2 extent(map.Width() * map.Resolution(), map.Height() * map.Resolution());
    for (double y = o.y() + 0.5 * step; y < o.y() + extent.y(); y += step)
      for (double x = o.x() + 0.5 * step; x < o.x() + extent.x(); x += step)
        if (clearance.IsFree(Vec2(x, y), p.global_min_clearance))
          search_positions.emplace_back(x, y);
  }
};

Amcl::Amcl(const OccupancyGrid& map, const AmclParams& params, std::uint64_t seed)
    : params_(params), seed_(seed) {
  params_.Validate();
  impl_ = std::make_unique<Impl>(map, params_);
  estimate_.message = "no initial pose";
}

Amcl::~Amcl() = default;
Amcl::Amcl(Amcl&&) noexcept = default;
Amcl& Amcl::operator=(Amcl&&) noexcept = default;

namespace {
std::uint64_t Key(std::uint64_t seed, std::string_view stream, std::uint64_t a, std::uint64_t b) {
  return DeriveKey(DeriveKey(DeriveKey(Mix64(seed), HashName(stream)), a), b);
}

// Unit normals (base_link) of a sweep's surface at its beams' endpoints, in scan order: the
// line through the endpoint and its contiguous neighbours within a radius, from
// max(min_radius, 2.5 x the gap to the nearer neighbour) (a far wall seen at a grazing angle
// is sampled tens of cm apart) grown by half up to max_radius until the neighbourhood is
// line-like (kLineLikeRatio, the grid's rule for a cell's returns; range noise of a few cm
// needs tens of cm of surface); zero where none is (a corner, a lone return).
std::vector<Vec2> SweepNormals(const std::vector<Vec2>& pts, double min_radius, double max_radius) {
  std::vector<Vec2> normals(pts.size(), Vec2::Zero());
  const std::size_t n = pts.size();
  for (std::size_t b = 0; b < n; ++b) {
    double gap = std::numeric_limits<double>::infinity();
    if (b > 0) gap = std::min(gap, (pts[b] - pts[b - 1]).norm());
    if (b + 1 < n) gap = std::min(gap, (pts[b] - pts[b + 1]).norm());
    for (double radius = std::max(min_radius, 2.5 * gap); radius <= max_radius + 1e-9;
         radius *= 1.5) {
      std::size_t lo = b, hi = b;
      while (lo > 0 && (pts[lo - 1] - pts[lo]).norm() <= radius &&
             (pts[lo - 1] - pts[b]).norm() <= radius)
        --lo;
      while (hi + 1 < n && (pts[hi + 1] - pts[hi]).norm() <= radius &&
             (pts[hi + 1] - pts[b]).norm() <= radius)
        ++hi;
      if (hi - lo < 2) continue;
      Vec2 mean = Vec2::Zero();
      for (std::size_t j = lo; j <= hi; ++j) mean += pts[j];
      mean /= static_cast<double>(hi - lo + 1);
      Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
      for (std::size_t j = lo; j <= hi; ++j) cov += (pts[j] - mean) * (pts[j] - mean).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
      if (!(es.eigenvalues()(1) > 0.0) ||
          es.eigenvalues()(0) > kLineLikeRatio * es.eigenvalues()(1))
        continue;
      normals[b] = es.eigenvectors().col(0).normalized();
      break;
    }
  }
  return normals;
}
}  // namespace

void Amcl::SetInitialPose(const Pose2& X_MB, const Eigen::Matrix3d& cov) {
  const Eigen::LLT<Eigen::Matrix3d> llt(cov);
  if (llt.info() != Eigen::Success || !cov.allFinite()) {
    throw InputError("", "AMCL initial covariance must be symmetric positive definite");
  }
  const Eigen::Matrix3d L = llt.matrixL();
  const std::uint64_t epoch = ++impl_->update_index;
  const int n = params_.max_particles;
  particles_.assign(static_cast<std::size_t>(n), Particle{});
  for (int k = 0; k < n; ++k) {
    CounterRng rng(Key(seed_, "amcl/initial", epoch, static_cast<std::uint64_t>(k)));
    const Eigen::Vector3d z(rng.Normal(), rng.Normal(), rng.Normal());
    const Eigen::Vector3d d = L * z;
    particles_[static_cast<std::size_t>(k)] = {X_MB.x + d.x(), X_MB.y + d.y(),
                                               WrapAngle(X_MB.yaw + d.z()), 1.0 / n};
  }
  impl_->relocalising = false;
  impl_->pending_search = false;
  impl_->bad_count = 0;
  impl_->force_next = true;
  impl_->have_last_odom = false;
  impl_->w_slow = impl_->w_fast = 0.0;
  estimate_ = LocalisationEstimate{};
  estimate_.status = LocalisationStatus::kUncertain;
  estimate_.message = "initial pose set; waiting for the first scan";
  estimate_.X_MB = X_MB;
  estimate_.covariance = cov;
  estimate_.particles = n;
  estimate_.n_eff = n;
}

void Amcl::StartGlobalLocalisation() {
  if (impl_->free_centres.empty()) {
    throw InputError("", "AMCL global localisation: the map has no free cell with clearance", "",
                     ">= " + std::to_string(params_.global_min_clearance) + " m");
  }
  const std::uint64_t epoch = ++impl_->update_index;
  const int n = params_.max_particles;
  const double r = impl_->resolution;
  particles_.assign(static_cast<std::size_t>(n), Particle{});
  for (int k = 0; k < n; ++k) {
    CounterRng rng(Key(seed_, "amcl/global", epoch, static_cast<std::uint64_t>(k)));
    const Vec2& c = impl_->free_centres[rng.Below(impl_->free_centres.size())];
    particles_[static_cast<std::size_t>(k)] = {c.x() + rng.Uniform(-0.5, 0.5) * r,
                                               c.y() + rng.Uniform(-0.5, 0.5) * r,
                                               rng.Uniform(-kPi, kPi), 1.0 / n};
  }
  impl_->relocalising = true;
  impl_->pending_search = true;
  impl_->reloc_updates = 0;
  impl_->bad_count = 0;
  impl_->force_next = true;
  impl_->w_slow = impl_->w_fast = 0.0;
  if (estimate_.status != LocalisationStatus::kLost) {
    estimate_.status = LocalisationStatus::kRelocalising;
    estimate_.message = "global localisation started";
  }
  estimate_.particles = n;
}

void Amcl::MotionUpdate(const Pose2& last, const Pose2& cur, std::uint64_t u) {
  const AmclParams& p = params_;
  const double dx = cur.x - last.x, dy = cur.y - last.y;
  const double trans = std::hypot(dx, dy);
  const double dyaw = WrapAngle(cur.yaw - last.yaw);
  if (!(trans > 0.0 || dyaw != 0.0)) return;
  const double rot1 = trans < 0.01 ? 0.0 : WrapAngle(std::atan2(dy, dx) - last.yaw);
  const double rot2 = WrapAngle(dyaw - rot1);
  // Driving backwards makes rot1 ~ pi; the noise must not scale with that (ROS amcl).
  const double r1n = std::min(std::abs(rot1), std::abs(WrapAngle(rot1 - kPi)));
  const double r2n = std::min(std::abs(rot2), std::abs(WrapAngle(rot2 - kPi)));
  const double s_rot1 = std::sqrt(p.odom_alpha1 * r1n * r1n + p.odom_alpha2 * trans * trans);
  const double s_trans =
      std::sqrt(p.odom_alpha3 * trans * trans + p.odom_alpha4 * (r1n * r1n + r2n * r2n));
  const double s_rot2 = std::sqrt(p.odom_alpha1 * r2n * r2n + p.odom_alpha2 * trans * trans);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, particles_.size()), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      CounterRng rng(Key(seed_, "amcl/motion", u, k));
      const double r1 = rot1 - s_rot1 * rng.Normal();
      const double t = trans - s_trans * rng.Normal();
      const double r2 = rot2 - s_rot2 * rng.Normal();
      Particle& q = particles_[k];
      q.x += t * std::cos(q.yaw + r1);
      q.y += t * std::sin(q.yaw + r1);
      q.yaw = WrapAngle(q.yaw + r1 + r2);
    }
  });
}

// Evenly spaced valid returns, projected to base_link.
std::vector<Vec2> Amcl::SelectBeams(const interfaces::LrfScan& scan, int max_beams) const {
  std::vector<Vec2> beams;
  std::vector<std::size_t> valid;
  for (std::size_t k = 0; k < scan.ranges.size(); ++k) {
    const double r = scan.ranges[k];
    if (std::isfinite(r) && r >= scan.range_min && r < scan.range_max) valid.push_back(k);
  }
  const std::size_t want = std::min<std::size_t>(
      valid.size(), static_cast<std::size_t>(max_beams > 0 ? max_beams : params_.max_beams));
  const Pose3& X_BL = scan.X_BL;
  for (std::size_t b = 0; b < want; ++b) {
    const std::size_t k = valid[b * valid.size() / want];
    const double a = scan.angle_min + scan.angle_increment * static_cast<double>(k);
    const double r = scan.ranges[k];
    const Eigen::Vector3d q = X_BL * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0.0);
    beams.emplace_back(q.x(), q.y());
  }
  return beams;
}

double Amcl::MeasurementUpdate(const std::vector<Vec2>& beams, const interfaces::LrfScan& scan) {
  Impl& m = *impl_;
  const AmclParams& p = params_;
  const std::size_t n = particles_.size();
  const double sigma = m.relocalising ? p.global_sigma_hit : p.sigma_hit;
  const double range_max = scan.range_max > 0.0 ? scan.range_max : p.likelihood_max_dist;
  const double rand_term = p.z_rand / range_max;
  const double hit_norm = p.z_hit / (kSqrt2Pi * sigma);
  const double nb = static_cast<double>(beams.size());
  std::vector<double> loglik(n, 0.0);
  if (!beams.empty()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        const Particle& q = particles_[k];
        const double c = std::cos(q.yaw), s = std::sin(q.yaw);
        double sum = 0.0;
        for (const Vec2& b : beams) {
          const Vec2 e(q.x + c * b.x() - s * b.y(), q.y + s * b.x() + c * b.y());
          double d = m.likelihood.ObstacleDistance(e, p.likelihood_max_dist);
          if (p.unknown_endpoint_distance > 0.0 && d > m.resolution && !m.Known(e))
            d = p.unknown_endpoint_distance;
          sum += std::log(hit_norm * std::exp(-0.5 * d * d / (sigma * sigma)) + rand_term);
        }
        loglik[k] = sum;
      }
    });
  }
  // Augmented MCL averages over the per-beam (geometric mean) likelihood.
  double w_avg = 0.0;
  double max_log = -std::numeric_limits<double>::infinity();
  std::vector<double> logw(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (nb > 0) w_avg += particles_[k].weight * std::exp(loglik[k] / nb);
    logw[k] = particles_[k].weight > 0.0 ? std::log(particles_[k].weight) + loglik[k]
                                         : -std::numeric_limits<double>::infinity();
    max_log = std::max(max_log, logw[k]);
  }
  double total = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    particles_[k].weight = std::isfinite(logw[k]) ? std::exp(logw[k] - max_log) : 0.0;
    total += particles_[k].weight;
  }
  if (!(total > 0.0)) {
    for (auto& q : particles_) q.weight = 1.0 / static_cast<double>(n);
  } else {
    for (auto& q : particles_) q.weight /= total;
  }
  if (nb > 0) {
    if (m.w_slow == 0.0) {
      m.w_slow = m.w_fast = w_avg;
    } else {
      m.w_slow += p.recovery_alpha_slow * (w_avg - m.w_slow);
      m.w_fast += p.recovery_alpha_fast * (w_avg - m.w_fast);
    }
  }
  double sum_sq = 0.0;
  for (const auto& q : particles_) sum_sq += q.weight * q.weight;
  return 1.0 / sum_sq;
}

std::int64_t Amcl::BinKey(const Particle& q) const {
  const double bxy = params_.bin_size_xy, byaw = DegToRad(params_.bin_size_yaw_deg);
  const auto bx = static_cast<std::int64_t>(std::floor(q.x / bxy)) + (1 << 20);
  const auto by = static_cast<std::int64_t>(std::floor(q.y / bxy)) + (1 << 20);
  const auto bt = static_cast<std::int64_t>(std::floor((q.yaw + kPi) / byaw));
  return (bx << 42) | (by << 20) | bt;
}

Pose2 Amcl::ClusterEstimate(Eigen::Matrix3d* cov) const {
  const AmclParams& p = params_;
  const std::size_t n = particles_.size();
  auto weighted_mean = [&](auto&& include) {
    double sx = 0, sy = 0, sc = 0, ss = 0, sw = 0;
    for (const auto& q : particles_) {
      if (!include(q)) continue;
      sx += q.weight * q.x;
      sy += q.weight * q.y;
      sc += q.weight * std::cos(q.yaw);
      ss += q.weight * std::sin(q.yaw);
      sw += q.weight;
    }
    PoseMean r;
    if (sw > 0) r = {sx / sw, sy / sw, std::atan2(ss, sc)};
    return r;
  };
  PoseMean mode;
  {
    std::vector<std::pair<std::int64_t, std::size_t>> keyed(n);
    for (std::size_t k = 0; k < n; ++k) keyed[k] = {BinKey(particles_[k]), k};
    std::sort(keyed.begin(), keyed.end());
    double best_w = -1.0;
    std::int64_t best_key = 0;
    for (std::size_t a = 0; a < n;) {
      std::size_t b = a;
      double w = 0.0;
      while (b < n && keyed[b].first == keyed[a].first) w += particles_[keyed[b++].second].weight;
      if (w > best_w) {
        best_w = w;
        best_key = keyed[a].first;
      }
      a = b;
    }
    mode = weighted_mean([&](const Particle& q) { return BinKey(q) == best_key; });
  }
  const double cr = p.cluster_radius, ca = DegToRad(p.cluster_angle_deg);
  const PoseMean mean = weighted_mean([&](const Particle& q) {
    return std::hypot(q.x - mode.x, q.y - mode.y) <= cr &&
           std::abs(WrapAngle(q.yaw - mode.yaw)) <= ca;
  });
  *cov = Eigen::Matrix3d::Zero();
  for (const auto& q : particles_) {
    const Eigen::Vector3d d(q.x - mean.x, q.y - mean.y, WrapAngle(q.yaw - mean.yaw));
    *cov += q.weight * d * d.transpose();
  }
  return Pose2{mean.x, mean.y, WrapAngle(mean.yaw)};
}

// A beam ending where the map is unknown (a room seen only through its door) is no evidence
// either way.
void Amcl::CountInliers(const std::vector<Vec2>& beams, const Pose2& X_MB, int* inliers,
                        int* mapped_beams) const {
  const Impl& m = *impl_;
  const double c = std::cos(X_MB.yaw), s = std::sin(X_MB.yaw);
  for (const Vec2& b : beams) {
    const Vec2 e(X_MB.x + c * b.x() - s * b.y(), X_MB.y + s * b.x() + c * b.y());
    const bool near_obstacle =
        m.likelihood.ObstacleDistance(e, params_.likelihood_max_dist) < params_.inlier_distance;
    if (!m.Known(e) && !near_obstacle) continue;
    ++*mapped_beams;
    if (near_obstacle) ++*inliers;
  }
}

bool Amcl::Refine(const interfaces::LrfScan& scan, Pose2* X_MB) const {
  const Impl& m = *impl_;
  const AmclParams& p = params_;
  const std::vector<Vec2> beams = SelectBeams(scan, p.refine_max_beams);
  struct Row {
    Eigen::Vector3d J;  // d(distance)/d(x, y, yaw)
    double r;           // m, distance to the nearest return
    std::size_t beam;
  };
  // Each beam's residual is measured along its own surface's normal where the sweep has one
  // (point-to-plane with the sensor's normals): the map's far walls are sampled sparsely, and
  // a beam ending between two of their returns is on the wall, not off the end of a return.
  const std::vector<Vec2> normals_B =
      SweepNormals(beams, p.refine_normal_radius, p.refine_normal_max_radius);
  std::vector<Row> rows;
  // A beam ending in unknown space away from any return at the filter's estimate (on the
  // unmapped near face of a wall whose far face the map holds) stays out of the match: moved
  // by the wall's thickness it would end on that far face and pull the estimate there.
  std::vector<std::uint8_t> excluded(beams.size(), 0);
  const double cos_max_normal_angle = std::cos(DegToRad(p.refine_max_normal_angle_deg));
  bool first = true;
  // Matched beams at X (rows, in beam order). The beams are matched in parallel, each into its
  // own slot, and the rows gathered in beam order: the sums below see the same order on any
  // number of threads.
  std::vector<std::optional<Row>> slots(beams.size());
  auto match = [&](const Pose2& X) {
    const double c = std::cos(X.yaw), s = std::sin(X.yaw);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, beams.size(), kRefineBeamsPerTask),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t k = range.begin(); k < range.end(); ++k) {
            slots[k].reset();
            if (excluded[k]) continue;
            const Vec2& b = beams[k];
            const Vec2 lever(c * b.x() - s * b.y(), s * b.x() + c * b.y());  // e - t
            const Vec2 e(X.x + lever.x(), X.y + lever.y());
            const DistanceField::Nearest near = m.likelihood.NearestReturn(e);
            // A beam ending in unknown space matches only when it ends on a return.
            const bool on_return = near.found && near.distance <= m.resolution;
            if (!m.Known(e) && !on_return) {
              if (first) excluded[k] = 1;
              continue;
            }
            if (!near.found || near.distance > p.refine_gate) continue;
            // Without a surface normal (a corner, a lone return) the beam stays out: towards
            // the nearest return it would pull along a wall whose returns end there.
            const Vec2& nb = normals_B[k];
            if (nb.squaredNorm() == 0.0) continue;
            const Vec2 n(c * nb.x() - s * nb.y(), s * nb.x() + c * nb.y());
            // A surface the map did not see (a reveal across the wall whose returns are
            // nearest) is no correspondence: its normal crosses the mapped surface's.
            if (near.surface_normal.squaredNorm() > 0.0 &&
                std::abs(n.dot(near.surface_normal)) < cos_max_normal_angle)
              continue;
            const double r = near.distance * n.dot(near.normal);  // n . (e - nearest return)
            slots[k] =
                Row{Eigen::Vector3d(n.x(), n.y(), n.x() * -lever.y() + n.y() * lever.x()), r, k};
          }
        });
    rows.clear();
    for (const std::optional<Row>& slot : slots)
      if (slot) rows.push_back(*slot);
  };
  const auto huber = [&](double r) {
    const double k = p.refine_huber, a = std::abs(r);
    return a <= k ? 0.5 * a * a : k * (a - 0.5 * k);
  };
  match(*X_MB);
  first = false;
  const std::vector<Row> before = rows;
  Pose2 X = *X_MB;
  for (int it = 0; it < p.refine_iterations; ++it) {
    if (it > 0) match(X);
    if (static_cast<int>(rows.size()) < p.refine_min_beams) return false;
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const Row& row : rows) {
      const double a = std::abs(row.r);
      const double w = a <= p.refine_huber ? 1.0 : p.refine_huber / a;
      H += w * row.J * row.J.transpose();
      g += w * row.J * row.r;
    }
    // Steps only along the directions the beams constrain (rotation as the displacement 1 m
    // from the base, so all three eigenvalues count beams).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const double lambda = es.eigenvalues()(k);
      if (lambda < p.refine_min_constraint) continue;
      const Eigen::Vector3d v = es.eigenvectors().col(k);
      delta -= (v.dot(g) / lambda) * v;
    }
    X = Pose2{X.x + delta.x(), X.y + delta.y(), WrapAngle(X.yaw + delta.z())};
    if (delta.norm() < 1e-5) break;
  }
  match(X);
  if (static_cast<int>(rows.size()) < p.refine_min_beams) return false;
  // The robust cost over the beams matched at both poses must not grow (a Gauss-Newton that
  // wandered off).
  double cost_before = 0.0, cost_after = 0.0;
  for (std::size_t i = 0, j = 0; i < before.size() && j < rows.size();) {
    if (before[i].beam < rows[j].beam) {
      ++i;
    } else if (rows[j].beam < before[i].beam) {
      ++j;
    } else {
      cost_before += huber(before[i++].r);
      cost_after += huber(rows[j++].r);
    }
  }
  if (cost_after > cost_before) return false;
  if (std::hypot(X.x - X_MB->x, X.y - X_MB->y) > p.refine_max_shift ||
      std::abs(WrapAngle(X.yaw - X_MB->yaw)) > DegToRad(p.refine_max_turn_deg))
    return false;
  *X_MB = X;
  return true;
}

// KLD-adapted size (Fox 2003) and Augmented MCL injection of `p_inject` random particles.
void Amcl::Resample(std::uint64_t u, double p_inject) {
  const Impl& m = *impl_;
  const AmclParams& p = params_;
  CounterRng rng(Key(seed_, "amcl/resample", u, 0));
  // KLD: k = bins a large resampled set would occupy.
  const auto comb =
      LowVariance(particles_, static_cast<std::size_t>(p.max_particles), rng.Uniform());
  std::vector<std::int64_t> bins;
  bins.reserve(comb.size());
  for (std::size_t idx : comb) bins.push_back(BinKey(particles_[idx]));
  std::sort(bins.begin(), bins.end());
  const auto k_bins = static_cast<double>(std::unique(bins.begin(), bins.end()) - bins.begin());
  double n_kld = p.min_particles;
  if (k_bins > 1) {
    const double a = 2.0 / (9.0 * (k_bins - 1.0));
    const double t = 1.0 - a + std::sqrt(a) * p.kld_z;
    n_kld = (k_bins - 1.0) / (2.0 * p.kld_err) * t * t * t;
  }
  const auto target =
      static_cast<std::size_t>(std::clamp(std::ceil(n_kld), static_cast<double>(p.min_particles),
                                          static_cast<double>(p.max_particles)));
  const auto pick = LowVariance(particles_, target, rng.Uniform());
  std::vector<Particle> next(target);
  const bool can_inject = p_inject > 0.0 && !m.free_centres.empty();
  for (std::size_t k = 0; k < target; ++k) {
    next[k] = particles_[pick[k]];
    next[k].weight = 1.0 / static_cast<double>(target);
    if (can_inject) {
      CounterRng irng(Key(seed_, "amcl/inject", u, k));
      if (irng.Uniform() < p_inject) {
        const Vec2& c = m.free_centres[irng.Below(m.free_centres.size())];
        next[k].x = c.x() + irng.Uniform(-0.5, 0.5) * m.resolution;
        next[k].y = c.y() + irng.Uniform(-0.5, 0.5) * m.resolution;
        next[k].yaw = irng.Uniform(-kPi, kPi);
      }
    }
  }
  particles_.swap(next);
}

void Amcl::RefineEstimate(const interfaces::LrfScan& scan, bool have_beams, Pose2* X_MB_io,
                          Eigen::Matrix3d* cov) {
  estimate_.refined = false;
  estimate_.refinement = Pose2{};
  if (params_.refine && !impl_->relocalising && have_beams) {
    Pose2 refined = *X_MB_io;
    if (Refine(scan, &refined)) {
      const Pose2 D = Compose(refined, Inverse(*X_MB_io));
      for (Particle& q : particles_) {
        const Pose2 moved = Compose(D, Pose2{q.x, q.y, q.yaw});
        q.x = moved.x;
        q.y = moved.y;
        q.yaw = moved.yaw;
      }
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      R.topLeftCorner<2, 2>() << std::cos(D.yaw), -std::sin(D.yaw), std::sin(D.yaw),
          std::cos(D.yaw);
      *cov = R * *cov * R.transpose();
      estimate_.refined = true;
      estimate_.refinement = Pose2{refined.x - X_MB_io->x, refined.y - X_MB_io->y,
                                   WrapAngle(refined.yaw - X_MB_io->yaw)};
      *X_MB_io = refined;
    }
  }
}

AmclUpdateResult Amcl::Update(const interfaces::Odometry& odom, const interfaces::LrfScan& scan,
                              bool force) {
  AmclUpdateResult result;
  if (particles_.empty()) return result;
  Impl& m = *impl_;
  const AmclParams& p = params_;
  const Pose2 cur = odom.X_OB;
  if (!m.have_last_odom) {
    m.last_odom = cur;
    m.have_last_odom = true;
  }
  // Odometry increment in the odom frame (Probabilistic Robotics Table 5.6).
  const double trans = std::hypot(cur.x - m.last_odom.x, cur.y - m.last_odom.y);
  const double dyaw = WrapAngle(cur.yaw - m.last_odom.yaw);
  const bool moved = trans >= p.update_min_d || std::abs(dyaw) >= DegToRad(p.update_min_a_deg);
  if (!moved && !force && !m.force_next) return result;
  m.force_next = false;
  result.updated = true;
  const std::uint64_t u = ++m.update_index;

  // 1. Motion update. 2. Beams. (Global localisation pending: seed the particles from a
  // correlative search of this scan.) 3. Measurement update.
  MotionUpdate(m.last_odom, cur, u);
  m.last_odom = cur;
  const std::vector<Vec2> beams = SelectBeams(scan);
  if (m.pending_search && !beams.empty()) {
    SeedFromGlobalSearch(beams, scan.range_max > 0.0 ? scan.range_max : p.likelihood_max_dist, u);
    m.pending_search = false;
  }
  const std::size_t n = particles_.size();
  const double nb = static_cast<double>(beams.size());
  const double n_eff = MeasurementUpdate(beams, scan);

  // 4. Estimate: weighted mean of the cluster around the heaviest KLD bin; covariance of the
  // whole set about it (so a multi-modal set reads as uncertain). Inliers among the beams that
  // end in mapped space.
  Eigen::Matrix3d cov;
  Pose2 X_MB = ClusterEstimate(&cov);
  // 4b. Refinement while tracking: the whole set moves rigidly by the correction.
  RefineEstimate(scan, !beams.empty(), &X_MB, &cov);
  int inliers = 0, mapped_beams = 0;
  CountInliers(beams, X_MB, &inliers, &mapped_beams);
  const double inlier_ratio = mapped_beams == 0 ? 0.0 : static_cast<double>(inliers) / mapped_beams;
  // Too few beams in mapped space: the update says nothing about loss.
  const bool inconclusive = mapped_beams < p.min_mapped_beam_fraction * nb;

  // 5. Resampling.
  const double p_inject =
      (m.w_slow > 0.0 && p.recovery_alpha_slow > 0.0 && p.recovery_alpha_fast > 0.0)
          ? std::max(0.0, 1.0 - m.w_fast / m.w_slow)
          : 0.0;
  if (n_eff < p.resample_neff_ratio * static_cast<double>(n) || m.relocalising || p_inject > 0.05) {
    result.resampled = true;
    Resample(u, p_inject);
  }

  // 6. Health and status.
  LocalisationEstimate& e = estimate_;
  e.X_MB = X_MB;
  e.X_MO = Compose(X_MB, Inverse(cur));
  e.covariance = cov;
  e.n_eff = n_eff;
  e.particles = static_cast<int>(particles_.size());
  e.inlier_ratio = inlier_ratio;
  e.w_slow = m.w_slow;
  e.w_fast = m.w_fast;
  e.updates = u;
  e.timestamp = odom.timestamp;
  const double sxy = std::sqrt(std::max(0.0, cov(0, 0) + cov(1, 1)));
  const double syaw = std::sqrt(std::max(0.0, cov(2, 2)));
  const bool converged = sxy < p.converged_sigma_xy && syaw < DegToRad(p.converged_sigma_yaw_deg);
  const bool good_match = !beams.empty() && !inconclusive && inlier_ratio >= p.lost_inlier_ratio;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "sigma_xy %.3f m, sigma_yaw %.2f deg, inliers %.0f%%, N_eff %.0f/%zu", sxy,
                RadToDeg(syaw), 100.0 * inlier_ratio, n_eff, n);
  const std::string health(buf);
  if (m.relocalising) {
    ++m.reloc_updates;
    if (converged && good_match &&
        m.reloc_updates >= static_cast<std::uint64_t>(p.relocalisation_min_updates)) {
      m.relocalising = false;
      m.bad_count = 0;
      e.status = LocalisationStatus::kLocalised;
      e.message = "re-localised after " + std::to_string(m.reloc_updates) + " updates; " + health;
    } else {
      e.status = LocalisationStatus::kRelocalising;
      e.message =
          "global re-localisation, update " + std::to_string(m.reloc_updates) + "; " + health;
    }
    return result;
  }
  if (!inconclusive) m.bad_count = good_match ? 0 : m.bad_count + 1;
  if (m.bad_count >= p.lost_updates) {
    result.lost_detected = true;
    e.status = LocalisationStatus::kLost;
    e.message = "lost: scan does not match the map for " + std::to_string(m.bad_count) +
                " updates (" + health + ")";
    if (p.relocalise_when_lost) {
      StartGlobalLocalisation();
      e.message += "; global re-localisation started";
    }
  } else if (converged && good_match) {
    e.status = LocalisationStatus::kLocalised;
    e.message = health;
  } else {
    e.status = LocalisationStatus::kUncertain;
    e.message = (good_match ? "spread too large: " : "poor scan match: ") + health;
  }
  return result;
}

void Amcl::SeedFromGlobalSearch(const std::vector<Vec2>& beams_B, double range_max,
                                std::uint64_t update) {
  const AmclParams& p = params_;
  const Impl& m = *impl_;
  const std::size_t n_pos = m.search_positions.size();
  if (n_pos == 0) return;
  const int n_yaw = std::max(1, static_cast<int>(std::lround(360.0 / p.global_search_yaw_deg)));
  const double yaw_step = 2.0 * kPi / n_yaw;
  // Beams to score, evenly spaced.
  std::vector<Vec2> beams;
  const std::size_t want =
      std::min<std::size_t>(beams_B.size(), static_cast<std::size_t>(p.global_search_beams));
  for (std::size_t b = 0; b < want; ++b) beams.push_back(beams_B[b * beams_B.size() / want]);
  // Beam endpoints rotated for every yaw bin.
  std::vector<Vec2> rotated(static_cast<std::size_t>(n_yaw) * beams.size());
  for (int t = 0; t < n_yaw; ++t) {
    const double yaw = -kPi + t * yaw_step, c = std::cos(yaw), s = std::sin(yaw);
    for (std::size_t b = 0; b < beams.size(); ++b)
      rotated[t * beams.size() + b] =
          Vec2(c * beams[b].x() - s * beams[b].y(), s * beams[b].x() + c * beams[b].y());
  }
  const double sigma = p.global_sigma_hit;
  const double hit_norm = p.z_hit / (kSqrt2Pi * sigma), rand_term = p.z_rand / range_max;
  std::vector<float> score(n_pos * static_cast<std::size_t>(n_yaw));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_pos), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const Vec2& x = m.search_positions[k];
      for (int t = 0; t < n_yaw; ++t) {
        double sum = 0.0;
        for (std::size_t b = 0; b < beams.size(); ++b) {
          const double d =
              m.likelihood.CentreDistance(x + rotated[t * beams.size() + b], p.likelihood_max_dist);
          sum += std::log(hit_norm * std::exp(-0.5 * d * d / (sigma * sigma)) + rand_term);
        }
        score[k * n_yaw + t] = static_cast<float>(sum);
      }
    }
  });
  // Best distinct hypotheses (non-maximum suppression), ties broken by index.
  std::vector<std::uint32_t> order(score.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
  const std::size_t top = std::min<std::size_t>(order.size(), 50000);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(top), order.end(),
                    [&](std::uint32_t a, std::uint32_t b) {
                      return score[a] > score[b] || (score[a] == score[b] && a < b);
                    });
  std::vector<Pose2> hyps;
  for (std::size_t r = 0; r < top && static_cast<int>(hyps.size()) < p.global_hypotheses; ++r) {
    const Vec2& x = m.search_positions[order[r] / n_yaw];
    const double yaw = -kPi + static_cast<double>(order[r] % n_yaw) * yaw_step;
    bool distinct = true;
    for (const auto& h : hyps)
      distinct &= std::hypot(h.x - x.x(), h.y - x.y()) > 3.0 * p.global_search_step ||
                  std::abs(WrapAngle(h.yaw - yaw)) > 4.0 * yaw_step;
    if (distinct) hyps.push_back({x.x(), x.y(), yaw});
  }
  // Particles: max_particles shared among the hypotheses, Gaussian about each.
  const int n = p.max_particles;
  particles_.assign(static_cast<std::size_t>(n), Particle{});
  for (int k = 0; k < n; ++k) {
    const Pose2& h = hyps[static_cast<std::size_t>(k) % hyps.size()];
    CounterRng rng(Key(seed_, "amcl/global_seed", update, static_cast<std::uint64_t>(k)));
    particles_[static_cast<std::size_t>(k)] = {h.x + 0.5 * p.global_search_step * rng.Normal(),
                                               h.y + 0.5 * p.global_search_step * rng.Normal(),
                                               WrapAngle(h.yaw + 0.5 * yaw_step * rng.Normal()),
                                               1.0 / n};
  }
}

}  // namespace mopad::perception
