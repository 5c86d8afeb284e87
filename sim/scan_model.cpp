#include "sim/scan_model.h"

#include <algorithm>

#include "sim/tls_params.h"

namespace mopad::sim {

// ZIGNOR constants for 128 layers: R is the start of the tail, V the area of each layer.
namespace {
constexpr double kZigV = 9.91256303526217e-3;
}  // namespace

Ziggurat::Ziggurat() {
  double f = std::exp(-0.5 * kR * kR);
  x_[0] = kZigV / f;  // the bottom layer including the tail
  x_[1] = kR;
  x_[128] = 0.0;
  for (int i = 2; i < 128; ++i) {
    x_[i] = std::sqrt(-2.0 * std::log(kZigV / x_[i - 1] + f));
    f = std::exp(-0.5 * x_[i] * x_[i]);
  }
  for (int i = 0; i < 128; ++i) rf_[i] = static_cast<float>(x_[i + 1] / x_[i]);
  for (int i = 0; i <= 128; ++i) xf_[i] = static_cast<float>(x_[i]);
}

const Ziggurat& Ziggurat::Get() {
  static const Ziggurat z;
  return z;
}

double Ziggurat::Tail(double u1, double u2) const {
  // Marsaglia (1964): x = -ln(u1) / R, accepted when -2 ln(u2) >= x^2 (NaN = reject).
  const double x = std::log(1.0 - u1) / kR;
  const double y = std::log(1.0 - u2);
  return -2.0 * y < x * x ? std::numeric_limits<double>::quiet_NaN() : x;
}

BeamModel::BeamModel(const BeamConfig& c) : c_(c) {
  const int K = std::max(1, c.rays);
  subs_.assign(static_cast<std::size_t>(K), SubRay{});
  if (K > 1) {
    // Centre ray plus K-1 rays evenly on a ring at `ring` x the 1/e^2 beam radius; weights from
    // the Gaussian beam profile I(r) ~ exp(-2 r^2 / w^2) (Siegman, Lasers, 1986, ch. 17).
    const float ring = static_cast<float>(c.ring);
    const float w_ring = std::exp(-2.0f * ring * ring);
    const float total = 1.0f + (K - 1) * w_ring;
    subs_[0].weight = 1.0f / total;
    for (int k = 1; k < K; ++k) {
      const float phi = 6.2831853f * static_cast<float>(k - 1) / static_cast<float>(K - 1);
      SubRay& sr = subs_[static_cast<std::size_t>(k)];
      sr.a = ring * std::cos(phi);
      sr.b = ring * std::sin(phi);
      sr.weight = w_ring / total;
      const double h = c.half_divergence * ring;
      sr.inv_norm = static_cast<float>(1.0 / std::sqrt(1.0 + h * h));
    }
  }
  min_cos_noise_ = static_cast<float>(std::cos(c.max_noise_incidence));
  zig_ = &Ziggurat::Get();
  intensity_noise_ = static_cast<float>(c.intensity_noise);
  colour_noise_ = static_cast<float>(c.colour_noise);
  ambient_ = static_cast<float>(c.ambient);
  top_light_ = static_cast<float>(c.top_light);
  srgb_ = &SrgbTables::Get();
  // With q = rho / rho_ref and 0 <= 2k <= 1, q^(2k) >= min(1, q); hence
  // min(rho, rho_ref) >= R^2 * sure_detect_ implies s >= exp(40 / gamma), i.e. P_detect = 1 to
  // 4e-18, without logarithms (see Finish).
  if (2.0 * c.reflectance_exponent <= 1.0) {
    sure_detect_ =
        std::exp(40.0 / c.detection_sharpness) * c.reflectance_ref / (c.range_ref * c.range_ref);
  }
}

BeamModel::BeamModel(const TlsParams& p)
    : BeamModel([&] {
        BeamConfig c;
        c.rays = p.footprint_rays;
        c.half_divergence = 0.5e-3 * p.beam_divergence_mrad;
        c.exit_radius = 0.5 * p.beam_exit_diameter;
        c.ring = p.footprint_ring;
        c.echo_separation = p.echo_separation;
        c.mode = p.echo_mode == "first"
                     ? EchoMode::kFirst
                     : (p.echo_mode == "last" ? EchoMode::kLast : EchoMode::kStrongest);
        c.range_min = p.range_min;
        c.range_ref = p.range_ref;
        c.reflectance_ref = p.reflectance_ref;
        c.reflectance_exponent = p.reflectance_exponent;
        c.detection_sharpness = p.detection_sharpness;
        c.min_reflectance = p.min_reflectance;
        c.dropouts = p.dropouts;
        c.precision = p.range_precision;
        c.incidence_exponent = p.incidence_noise_exponent;
        c.max_noise_incidence = p.max_noise_incidence_deg * 3.14159265358979323846 / 180.0;
        c.intensity_attenuation = p.intensity_attenuation;
        c.intensity_noise = p.intensity_noise;
        c.ambient = p.ambient_light;
        c.top_light = p.top_light;
        c.colour_noise = p.colour_noise;
        return c;
      }()) {}

double BeamModel::DetectionProbability(double R, double rho_c) const {
  const double ln_s =
      2.0 * (c_.reflectance_exponent * std::log(std::max(rho_c, 1e-9) / c_.reflectance_ref) -
             std::log(R / c_.range_ref));
  const double x = c_.detection_sharpness * ln_s;
  return x > 40.0 ? 1.0 : 1.0 / (1.0 + std::exp(-x));
}

void BeamModel::Measure(const EmbreeWorld&, const SurfaceTable& surfaces, const SubHit* subs,
                        std::uint64_t noise_key, std::uint64_t index, EchoResult* out) const {
  PulseStream rng(noise_key, index);
  const int K = rays();
  *out = EchoResult{};
  if (K == 1) {
    // One ray per pulse: no echo merging.
    const SubHit& s = subs[0];
    if (!s.hit.hit()) return;
    out->dominant = &s;
    if (s.transmitted) out->flags |= kTruthTransmitted;
    if (s.hit.t < c_.range_min) {
      out->flags |= kTruthTooClose;
      return;
    }
    const float ca = std::clamp(std::abs(s.hit.normal.dot(s.dir)), 1e-4f, 1.0f);
    Finish(s.hit.t, LookupReflectance(surfaces.part(s.hit.part), ca), ca, rng, out);
    return;
  }
  // Per sub-ray echo: effective reflectance and received energy (radar equation, extended
  // target: P ~ rho_eff / R^2; Jelalian, Laser Radar Systems, 1992).
  float rho[64], energy[64], cosa[64];
  int order[64];
  int m = 0;
  for (int k = 0; k < K; ++k) {
    const SubHit& s = subs[k];
    if (!s.hit.hit()) continue;
    const float ca = std::clamp(std::abs(s.hit.normal.dot(s.dir)), 1e-4f, 1.0f);
    cosa[k] = ca;
    rho[k] = LookupReflectance(surfaces.part(s.hit.part), ca);
    const float t = std::max(s.hit.t, 1e-3f);
    energy[k] = subs_[static_cast<std::size_t>(k)].weight * rho[k] / (t * t);
    order[m++] = k;
  }
  if (m == 0) return;  // nothing hit: no return, no truth

  // Echo clusters: sub-ray echoes sorted by range; neighbours closer than echo_separation merge.
  int begin = 0, end = m;  // the chosen cluster in `order`
  if (K > 1) {
    // Insertion sort by range (m <= 64, usually 7): stable, cheap for tiny arrays.
    for (int a = 1; a < m; ++a) {
      const int v = order[a];
      int b = a;
      for (; b > 0 && subs[order[b - 1]].hit.t > subs[v].hit.t; --b) order[b] = order[b - 1];
      order[b] = v;
    }
    const float sep = static_cast<float>(c_.echo_separation);
    int best_b = -1, best_e = -1;
    float best_energy = -1.0f;
    bool any_too_close = false;
    for (int b = 0; b < m;) {
      int e = b + 1;
      while (e < m && subs[order[e]].hit.t - subs[order[e - 1]].hit.t < sep) ++e;
      float en = 0.0f, et = 0.0f;
      for (int i = b; i < e; ++i) {
        en += energy[order[i]];
        et += energy[order[i]] * subs[order[i]].hit.t;
      }
      const float mean_t = en > 0 ? et / en : subs[order[b]].hit.t;
      if (mean_t < c_.range_min) {
        any_too_close = true;  // the scanner blanks echoes inside its minimum range
      } else if (best_b < 0 || c_.mode == EchoMode::kLast ||
                 (c_.mode == EchoMode::kStrongest && en > best_energy)) {
        best_b = b;  // kFirst keeps the first valid cluster only
        best_e = e;
        best_energy = en;
      }
      b = e;
    }
    if (best_b < 0) {
      out->flags |= any_too_close ? kTruthTooClose : 0;
      out->dominant = &subs[order[0]];
      return;
    }
    begin = best_b;
    end = best_e;
  }

  // Dominant sub-ray, mixed-pixel flag, merged range and reflectance.
  int dom = order[begin];
  double sum_e = 0.0, sum_et = 0.0, rho_c = 0.0;
  bool mixed = false;
  for (int i = begin; i < end; ++i) {
    const int k = order[i];
    if (energy[k] > energy[dom]) dom = k;
    sum_e += energy[k];
    sum_et += static_cast<double>(energy[k]) * subs[k].hit.t;
    rho_c += subs_[static_cast<std::size_t>(k)].weight * rho[k];
    const RayHit& h0 = subs[order[begin]].hit;
    if (subs[k].hit.part != h0.part || subs[k].hit.normal.dot(h0.normal) < 0.985f) mixed = true;
  }
  const SubHit& d = subs[dom];
  out->dominant = &d;
  if (d.transmitted) out->flags |= kTruthTransmitted;
  if (mixed) out->flags |= kTruthMixed;
  const double R = sum_e > 0 ? sum_et / sum_e : d.hit.t;
  if (R < c_.range_min) {
    out->flags |= kTruthTooClose;
    return;
  }

  Finish(R, rho_c, cosa[dom], rng, out);
}

}  // namespace mopad::sim
