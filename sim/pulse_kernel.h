#pragma once
// Internal to sim/: the per-pulse sensor model of the single-ray TLS fast path, for 16 pulses
// at a time in structure-of-arrays form, so that the compiler vectorises it. Built twice from
// one source: for the baseline x86-64 target and for AVX-512 (chosen at run time). The file is
// compiled with -ffp-contract=off and uses only IEEE basic operations and integer hashing, so
// both builds give the same bits (a test checks it).
//
// It is the same model as BeamModel::Finish + BeamModel::ColourOf for a pulse whose single ray
// hit an opaque static surface: draws d1 = stream(noise_key, pulse)[0] (dropout, intensity and
// colour noise bits) and d2 = [1] (range normal, ziggurat fast test). Lanes it cannot finish
// exactly (ziggurat wedge/tail, the detection logistic, long-range fade) come back with
// kNeedsGeneral and go through the general path, which draws the same d1, d2 first.

#include <cstdint>

namespace mopad::sim {

struct PulseLanes {
  static constexpr int kLanes = 16;
  // inputs (lanes with active = 0 are ignored)
  std::uint64_t pulse[kLanes];
  float t[kLanes];                  ///< m, true range
  float cos_a[kLanes];              ///< incidence cosine, (0, 1]
  std::int32_t rho_offset[kLanes];  ///< the surface's table in PulseKernelConstants::rho_tables
  float facing_nz[kLanes];          ///< normal's z, turned towards the scanner
  float albedo[3][kLanes];          ///< linear RGB
  std::int32_t active[kLanes];
  // outputs
  float rho[kLanes];  ///< effective reflectance (LookupReflectance)
  float range[kLanes];
  float intensity[kLanes];
  std::uint8_t rgb[3][kLanes];
  std::int32_t status[kLanes];  ///< kReturned, kDropped or kNeedsGeneral
};

enum PulseStatus : std::int32_t { kReturned = 0, kDropped = 1, kNeedsGeneral = 2 };

struct PulseKernelConstants {
  std::uint64_t noise_key = 0;
  float bias = 0, precision = 0, min_cos = 0.087f;
  bool dropouts = true;
  float min_reflectance = 0, sure_detect = 0;  ///< sure_detect 0: always general
  float reflectance_ref = 0.2f;  ///< detection is sure when min(rho, this) >= t^2 sure_detect
  float intensity_attenuation = 0, intensity_noise = 0;
  float ambient = 1, top_light = 0, colour_noise = 0;
  const float* zig_r = nullptr;        ///< Ziggurat::rf()
  const float* zig_x = nullptr;        ///< Ziggurat::xf()
  const float* srgb_encode = nullptr;  ///< SrgbTables::encode_table()
  const float* rho_tables = nullptr;   ///< SurfaceTable::rho_tables()
};

/// Flat per-scan tables for resolving Embree hits inside the 16-wide path (ResolveStaticLanes).
struct ResolveTables {
  const std::int32_t* geom_to_part = nullptr;     ///< top-level geomID -> part
  const float* normals = nullptr;                 ///< unit triangle normals, xyz per triangle
  const std::uint32_t* first_triangle = nullptr;  ///< per part
  const std::int32_t* part_simple = nullptr;      ///< per part: 1 = opaque and untextured
  const std::int32_t* part_rho_offset = nullptr;  ///< per part: SurfaceProps::rho_offset
  const float* part_base = nullptr;               ///< per part: base_linear rgb (3 floats)
  float range_min = 0.0f;
};

/// Embree's hit fields of one 16-wide packet (pointers into RTCRayHit16).
struct HitLanes {
  const std::uint32_t* geom;
  const std::uint32_t* inst;
  const std::uint32_t* prim;
  const float* tfar;
  const float* dir_x;
  const float* dir_y;
  const float* dir_z;
};

/// The exact counterpart of the scalar hit resolution of the single-ray path, for lanes j < n
/// that hit a static (non-instanced), opaque, untextured part: sets lanes.t, and unless
/// t < range_min (bit set in *too_close) also cos_a, rho_offset, facing_nz, albedo and
/// active = 1; part[j]. Returns the mask of lanes it handled; other lanes are untouched and go
/// through the scalar resolution. Returns 0 (handles nothing) without AVX-512.
std::uint32_t ResolveStaticLanes(const ResolveTables& t, const HitLanes& h, int n,
                                 PulseLanes& lanes, std::int32_t* part, std::uint32_t* too_close);

/// Runs the kernel on the best variant for this CPU.
void RunPulseKernel(const PulseKernelConstants& k, PulseLanes& lanes);
/// For tests: force the baseline variant (true) or restore automatic choice (false).
void ForceBaselinePulseKernel(bool force);
/// Whether the AVX-512 variant is in use.
bool PulseKernelUsesAvx512();

}  // namespace mopad::sim
