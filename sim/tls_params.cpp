#include "sim/tls_params.h"

#include <string>
#include <vector>

#include "common/error.h"

namespace mopad::sim {

void TlsParams::Validate() const {
  ValidateParams(*this, "tls.");
  if (elevation_min_deg >= elevation_max_deg) {
    throw InputError("", "parameter 'tls.elevation_min_deg' must be below elevation_max_deg",
                     std::to_string(elevation_min_deg), "< " + std::to_string(elevation_max_deg));
  }
  if (range_accuracy < range_precision) {
    throw InputError(
        "", "parameter 'tls.range_accuracy' is the total error and must be >= range_precision",
        std::to_string(range_accuracy), ">= " + std::to_string(range_precision));
  }
  if (echo_mode != "first" && echo_mode != "strongest" && echo_mode != "last") {
    throw InputError("", "parameter 'tls.echo_mode' unknown", "'" + echo_mode + "'",
                     "first, strongest or last");
  }
  if (footprint_rays == 2) {
    throw InputError("", "parameter 'tls.footprint_rays' must be 1 or >= 3", "2", "1 or 3..64");
  }
  if (camera_offset.size() != 3 || camera_rpy_deg.size() != 3 || mount_xyz.size() != 3 ||
      mount_rpy_deg.size() != 3) {
    throw InputError("",
                     "parameters 'tls.camera_offset', 'tls.camera_rpy_deg', 'tls.mount_xyz' and "
                     "'tls.mount_rpy_deg' need 3 values");
  }
}

TlsParams TlsParams::NoiseFree() const {
  TlsParams p = *this;
  p.dropouts = false;
  p.range_precision = p.range_accuracy = p.range_offset = 0.0;
  p.intensity_noise = p.colour_noise = 0.0;
  p.tilt_sigma_deg = p.angle_noise_deg = 0.0;
  p.exposure_sigma_stops = p.white_balance_sigma = p.window_light_sigma_stops = 0.0;
  return p;
}

TlsParams TlsProfile(const std::string& name) {
  TlsParams p;
  if (name == "riegl_vz400") return p;
  if (name == "riegl_vz400_long_range") {
    // Data sheet, 100 kHz "long range" mode: 350 m at 20 %, 600 m at 90 %.
    p.name = name;
    p.pulse_rate_hz = 100000.0;
    p.range_ref = 350.0;
    p.reflectance_exponent = 0.358;  // ln(600/350) / ln(0.9/0.2)
    return p;
  }
  std::string known;
  for (const auto& n : TlsProfileNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("", "unknown TLS profile", "'" + name + "'", known);
}

std::vector<std::string> TlsProfileNames() { return {"riegl_vz400", "riegl_vz400_long_range"}; }

}  // namespace mopad::sim
