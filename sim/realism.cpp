#include "sim/realism.h"

#include "common/error.h"
#include "common/rng.h"

namespace mopad::sim {

RealismParams RealismProfile(const std::string& name) {
  RealismParams p;
  p.profile = name;
  if (name == "ideal") return p;
  ScannerRealism& s = p.scanner;
  if (name == "typical") {
    // A calibrated instrument in an office: docs/realism.md, "Scanner".
    s.axis_error_sigma_deg = 0.005;
    s.range_scale_sigma_ppm = 20.0;
    s.low_signal_range_bias = 0.002;
    s.exposure_sigma_stops = 0.3;
    s.white_balance_sigma = 0.05;
    // Finished walls and ceilings within DIN 18202 table 3 line 6: docs/realism.md, "As built".
    p.geometry.flatness_mm = 2.0;
    p.geometry.lean_sigma_deg = 0.05;
    // A furnished office: docs/realism.md, "Building details".
    p.details.skirting_height = 0.06;
    p.details.ducts_per_room = 0.5;
    p.details.pipes_per_room = 0.3;
    p.details.posters_per_room = 2.0;
    p.details.frames_in_wall_colour = 0.3;
    p.details.glazed_doors = 0.2;
    return p;
  }
  if (name == "hard") {
    // An instrument due for calibration, mixed daylight and lamps.
    s.axis_error_sigma_deg = 0.02;
    s.range_scale_sigma_ppm = 100.0;
    s.low_signal_range_bias = 0.005;
    s.exposure_sigma_stops = 0.7;
    s.white_balance_sigma = 0.12;
    s.window_light = 6.0;
    s.window_light_sigma_stops = 0.5;
    s.camera_misalignment_sigma_deg = 0.15;
    // Unfinished walls and slab undersides, DIN 18202 table 3 line 5.
    p.geometry.flatness_mm = 4.0;
    p.geometry.lean_sigma_deg = 0.1;
    // Every detail, more often; most frames painted with the walls.
    p.details.skirting_height = 0.08;
    p.details.ceiling_trim_height = 0.05;
    p.details.ducts_per_room = 1.0;
    p.details.pipes_per_room = 1.0;
    p.details.posters_per_room = 4.0;
    p.details.frames_in_wall_colour = 0.6;
    p.details.glazed_doors = 0.4;
    return p;
  }
  std::string known;
  for (const std::string& n : RealismProfileNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("", "parameter 'realism.profile' unknown", "'" + name + "'", "one of " + known);
}

std::vector<std::string> RealismProfileNames() { return {"ideal", "typical", "hard"}; }

void RealismParams::StartFromProfile() { *this = RealismProfile(profile); }

scenes::AsBuiltParams RunGeometry(const RealismParams& realism, std::uint64_t run_seed) {
  scenes::AsBuiltParams g = realism.geometry;
  if (g.seed == 0) g.seed = run_seed;
  return g;
}

scenes::DetailsParams RunDetails(const RealismParams& realism, std::uint64_t run_seed) {
  scenes::DetailsParams d = realism.details;
  if (d.seed == 0) d.seed = run_seed;
  return d;
}

void RealismParams::Validate() const { (void)RealismProfile(profile); }

TlsParams RealisticTls(const TlsParams& base, const ScannerRealism& r, std::uint64_t seed) {
  TlsParams p = base;
  // One stream per run: every draw is taken whatever the sigmas, so that one factor's sigma
  // does not move another's value.
  CounterRng rng(seed, "sim/instrument");
  const double c = rng.Normal(), i = rng.Normal(), v = rng.Normal(), scale = rng.Normal();
  if (r.axis_error_sigma_deg > 0.0) {
    p.collimation_error_deg += r.axis_error_sigma_deg * c;
    p.trunnion_axis_error_deg += r.axis_error_sigma_deg * i;
    p.vertical_index_error_deg += r.axis_error_sigma_deg * v;
  }
  if (r.range_scale_sigma_ppm > 0.0) p.range_scale_ppm += r.range_scale_sigma_ppm * scale;
  if (r.low_signal_range_bias != 0.0) p.low_signal_range_bias = r.low_signal_range_bias;
  if (r.exposure_sigma_stops > 0.0) p.exposure_sigma_stops = r.exposure_sigma_stops;
  if (r.white_balance_sigma > 0.0) p.white_balance_sigma = r.white_balance_sigma;
  if (r.window_light > 0.0) p.window_light = r.window_light;
  if (r.window_light_sigma_stops > 0.0) p.window_light_sigma_stops = r.window_light_sigma_stops;
  const double roll = rng.Normal(), pitch = rng.Normal(), yaw = rng.Normal();
  if (r.camera_misalignment_sigma_deg > 0.0) {
    p.camera_rpy_deg[0] += r.camera_misalignment_sigma_deg * roll;
    p.camera_rpy_deg[1] += r.camera_misalignment_sigma_deg * pitch;
    p.camera_rpy_deg[2] += r.camera_misalignment_sigma_deg * yaw;
  }
  return p;
}

}  // namespace mopad::sim
