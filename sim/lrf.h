#pragma once
// 2D laser range finder (LRF) simulation over an EmbreeWorld, producing interfaces::LrfScan.
//
// A sweep of beams in the sensor's x-y plane (x forward, z up), counter-clockwise from
// angle_min, traced in 16-wide packets; each beam as 1 or K sub-rays (divergence footprint,
// mixed pixels), with the same echo, dropout and glass model as the TLS (sim/scan_model.h):
// range noise N(0, sigma_near) up to sigma_switch_range and N(0, sigma_far) beyond, plus a
// per-sweep bias N(0, bias_sigma). No return (nothing within range_max, too close, dropout)
// reads exactly range_max, as LrfScan documents.
//
// Defaults are the `hokuyo_utm30lx` profile (Hokuyo UTM-30LX spec sheet: 270 deg, 0.25 deg,
// 0.1-30 m, +-30 mm to 10 m and +-50 mm to 30 m, 25 ms/scan). `sick_lms111`: SICK LMS111-10100
// operating instructions (270 deg, 0.25/0.5 deg at 25/50 Hz, 0.5-20 m, statistical error
// 12 mm, systematic +-30 mm, beam divergence 15 mrad).
//
// Determinism: noise keyed by (seed, frame name, seq, beam index, sub-ray).
// Thread-safety: Scan is const; same rules as TlsScanner.

#include <memory>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/lrf_scan.h"
#include "sim/embree_world.h"

namespace mopad::sim {

class SurfaceTable;

struct LrfParams {
  std::string name = "hokuyo_utm30lx";    ///< profile name
  std::string frame = "lrf";              ///< LrfScan::frame
  double angle_min_deg = -135.0;          ///< deg, first beam, CCW from +x, [-180, 180]
  double angle_max_deg = 135.0;           ///< deg, last beam at or below this, [-180, 180]
  double angle_increment_deg = 0.25;      ///< deg, (0, 10]
  double rate_hz = 40.0;                  ///< Hz, sweeps per second (timestamps), (0, 1000]
  double range_min = 0.1;                 ///< m, [0, 100]
  double range_max = 30.0;                ///< m, no-return reading, (0, 1000]
  double sigma_near = 0.03;               ///< m, 1 sigma up to sigma_switch_range, [0, 1]
  double sigma_far = 0.05;                ///< m, 1 sigma beyond, [0, 1]
  double sigma_switch_range = 10.0;       ///< m, [0, 1000]
  double bias_sigma = 0.0;                ///< m, per-sweep systematic error, 1 sigma, [0, 1]
  double incidence_noise_exponent = 0.0;  ///< sigma / cos(alpha)^k, [0, 4]
  double beam_divergence_mrad = 0.0;      ///< mrad, full angle, [0, 100]
  double beam_exit_diameter = 0.0;        ///< m, [0, 1]
  int footprint_rays = 1;                 ///< 1 or >= 3 sub-rays, [1, 64]
  double echo_separation = 0.3;           ///< m, [0, 100]
  /// m, maximum range at reflectance_ref, normal incidence; darker targets scale with the radar
  /// law R_max ~ sqrt(rho) (UTM-30LX: 30 m on white Kent sheet, taken as rho = 0.9).
  double range_ref = 30.0;
  double reflectance_ref = 0.9;   ///< [0.001, 1]
  double min_reflectance = 0.01;  ///< dark/grazing dropout threshold, [0, 1]
  bool dropouts = true;
  int max_transmissions = 4;                            ///< glass layers a beam may pass, [0, 64]
  std::vector<double> mount_xyz = {0.0, 0.0, 0.25};     ///< m, sensor in base_link (X_BL)
  std::vector<double> mount_rpy_deg = {0.0, 0.0, 0.0};  ///< deg

  template <class V>
  void Visit(V& v) {
    v("name", name);
    v("frame", frame);
    v("angle_min_deg", angle_min_deg, Bounds{-180, 180});
    v("angle_max_deg", angle_max_deg, Bounds{-180, 180});
    v("angle_increment_deg", angle_increment_deg, Bounds{1e-3, 10});
    v("rate_hz", rate_hz, Bounds{1e-3, 1000});
    v("range_min", range_min, Bounds{0, 100});
    v("range_max", range_max, Bounds{1e-3, 1000});
    v("sigma_near", sigma_near, Bounds{0, 1});
    v("sigma_far", sigma_far, Bounds{0, 1});
    v("sigma_switch_range", sigma_switch_range, Bounds{0, 1000});
    v("bias_sigma", bias_sigma, Bounds{0, 1});
    v("incidence_noise_exponent", incidence_noise_exponent, Bounds{0, 4});
    v("beam_divergence_mrad", beam_divergence_mrad, Bounds{0, 100});
    v("beam_exit_diameter", beam_exit_diameter, Bounds{0, 1});
    v("footprint_rays", footprint_rays, Bounds{1, 64});
    v("echo_separation", echo_separation, Bounds{0, 100});
    v("range_ref", range_ref, Bounds{0.1, 1e4});
    v("reflectance_ref", reflectance_ref, Bounds{0.001, 1});
    v("min_reflectance", min_reflectance, Bounds{0, 1});
    v("dropouts", dropouts);
    v("max_transmissions", max_transmissions, Bounds{0, 64});
    v("mount_xyz", mount_xyz, Bounds{-100, 100});
    v("mount_rpy_deg", mount_rpy_deg, Bounds{-360, 360});
  }
  void Validate() const;
  /// Every stochastic effect off (noise, bias, dropouts).
  LrfParams NoiseFree() const;
  /// Calibrated mount on base_link.
  Pose3 X_BL() const;
};

/// Built-in profile: "hokuyo_utm30lx", "sick_lms111" (0.5 deg, 50 Hz), "sick_lms111_fine"
/// (0.25 deg, 25 Hz). InputError otherwise.
LrfParams LrfProfile(const std::string& name);
std::vector<std::string> LrfProfileNames();
/// The paper's robot (MoPAD, Sec. 3.1): LRF1 near the scanner (frame "lrf_top", 1.2 m) and
/// LRF2 at the base (frame "lrf_base", 0.25 m), both `profile`.
std::vector<LrfParams> PaperLrfRig(const std::string& profile = "hokuyo_utm30lx");

class LrfSimulator {
 public:
  /// Validates (InputError). Keeps a reference to `world`.
  LrfSimulator(const EmbreeWorld& world, LrfParams params);
  const LrfParams& params() const { return params_; }
  int beams() const { return beams_; }
  /// One sweep from base pose X_WB (world). `seq` numbers the sweeps; `timestamp` in s.
  interfaces::LrfScan Scan(const Pose3& X_WB, std::uint64_t seed, std::uint64_t seq,
                           double timestamp) const;

 private:
  const EmbreeWorld& world_;
  LrfParams params_;
  int beams_ = 0;
  std::shared_ptr<const SurfaceTable> surfaces_;  // built once: materials do not change
};

}  // namespace mopad::sim
