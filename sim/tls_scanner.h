#pragma once
// Terrestrial laser scanner (TLS) simulation over an EmbreeWorld.
//
// What is modelled (docs/sensors.md gives the equations and sources): an organised grid of
// pulses (rows = elevation top to bottom, columns = azimuth CCW), each traced as 1 or K
// sub-rays (beam footprint: exit diameter + divergence) in 16-wide Embree packets, in scan-line
// order (column by column) and in parallel over blocks of columns (TBB); glass transmits a
// sub-ray with Material::transmission probability; detection probability from the radar law on
// effective reflectance (diffuse + specular backscatter lobe) and range, plus dark/grazing
// dropouts; sub-ray echoes closer than echo_separation merge into mixed pixels; range noise =
// per-scan bias + per-point noise growing with incidence; intensity from reflectance, incidence
// and range; colour = base colour x texture at the hit UV x simple illumination + noise,
// optionally seen from an offset camera; per-scan tilt and per-pulse direction jitter.
//
// Frames: points are in the *nominal* scanner frame S (what the scanner believes: encoder
// angles x measured range). The true scanner pose X_WS = X_WB * X_BS * tilt goes to the truth
// sidecar only.
//
// Determinism: every random draw is a counter-based function of (seed, scan_id, purpose, pulse
// index [, sub-ray]) (pulse index = column * rows + row; sim/scan_model.h PulseStream), never of
// thread or call order: the same request gives the same bytes with 1 or N threads, and on CPUs
// with or without AVX-512 (sim/pulse_kernel.h).
//
// Thread-safety: Scan/ScanStreamed are const and may run concurrently on one scanner (and one
// world) as long as nobody calls EmbreeWorld::SetDoorAngle meanwhile.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "interfaces/tls_scan.h"
#include "sim/embree_world.h"
#include "sim/tls_params.h"
#include "sim/tls_truth.h"

namespace mopad::sim {

/// One scan to take.
struct ScanRequest {
  std::uint64_t seed = 0;          ///< run seed
  std::uint64_t scan_id = 0;       ///< scan number within the run (keys the noise)
  double start_time = 0.0;         ///< s, simulation time of the first pulse
  Pose3 X_WB = Pose3::Identity();  ///< true pose of base_link in the world
  /// Pose stamped into TlsScan::X_MS_estimate (the robot's belief). Unset: the nominal
  /// X_WB * X_BS (no tilt), as a perfectly localised robot would stamp it.
  std::optional<Pose3> X_MS_estimate;
};

/// A block of whole columns produced by the streaming scanner. Layout: column-major inside the
/// block, cell (r, c) at (c - column_begin) * rows + r.
struct ScanBlock {
  std::uint32_t column_begin = 0;
  std::uint32_t column_end = 0;
  std::uint32_t rows = 0;
  std::vector<interfaces::TlsPoint> points;
  std::vector<TlsPointTruth> truth;
  /// Scratch for sinks (e.g. encoded file bytes), reused across blocks.
  std::array<std::string, 3> encoded;
  std::array<std::uint64_t, 3> encoded_count{};
};

/// Receives the blocks of a streamed scan.
class ScanSink {
 public:
  virtual ~ScanSink() = default;
  /// Called once per block from worker threads, concurrently and in any order; must only touch
  /// the block (and disjoint state).
  virtual void Process(ScanBlock& /*block*/) {}
  /// Called once per block, serially, in increasing column order.
  virtual void Consume(ScanBlock& block) = 0;
};

class TlsScanner {
 public:
  /// Validates the parameters (InputError). Keeps a reference to `world`.
  TlsScanner(const EmbreeWorld& world, TlsParams params);

  const TlsParams& params() const { return params_; }
  std::uint32_t rows() const { return rows_; }
  std::uint32_t columns() const { return columns_; }
  std::uint64_t pulses() const { return static_cast<std::uint64_t>(rows_) * columns_; }
  /// Calibrated mount of the scanner on base_link, from the profile.
  Pose3 X_BS() const;

  /// Scan metadata (grid geometry, poses, ids) without points.
  interfaces::TlsScan MakeHeader(const ScanRequest& request) const;
  /// Truth metadata (true pose, per-scan bias and tilt, element table) without points.
  TlsTruth MakeTruthHeader(const ScanRequest& request) const;

  /// A whole scan in memory (row-major grid). If `truth` is given it receives the sidecar in
  /// the same layout. Memory: ~40 B per pulse (+16 B with truth).
  interfaces::TlsScan Scan(const ScanRequest& request, TlsTruth* truth = nullptr) const;

  /// Streams the scan block by block (bounded memory); the sink sees every column once.
  void ScanStreamed(const ScanRequest& request, ScanSink& sink) const;

 private:
  const EmbreeWorld& world_;
  TlsParams params_;
  std::uint32_t rows_ = 0, columns_ = 0;
};

}  // namespace mopad::sim
