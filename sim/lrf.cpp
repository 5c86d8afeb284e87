#include "sim/lrf.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include "common/error.h"
#include "common/rng.h"
#include "sim/scan_model.h"
#include "sim/surface_model.h"

namespace mopad::sim {
namespace {

// Work per task of a sweep (a 1081-beam sweep in a few tasks: TBB's overhead stays small).
constexpr std::size_t kPacketsPerTask = 16;
constexpr int kBeamsPerTask = 256;

}  // namespace

void LrfParams::Validate() const {
  ValidateParams(*this, "lrf.");
  if (angle_max_deg <= angle_min_deg) {
    throw InputError("", "parameter 'lrf.angle_max_deg' must exceed angle_min_deg",
                     std::to_string(angle_max_deg), "> " + std::to_string(angle_min_deg));
  }
  if (range_max <= range_min) {
    throw InputError("", "parameter 'lrf.range_max' must exceed range_min",
                     std::to_string(range_max), "> " + std::to_string(range_min));
  }
  if (footprint_rays == 2)
    throw InputError("", "parameter 'lrf.footprint_rays' must be 1 or >= 3", "2");
  if (mount_xyz.size() != 3 || mount_rpy_deg.size() != 3) {
    throw InputError("", "parameters 'lrf.mount_xyz' and 'lrf.mount_rpy_deg' need 3 values");
  }
}

LrfParams LrfParams::NoiseFree() const {
  LrfParams p = *this;
  p.sigma_near = p.sigma_far = p.bias_sigma = 0.0;
  p.dropouts = false;
  return p;
}

Pose3 LrfParams::X_BL() const {
  Pose3 X = Pose3::Identity();
  X.translation() = Eigen::Vector3d(mount_xyz[0], mount_xyz[1], mount_xyz[2]);
  X.linear() = (Eigen::AngleAxisd(DegToRad(mount_rpy_deg[2]), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(DegToRad(mount_rpy_deg[1]), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(DegToRad(mount_rpy_deg[0]), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

LrfParams LrfProfile(const std::string& name) {
  LrfParams p;
  if (name == "hokuyo_utm30lx") return p;
  if (name == "sick_lms111" || name == "sick_lms111_fine") {
    p.name = name;
    p.angle_increment_deg = name == "sick_lms111" ? 0.5 : 0.25;
    p.rate_hz = name == "sick_lms111" ? 50.0 : 25.0;
    p.range_min = 0.5;
    p.range_max = 20.0;
    p.sigma_near = p.sigma_far = 0.012;  // statistical error, 1 sigma
    p.bias_sigma = 0.03;                 // systematic error +-30 mm, drawn per sweep
    p.beam_divergence_mrad = 15.0;
    p.beam_exit_diameter = 0.008;
    p.footprint_rays = 7;
    p.range_ref = 18.0;  // 18 m at 10 % remission
    p.reflectance_ref = 0.1;
    return p;
  }
  std::string known;
  for (const auto& n : LrfProfileNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("", "unknown LRF profile", "'" + name + "'", known);
}

std::vector<std::string> LrfProfileNames() {
  return {"hokuyo_utm30lx", "sick_lms111", "sick_lms111_fine"};
}

std::vector<LrfParams> PaperLrfRig(const std::string& profile) {
  LrfParams top = LrfProfile(profile), base = LrfProfile(profile);
  top.frame = "lrf_top";
  top.mount_xyz = {0.0, 0.0, 1.2};
  base.frame = "lrf_base";
  base.mount_xyz = {0.2, 0.0, 0.25};
  return {top, base};
}

LrfSimulator::LrfSimulator(const EmbreeWorld& world, LrfParams params)
    : world_(world), params_(std::move(params)) {
  params_.Validate();
  beams_ =
      static_cast<int>(std::floor(
          (params_.angle_max_deg - params_.angle_min_deg) / params_.angle_increment_deg + 1e-6)) +
      1;
  surfaces_ = std::make_shared<const SurfaceTable>(world_);
}

interfaces::LrfScan LrfSimulator::Scan(const Pose3& X_WB, std::uint64_t seed, std::uint64_t seq,
                                       double timestamp) const {
  const LrfParams& p = params_;
  BeamConfig cfg;
  cfg.rays = p.footprint_rays;
  cfg.half_divergence = 0.5e-3 * p.beam_divergence_mrad;
  cfg.exit_radius = 0.5 * p.beam_exit_diameter;
  cfg.echo_separation = p.echo_separation;
  cfg.range_min = p.range_min;
  cfg.range_ref = p.range_ref;
  cfg.reflectance_ref = p.reflectance_ref;
  cfg.reflectance_exponent = 0.5;
  cfg.min_reflectance = p.min_reflectance;
  cfg.dropouts = p.dropouts;
  cfg.precision = p.sigma_near;
  cfg.precision_far = p.sigma_far;
  cfg.precision_switch_range = p.sigma_switch_range;
  cfg.incidence_exponent = p.incidence_noise_exponent;
  BeamModel beam(cfg);
  const SurfaceTable& surfaces = *surfaces_;
  if (surfaces.size() != static_cast<std::size_t>(world_.PartCount()))
    throw std::logic_error("LrfSimulator: the world gained movers after the LRF was made");

  const std::uint64_t sweep_key =
      DeriveKey(DeriveKey(DeriveKey(Mix64(seed), HashName("sim/lrf")), HashName(p.frame)), seq);
  CounterRng sweep_rng(DeriveKey(sweep_key, HashName("sweep")));
  beam.set_range_bias(p.bias_sigma * sweep_rng.Normal());
  const std::uint64_t noise_key = DeriveKey(sweep_key, HashName("noise"));
  const std::uint64_t glass_key = DeriveKey(sweep_key, HashName("glass"));

  const Pose3 X_WL = X_WB * p.X_BL();
  const Eigen::Matrix3f R = X_WL.linear().cast<float>();
  const Eigen::Vector3f o_W = X_WL.translation().cast<float>();
  const int K = beam.rays();
  const std::size_t n_rays = static_cast<std::size_t>(beams_) * K;
  // Ray order: sub-ray k of every beam together, beams in sweep order (coherent packets).
  std::vector<Eigen::Vector3f> origins(n_rays), dirs(n_rays);
  for (int k = 0; k < K; ++k) {
    const BeamModel::SubRay& sr = beam.sub(k);
    for (int i = 0; i < beams_; ++i) {
      const double a = DegToRad(p.angle_min_deg + i * p.angle_increment_deg);
      const Eigen::Vector3f d(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)),
                              0.0f);
      const Eigen::Vector3f e_az(-d.y(), d.x(), 0.0f), e_el = Eigen::Vector3f::UnitZ();
      const Eigen::Vector3f off = sr.a * e_az + sr.b * e_el;
      const std::size_t idx = static_cast<std::size_t>(k) * beams_ + i;
      origins[idx] = o_W + R * (beam.exit_radius() * off);
      dirs[idx] = R * (K > 1 ? (d + beam.half_divergence() * off).normalized() : d);
    }
  }
  // The sweep's rays in the same 16-ray packets as one serial call, split between threads at
  // packet boundaries; each beam's echo from its own random stream: the same bytes on any
  // number of threads.
  std::vector<RayHit> hits(n_rays);
  const std::size_t packets = (n_rays + 15) / 16;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, packets, kPacketsPerTask),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      const std::size_t a = 16 * r.begin(), b = std::min(n_rays, 16 * r.end());
                      world_.IntersectMany(std::span(origins).subspan(a, b - a),
                                           std::span(dirs).subspan(a, b - a), 0.0f,
                                           std::numeric_limits<float>::infinity(),
                                           std::span(hits).subspan(a, b - a), timestamp);
                    });

  interfaces::LrfScan scan;
  scan.frame = p.frame;
  scan.seq = seq;
  scan.timestamp = timestamp;
  scan.angle_min = DegToRad(p.angle_min_deg);
  scan.angle_increment = DegToRad(p.angle_increment_deg);
  scan.range_min = p.range_min;
  scan.range_max = p.range_max;
  scan.X_BL = p.X_BL();
  scan.ranges.assign(static_cast<std::size_t>(beams_), static_cast<float>(p.range_max));
  scan.intensities.assign(static_cast<std::size_t>(beams_), 0.0f);
  tbb::parallel_for(tbb::blocked_range<int>(0, beams_, kBeamsPerTask), [&](const auto& range) {
    std::vector<SubHit> subs(static_cast<std::size_t>(K));
    for (int i = range.begin(); i < range.end(); ++i) {
      for (int k = 0; k < K; ++k) {
        const std::size_t idx = static_cast<std::size_t>(k) * beams_ + i;
        SubHit& s = subs[static_cast<std::size_t>(k)];
        s = SubHit{};
        s.hit = hits[idx];
        s.origin = origins[idx];
        s.dir = dirs[idx];
        s.time = timestamp;
        ContinueThroughGlass(world_, surfaces, p.max_transmissions, glass_key,
                             static_cast<std::uint64_t>(i) * 64 + static_cast<std::uint64_t>(k),
                             &s);
      }
      EchoResult echo;
      beam.Measure(world_, surfaces, subs.data(), noise_key, static_cast<std::uint64_t>(i), &echo);
      if (echo.returned && echo.range < p.range_max) {
        scan.ranges[static_cast<std::size_t>(i)] = echo.range;
        scan.intensities[static_cast<std::size_t>(i)] = echo.intensity;
      }
    }
  });
  return scan;
}

}  // namespace mopad::sim
