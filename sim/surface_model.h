#pragma once
// Internal to sim/: per-part optical properties for the laser (reflectance, specular lobe,
// transmission) and the camera (base colour, texture sampling), precomputed once per world.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "scenes/scene.h"
#include "sim/embree_world.h"

namespace mopad::sim {

/// sRGB transfer functions (IEC 61966-2-1) through tables: exact decode of 8-bit values, and an
/// encode table fine enough (16384 entries) that decode -> encode returns the same 8-bit value.
class SrgbTables {
 public:
  static const SrgbTables& Get();
  float Decode(std::uint8_t v) const { return decode_[v]; }
  /// Linear [0, 1] (clamped) -> sRGB in [0, 255] as float (not rounded).
  float Encode(float linear) const {
    const float x = linear <= 0.f ? 0.f : (linear >= 1.f ? 1.f : linear);
    return encode_[static_cast<std::size_t>(x * (kEncodeSize - 1) + 0.5f)];
  }
  static double EncodeExact(double linear);
  static double DecodeExact(double srgb01);
  static constexpr int kEncodeSize = 16384;
  /// The encode table: entry i is 255 * EncodeExact(i / (kEncodeSize - 1)).
  const float* encode_table() const { return encode_.data(); }

 private:
  SrgbTables();
  std::array<float, 256> decode_;
  std::vector<float> encode_;
};

struct SurfaceProps {
  Eigen::Vector3f base_linear{0.8f, 0.8f, 0.8f};  ///< base colour factor (linear)
  const scenes::Texture* texture = nullptr;
  float reflectance = 0.6f;  ///< laser-wavelength diffuse reflectance rho
  float metallic = 0.0f;
  float specular_f0 = 0.04f;  ///< Fresnel reflectance at normal incidence
  float alpha = 1.0f;         ///< Beckmann slope parameter (glTF roughness^2)
  float lobe_inv_a2 = 1.0f;   ///< 1 / alpha^2
  float lobe_scale = 0.01f;   ///< F0 / (4 alpha^2)
  float transmission = 0.0f;
  const float* rho_table = nullptr;  ///< EffectiveReflectance sampled for LookupReflectance
  std::int32_t rho_offset = 0;       ///< the same table's offset in SurfaceTable::rho_tables()
  std::int32_t element = -1;
  std::uint8_t element_class = 0;
};

/// Effective backscatter reflectance, in the units of a Lambertian target's rho*cos(a) (the
/// received energy is proportional to it): rho (1 - metallic) cos(a) plus the Cook-Torrance
/// specular lobe for a monostatic sensor, where the half vector is the beam itself:
///   pi f_s cos(a) = F0 D(a) G / (4 cos(a)),  D = exp(-tan^2 a / alpha^2) / (pi alpha^2 cos^4 a),
/// i.e. F0 exp(-tan^2 a / alpha^2) G / (4 alpha^2 cos^5 a), with Smith's G1 for Beckmann squared
/// (Walter et al. 2007, "Microfacet models for refraction", eqs. 20, 25, 27). Clamped to [0, 1].
/// `cos_a` in (0, 1].
inline float EffectiveReflectance(const SurfaceProps& s, float cos_a) {
  const float c2 = cos_a * cos_a;
  const float tan2 = (1.0f - c2) / c2;
  float rho = s.reflectance * (1.0f - s.metallic) * cos_a;
  const float x = tan2 * s.lobe_inv_a2;
  if (x < 40.0f) {
    float g1 = 1.0f;
    if (tan2 > 0.0f) {
      const float a = 1.0f / (s.alpha * std::sqrt(tan2));
      if (a < 1.6f) g1 = (3.535f * a + 2.181f * a * a) / (1.0f + 2.276f * a + 2.577f * a * a);
    }
    rho += s.lobe_scale * std::exp(-x) * g1 * g1 / (c2 * c2 * cos_a);
  }
  return std::min(rho, 1.0f);
}

/// Samples of EffectiveReflectance at s = sqrt(1 - cos a) = 0, 1/N, ..., 1 (s is nearly
/// proportional to the angle near normal incidence, where specular lobes are narrow).
inline constexpr int kRhoTableSize = 1024;

/// EffectiveReflectance by linear interpolation in the part's table (a few ns instead of an
/// exp, a sqrt and a division per pulse).
inline float LookupReflectance(const SurfaceProps& s, float cos_a) {
  const float x = std::sqrt(std::max(0.0f, 1.0f - cos_a)) * static_cast<float>(kRhoTableSize);
  const int i = std::min(static_cast<int>(x), kRhoTableSize - 1);
  const float f = x - static_cast<float>(i);
  return s.rho_table[i] + f * (s.rho_table[i + 1] - s.rho_table[i]);
}

class SurfaceTable {
 public:
  explicit SurfaceTable(const EmbreeWorld& world);
  const SurfaceProps& part(std::int32_t p) const { return parts_[static_cast<std::size_t>(p)]; }
  std::size_t size() const { return parts_.size(); }  ///< the world's parts when it was made
  /// Linear RGB of the surface at a hit: base colour x texture (bilinear, wrap per texture).
  Eigen::Vector3f Albedo(const EmbreeWorld& world, const RayHit& hit) const {
    const SurfaceProps& s = part(hit.part);
    return s.texture ? Textured(world, hit, s) : s.base_linear;
  }

  /// All reflectance tables, back to back (kRhoTableSize + 1 floats each).
  const float* rho_tables() const { return rho_tables_.data(); }

 private:
  Eigen::Vector3f Textured(const EmbreeWorld& world, const RayHit& hit,
                           const SurfaceProps& s) const;
  std::vector<SurfaceProps> parts_;
  std::vector<float> rho_tables_;  ///< one table per material (+ the default), concatenated
};

}  // namespace mopad::sim
