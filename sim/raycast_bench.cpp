#include "sim/raycast_bench.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cmath>

#include "sim/embree_world_impl.h"

namespace mopad::sim {

std::uint64_t BareRaycast(const EmbreeWorld& world, const TlsScanner& scanner,
                          const ScanRequest& request, std::vector<float>& distances) {
  const TlsParams& p = scanner.params();
  const std::uint32_t rows = scanner.rows(), cols = scanner.columns();
  distances.resize(static_cast<std::size_t>(rows) * cols);
  const double step = DegToRad(p.step_deg);
  const double vstep = DegToRad(p.vertical_step_deg > 0 ? p.vertical_step_deg : p.step_deg);
  std::vector<float> saz(cols), caz(cols), sel(rows), cel(rows);
  for (std::uint32_t c = 0; c < cols; ++c) {
    saz[c] = static_cast<float>(std::sin(DegToRad(p.azimuth_min_deg) + c * step));
    caz[c] = static_cast<float>(std::cos(DegToRad(p.azimuth_min_deg) + c * step));
  }
  for (std::uint32_t r = 0; r < rows; ++r) {
    sel[r] = static_cast<float>(std::sin(DegToRad(p.elevation_max_deg) - r * vstep));
    cel[r] = static_cast<float>(std::cos(DegToRad(p.elevation_max_deg) - r * vstep));
  }
  const Pose3 X_WS = request.X_WB * scanner.X_BS();
  const Eigen::Matrix3f R = X_WS.linear().cast<float>();
  const Eigen::Vector3f o = X_WS.translation().cast<float>();
  const RTCScene top = world.impl().top;
  const std::uint32_t per_block =
      std::max<std::uint32_t>(1, 8192 / std::max<std::uint32_t>(rows, 1));
  const std::uint32_t blocks = (cols + per_block - 1) / per_block;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, blocks, 1), std::uint64_t{0},
      [&](const tbb::blocked_range<std::uint32_t>& range, std::uint64_t hits) {
        RTCIntersectContext ctx;
        InitCoherentContext(&ctx);
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        for (std::uint32_t b = range.begin(); b != range.end(); ++b) {
          const std::uint32_t c1 = std::min(cols, (b + 1) * per_block);
          for (std::uint32_t c = b * per_block; c < c1; ++c) {
            for (std::uint32_t r0 = 0; r0 < rows; r0 += 16) {
              const int n = static_cast<int>(std::min<std::uint32_t>(16, rows - r0));
              for (int j = 0; j < 16; ++j) {
                const std::uint32_t r = r0 + static_cast<std::uint32_t>(std::min(j, n - 1));
                const Eigen::Vector3f d =
                    R * Eigen::Vector3f(cel[r] * caz[c], cel[r] * saz[c], sel[r]);
                valid[j] = j < n ? -1 : 0;
                rh.ray.org_x[j] = o.x();
                rh.ray.org_y[j] = o.y();
                rh.ray.org_z[j] = o.z();
                rh.ray.dir_x[j] = d.x();
                rh.ray.dir_y[j] = d.y();
                rh.ray.dir_z[j] = d.z();
                rh.ray.tnear[j] = 0.0f;
                rh.ray.tfar[j] = std::numeric_limits<float>::infinity();
                rh.ray.time[j] = 0.0f;
                rh.ray.mask[j] = 0xFFFFFFFFu;
                rh.ray.id[j] = 0;
                rh.ray.flags[j] = 0;
                rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
              }
              rtcIntersect16(valid, top, &ctx, &rh);
              float* out = distances.data() + static_cast<std::size_t>(c) * rows + r0;
              for (int j = 0; j < n; ++j) {
                const bool hit = rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
                out[j] = hit ? rh.ray.tfar[j] : std::numeric_limits<float>::infinity();
                hits += hit;
              }
            }
          }
        }
        return hits;
      },
      [](std::uint64_t a, std::uint64_t b) { return a + b; });
}

}  // namespace mopad::sim
