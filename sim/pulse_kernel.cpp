#include "sim/pulse_kernel.h"

#include <immintrin.h>

#include <atomic>
#include <cmath>

#include "common/rng.h"

namespace mopad::sim {

namespace {

constexpr int kEncodeSize = 16384;  // SrgbTables::kEncodeSize
constexpr int kRhoTable = 1024;     // kRhoTableSize

// The kernel body: straight loops over the lanes on local copies (no aliasing for the
// vectoriser to fear), bitwise logic and selects instead of branches, so that GCC vectorises
// each loop for the target of the function it is inlined into.
inline __attribute__((always_inline)) void KernelBody(const PulseKernelConstants& k,
                                                      PulseLanes& L) {
  constexpr int N = PulseLanes::kLanes;
  const float* __restrict zig_r = k.zig_r;
  const float* __restrict zig_x = k.zig_x;
  const float* __restrict enc = k.srgb_encode;
  const float* __restrict rho_tables = k.rho_tables;
  const std::uint64_t key = k.noise_key;
  const float sure_detect = k.sure_detect, min_refl = k.min_reflectance,
              att = k.intensity_attenuation;
  const float rref = k.reflectance_ref;
  const float min_cos = k.min_cos, precision = k.precision, bias = k.bias,
              inoise = k.intensity_noise;
  const float ambient = k.ambient, top = k.top_light, cnoise = k.colour_noise;
  const std::int32_t dropouts = k.dropouts ? 1 : 0;
  const std::int32_t have_sure = sure_detect > 0.0f ? 1 : 0;

  alignas(64) std::uint64_t pulse[N], d1[N], d2[N];
  alignas(64) float t[N], cos_a[N], rho[N], nz[N], alb[3][N];
  alignas(64) float n_range[N], range[N], inten[N];
  alignas(64) std::int32_t status[N], active[N], rho_off[N];
  alignas(64) std::uint8_t rgb[3][N];
  for (int j = 0; j < N; ++j) {
    pulse[j] = L.pulse[j];
    t[j] = L.t[j];
    cos_a[j] = L.cos_a[j];
    rho_off[j] = L.rho_offset[j];
    nz[j] = L.facing_nz[j];
    alb[0][j] = L.albedo[0][j];
    alb[1][j] = L.albedo[1][j];
    alb[2][j] = L.albedo[2][j];
    active[j] = L.active[j];
  }
  for (int j = 0; j < N; ++j) {
    // LookupReflectance: linear interpolation in the surface's table at sqrt(1 - cos a).
    const float om = 1.0f - cos_a[j];
    const float x = __builtin_sqrtf(om > 0.0f ? om : 0.0f) * static_cast<float>(kRhoTable);
    std::int32_t i = static_cast<std::int32_t>(x);
    i = i < kRhoTable - 1 ? i : kRhoTable - 1;
    const float f = x - static_cast<float>(i);
    const float a = rho_tables[rho_off[j] + i], b = rho_tables[rho_off[j] + i + 1];
    rho[j] = a + f * (b - a);
  }
  for (int j = 0; j < N; ++j) {
    // PulseStream(noise_key, pulse): draw c is Mix64(key + (64 pulse + c) * golden).
    const std::uint64_t base = key + (pulse[j] * 64) * 0x9E3779B97F4A7C15ull;
    d1[j] = Mix64(base);
    d2[j] = Mix64(base + 0x9E3779B97F4A7C15ull);
  }
  for (int j = 0; j < N; ++j) {
    // Dropout: the same test as BeamModel::Finish, in float; lanes needing the detection
    // logistic go to the general path.
    const float u_drop =
        (static_cast<float>(static_cast<std::int32_t>(d1[j] & 0xFFFFFF)) + 0.5f) * 0x1.0p-24f;
    const float rm = rho[j] < rref ? rho[j] : rref;
    const std::int32_t sure =
        static_cast<std::int32_t>(rm >= t[j] * t[j] * sure_detect) & have_sure;
    const float p = rho[j] < min_refl ? rho[j] / min_refl : 1.0f;
    const std::int32_t dropped = dropouts & static_cast<std::int32_t>(!(u_drop < p));
    // Ziggurat fast test on d2 (Ziggurat::Normal).
    const std::int32_t i = static_cast<std::int32_t>(d2[j] & 0x7F);
    const float u = static_cast<float>(static_cast<std::int32_t>(d2[j] >> 40)) * 0x1.0p-23f - 1.0f;
    const float au = u < 0.0f ? -u : u;
    const std::int32_t zig_ok = static_cast<std::int32_t>(au < zig_r[i]);
    n_range[j] = u * zig_x[i];
    const std::int32_t fade_ok = static_cast<std::int32_t>(att * t[j] < 0.5f);
    const std::int32_t general =
        (dropouts & (1 - sure)) | ((1 - dropped) & (1 - (zig_ok & fade_ok))) | (1 - active[j]);
    status[j] = general ? kNeedsGeneral : (dropped ? kDropped : kReturned);
  }
  for (int j = 0; j < N; ++j) {
    const float ca = cos_a[j] > min_cos ? cos_a[j] : min_cos;
    const float r = t[j] + (precision / ca) * n_range[j] + bias;
    range[j] = r > 1e-6f ? r : 1e-6f;
    const float x = att * t[j];
    const float fade =
        1.0f - x * (1.0f - 0.5f * x * (1.0f - (1.0f / 3.0f) * x * (1.0f - 0.25f * x)));
    const std::int32_t ib = static_cast<std::int32_t>((d1[j] >> 24) & 0xFFFF);
    const float isum =
        static_cast<float>((ib & 15) + ((ib >> 4) & 15) + ((ib >> 8) & 15) + ((ib >> 12) & 15));
    const float v = rho[j] * fade + inoise * ((isum - 30.0f) * (1.0f / 9.2195445f));
    inten[j] = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
  }
  alignas(64) float light[N];
  for (int j = 0; j < N; ++j) light[j] = ambient + top * (nz[j] > 0.0f ? nz[j] : 0.0f);
  for (int ch = 0; ch < 3; ++ch) {
    alignas(64) std::int32_t idx[N];
    alignas(64) float srgb[N];
    for (int j = 0; j < N; ++j) {
      float lin = alb[ch][j] * light[j];
      lin = lin > 0.0f ? lin : 0.0f;
      lin = lin < 1.0f ? lin : 1.0f;
      idx[j] = static_cast<std::int32_t>(lin * static_cast<float>(kEncodeSize - 1) + 0.5f) &
               (kEncodeSize - 1);
    }
    for (int j = 0; j < N; ++j) srgb[j] = enc[idx[j]];
    for (int j = 0; j < N; ++j) {
      const std::int32_t bits = static_cast<std::int32_t>((d1[j] >> (40 + 8 * ch)) & 0xFF);
      const float sum = static_cast<float>((bits & 15) + ((bits >> 4) & 15));
      float v = srgb[j] + cnoise * ((sum - 15.0f) * (1.0f / 6.5192024f));
      v = v > 0.0f ? v : 0.0f;
      v = v < 255.0f ? v : 255.0f;
      rgb[ch][j] = static_cast<std::uint8_t>(static_cast<std::int32_t>(v + 0.5f));
    }
  }
  for (int j = 0; j < N; ++j) {
    L.rho[j] = rho[j];
    L.status[j] = status[j];
    L.range[j] = range[j];
    L.intensity[j] = inten[j];
    L.rgb[0][j] = rgb[0][j];
    L.rgb[1][j] = rgb[1][j];
    L.rgb[2][j] = rgb[2][j];
  }
}

void KernelBaseline(const PulseKernelConstants& k, PulseLanes& L) { KernelBody(k, L); }

// GCC 12 warns about the deliberately undefined pass-through operand inside its own AVX-512
// shift intrinsics (avx512fintrin.h, _mm512_undefined_epi32); not our code.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// The same computation with AVX-512 intrinsics, operation for operation (GCC's
// auto-vectoriser turned the fixed 16-lane loops into long scalar sequences). Every float
// operation is the IEEE-rounded counterpart of the scalar expression above, in the same order.
#define MOPAD_AVX512 __attribute__((target("avx512f,avx512dq,avx512bw,avx512vl")))

MOPAD_AVX512 inline __m512i Mix64x8(__m512i z) {
  z = _mm512_add_epi64(z, _mm512_set1_epi64(static_cast<long long>(0x9E3779B97F4A7C15ull)));
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)),
                         _mm512_set1_epi64(static_cast<long long>(0xBF58476D1CE4E5B9ull)));
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)),
                         _mm512_set1_epi64(static_cast<long long>(0x94D049BB133111EBull)));
  return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

// 16 x 64-bit (two halves) -> the 32-bit field (v >> shift) & mask of each, as 16 x int32.
MOPAD_AVX512 inline __m512i Field(__m512i lo, __m512i hi, unsigned shift, long long mask) {
  const __m512i m = _mm512_set1_epi64(mask);
  const __m256i a = _mm512_cvtepi64_epi32(_mm512_and_si512(_mm512_srli_epi64(lo, shift), m));
  const __m256i b = _mm512_cvtepi64_epi32(_mm512_and_si512(_mm512_srli_epi64(hi, shift), m));
  return _mm512_inserti64x4(_mm512_castsi256_si512(a), b, 1);
}

MOPAD_AVX512 void KernelAvx512(const PulseKernelConstants& k, PulseLanes& L) {
  const __m512i golden = _mm512_set1_epi64(static_cast<long long>(0x9E3779B97F4A7C15ull));
  const __m512i key = _mm512_set1_epi64(static_cast<long long>(k.noise_key));
  __m512i d1[2], d2[2];
  for (int h = 0; h < 2; ++h) {
    const __m512i pulse = _mm512_loadu_si512(L.pulse + 8 * h);
    const __m512i base =
        _mm512_add_epi64(key, _mm512_mullo_epi64(_mm512_slli_epi64(pulse, 6), golden));
    d1[h] = Mix64x8(base);
    d2[h] = Mix64x8(_mm512_add_epi64(base, golden));
  }
  const __m512 t = _mm512_loadu_ps(L.t), cos_a = _mm512_loadu_ps(L.cos_a);
  const __m512 one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps(), half = _mm512_set1_ps(0.5f);
  // Reflectance table lookup.
  __m512 rho;
  {
    const __m512 om = _mm512_sub_ps(one, cos_a);
    const __m512 x = _mm512_mul_ps(
        _mm512_sqrt_ps(_mm512_mask_blend_ps(_mm512_cmp_ps_mask(om, zero, _CMP_GT_OQ), zero, om)),
        _mm512_set1_ps(static_cast<float>(kRhoTable)));
    const __m512i i = _mm512_min_epi32(_mm512_cvttps_epi32(x), _mm512_set1_epi32(kRhoTable - 1));
    const __m512 f = _mm512_sub_ps(x, _mm512_cvtepi32_ps(i));
    const __m512i at = _mm512_add_epi32(_mm512_loadu_si512(L.rho_offset), i);
    const __m512 a = _mm512_i32gather_ps(at, k.rho_tables, 4);
    const __m512 b =
        _mm512_i32gather_ps(_mm512_add_epi32(at, _mm512_set1_epi32(1)), k.rho_tables, 4);
    rho = _mm512_add_ps(a, _mm512_mul_ps(f, _mm512_sub_ps(b, a)));
    _mm512_storeu_ps(L.rho, rho);
  }
  // Dropout.
  const __m512 u_drop =
      _mm512_mul_ps(_mm512_add_ps(_mm512_cvtepi32_ps(Field(d1[0], d1[1], 0, 0xFFFFFF)), half),
                    _mm512_set1_ps(0x1.0p-24f));
  const __m512 rref = _mm512_set1_ps(k.reflectance_ref);
  const __m512 rm = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(rho, rref, _CMP_LT_OQ), rref, rho);
  __mmask16 sure = _mm512_cmp_ps_mask(
      rm, _mm512_mul_ps(_mm512_mul_ps(t, t), _mm512_set1_ps(k.sure_detect)), _CMP_GE_OQ);
  if (!(k.sure_detect > 0.0f)) sure = 0;
  const __m512 min_refl = _mm512_set1_ps(k.min_reflectance);
  const __m512 p = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(rho, min_refl, _CMP_LT_OQ), one,
                                        _mm512_div_ps(rho, min_refl));
  __mmask16 dropped = _mm512_cmp_ps_mask(u_drop, p, _CMP_NLT_UQ);  // !(u_drop < p)
  if (!k.dropouts) dropped = 0;
  // Ziggurat fast test.
  const __m512i zi = Field(d2[0], d2[1], 0, 0x7F);
  const __m512 u =
      _mm512_sub_ps(_mm512_mul_ps(_mm512_cvtepi32_ps(Field(d2[0], d2[1], 40, 0xFFFFFF)),
                                  _mm512_set1_ps(0x1.0p-23f)),
                    one);
  const __m512 au =
      _mm512_mask_blend_ps(_mm512_cmp_ps_mask(u, zero, _CMP_LT_OQ), u, _mm512_sub_ps(zero, u));
  const __m512 zr = _mm512_i32gather_ps(zi, k.zig_r, 4);
  const __m512 zx = _mm512_i32gather_ps(zi, k.zig_x, 4);
  const __mmask16 zig_ok = _mm512_cmp_ps_mask(au, zr, _CMP_LT_OQ);
  const __m512 n_range = _mm512_mul_ps(u, zx);
  const __m512 att = _mm512_set1_ps(k.intensity_attenuation);
  const __m512 x = _mm512_mul_ps(att, t);
  const __mmask16 fade_ok = _mm512_cmp_ps_mask(x, half, _CMP_LT_OQ);
  __mmask16 active =
      _mm512_cmp_epi32_mask(_mm512_loadu_si512(L.active), _mm512_setzero_si512(), _MM_CMPINT_NE);
  const __mmask16 general =
      static_cast<__mmask16>((k.dropouts ? ~sure : 0) | (~dropped & ~(zig_ok & fade_ok)) | ~active);
  __m512i status =
      _mm512_mask_blend_epi32(dropped, _mm512_set1_epi32(kReturned), _mm512_set1_epi32(kDropped));
  status = _mm512_mask_blend_epi32(general, status, _mm512_set1_epi32(kNeedsGeneral));
  _mm512_storeu_si512(L.status, status);
  // Range.
  const __m512 min_cos = _mm512_set1_ps(k.min_cos);
  const __m512 ca =
      _mm512_mask_blend_ps(_mm512_cmp_ps_mask(cos_a, min_cos, _CMP_GT_OQ), min_cos, cos_a);
  __m512 r = _mm512_add_ps(
      _mm512_add_ps(t, _mm512_mul_ps(_mm512_div_ps(_mm512_set1_ps(k.precision), ca), n_range)),
      _mm512_set1_ps(k.bias));
  const __m512 tiny = _mm512_set1_ps(1e-6f);
  r = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(r, tiny, _CMP_GT_OQ), tiny, r);
  _mm512_storeu_ps(L.range, r);
  // Intensity.
  const __m512 third = _mm512_set1_ps(1.0f / 3.0f), quarter = _mm512_set1_ps(0.25f);
  const __m512 f3 =
      _mm512_mul_ps(_mm512_mul_ps(third, x), _mm512_sub_ps(one, _mm512_mul_ps(quarter, x)));
  const __m512 f2 = _mm512_mul_ps(_mm512_mul_ps(half, x), _mm512_sub_ps(one, f3));
  const __m512 fade = _mm512_sub_ps(one, _mm512_mul_ps(x, _mm512_sub_ps(one, f2)));
  const __m512i ib = Field(d1[0], d1[1], 24, 0xFFFF);
  const __m512i m15 = _mm512_set1_epi32(15);
  const __m512i isum_i = _mm512_add_epi32(
      _mm512_add_epi32(_mm512_add_epi32(_mm512_and_si512(ib, m15),
                                        _mm512_and_si512(_mm512_srli_epi32(ib, 4), m15)),
                       _mm512_and_si512(_mm512_srli_epi32(ib, 8), m15)),
      _mm512_and_si512(_mm512_srli_epi32(ib, 12), m15));
  const __m512 n_int =
      _mm512_mul_ps(_mm512_sub_ps(_mm512_cvtepi32_ps(isum_i), _mm512_set1_ps(30.0f)),
                    _mm512_set1_ps(1.0f / 9.2195445f));
  __m512 inten = _mm512_add_ps(_mm512_mul_ps(rho, fade),
                               _mm512_mul_ps(_mm512_set1_ps(k.intensity_noise), n_int));
  inten = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(inten, zero, _CMP_LT_OQ), inten, zero);
  inten = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(inten, one, _CMP_GT_OQ), inten, one);
  _mm512_storeu_ps(L.intensity, inten);
  // Colour.
  const __m512 nz = _mm512_loadu_ps(L.facing_nz);
  const __m512 nz_pos = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(nz, zero, _CMP_GT_OQ), zero, nz);
  const __m512 light =
      _mm512_add_ps(_mm512_set1_ps(k.ambient), _mm512_mul_ps(_mm512_set1_ps(k.top_light), nz_pos));
  const __m512 c255 = _mm512_set1_ps(255.0f);
  for (int ch = 0; ch < 3; ++ch) {
    __m512 lin = _mm512_mul_ps(_mm512_loadu_ps(L.albedo[ch]), light);
    lin = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(lin, zero, _CMP_GT_OQ), zero, lin);
    lin = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(lin, one, _CMP_LT_OQ), one, lin);
    const __m512i idx = _mm512_and_si512(
        _mm512_cvttps_epi32(_mm512_add_ps(
            _mm512_mul_ps(lin, _mm512_set1_ps(static_cast<float>(kEncodeSize - 1))), half)),
        _mm512_set1_epi32(kEncodeSize - 1));
    const __m512 srgb = _mm512_i32gather_ps(idx, k.srgb_encode, 4);
    const __m512i bits = Field(d1[0], d1[1], 40 + 8 * static_cast<unsigned>(ch), 0xFF);
    const __m512i sum_i = _mm512_add_epi32(_mm512_and_si512(bits, m15),
                                           _mm512_and_si512(_mm512_srli_epi32(bits, 4), m15));
    const __m512 cn = _mm512_mul_ps(_mm512_sub_ps(_mm512_cvtepi32_ps(sum_i), _mm512_set1_ps(15.0f)),
                                    _mm512_set1_ps(1.0f / 6.5192024f));
    __m512 v = _mm512_add_ps(srgb, _mm512_mul_ps(_mm512_set1_ps(k.colour_noise), cn));
    v = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(v, zero, _CMP_GT_OQ), zero, v);
    v = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(v, c255, _CMP_LT_OQ), c255, v);
    const __m128i bytes = _mm512_cvtepi32_epi8(_mm512_cvttps_epi32(_mm512_add_ps(v, half)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(L.rgb[ch]), bytes);
  }
}

MOPAD_AVX512 std::uint32_t ResolveAvx512(const ResolveTables& T, const HitLanes& H, int n,
                                         PulseLanes& L, std::int32_t* part_out,
                                         std::uint32_t* too_close) {
  const __m512i zero_i = _mm512_setzero_si512();
  const __m512i invalid = _mm512_set1_epi32(-1);
  *too_close = 0;
  __mmask16 m = static_cast<__mmask16>(n >= 16 ? 0xFFFFu : ((1u << n) - 1u));
  const __m512i geom = _mm512_loadu_si512(H.geom);
  const __m512i inst = _mm512_loadu_si512(H.inst);
  m = static_cast<__mmask16>(m & _mm512_cmpneq_epi32_mask(geom, invalid) &
                             _mm512_cmpeq_epi32_mask(inst, invalid));
  if (!m) return 0;
  // Lanes of a packet mostly hit one part (often one triangle): then the per-part terms are
  // broadcast instead of gathered (the same values either way).
  const int j0 = __builtin_ctz(static_cast<unsigned>(m));
  const std::uint32_t g0 = H.geom[j0];
  const bool one_geom =
      static_cast<__mmask16>(
          _mm512_cmpeq_epi32_mask(geom, _mm512_set1_epi32(static_cast<int>(g0))) & m) == m;
  __m512i part, first, rho_off;
  __m512 base[3];
  const __m512 zero = _mm512_setzero_ps();
  if (one_geom) {
    const std::int32_t p0 = T.geom_to_part[g0];
    if (!T.part_simple[p0]) return 0;
    part = _mm512_set1_epi32(p0);
    first = _mm512_set1_epi32(static_cast<int>(T.first_triangle[p0]));
    rho_off = _mm512_set1_epi32(T.part_rho_offset[p0]);
    for (int ch = 0; ch < 3; ++ch)
      base[ch] = _mm512_set1_ps(
          T.part_base[3 * static_cast<std::size_t>(p0) + static_cast<std::size_t>(ch)]);
  } else {
    part = _mm512_mask_i32gather_epi32(zero_i, m, geom, T.geom_to_part, 4);
    const __m512i simple = _mm512_mask_i32gather_epi32(zero_i, m, part, T.part_simple, 4);
    m = static_cast<__mmask16>(m & _mm512_cmpneq_epi32_mask(simple, zero_i));
    if (!m) return 0;
    first = _mm512_mask_i32gather_epi32(zero_i, m, part, T.first_triangle, 4);
    rho_off = _mm512_mask_i32gather_epi32(zero_i, m, part, T.part_rho_offset, 4);
    const __m512i p3 = _mm512_add_epi32(_mm512_add_epi32(part, part), part);
    for (int ch = 0; ch < 3; ++ch)
      base[ch] = _mm512_mask_i32gather_ps(zero, m, p3, T.part_base + ch, 4);
  }
  const __m512 t = _mm512_loadu_ps(H.tfar);
  const __mmask16 close =
      static_cast<__mmask16>(m & _mm512_cmp_ps_mask(t, _mm512_set1_ps(T.range_min), _CMP_LT_OQ));
  const __mmask16 act = static_cast<__mmask16>(m & ~close);
  _mm512_mask_storeu_epi32(part_out, m, part);
  _mm512_mask_storeu_ps(L.t, m, t);
  *too_close = close;
  if (act) {
    const __m512i prim = _mm512_loadu_si512(H.prim);
    __m512 nx, ny, nz;
    const int a0 = __builtin_ctz(static_cast<unsigned>(act));
    if (one_geom &&
        static_cast<__mmask16>(
            _mm512_cmpeq_epi32_mask(prim, _mm512_set1_epi32(static_cast<int>(H.prim[a0]))) & act) ==
            act) {
      const float* nrm =
          T.normals + 3 * static_cast<std::size_t>(static_cast<std::uint32_t>(_mm_cvtsi128_si32(
                                                       _mm512_castsi512_si128(first))) +
                                                   H.prim[a0]);
      nx = _mm512_set1_ps(nrm[0]);
      ny = _mm512_set1_ps(nrm[1]);
      nz = _mm512_set1_ps(nrm[2]);
    } else {
      const __m512i tri = _mm512_add_epi32(first, prim);
      const __m512i i3 = _mm512_add_epi32(_mm512_add_epi32(tri, tri), tri);
      nx = _mm512_mask_i32gather_ps(zero, act, i3, T.normals, 4);
      ny = _mm512_mask_i32gather_ps(zero, act, i3, T.normals + 1, 4);
      nz = _mm512_mask_i32gather_ps(zero, act, i3, T.normals + 2, 4);
    }
    const __m512 dot = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(nx, _mm512_loadu_ps(H.dir_x)),
                                                   _mm512_mul_ps(ny, _mm512_loadu_ps(H.dir_y))),
                                     _mm512_mul_ps(nz, _mm512_loadu_ps(H.dir_z)));
    const __m512 sign = _mm512_castsi512_ps(_mm512_set1_epi32(static_cast<int>(0x80000000u)));
    __m512 ca = _mm512_andnot_ps(sign, dot);
    const __m512 lo = _mm512_set1_ps(1e-4f), hi = _mm512_set1_ps(1.0f);
    ca = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(ca, lo, _CMP_LT_OQ), ca, lo);
    ca = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(hi, ca, _CMP_LT_OQ), ca, hi);
    _mm512_mask_storeu_ps(L.cos_a, act, ca);
    const __m512 fnz = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(dot, zero, _CMP_GT_OQ), nz,
                                            _mm512_xor_ps(nz, sign));
    _mm512_mask_storeu_ps(L.facing_nz, act, fnz);
    _mm512_mask_storeu_epi32(L.rho_offset, act, rho_off);
    for (int ch = 0; ch < 3; ++ch) _mm512_mask_storeu_ps(L.albedo[ch], act, base[ch]);
    _mm512_mask_storeu_epi32(L.active, act, _mm512_set1_epi32(1));
  }
  return m;
}

#pragma GCC diagnostic pop

bool CpuHasAvx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
}

std::atomic<bool> g_force_baseline{false};

}  // namespace

void RunPulseKernel(const PulseKernelConstants& k, PulseLanes& lanes) {
  static const bool avx512 = CpuHasAvx512();
  if (avx512 && !g_force_baseline.load(std::memory_order_relaxed)) {
    KernelAvx512(k, lanes);
  } else {
    KernelBaseline(k, lanes);
  }
}

std::uint32_t ResolveStaticLanes(const ResolveTables& t, const HitLanes& h, int n,
                                 PulseLanes& lanes, std::int32_t* part, std::uint32_t* too_close) {
  static const bool avx512 = CpuHasAvx512();
  *too_close = 0;
  if (!avx512 || g_force_baseline.load(std::memory_order_relaxed)) return 0;
  return ResolveAvx512(t, h, n, lanes, part, too_close);
}

void ForceBaselinePulseKernel(bool force) { g_force_baseline.store(force); }

bool PulseKernelUsesAvx512() {
  static const bool avx512 = CpuHasAvx512();
  return avx512 && !g_force_baseline.load();
}

}  // namespace mopad::sim
