#pragma once
// Internal to sim/: the per-pulse sensor model shared by the TLS and the LRFs — beam footprint
// (sub-rays), echo formation (mixed pixels), detection and dropouts, range noise, intensity and
// colour. Equations and sources: docs/sensors.md.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/rng.h"
#include "sim/embree_world.h"
#include "sim/surface_model.h"
#include "sim/tls_truth.h"

namespace mopad::sim {

struct TlsParams;

/// The random stream of one pulse (or beam, or sub-ray): draw j of item i under `key` is
/// SplitMix64's output Mix64(key + (64 i + j) * golden), i.e. a counter-based generator keyed by
/// (key, item index, draw) as CounterRng, at one mixing per draw. Each item owns 64 counters; a
/// pulse needs 3-6, and should it ever need more (ziggurat rejections) it continues with
/// CounterRng(DeriveKey(key, i)), still a pure function of (key, i). Keys come from
/// DeriveKey(seed-derived key, HashName(purpose)), so purposes never share a stream.
class PulseStream {
 public:
  static constexpr std::uint64_t kSlots = 64;
  PulseStream(std::uint64_t key, std::uint64_t index)
      : key_(key), index_(index), counter_(index * kSlots) {}
  std::uint64_t NextU64() {
    if (used_ < kSlots) {
      ++used_;
      return Mix64(key_ + (counter_++) * 0x9E3779B97F4A7C15ull);
    }
    return Overflow();
  }
  /// Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t Overflow() {
    if (used_++ == kSlots) overflow_key_ = DeriveKey(key_, index_);
    return Mix64(overflow_key_ ^ Mix64(used_));
  }
  std::uint64_t key_, index_, counter_;
  std::uint64_t used_ = 0;
  std::uint64_t overflow_key_ = 0;
};

/// Standard normal by the ziggurat method with 128 layers (Marsaglia & Tsang 2000, J. Stat.
/// Softw. 5(8)), in Doornik's ZIGNOR form (2005, "An improved ziggurat method to generate
/// normal random samples"), which takes the layer index from bits independent of the uniform.
/// ~99 % of draws cost one 64-bit number, a table lookup and a compare; the rest fall back to the
/// exact wedge/tail tests. The draws consumed are a pure function of the generator's stream.
class Ziggurat {
 public:
  static const Ziggurat& Get();
  /// One standard normal. The fast test uses the top 24 bits as a float uniform and float
  /// tables, exactly as the vectorised pulse kernel (sim/pulse_kernel.h) does.
  template <class Rng>
  double Normal(Rng& rng) const {
    for (;;) {
      const std::uint64_t bits = rng.NextU64();
      const unsigned i = static_cast<unsigned>(bits & 0x7F);
      const float u = static_cast<float>(bits >> 40) * 0x1.0p-23f - 1.0f;  // [-1, 1)
      if (std::abs(u) < rf_[i]) return static_cast<double>(u * xf_[i]);
      const double w = SlowPath(rng, static_cast<double>(u), i);
      if (w == w) return w;  // NaN: rejected, draw again
    }
  }
  const float* rf() const { return rf_; }  ///< x[i+1] / x[i], 128 entries
  const float* xf() const { return xf_; }  ///< layer edges x[i], 129 entries

 private:
  static constexpr double kR = 3.442619855899;  ///< start of the tail (ZIGNOR, 128 layers)
  Ziggurat();
  template <class Rng>
  double SlowPath(Rng& rng, double u, unsigned i) const;
  double Tail(double u1, double u2) const;
  double x_[129];
  float xf_[129];
  float rf_[128];
};

template <class Rng>
double Ziggurat::SlowPath(Rng& rng, double u, unsigned i) const {
  if (i == 0) {  // the tail beyond R
    for (;;) {
      const double u1 = rng.Uniform();
      const double u2 = rng.Uniform();
      const double x = Tail(u1, u2);
      if (x == x) return u < 0 ? x - kR : kR - x;
    }
  }
  // Wedge between layer i and i+1: accept under the density.
  const double x = u * x_[i];
  const double f0 = std::exp(-0.5 * (x_[i] * x_[i] - x * x));
  const double f1 = std::exp(-0.5 * (x_[i + 1] * x_[i + 1] - x * x));
  if (f1 + (f0 - f1) * rng.Uniform() < 1.0) return x;
  return std::numeric_limits<double>::quiet_NaN();
}

/// One sub-ray's trace: where it started, where it went, what it hit (after glass).
struct SubHit {
  RayHit hit;
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f dir = Eigen::Vector3f::UnitX();
  bool transmitted = false;
  /// s, when the ray went (places the world's movers); the default: the movers' track start
  double time = -std::numeric_limits<double>::infinity();
};

/// Lets a sub-ray pass up to `max_layers` transmitting surfaces (glass): at each, it continues
/// with the material's transmission probability (one uniform per crossing from the stream
/// (key, index)).
inline void ContinueThroughGlass(const EmbreeWorld& world, const SurfaceTable& surfaces,
                                 int max_layers, std::uint64_t key, std::uint64_t index,
                                 SubHit* s) {
  if (!s->hit.hit() || max_layers == 0) return;
  PulseStream rng(key, index);
  for (int layer = 0; layer < max_layers && s->hit.hit(); ++layer) {
    const float tr = surfaces.part(s->hit.part).transmission;
    if (tr <= 0.0f || !(rng.Uniform() < tr)) return;
    s->transmitted = true;
    // Restart just beyond the surface along the same ray (same origin: no drift).
    s->hit = world.Intersect(s->origin, s->dir, s->hit.t + 1e-4f,
                             std::numeric_limits<float>::infinity(), s->time);
  }
}

struct EchoResult {
  bool returned = false;
  float range = 0.0f;                 ///< m, measured (with noise and bias)
  float intensity = 0.0f;             ///< [0, 1]
  const SubHit* dominant = nullptr;   ///< sub-ray that carried most energy of the reported echo
  std::uint8_t flags = 0;             ///< TruthFlags
  float colour_noise[3] = {0, 0, 0};  ///< sRGB levels to add
};

enum class EchoMode { kFirst, kStrongest, kLast };

/// The model's constants (from TlsParams or LrfParams).
struct BeamConfig {
  int rays = 1;
  double half_divergence = 0.0;  ///< rad, 1/e^2 half angle
  double exit_radius = 0.0;      ///< m
  double ring = 0.7;             ///< ring radius as a fraction of the beam radius
  double echo_separation = 0.5;  ///< m
  EchoMode mode = EchoMode::kStrongest;
  double range_min = 0.0, range_ref = 100.0, reflectance_ref = 0.2, reflectance_exponent = 0.5;
  double detection_sharpness = 8.0, min_reflectance = 0.0;
  bool dropouts = true;
  double precision = 0.0;       ///< m, 1 sigma at normal incidence (ranges < precision_switch)
  double precision_far = -1.0;  ///< m, beyond precision_switch_range (< 0: same)
  double precision_switch_range = std::numeric_limits<double>::infinity();
  double incidence_exponent = 1.0;
  double max_noise_incidence = 1.4835;  ///< rad
  double intensity_attenuation = 0.0, intensity_noise = 0.0;
  double ambient = 1.0, top_light = 0.0, colour_noise = 0.0;
};

class BeamModel {
 public:
  struct SubRay {
    float a = 0, b = 0;  ///< offset direction in the beam's (azimuth, elevation) tangent plane,
                         ///< scaled by the ring fraction
    float weight = 1;    ///< normalised (sum over sub-rays = 1)
    float inv_norm = 1;  ///< 1 / |beam + half_divergence (a, b)|: makes the sub-ray unit
  };

  BeamModel() = default;
  explicit BeamModel(const BeamConfig& c);
  explicit BeamModel(const TlsParams& p);

  int rays() const { return static_cast<int>(subs_.size()); }
  const SubRay& sub(int k) const { return subs_[static_cast<std::size_t>(k)]; }
  float half_divergence() const { return static_cast<float>(c_.half_divergence); }
  float exit_radius() const { return static_cast<float>(c_.exit_radius); }
  const BeamConfig& config() const { return c_; }
  void set_range_bias(double b) { bias_ = b; }
  /// min(rho, reflectance_ref) >= R^2 * sure_detect() proves P_detect = 1 (0: no such bound).
  double sure_detect() const { return sure_detect_; }

  /// Forms the reported echo of one pulse from its rays() sub-hits; noise from the stream
  /// (noise_key, index).
  void Measure(const EmbreeWorld& world, const SurfaceTable& surfaces, const SubHit* subs,
               std::uint64_t noise_key, std::uint64_t index, EchoResult* out) const;
  /// Dropout, noise, intensity and colour noise of an echo at range R (m) with effective
  /// reflectance rho_c and incidence cosine cos_a (sets out->range, intensity, colour_noise,
  /// returned, or the kTruthDropped flag). Inline: it is the per-pulse hot path.
  void Finish(double R, double rho_c, float cos_a, PulseStream& rng, EchoResult* out) const {
    // Two draws per pulse. The first is split: bits 0-23 the dropout uniform, 24-39 the
    // intensity noise (Irwin-Hall sum of four 4-bit uniforms), 40-63 the colour noise (per
    // channel the sum of two 4-bit uniforms); the second feeds the exact normal (ziggurat) of
    // the range noise, the one whose distribution the tests pin.
    const std::uint64_t d1 = rng.NextU64();
    if (c_.dropouts) {
      const double u_drop = (static_cast<double>(d1 & 0xFFFFFF) + 0.5) * 0x1.0p-24;
      double p = 1.0;
      // Detection: s = (rho/rho_ref)^(2k) (R_ref/R)^2 is the received energy relative to the
      // detection threshold (s = 1 at the data sheet's maximum range); P = 1 / (1 + s^-gamma).
      // Indoors s is huge: skip the logarithms when a cheap bound proves P = 1 to 1e-17.
      if (!(sure_detect_ > 0.0 && std::min(rho_c, c_.reflectance_ref) >= R * R * sure_detect_)) {
        p = DetectionProbability(R, rho_c);
      }
      if (c_.min_reflectance > 0.0 && rho_c < c_.min_reflectance) p *= rho_c / c_.min_reflectance;
      if (!(u_drop < p)) {
        out->flags |= kTruthDropped;
        return;
      }
    }
    // Range noise: per-scan bias + N(0, sigma(R) / cos(alpha)^k), capped at max_noise_incidence.
    double sigma = (c_.precision_far >= 0.0 && R > c_.precision_switch_range) ? c_.precision_far
                                                                              : c_.precision;
    if (sigma > 0.0) {
      if (c_.incidence_exponent > 0.0) {
        const float ca = std::max(cos_a, min_cos_noise_);
        sigma *= c_.incidence_exponent == 1.0 ? 1.0 / ca : std::pow(ca, -c_.incidence_exponent);
      }
      R += sigma * zig_->Normal(rng);
    }
    out->range = static_cast<float>(std::max(1e-6, R + bias_));
    // Intensity: reflectance with a residual range fall-off exp(-a R) (4th-order Taylor below
    // a R = 0.5, error < 3e-4) plus noise.
    const float x = static_cast<float>(c_.intensity_attenuation * R);
    const float fade =
        x < 0.5f ? 1.0f - x * (1.0f - 0.5f * x * (1.0f - (1.0f / 3.0f) * x * (1.0f - 0.25f * x)))
                 : std::exp(-x);
    const std::uint64_t ib = d1 >> 24;
    const int isum =
        static_cast<int>((ib & 15) + ((ib >> 4) & 15) + ((ib >> 8) & 15) + ((ib >> 12) & 15));
    const float n_int =
        (static_cast<float>(isum) - 30.0f) * (1.0f / 9.2195445f);  // sigma of the sum: sqrt(85)
    out->intensity =
        std::clamp(static_cast<float>(rho_c) * fade + intensity_noise_ * n_int, 0.0f, 1.0f);
    if (colour_noise_ > 0.0f) {
      std::uint64_t cb = d1 >> 40;
      for (float& cn : out->colour_noise) {
        const int sum = static_cast<int>((cb & 15) + ((cb >> 4) & 15));
        cn = colour_noise_ * (static_cast<float>(sum) - 15.0f) * (1.0f / 6.5192024f);  // sqrt(42.5)
        cb >>= 8;
      }
    }
    out->returned = true;
  }
  /// sRGB colour (rounded) of a surface hit seen along `dir`, plus noise (sRGB levels).
  std::array<std::uint8_t, 3> Colour(const EmbreeWorld& world, const SurfaceTable& surfaces,
                                     const RayHit& hit, const Eigen::Vector3f& dir,
                                     const float noise[3]) const {
    return ColourOf(surfaces.Albedo(world, hit),
                    hit.normal.dot(dir) > 0.0f ? -hit.normal.z() : hit.normal.z(), noise);
  }
  /// The same from the linear albedo and the z component of the normal turned to face the
  /// viewer. Illumination: ambient + light from above on up-facing surfaces.
  std::array<std::uint8_t, 3> ColourOf(const Eigen::Vector3f& albedo, float facing_nz,
                                       const float noise[3]) const {
    const float light = ambient_ + top_light_ * std::max(0.0f, facing_nz);
    std::array<std::uint8_t, 3> out;
    for (int i = 0; i < 3; ++i) {
      const float v = srgb_->Encode(albedo[i] * light) + noise[i];
      out[static_cast<std::size_t>(i)] =
          static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f);
    }
    return out;
  }

 private:
  double DetectionProbability(double R, double rho_c) const;

  BeamConfig c_;
  const Ziggurat* zig_ = nullptr;
  const SrgbTables* srgb_ = nullptr;
  std::vector<SubRay> subs_{SubRay{}};
  double bias_ = 0.0;
  float min_cos_noise_ = 0.087f;
  double sure_detect_ = 0.0;  ///< see the constructor; 0 = always evaluate P_detect
  float intensity_noise_ = 0.0f, colour_noise_ = 0.0f, ambient_ = 1.0f, top_light_ = 0.0f;
};

}  // namespace mopad::sim
