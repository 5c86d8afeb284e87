#pragma once
// The sensor commands' work (`mopad scan`, `mopad lrf`, `mopad bench raycast`): a SCENE argument
// (generated folder, scene file or spec .yaml), a sensor profile and a pose in, scan files and
// figures out (docs/sensors.md). World side: they read the truth sidecar when there is one.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mopad::sim {

struct ScanOptions {
  std::string scene, pose, profile = "riegl_vz400", profile_file, output, ptx, truth;
  std::string realism = "ideal";      ///< realism profile (sim/realism.h), drawn for `seed`
  std::optional<double> step_deg;     ///< deg; not given: the profile's
  std::optional<int> footprint_rays;  ///< sub-rays per pulse; not given: the profile's
  std::uint64_t seed = 1, scan_id = 0;
  int threads = 0;
  std::vector<std::string> doors;
};

struct LrfOptions {
  std::string scene, pose, profile = "hokuyo_utm30lx", profile_file, output;
  std::vector<double> heights;
  bool paper_rig = false;
  std::uint64_t seed = 1, seq = 0;
  double time = 0.0;
  std::vector<std::string> doors;
};

struct BenchOptions {
  std::string scene, pose = "", profile = "riegl_vz400";
  double step_deg = 0.04;
  int footprint_rays = 7;
  int threads = 0;
  int repeat = 2;
  std::uint64_t seed = 1;
};

/// One TLS scan: writes the PLY (and PTX, truth sidecar when asked) and prints its figures.
void RunScan(const ScanOptions& options);
/// One LRF sweep (or the paper's two-LRF rig): writes CSV or JSON.
void RunLrf(const LrfOptions& options);
/// The ray-casting benchmark: the full TLS model against the bare Embree limit.
void RunBench(const BenchOptions& options);

}  // namespace mopad::sim
