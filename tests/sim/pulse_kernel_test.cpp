// The vectorised single-ray pulse kernel must give the same bits on every CPU: its AVX-512 and
// baseline builds are compared lane by lane on random inputs.
#include "sim/pulse_kernel.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "common/rng.h"
#include "sim/scan_model.h"
#include "sim/surface_model.h"

namespace mopad::sim {
namespace {

TEST(PulseKernel, Avx512AndBaselineBuildsGiveTheSameBits) {
  if (!PulseKernelUsesAvx512())
    GTEST_SKIP() << "no AVX-512 on this CPU: only the baseline build runs";
  std::vector<float> tables(3 * (kRhoTableSize + 1));
  for (std::size_t i = 0; i < tables.size(); ++i)
    tables[i] = static_cast<float>((i * 7919) % 1000) / 1000.0f;
  PulseKernelConstants k;
  k.noise_key = 123;
  k.precision = 0.003f;
  k.bias = 0.004f;
  k.min_cos = 0.087f;
  k.min_reflectance = 0.03f;
  k.sure_detect = 0.00116f;
  k.reflectance_ref = 0.2f;
  k.intensity_attenuation = 0.01f;
  k.intensity_noise = 0.01f;
  k.colour_noise = 2.0f;
  k.ambient = 0.6f;
  k.top_light = 0.4f;
  k.zig_r = Ziggurat::Get().rf();
  k.zig_x = Ziggurat::Get().xf();
  k.srgb_encode = SrgbTables::Get().encode_table();
  k.rho_tables = tables.data();
  CounterRng rng(5);
  std::size_t compared = 0;
  for (int it = 0; it < 40000; ++it) {
    PulseLanes a;
    for (int j = 0; j < PulseLanes::kLanes; ++j) {
      a.pulse[j] = rng.NextU64() >> 20;
      a.t[j] = static_cast<float>(rng.Uniform(0.5, 40));
      a.cos_a[j] = static_cast<float>(rng.Uniform(1e-4, 1));
      a.rho_offset[j] = static_cast<std::int32_t>(rng.Below(3) * (kRhoTableSize + 1));
      a.facing_nz[j] = static_cast<float>(rng.Uniform(-1, 1));
      for (auto& c : a.albedo) c[j] = static_cast<float>(rng.Uniform(-0.1, 1.2));
      a.active[j] = rng.Uniform() < 0.9;
    }
    PulseLanes b = a;
    ForceBaselinePulseKernel(false);
    RunPulseKernel(k, a);
    ForceBaselinePulseKernel(true);
    RunPulseKernel(k, b);
    ForceBaselinePulseKernel(false);
    for (int j = 0; j < PulseLanes::kLanes; ++j) {
      ASSERT_EQ(a.status[j], b.status[j]);
      ASSERT_EQ(std::memcmp(&a.rho[j], &b.rho[j], 4), 0);
      if (a.status[j] == kNeedsGeneral) continue;
      ++compared;
      ASSERT_EQ(std::memcmp(&a.range[j], &b.range[j], 4), 0) << a.range[j] << " vs " << b.range[j];
      ASSERT_EQ(std::memcmp(&a.intensity[j], &b.intensity[j], 4), 0);
      for (int c = 0; c < 3; ++c) ASSERT_EQ(a.rgb[c][j], b.rgb[c][j]);
    }
  }
  EXPECT_GT(compared, 100000u);
}

}  // namespace
}  // namespace mopad::sim
