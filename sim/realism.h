#pragma once
// Realism profiles: how far the simulated world departs from an ideal one, so that a benchmark
// has a noise floor to rank methods against (docs/realism.md gives every value's source).
// `ideal` is the world as the instrument profiles describe it, byte for byte; `typical` and
// `hard` add what real buildings and real scanners do. World side: the robot never reads it.
//
// A profile holds the scanner's errors beyond its data-sheet noise (the instrument's residual
// calibration errors, drawn once per run from the run's seed: one run, one instrument; the
// camera's per-scan exposure and white balance) and the building's as-built geometry (applied
// by the scene generator to a generated scene: scenes/as_built.h) and its details
// (scenes/details_params.h), and the people walking through its rooms during a mission
// (sim/people.h); a profile keeps one name for all.

#include <cstdint>
#include <string>
#include <vector>

#include "common/params.h"
#include "scenes/as_built_params.h"
#include "scenes/details_params.h"
#include "sim/people.h"
#include "sim/tls_params.h"

namespace mopad::sim {

/// The scanner's realism. Fixed errors are drawn once per run (1 sigma here); per-scan ones are
/// sigmas the scanner draws for every scan (sim/tls_params.h).
struct ScannerRealism {
  /// deg, 1 sigma of each of the collimation, trunnion-axis and vertical-index errors, [0, 0.5]
  double axis_error_sigma_deg = 0.0;
  double range_scale_sigma_ppm = 0.0;  ///< ppm, 1 sigma of the range scale error, [0, 1000]
  /// m, range walk of a return at intensity 0 (TlsParams::low_signal_range_bias), [-0.1, 0.1]
  double low_signal_range_bias = 0.0;
  double exposure_sigma_stops = 0.0;  ///< stops, 1 sigma per scan, [0, 4]
  double white_balance_sigma = 0.0;   ///< 1 sigma of ln(red, blue gain) per scan, [0, 1]
  /// Daylight through the windows (TlsParams::window_light), in the units of the scene's
  /// ambient light, [0, 20]; and its change from scan to scan, stops, [0, 4]
  double window_light = 0.0;
  double window_light_sigma_stops = 0.0;
  /// deg, 1 sigma of each of the camera's roll, pitch and yaw from its calibration
  /// (TlsParams::camera_rpy_deg), drawn once per run, [0, 2]
  double camera_misalignment_sigma_deg = 0.0;

  template <class V>
  void Visit(V& v) {
    v("axis_error_sigma_deg", axis_error_sigma_deg, Bounds{0, 0.5});
    v("range_scale_sigma_ppm", range_scale_sigma_ppm, Bounds{0, 1000});
    v("low_signal_range_bias", low_signal_range_bias, Bounds{-0.1, 0.1});
    v("exposure_sigma_stops", exposure_sigma_stops, Bounds{0, 4});
    v("white_balance_sigma", white_balance_sigma, Bounds{0, 1});
    v("window_light", window_light, Bounds{0, 20});
    v("window_light_sigma_stops", window_light_sigma_stops, Bounds{0, 4});
    v("camera_misalignment_sigma_deg", camera_misalignment_sigma_deg, Bounds{0, 2});
  }
};

/// A realism profile and its values. YAML: `profile` names the starting point (a config that
/// names a profile gets that profile's values, then its own keys override them); the sections
/// follow.
struct RealismParams {
  std::string profile = "ideal";  ///< ideal | typical | hard
  ScannerRealism scanner;
  /// The building as built, applied to a generated scene before the run (a scene folder is
  /// used as it is). `seed` 0 draws the building from the run seed: one run, one building.
  scenes::AsBuiltParams geometry = NoGeometry();
  /// The building's details (skirting, trims, ducts, pipes, posters, door frames in the wall's
  /// colour, glazed doors), added to a generated scene like the geometry; `seed` 0 = the run's.
  scenes::DetailsParams details = NoDetails();
  /// People walking through the rooms during a mission (moving occluders, never in the truth);
  /// `seed` 0 = the run's.
  PeopleParams people;

  template <class V>
  void Visit(V& v) {
    const std::string named = profile;
    v("profile", profile);
    if (profile != named) StartFromProfile();
    v("scanner", scanner);
    v("geometry", geometry);
    v("details", details);
    v("people", people);
  }
  /// InputError when `profile` names no profile.
  void Validate() const;
  /// True when the profile changes the building (as-built geometry or details), which a run
  /// can do only to a scene it generates.
  bool ChangesTheBuilding() const { return geometry.Enabled() || details.Enabled(); }

 private:
  void StartFromProfile();  ///< this = RealismProfile(profile)
  static scenes::AsBuiltParams NoGeometry() {
    scenes::AsBuiltParams g;
    g.seed = 0;
    return g;
  }
  static scenes::DetailsParams NoDetails() {
    scenes::DetailsParams d;
    d.seed = 0;
    return d;
  }
};

/// The as-built parameters a run applies to its generated scene: `realism.geometry` with seed
/// 0 replaced by the run seed.
scenes::AsBuiltParams RunGeometry(const RealismParams& realism, std::uint64_t run_seed);
/// The details a run adds to its generated scene: `realism.details`, a zero seed replaced by the
/// run seed.
scenes::DetailsParams RunDetails(const RealismParams& realism, std::uint64_t run_seed);

/// The built-in profile of that name; InputError naming the known ones otherwise.
RealismParams RealismProfile(const std::string& name);
std::vector<std::string> RealismProfileNames();  ///< ideal, typical, hard

/// The scanner of a run: `base` with the realism's errors; the fixed ones drawn from `seed` (the
/// run seed: the same seed, the same instrument). A zero sigma leaves its field untouched, so
/// `ideal` returns `base` unchanged.
TlsParams RealisticTls(const TlsParams& base, const ScannerRealism& realism, std::uint64_t seed);

}  // namespace mopad::sim
