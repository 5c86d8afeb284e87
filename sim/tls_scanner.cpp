#include "sim/tls_scanner.h"

#include <tbb/concurrent_queue.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "common/rng.h"
#include "sim/daylight_internal.h"
#include "sim/embree_world_impl.h"
#include "sim/pulse_kernel.h"
#include "sim/scan_model.h"
#include "sim/surface_model.h"

namespace mopad::sim {

// ------------------------------------------------------------------ scanner

namespace {

// Everything of packet lane j but origin and direction: full range, all masks (Debian's Embree
// is built with ray masks: mask 0 hits nothing), no hit yet.
inline void ResetLane(RTCRayHit16* rh, int j) {
  rh->ray.tnear[j] = 0.0f;
  rh->ray.tfar[j] = std::numeric_limits<float>::infinity();
  rh->ray.time[j] = 0.0f;
  rh->ray.mask[j] = 0xFFFFFFFFu;
  rh->ray.id[j] = static_cast<unsigned>(j);
  rh->ray.flags[j] = 0;
  rh->hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
}

std::uint32_t CountRows(const TlsParams& p) {
  const double vstep = p.vertical_step_deg > 0 ? p.vertical_step_deg : p.step_deg;
  return static_cast<std::uint32_t>(
             std::floor((p.elevation_max_deg - p.elevation_min_deg) / vstep + 1e-6)) +
         1;
}

std::uint32_t CountColumns(const TlsParams& p) {
  if (p.azimuth_span_deg >= 360.0 - 1e-9)
    return static_cast<std::uint32_t>(std::llround(360.0 / p.step_deg));
  return static_cast<std::uint32_t>(std::floor(p.azimuth_span_deg / p.step_deg + 1e-6)) + 1;
}

Eigen::Matrix3d Rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Pose3 MountPose(const TlsParams& p) {
  Pose3 X = Pose3::Identity();
  X.translation() = Eigen::Vector3d(p.mount_xyz[0], p.mount_xyz[1], p.mount_xyz[2]);
  X.linear() =
      Rpy(DegToRad(p.mount_rpy_deg[0]), DegToRad(p.mount_rpy_deg[1]), DegToRad(p.mount_rpy_deg[2]));
  return X;
}

std::uint64_t ScanKey(const ScanRequest& r) {
  return DeriveKey(DeriveKey(Mix64(r.seed), HashName("sim/tls")), r.scan_id);
}

struct ScanDraws {
  double bias = 0.0;
  double roll = 0.0, pitch = 0.0;
  std::array<double, 3> colour_gain{1.0, 1.0, 1.0};  ///< exposure x white balance, linear RGB
  double window_light = 0.0;                         ///< this scan's daylight (TlsParams)
};

ScanDraws DrawScan(const TlsParams& p, const ScanRequest& r) {
  CounterRng rng(DeriveKey(ScanKey(r), HashName("scan")));
  ScanDraws d;
  const double sys = std::sqrt(
      std::max(0.0, p.range_accuracy * p.range_accuracy - p.range_precision * p.range_precision));
  d.bias = p.range_offset + sys * rng.Normal();
  d.roll = DegToRad(p.tilt_sigma_deg) * rng.Normal();
  d.pitch = DegToRad(p.tilt_sigma_deg) * rng.Normal();
  // Drawn whatever the sigmas, so that turning one on does not move the other draws; a zero
  // sigma gives a gain of exactly 1.
  const double exposure = std::exp2(p.exposure_sigma_stops * rng.Normal());
  const double red = std::exp(p.white_balance_sigma * rng.Normal());
  const double blue = std::exp(p.white_balance_sigma * rng.Normal());
  d.colour_gain = {exposure * red, exposure, exposure * blue};
  d.window_light = p.window_light * std::exp2(p.window_light_sigma_stops * rng.Normal());
  return d;
}

// Everything fixed for one scan.
struct ScanContext {
  const EmbreeWorld::Impl* world = nullptr;
  const EmbreeWorld* world_api = nullptr;
  const SurfaceTable* surfaces = nullptr;
  BeamModel beam;
  std::uint32_t rows = 0, columns = 0;
  std::vector<float> sin_az, cos_az, sin_el, cos_el;
  Eigen::Matrix3f R_WS;
  Eigen::Vector3f p_WS;
  bool camera = false;  // colour from the camera's own ray: camera_offset or camera_rpy_deg
  Eigen::Vector3f p_WC;
  bool camera_turned = false;  // camera_rpy_deg: R_cam turns a calibrated direction (world)
  Eigen::Matrix3f R_cam = Eigen::Matrix3f::Identity();
  // Stream keys per purpose; the item index is the pulse index (glass: pulse * 64 + sub-ray).
  std::uint64_t noise_key = 0, jitter_key = 0, glass_key = 0;
  double start_time = 0.0, pulse_period = 0.0;
  float jitter_sigma = 0.0f;  // rad
  bool use_kernel = false;    // the vectorised single-ray path applies (sim/pulse_kernel.h)
  PulseKernelConstants kernel;
  int max_transmissions = 0;
  // The instrument's axis errors (TlsParams::collimation_error_deg ...): per row, the true beam
  // is true_a A + true_c C + true_b B in the column's basis (A horizontal at the encoder
  // azimuth, C its left normal, B the scanner's z axis). Off: the encoder angles are the beam's.
  bool axis_errors = false;
  std::vector<float> true_a, true_b, true_c;
  // Errors applied to each reported point after the model (ApplyInstrumentErrors): range scale
  // and low-signal range walk, and the camera's per-scan gains as one table per channel.
  bool range_errors = false, colour_gains = false;
  float range_scale = 1.0f, low_signal_bias = 0.0f, low_signal_intensity = 1.0f;
  std::array<std::array<std::uint8_t, 256>, 3> colour_table{};
  Daylight daylight;  // TlsParams::window_light; off: the colour is as without
  std::uint64_t shadow_key = 0;  // daylight's shadow rays: pulse index, two uniforms per window
  // Flat per-part tables for resolving hits 16 at a time (ResolveStaticLanes).
  std::vector<std::int32_t> part_simple, part_rho_offset;
  std::vector<float> part_base;
  std::vector<std::int32_t> part_element;
  std::vector<std::uint8_t> part_class;
  ResolveTables resolve;
};

// The colour of `hit`, seen along `dir` from `origin` at pulse `pulse`, with daylight (and its
// shadows) when the scan has it.
std::array<std::uint8_t, 3> ColourAt(const ScanContext& ctx, const RayHit& hit,
                                     const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                                     std::uint64_t pulse, const float noise[3]) {
  if (!ctx.daylight.on() || hit.part < 0)
    return ctx.beam.Colour(*ctx.world_api, *ctx.surfaces, hit, dir, noise);
  const Eigen::Vector3f n = hit.normal.dot(dir) > 0.0f ? -hit.normal : hit.normal;
  const Eigen::Vector3f q = origin + hit.t * dir;
  const float f = ctx.daylight.Factor(
      q, n, hit.part,
      LitWindows(ctx.daylight, ctx.world->top, ctx.shadow_key, q, n, hit.part, pulse));
  return ctx.beam.ColourOf(ctx.surfaces->Albedo(*ctx.world_api, hit) * f, n.z(), noise);
}

// The general per-pulse path: any number of sub-rays, glass, camera offset. Writes the cell.
void EmitPulse(const ScanContext& ctx, const SubHit* subs, std::uint64_t pulse, std::uint32_t r,
               std::uint32_t c, interfaces::TlsPoint& pt, TlsPointTruth& tr) {
  pt = interfaces::TlsPoint{};
  pt.row = r;
  pt.column = c;
  pt.timestamp =
      ctx.start_time + static_cast<double>(static_cast<std::int64_t>(pulse)) * ctx.pulse_period;
  tr = TlsPointTruth{};
  EchoResult echo;
  ctx.beam.Measure(*ctx.world_api, *ctx.surfaces, subs, ctx.noise_key, pulse, &echo);
  tr.flags = echo.flags;
  if (echo.dominant && echo.dominant->hit.hit()) {
    const RayHit& h = echo.dominant->hit;
    const SurfaceProps& sp = ctx.surfaces->part(h.part);
    tr.true_range = h.t;
    tr.part = h.part;
    tr.element = sp.element;
    tr.element_class = sp.element_class;
    tr.door = static_cast<std::int16_t>(h.door);
  }
  if (!echo.returned) return;
  // The reported point: measured range along the nominal (encoder) direction.
  const float sel = ctx.sin_el[r], cel = ctx.cos_el[r];
  pt.range = echo.range;
  pt.x = echo.range * cel * ctx.cos_az[c];
  pt.y = echo.range * cel * ctx.sin_az[c];
  pt.z = echo.range * sel;
  pt.intensity = echo.intensity;
  // Colour: what the camera sees at the true surface point.
  const SubHit& dom = *echo.dominant;
  std::array<std::uint8_t, 3> rgb;
  if (ctx.camera) {
    // The camera's own ray to the true point: occluders in front of it paint the point. A
    // camera turned from its calibration looks along that ray turned, at whatever is first.
    const Eigen::Vector3f p_true = dom.origin + dom.hit.t * dom.dir;
    const Eigen::Vector3f to = p_true - ctx.p_WC;
    const float dist = to.norm();
    const Eigen::Vector3f dir =
        ctx.camera_turned ? Eigen::Vector3f(ctx.R_cam * (to / dist)) : Eigen::Vector3f(to / dist);
    const float tfar =
        ctx.camera_turned ? std::numeric_limits<float>::infinity() : dist * (1.0f - 1e-4f) - 1e-3f;
    const RayHit seen = ctx.world_api->Intersect(ctx.p_WC, dir, 0.0f, tfar, pt.timestamp);
    rgb = seen.hit() ? ColourAt(ctx, seen, ctx.p_WC, dir, pulse, echo.colour_noise)
                     : ColourAt(ctx, dom.hit, dom.origin, dom.dir, pulse, echo.colour_noise);
  } else {
    rgb = ColourAt(ctx, dom.hit, dom.origin, dom.dir, pulse, echo.colour_noise);
  }
  pt.r = rgb[0];
  pt.g = rgb[1];
  pt.b = rgb[2];
}

// A single-ray packet lane as a SubHit (after PassGlassInPackets).
void SubHitFromPacket(const ScanContext& ctx, const RTCRayHit16& rh, int j, bool transmitted,
                      SubHit* s) {
  s->transmitted = transmitted;
  s->origin = Eigen::Vector3f(rh.ray.org_x[j], rh.ray.org_y[j], rh.ray.org_z[j]);
  s->dir = Eigen::Vector3f(rh.ray.dir_x[j], rh.ray.dir_y[j], rh.ray.dir_z[j]);
  s->hit = RayHit{};
  if (rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID) {
    ctx.world->Resolve(rh.hit.geomID[j], rh.hit.primID[j], rh.hit.instID[0][j], rh.ray.tfar[j],
                       rh.hit.u[j], rh.hit.v[j], &s->hit, rh.ray.time[j]);
  }
}

// Completes a sub-ray from Embree's packet result (misses already re-traced watertight): resolve,
// pass glass.
void CompleteSubHit(const ScanContext& ctx, const RTCRayHit16& rh, int j, std::uint64_t pulse,
                    int k, SubHit* s) {
  SubHitFromPacket(ctx, rh, j, false, s);
  s->time =
      ctx.start_time + static_cast<double>(static_cast<std::int64_t>(pulse)) * ctx.pulse_period;
  if (s->hit.hit() && ctx.surfaces->part(s->hit.part).transmission > 0.0f) {
    ContinueThroughGlass(*ctx.world_api, *ctx.surfaces, ctx.max_transmissions, ctx.glass_key,
                         pulse * 64 + static_cast<std::uint64_t>(k), s);
  }
}

// Re-traces the lanes of a packet that missed in the watertight scene (one more packet query:
// misses through windows and doors are coherent), so a ray aimed exactly at an edge shared by two
// parts cannot slip out of a closed room.
void RetraceMissesWatertight(const EmbreeWorld::Impl& w, const int* valid,
                             RTCIntersectContext* rctx, RTCRayHit16* rh) {
  alignas(64) int miss[16];
  bool any = false;
  for (int j = 0; j < 16; ++j) {
    miss[j] = valid[j] && rh->hit.geomID[j] == RTC_INVALID_GEOMETRY_ID ? -1 : 0;
    any |= miss[j] != 0;
  }
  if (!any) return;
  for (int j = 0; j < 16; ++j) {
    if (miss[j]) rh->ray.tfar[j] = std::numeric_limits<float>::infinity();
  }
  rtcIntersect16(miss, w.robust, rctx, rh);
}

// Glass for single-ray packets: lanes that hit a transmitting surface continue with its
// transmission probability (draw `layer` of the stream (glass_key, 64 pulse), as
// ContinueThroughGlass draws), re-traced together as one packet per layer.
void PassGlassInPackets(const ScanContext& ctx, const std::uint64_t* pulse, const int* valid,
                        RTCIntersectContext* rctx, RTCRayHit16* rh, bool* transmitted) {
  const EmbreeWorld::Impl& w = *ctx.world;
  for (int j = 0; j < 16; ++j) transmitted[j] = false;
  for (int layer = 0; layer < ctx.max_transmissions; ++layer) {
    alignas(64) int go[16];
    bool any = false;
    for (int j = 0; j < 16; ++j) {
      go[j] = 0;
      const unsigned geom = rh->hit.geomID[j];
      if (!valid[j] || geom == RTC_INVALID_GEOMETRY_ID) continue;
      std::int32_t door;
      const std::int32_t part = w.PartOfHit(geom, rh->hit.instID[0][j], &door);
      const float tr = ctx.surfaces->part(part).transmission;
      if (tr <= 0.0f) continue;
      const std::uint64_t bits = Mix64(ctx.glass_key + ((pulse[j] * 64) * PulseStream::kSlots +
                                                        static_cast<std::uint64_t>(layer)) *
                                                           0x9E3779B97F4A7C15ull);
      if (!(static_cast<double>(bits >> 11) * 0x1.0p-53 < tr)) continue;
      go[j] = -1;
      any = true;
      transmitted[j] = true;
      rh->ray.tnear[j] = rh->ray.tfar[j] + 1e-4f;  // just beyond the surface, same ray
      rh->ray.tfar[j] = std::numeric_limits<float>::infinity();
      rh->hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
      rh->hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
    }
    if (!any) return;
    rtcIntersect16(go, w.top, rctx, rh);
    if (w.robust) RetraceMissesWatertight(w, go, rctx, rh);
    w.TraceMovers16(go, rctx, rh);
  }
}

// One packet in the world: the building (misses re-traced watertight), then the movers where
// the scan's pulse times place them.
void TracePacket(const ScanContext& ctx, const std::uint64_t* pulse, const int* valid,
                 RTCIntersectContext* rctx, RTCRayHit16* rh) {
  const EmbreeWorld::Impl& w = *ctx.world;
  rtcIntersect16(valid, w.top, rctx, rh);
  if (w.robust) RetraceMissesWatertight(w, valid, rctx, rh);
  if (!w.movers) return;
  for (int j = 0; j < 16; ++j)
    rh->ray.time[j] = ctx.world_api->TrackTime(
        ctx.start_time +
        static_cast<double>(static_cast<std::int64_t>(pulse[j])) * ctx.pulse_period);
  w.TraceMovers16(valid, rctx, rh);
}

void TraceBlock(const ScanContext& ctx, ScanBlock& block) {
  const std::uint32_t rows = ctx.rows;
  const int K = ctx.beam.rays();
  const std::size_t cells = static_cast<std::size_t>(block.column_end - block.column_begin) * rows;
  block.rows = rows;
  block.points.resize(cells);
  block.truth.resize(cells);

  RTCIntersectContext rctx;
  InitCoherentContext(&rctx);
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  std::vector<SubHit> subs(static_cast<std::size_t>(16) * K);
  Eigen::Vector3f d_true[16], e_az[16], e_el[16];
  std::uint64_t pulse[16];
  bool transmitted[16];
  const Eigen::Vector3f B = ctx.R_WS.col(2);  // scanner z axis in the world
  const EmbreeWorld::Impl& w = *ctx.world;
  const float range_min = static_cast<float>(ctx.beam.config().range_min);
  const bool need_basis = K > 1 || ctx.jitter_sigma > 0.0f;
  const bool simple_rays = K == 1 && !(ctx.jitter_sigma > 0.0f);
  const float ox = ctx.p_WS.x(), oy = ctx.p_WS.y(), oz = ctx.p_WS.z();
  const std::int32_t* __restrict part_element = ctx.part_element.data();
  const std::uint8_t* __restrict part_class = ctx.part_class.data();
  const float* __restrict sin_el = ctx.sin_el.data();
  const float* __restrict cos_el = ctx.cos_el.data();
  const double start_time = ctx.start_time, pulse_period = ctx.pulse_period;

  for (std::uint32_t c = block.column_begin; c < block.column_end; ++c) {
    const float saz = ctx.sin_az[c], caz = ctx.cos_az[c];
    // World-frame bases of this column: d = cel A + sel B, e_az = C, e_el = -sel A + cel B.
    const Eigen::Vector3f A = caz * ctx.R_WS.col(0) + saz * ctx.R_WS.col(1);
    const Eigen::Vector3f C = -saz * ctx.R_WS.col(0) + caz * ctx.R_WS.col(1);
    const std::size_t column_base = static_cast<std::size_t>(c - block.column_begin) * rows;
    for (std::uint32_t r0 = 0; r0 < rows; r0 += 16) {
      const int n = static_cast<int>(std::min<std::uint32_t>(16, rows - r0));
      if (simple_rays) {
        // One unjittered ray per pulse: straight structure-of-arrays loops (vectorised), the same
        // float operations as d_true = cel A + sel B below.
        alignas(64) float sel_l[16], cel_l[16];
        for (int j = 0; j < 16; ++j) {
          const std::uint32_t r = r0 + static_cast<std::uint32_t>(j < n ? j : n - 1);
          sel_l[j] = ctx.sin_el[r];
          cel_l[j] = ctx.cos_el[r];
          pulse[j] = static_cast<std::uint64_t>(c) * rows + r;
          valid[j] = j < n ? -1 : 0;
        }
        const float ax = A.x(), ay = A.y(), az = A.z(), bx = B.x(), by = B.y(), bz = B.z();
        if (ctx.axis_errors) {
          for (int j = 0; j < 16; ++j) {
            const std::uint32_t r = r0 + static_cast<std::uint32_t>(j < n ? j : n - 1);
            const Eigen::Vector3f d = ctx.true_a[r] * A + ctx.true_c[r] * C + ctx.true_b[r] * B;
            rh.ray.dir_x[j] = d.x();
            rh.ray.dir_y[j] = d.y();
            rh.ray.dir_z[j] = d.z();
          }
        } else {
          for (int j = 0; j < 16; ++j) {
            rh.ray.dir_x[j] = cel_l[j] * ax + sel_l[j] * bx;
            rh.ray.dir_y[j] = cel_l[j] * ay + sel_l[j] * by;
            rh.ray.dir_z[j] = cel_l[j] * az + sel_l[j] * bz;
          }
        }
        for (int j = 0; j < 16; ++j) {
          rh.ray.org_x[j] = ox;
          rh.ray.org_y[j] = oy;
          rh.ray.org_z[j] = oz;
          ResetLane(&rh, j);
        }
        TracePacket(ctx, pulse, valid, &rctx, &rh);
        PassGlassInPackets(ctx, pulse, valid, &rctx, &rh, transmitted);
      } else {
        for (int j = 0; j < 16; ++j) {
          const std::uint32_t r = r0 + static_cast<std::uint32_t>(std::min(j, n - 1));
          const float sel = ctx.sin_el[r], cel = ctx.cos_el[r];
          d_true[j] =
              ctx.axis_errors
                  ? Eigen::Vector3f(ctx.true_a[r] * A + ctx.true_c[r] * C + ctx.true_b[r] * B)
                  : Eigen::Vector3f(cel * A + sel * B);
          pulse[j] = static_cast<std::uint64_t>(c) * rows + r;
          valid[j] = j < n ? -1 : 0;
          if (need_basis) {
            e_az[j] = C;
            e_el[j] = -sel * A + cel * B;
          }
          if (ctx.jitter_sigma > 0.0f) {
            // Per-pulse direction jitter: the true beam differs from the encoder angles. First
            // order in sigma (~1e-5 rad): the direction stays unit to 1e-10. One draw: per axis an
            // Irwin-Hall sum of four 8-bit uniforms (sigma 147.8 units).
            PulseStream jr(ctx.jitter_key, pulse[j]);
            const std::uint64_t bits = jr.NextU64();
            const auto sum4 = [](std::uint64_t v) {
              return static_cast<float>((v & 255) + ((v >> 8) & 255) + ((v >> 16) & 255) +
                                        ((v >> 24) & 255)) -
                     510.0f;
            };
            const float a = sum4(bits) * (1.0f / 147.80054f),
                        b = sum4(bits >> 32) * (1.0f / 147.80054f);
            d_true[j] += ctx.jitter_sigma * (a * cel * e_az[j] + b * e_el[j]);
          }
        }
        for (int k = 0; k < K; ++k) {
          const BeamModel::SubRay& sr = ctx.beam.sub(k);
          for (int j = 0; j < 16; ++j) {
            Eigen::Vector3f o = ctx.p_WS, d = d_true[j];
            if (K > 1) {
              // off is orthogonal to the (unit) beam, so |d + h off|^2 = 1 + (h ring)^2 for every
              // lane: one precomputed scale instead of a normalisation (jitter changes it by
              // ~1e-9).
              const Eigen::Vector3f off = sr.a * e_az[j] + sr.b * e_el[j];
              o += ctx.beam.exit_radius() * off;
              d = (d + ctx.beam.half_divergence() * off) * sr.inv_norm;
            }
            rh.ray.org_x[j] = o.x();
            rh.ray.org_y[j] = o.y();
            rh.ray.org_z[j] = o.z();
            rh.ray.dir_x[j] = d.x();
            rh.ray.dir_y[j] = d.y();
            rh.ray.dir_z[j] = d.z();
            ResetLane(&rh, j);
          }
          TracePacket(ctx, pulse, valid, &rctx, &rh);
          if (K == 1) PassGlassInPackets(ctx, pulse, valid, &rctx, &rh, transmitted);
          if (K > 1) {
            for (int j = 0; j < n; ++j)
              CompleteSubHit(ctx, rh, j, pulse[j], k, &subs[static_cast<std::size_t>(j) * K + k]);
          }
        }
      }
      if (K > 1) {
        for (int j = 0; j < n; ++j) {
          const std::uint32_t r = r0 + static_cast<std::uint32_t>(j);
          EmitPulse(ctx, &subs[static_cast<std::size_t>(j) * K], pulse[j], r, c,
                    block.points[column_base + r], block.truth[column_base + r]);
        }
        continue;
      }
      // One ray per pulse, the common case. Pass 1: resolve the hits and gather the surface
      // terms (16 lanes at once for static, opaque, untextured parts with AVX-512; scalar for
      // the rest); pass 2: the vectorised pulse kernel; pass 3: write the cells. Misses,
      // door leaves, glass and camera parallax take the general path.
      if (!ctx.use_kernel) {
        for (int j = 0; j < n; ++j) {
          const std::uint32_t r = r0 + static_cast<std::uint32_t>(j);
          SubHitFromPacket(ctx, rh, j, transmitted[j], &subs[0]);
          EmitPulse(ctx, &subs[0], pulse[j], r, c, block.points[column_base + r],
                    block.truth[column_base + r]);
        }
        continue;
      }
      alignas(64) PulseLanes lanes;
      alignas(64) std::int32_t lane_part[16], lane_door[16];
      bool too_close[16], lane_miss[16];
      Eigen::Vector3f day_q[16], day_n[16];  // daylight: each lit lane's surface point, normal
      std::uint32_t day = 0;                 // lanes that daylight lights
      for (int j = 0; j < 16; ++j) {
        lanes.active[j] = 0;
        too_close[j] = false;
        lanes.pulse[j] = pulse[j];
        lanes.t[j] = 1.0f;
        lanes.cos_a[j] = 1.0f;
        lanes.rho_offset[j] = 0;
        lanes.facing_nz[j] = 0.0f;
        lanes.albedo[0][j] = lanes.albedo[1][j] = lanes.albedo[2][j] = 0.0f;
        lane_part[j] = lane_door[j] = -1;
        lane_miss[j] = false;
      }
      // Lanes on static, opaque, untextured parts: resolved 16 at a time (AVX-512), exactly as
      // the scalar loop below would.
      std::uint32_t fast = 0, fast_close = 0;
      if (!ctx.camera) {
        const HitLanes hl{rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.ray.tfar,
                          rh.ray.dir_x,  rh.ray.dir_y,     rh.ray.dir_z};
        fast = ResolveStaticLanes(ctx.resolve, hl, n, lanes, lane_part, &fast_close);
      }
      for (int j = 0; j < n; ++j) {
        if ((fast >> j) & 1u) {
          too_close[j] = ((fast_close >> j) & 1u) != 0;
          continue;
        }
        const unsigned geom = rh.hit.geomID[j];
        if (geom == RTC_INVALID_GEOMETRY_ID) {
          lane_miss[j] = true;  // nothing there, even in the watertight scene
          continue;
        }
        const unsigned inst = rh.hit.instID[0][j];
        const std::int32_t part = w.PartOfHit(geom, inst, &lane_door[j]);
        const SurfaceProps& sp = ctx.surfaces->part(part);
        // Camera parallax, or a transmitting surface reached after max_transmissions (it
        // reflects): the general path.
        if (ctx.camera || sp.transmission > 0.0f) continue;
        const unsigned prim = rh.hit.primID[j];
        const Eigen::Vector3f nrm = w.NormalOfHit(part, prim, inst, lane_door[j], rh.ray.time[j]);
        const float t = rh.ray.tfar[j];
        lane_part[j] = part;
        lanes.t[j] = t;
        if (t < range_min) {
          too_close[j] = true;
          continue;
        }
        const float dot =
            nrm.x() * rh.ray.dir_x[j] + nrm.y() * rh.ray.dir_y[j] + nrm.z() * rh.ray.dir_z[j];
        const float ca = std::clamp(std::abs(dot), 1e-4f, 1.0f);
        lanes.cos_a[j] = ca;
        lanes.rho_offset[j] = sp.rho_offset;
        lanes.facing_nz[j] = dot > 0.0f ? -nrm.z() : nrm.z();
        Eigen::Vector3f albedo = sp.base_linear;
        if (sp.texture) {
          RayHit h;
          h.t = t;
          h.part = part;
          h.triangle = prim;
          h.u = rh.hit.u[j];
          h.v = rh.hit.v[j];
          albedo = ctx.surfaces->Albedo(*ctx.world_api, h);
        }
        if (ctx.daylight.on()) {
          const Eigen::Vector3f dir(rh.ray.dir_x[j], rh.ray.dir_y[j], rh.ray.dir_z[j]);
          const Eigen::Vector3f org(rh.ray.org_x[j], rh.ray.org_y[j], rh.ray.org_z[j]);
          day_q[j] = org + t * dir;
          day_n[j] = dot > 0.0f ? -nrm : nrm;
          day |= 1u << j;
        }
        lanes.albedo[0][j] = albedo.x();
        lanes.albedo[1][j] = albedo.y();
        lanes.albedo[2][j] = albedo.z();
        lanes.active[j] = 1;
      }
      // Daylight on every lane with a surface (the lanes resolved 16 at a time have static
      // parts), its shadow rays 16 at a time.
      if (ctx.daylight.on()) {
        for (int j = 0; j < n; ++j) {
          if (!(((fast & ~fast_close) >> j) & 1u)) continue;
          const std::int32_t part = lane_part[j];
          const Eigen::Vector3f nrm =
              w.normals[w.first_triangle[static_cast<std::size_t>(part)] + rh.hit.primID[j]];
          const Eigen::Vector3f dir(rh.ray.dir_x[j], rh.ray.dir_y[j], rh.ray.dir_z[j]);
          const Eigen::Vector3f org(rh.ray.org_x[j], rh.ray.org_y[j], rh.ray.org_z[j]);
          day_q[j] = org + lanes.t[j] * dir;
          day_n[j] = nrm.dot(dir) > 0.0f ? -nrm : nrm;
          day |= 1u << j;
        }
        std::uint32_t lit[16];
        LitWindows16(ctx.daylight, ctx.world->top, ctx.shadow_key, day, day_q, day_n, lane_part,
                     pulse, lit);
        for (int j = 0; j < n; ++j) {
          if (!((day >> j) & 1u)) continue;
          const float f = ctx.daylight.Factor(day_q[j], day_n[j], lane_part[j], lit[j]);
          for (int ch = 0; ch < 3; ++ch) lanes.albedo[ch][j] *= f;
        }
      }
      RunPulseKernel(ctx.kernel, lanes);
      for (int j = 0; j < n; ++j) {
        const std::uint32_t r = r0 + static_cast<std::uint32_t>(j);
        interfaces::TlsPoint& pt_out = block.points[column_base + r];
        TlsPointTruth& tr_out = block.truth[column_base + r];
        if (((fast & ~fast_close) >> j) & 1u) {
          const std::int32_t status = lanes.status[j];
          if (status != kNeedsGeneral) {
            // The common case: a static, opaque, untextured surface the kernel finished.
            const std::int32_t part = lane_part[j];
            TlsPointTruth tr;
            tr.true_range = lanes.t[j];
            tr.element = part_element[part];
            tr.part = part;
            tr.element_class = part_class[part];
            tr.door = -1;
            tr.flags = static_cast<std::uint8_t>((transmitted[j] ? kTruthTransmitted : 0) |
                                                 (status == kDropped ? kTruthDropped : 0));
            interfaces::TlsPoint pt;
            pt.row = r;
            pt.column = c;
            pt.timestamp = start_time +
                           static_cast<double>(static_cast<std::int64_t>(pulse[j])) * pulse_period;
            if (status != kDropped) {
              const float range = lanes.range[j];
              const float sel = sin_el[r], cel = cos_el[r];
              pt.range = range;
              pt.x = range * cel * caz;
              pt.y = range * cel * saz;
              pt.z = range * sel;
              pt.intensity = lanes.intensity[j];
              pt.r = lanes.rgb[0][j];
              pt.g = lanes.rgb[1][j];
              pt.b = lanes.rgb[2][j];
            }
            pt_out = pt;
            tr_out = tr;
            continue;
          }
        }
        if (lane_miss[j]) {
          interfaces::TlsPoint pt;
          pt.row = r;
          pt.column = c;
          pt.timestamp = ctx.start_time + static_cast<double>(static_cast<std::int64_t>(pulse[j])) *
                                              ctx.pulse_period;
          pt_out = pt;
          tr_out = TlsPointTruth{};
          continue;
        }
        if (!too_close[j] && !lanes.active[j]) {
          // General path from the packet's state (glass already passed).
          SubHitFromPacket(ctx, rh, j, transmitted[j], &subs[0]);
          EmitPulse(ctx, &subs[0], pulse[j], r, c, pt_out, tr_out);
          continue;
        }
        if (!too_close[j] && lanes.status[j] == kNeedsGeneral) {
          // The kernel's rare cases (ziggurat wedge/tail, detection logistic, long-range fade):
          // the scalar model, which draws the same numbers first.
          EchoResult echo;
          PulseStream rng(ctx.noise_key, pulse[j]);
          ctx.beam.Finish(lanes.t[j], lanes.rho[j], lanes.cos_a[j], rng, &echo);
          lanes.status[j] = echo.returned ? kReturned : kDropped;
          if (echo.returned) {
            lanes.range[j] = echo.range;
            lanes.intensity[j] = echo.intensity;
            const auto rgb = ctx.beam.ColourOf(
                Eigen::Vector3f(lanes.albedo[0][j], lanes.albedo[1][j], lanes.albedo[2][j]),
                lanes.facing_nz[j], echo.colour_noise);
            for (int ch = 0; ch < 3; ++ch) lanes.rgb[ch][j] = rgb[static_cast<std::size_t>(ch)];
          }
        }
        const SurfaceProps& sp = ctx.surfaces->part(lane_part[j]);
        TlsPointTruth tr;
        tr.true_range = lanes.t[j];
        tr.element = sp.element;
        tr.part = lane_part[j];
        tr.element_class = sp.element_class;
        tr.door = static_cast<std::int16_t>(lane_door[j]);
        interfaces::TlsPoint pt;
        pt.row = r;
        pt.column = c;
        pt.timestamp = ctx.start_time +
                       static_cast<double>(static_cast<std::int64_t>(pulse[j])) * ctx.pulse_period;
        if (transmitted[j]) tr.flags |= kTruthTransmitted;
        if (too_close[j]) {
          tr.flags |= kTruthTooClose;
        } else if (lanes.status[j] == kDropped) {
          tr.flags |= kTruthDropped;
        } else {
          // The reported point: measured range along the nominal (encoder) direction.
          const float range = lanes.range[j];
          const float sel = ctx.sin_el[r], cel = ctx.cos_el[r];
          pt.range = range;
          pt.x = range * cel * caz;
          pt.y = range * cel * saz;
          pt.z = range * sel;
          pt.intensity = lanes.intensity[j];
          pt.r = lanes.rgb[0][j];
          pt.g = lanes.rgb[1][j];
          pt.b = lanes.rgb[2][j];
        }
        pt_out = pt;
        tr_out = tr;
      }
    }
  }
}

// The instrument's errors that act on a reported point, not on the beam: the range scale, the
// low-signal range walk (from the return's own intensity, as the instrument's amplitude), the
// camera's exposure and white balance. The point moves along its nominal direction.
void ApplyInstrumentErrors(const ScanContext& ctx, ScanBlock& block) {
  if (!ctx.range_errors && !ctx.colour_gains) return;
  for (interfaces::TlsPoint& pt : block.points) {
    if (!pt.valid()) continue;
    if (ctx.range_errors) {
      const float weak = std::max(0.0f, 1.0f - pt.intensity / ctx.low_signal_intensity);
      const float range = std::max(1e-6f, pt.range * ctx.range_scale + ctx.low_signal_bias * weak);
      const float k = range / pt.range;
      pt.x *= k;
      pt.y *= k;
      pt.z *= k;
      pt.range = range;
    }
    if (ctx.colour_gains) {
      pt.r = ctx.colour_table[0][pt.r];
      pt.g = ctx.colour_table[1][pt.g];
      pt.b = ctx.colour_table[2][pt.b];
    }
  }
}

// The instrument's errors beyond the data sheet's noise (TlsParams::collimation_error_deg ...):
// the true beams of the rows, the point errors and the colour tables of this scan.
void SetInstrumentErrors(const TlsParams& p, const ScanDraws& draws, double el0, double vstep,
                         ScanContext& ctx) {
  const std::uint32_t rows = ctx.rows;
  ctx.axis_errors = p.collimation_error_deg != 0.0 || p.trunnion_axis_error_deg != 0.0 ||
                    p.vertical_index_error_deg != 0.0;
  if (ctx.axis_errors) {
    // Horizontal angle error c / cos(el) + i tan(el), elevation error v (the standard model of
    // a panoramic scanner's axis errors, Lichti 2007; docs/realism.md); cos(el) kept off 0 at the
    // pole, where the azimuth has no meaning.
    const double c_err = DegToRad(p.collimation_error_deg),
                 i_err = DegToRad(p.trunnion_axis_error_deg),
                 v_err = DegToRad(p.vertical_index_error_deg);
    ctx.true_a.resize(rows);
    ctx.true_b.resize(rows);
    ctx.true_c.resize(rows);
    for (std::uint32_t r = 0; r < rows; ++r) {
      const double e = el0 - r * vstep;
      const double ce = std::max(std::cos(e), 1e-6);
      const double d_az = c_err / ce + i_err * std::sin(e) / ce;
      const double e_true = e + v_err;
      ctx.true_a[r] = static_cast<float>(std::cos(e_true) * std::cos(d_az));
      ctx.true_c[r] = static_cast<float>(std::cos(e_true) * std::sin(d_az));
      ctx.true_b[r] = static_cast<float>(std::sin(e_true));
    }
  }
  ctx.range_errors = p.range_scale_ppm != 0.0 || p.low_signal_range_bias != 0.0;
  ctx.range_scale = static_cast<float>(1.0 + 1e-6 * p.range_scale_ppm);
  ctx.low_signal_bias = static_cast<float>(p.low_signal_range_bias);
  ctx.low_signal_intensity = static_cast<float>(p.low_signal_intensity);
  ctx.colour_gains = draws.colour_gain != std::array<double, 3>{1.0, 1.0, 1.0};
  if (ctx.colour_gains) {
    // The gain acts on the sensor's linear signal; the table maps each reported 8-bit sRGB level.
    const SrgbTables& srgb = SrgbTables::Get();
    for (int ch = 0; ch < 3; ++ch) {
      for (int v = 0; v < 256; ++v) {
        const double lin = std::min(1.0, draws.colour_gain[static_cast<std::size_t>(ch)] *
                                             srgb.Decode(static_cast<std::uint8_t>(v)));
        ctx.colour_table[static_cast<std::size_t>(ch)][static_cast<std::size_t>(v)] =
            static_cast<std::uint8_t>(std::lround(255.0 * SrgbTables::EncodeExact(lin)));
      }
    }
  }
}

ScanContext MakeContext(const EmbreeWorld& world, const SurfaceTable& surfaces, const TlsParams& p,
                        std::uint32_t rows, std::uint32_t columns, const ScanRequest& req) {
  ScanContext ctx;
  ctx.world = &world.impl();
  ctx.world_api = &world;
  ctx.surfaces = &surfaces;
  ctx.beam = BeamModel(p);
  ctx.rows = rows;
  ctx.columns = columns;
  const double step = DegToRad(p.step_deg);
  const double vstep = DegToRad(p.vertical_step_deg > 0 ? p.vertical_step_deg : p.step_deg);
  const double az0 = DegToRad(p.azimuth_min_deg), el0 = DegToRad(p.elevation_max_deg);
  ctx.sin_az.resize(columns);
  ctx.cos_az.resize(columns);
  for (std::uint32_t c = 0; c < columns; ++c) {
    const double a = az0 + c * step;
    ctx.sin_az[c] = static_cast<float>(std::sin(a));
    ctx.cos_az[c] = static_cast<float>(std::cos(a));
  }
  ctx.sin_el.resize(rows);
  ctx.cos_el.resize(rows);
  for (std::uint32_t r = 0; r < rows; ++r) {
    const double e = el0 - r * vstep;
    ctx.sin_el[r] = static_cast<float>(std::sin(e));
    ctx.cos_el[r] = static_cast<float>(std::cos(e));
  }
  const ScanDraws draws = DrawScan(p, req);
  const Pose3 X_WS_nominal = req.X_WB * MountPose(p);
  Pose3 X_WS = X_WS_nominal;
  X_WS.linear() = X_WS_nominal.linear() * Rpy(draws.roll, draws.pitch, 0.0);
  ctx.R_WS = X_WS.linear().cast<float>();
  ctx.p_WS = X_WS.translation().cast<float>();
  const Eigen::Vector3d cam(p.camera_offset[0], p.camera_offset[1], p.camera_offset[2]);
  ctx.camera_turned =
      p.camera_rpy_deg[0] != 0.0 || p.camera_rpy_deg[1] != 0.0 || p.camera_rpy_deg[2] != 0.0;
  ctx.camera = cam.squaredNorm() > 0.0 || ctx.camera_turned;
  ctx.p_WC = (X_WS * cam).cast<float>();
  ctx.R_cam = (X_WS.linear() *
               Rpy(DegToRad(p.camera_rpy_deg[0]), DegToRad(p.camera_rpy_deg[1]),
                   DegToRad(p.camera_rpy_deg[2])) *
               X_WS.linear().transpose())
                  .cast<float>();
  ctx.noise_key = DeriveKey(ScanKey(req), HashName("noise"));
  ctx.jitter_key = DeriveKey(ScanKey(req), HashName("jitter"));
  ctx.glass_key = DeriveKey(ScanKey(req), HashName("glass"));
  ctx.shadow_key = DeriveKey(ScanKey(req), HashName("shadow"));
  ctx.start_time = req.start_time;
  ctx.pulse_period = 1.0 / p.pulse_rate_hz;
  ctx.jitter_sigma = static_cast<float>(DegToRad(p.angle_noise_deg));
  ctx.max_transmissions = p.max_transmissions;
  ctx.beam.set_range_bias(draws.bias);
  SetInstrumentErrors(p, draws, el0, vstep, ctx);
  ctx.daylight = Daylight(ctx.world->scene, static_cast<float>(draws.window_light),
                          static_cast<float>(p.ambient_light), static_cast<float>(p.top_light));
  // The pulse kernel implements the single-ray model for sigma = precision / cos(a)^k with
  // k in {0, 1}; other settings use the general path everywhere.
  ctx.use_kernel = p.footprint_rays == 1 &&
                   (p.incidence_noise_exponent == 0.0 || p.incidence_noise_exponent == 1.0);
  PulseKernelConstants& k = ctx.kernel;
  k.noise_key = ctx.noise_key;
  k.bias = static_cast<float>(draws.bias);
  k.precision = static_cast<float>(p.range_precision);
  k.min_cos = p.incidence_noise_exponent == 0.0
                  ? 1.0f
                  : static_cast<float>(std::cos(DegToRad(p.max_noise_incidence_deg)));
  k.dropouts = p.dropouts;
  k.min_reflectance = static_cast<float>(p.min_reflectance);
  k.sure_detect = static_cast<float>(ctx.beam.sure_detect());
  k.reflectance_ref = static_cast<float>(p.reflectance_ref);
  k.intensity_attenuation = static_cast<float>(p.intensity_attenuation);
  k.intensity_noise = static_cast<float>(p.intensity_noise);
  k.ambient = static_cast<float>(p.ambient_light);
  k.top_light = static_cast<float>(p.top_light);
  k.colour_noise = static_cast<float>(p.colour_noise);
  k.zig_r = Ziggurat::Get().rf();
  k.zig_x = Ziggurat::Get().xf();
  k.srgb_encode = SrgbTables::Get().encode_table();
  k.rho_tables = surfaces.rho_tables();
  const std::size_t parts = ctx.world->first_triangle.size();
  ctx.part_simple.resize(parts);
  ctx.part_rho_offset.resize(parts);
  ctx.part_base.resize(3 * parts);
  ctx.part_element.resize(parts);
  ctx.part_class.resize(parts);
  for (std::size_t i = 0; i < parts; ++i) {
    const SurfaceProps& sp = surfaces.part(static_cast<std::int32_t>(i));
    ctx.part_simple[i] = (sp.transmission > 0.0f || sp.texture) ? 0 : 1;
    ctx.part_rho_offset[i] = sp.rho_offset;
    ctx.part_element[i] = sp.element;
    ctx.part_class[i] = sp.element_class;
    for (int ch = 0; ch < 3; ++ch)
      ctx.part_base[3 * i + static_cast<std::size_t>(ch)] = sp.base_linear[ch];
  }
  ResolveTables& rt = ctx.resolve;
  rt.geom_to_part = ctx.world->geom_to_part.data();
  rt.normals = ctx.world->normals.empty() ? nullptr : ctx.world->normals.front().data();
  rt.first_triangle = ctx.world->first_triangle.data();
  rt.part_simple = ctx.part_simple.data();
  rt.part_rho_offset = ctx.part_rho_offset.data();
  rt.part_base = ctx.part_base.data();
  rt.range_min = static_cast<float>(ctx.beam.config().range_min);
  return ctx;
}

// Block pool for the pipeline (blocks are big; reuse their buffers).
class BlockPool {
 public:
  ScanBlock* Acquire() {
    ScanBlock* b = nullptr;
    if (free_.try_pop(b)) return b;
    std::lock_guard<std::mutex> lock(mutex_);
    owned_.push_back(std::make_unique<ScanBlock>());
    return owned_.back().get();
  }
  void Release(ScanBlock* b) { free_.push(b); }

 private:
  tbb::concurrent_queue<ScanBlock*> free_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<ScanBlock>> owned_;
};

}  // namespace

TlsScanner::TlsScanner(const EmbreeWorld& world, TlsParams params)
    : world_(world), params_(std::move(params)) {
  params_.Validate();
  rows_ = CountRows(params_);
  columns_ = CountColumns(params_);
}

Pose3 TlsScanner::X_BS() const { return MountPose(params_); }

interfaces::TlsScan TlsScanner::MakeHeader(const ScanRequest& req) const {
  interfaces::TlsScan s;
  s.scan_id = req.scan_id;
  s.start_time = req.start_time;
  s.rows = rows_;
  s.columns = columns_;
  s.azimuth_min = DegToRad(params_.azimuth_min_deg);
  s.azimuth_step = DegToRad(params_.step_deg);
  s.elevation_max = DegToRad(params_.elevation_max_deg);
  s.elevation_step =
      DegToRad(params_.vertical_step_deg > 0 ? params_.vertical_step_deg : params_.step_deg);
  s.X_BS = X_BS();
  s.X_MS_estimate = req.X_MS_estimate ? *req.X_MS_estimate : req.X_WB * X_BS();
  return s;
}

TlsTruth TlsScanner::MakeTruthHeader(const ScanRequest& req) const {
  TlsTruth t;
  t.scan_id = req.scan_id;
  t.rows = rows_;
  t.columns = columns_;
  const ScanDraws d = DrawScan(params_, req);
  t.X_WB = req.X_WB;
  t.X_WS = req.X_WB * X_BS();
  t.X_WS.linear() = t.X_WS.linear() * Rpy(d.roll, d.pitch, 0.0);
  t.range_bias = d.bias;
  t.tilt_roll = d.roll;
  t.tilt_pitch = d.pitch;
  t.element_ids = world_.ElementIds();
  t.movers = world_.MoverCount() > 0;
  return t;
}

void TlsScanner::ScanStreamed(const ScanRequest& request, ScanSink& sink) const {
  const SurfaceTable surfaces(world_);
  const ScanContext ctx = MakeContext(world_, surfaces, params_, rows_, columns_, request);
  // Blocks of whole columns, ~8k pulses each (their buffers stay in L2): fixed by the grid, never
  // by the thread count.
  const std::uint32_t per_block =
      std::max<std::uint32_t>(1, 8192 / std::max<std::uint32_t>(rows_, 1));
  const std::uint32_t blocks = (columns_ + per_block - 1) / per_block;
  BlockPool pool;
  std::uint32_t next = 0;
  const std::size_t tokens =
      static_cast<std::size_t>(2 * tbb::this_task_arena::max_concurrency() + 2);
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, ScanBlock*>(tbb::filter_mode::serial_in_order,
                                         [&](tbb::flow_control& fc) -> ScanBlock* {
                                           if (next >= blocks) {
                                             fc.stop();
                                             return nullptr;
                                           }
                                           ScanBlock* b = pool.Acquire();
                                           b->column_begin = next * per_block;
                                           b->column_end =
                                               std::min(columns_, b->column_begin + per_block);
                                           ++next;
                                           return b;
                                         }) &
          tbb::make_filter<ScanBlock*, ScanBlock*>(tbb::filter_mode::parallel,
                                                   [&](ScanBlock* b) {
                                                     TraceBlock(ctx, *b);
                                                     ApplyInstrumentErrors(ctx, *b);
                                                     sink.Process(*b);
                                                     return b;
                                                   }) &
          tbb::make_filter<ScanBlock*, void>(tbb::filter_mode::serial_in_order, [&](ScanBlock* b) {
            sink.Consume(*b);
            pool.Release(b);
          }));
}

namespace {

class GridSink final : public ScanSink {
 public:
  GridSink(interfaces::TlsScan* scan, TlsTruth* truth) : scan_(scan), truth_(truth) {}
  void Process(ScanBlock& b) override {
    const std::uint32_t cols = scan_->columns;
    for (std::uint32_t c = b.column_begin; c < b.column_end; ++c) {
      const std::size_t base = static_cast<std::size_t>(c - b.column_begin) * b.rows;
      for (std::uint32_t r = 0; r < b.rows; ++r) {
        const std::size_t dst = static_cast<std::size_t>(r) * cols + c;
        scan_->points[dst] = b.points[base + r];
        if (truth_) truth_->points[dst] = b.truth[base + r];
      }
    }
  }
  void Consume(ScanBlock&) override {}

 private:
  interfaces::TlsScan* scan_;
  TlsTruth* truth_;
};

}  // namespace

interfaces::TlsScan TlsScanner::Scan(const ScanRequest& request, TlsTruth* truth) const {
  interfaces::TlsScan scan = MakeHeader(request);
  scan.points.resize(pulses());
  if (truth) {
    *truth = MakeTruthHeader(request);
    truth->points.resize(pulses());
  }
  GridSink sink(&scan, truth);
  ScanStreamed(request, sink);
  return scan;
}

}  // namespace mopad::sim
