#pragma once
// Parameters of the terrestrial laser scanner model (docs/sensors.md explains every term and
// cites its source). Defaults are the `riegl_vz400` profile (RIEGL VZ-400 data sheet,
// 2014-09-19: 300 kHz "high speed" mode). Units: SI, angles in degrees only here at the human
// edge (`_deg`), converted once by the scanner.

#include <string>
#include <vector>

#include "common/params.h"

namespace mopad::sim {

struct TlsParams {
  std::string name = "riegl_vz400";  ///< profile name, for the effective config

  // ---- field of view and sampling (scanner frame: x forward, y left, z up)
  double azimuth_min_deg = 0.0;      ///< deg, first column's azimuth, CCW from +x, [-360, 360]
  double azimuth_span_deg = 360.0;   ///< deg, (0, 360]; 360 = full turn without a repeated column
  double elevation_max_deg = 60.0;   ///< deg, row 0 (top), [-90, 90]
  double elevation_min_deg = -40.0;  ///< deg, last row at or above this, [-90, 90]
  double step_deg = 0.2;             ///< deg, azimuth step, [0.0024, 10]
  double vertical_step_deg = 0.0;    ///< deg, elevation step, 0 = same as step_deg, [0, 10]
  double pulse_rate_hz = 300000.0;   ///< Hz, measurement rate (timestamps), [1, 1e7]

  // ---- detection and range limits
  double range_min = 1.5;  ///< m, returns closer than this are not reported, [0, 100]
  /// m, maximum range at reflectance_ref and normal incidence (VZ-400 300 kHz: 160 m at 20 %).
  double range_ref = 160.0;
  double reflectance_ref = 0.2;  ///< [0.001, 1]
  /// R_max = range_ref * (rho_eff / reflectance_ref)^k; 0.372 fits the data sheet's 160 m at
  /// 20 % and 280 m at 90 % (0.5 would be the pure 1/R^2 radar law).
  double reflectance_exponent = 0.372;
  double detection_sharpness = 8.0;  ///< gamma in P_det = 1 / (1 + s^-gamma), [0.5, 100]
  /// Effective reflectance rho*cos(incidence) + specular lobe below which returns thin out:
  /// P = rho_eff / min_reflectance (dark, grazing and specular dropouts), [0, 1].
  double min_reflectance = 0.03;
  bool dropouts = true;  ///< false: every surface hit beyond range_min returns

  // ---- ranging noise (see docs/sensors.md: accuracy = total error, precision = repeatability)
  double range_precision = 0.003;  ///< m, 1 sigma per-point noise at normal incidence, [0, 1]
  /// m, 1 sigma total error. The per-scan systematic part sqrt(accuracy^2 - precision^2) is a
  /// range bias drawn once per scan. Must be >= range_precision. [0, 1]
  double range_accuracy = 0.005;
  double range_offset = 0.0;  ///< m, fixed calibration offset added to every range, [-1, 1]
  /// sigma(alpha) = precision / cos(alpha)^k (Soudarissanane et al. 2011), [0, 4]
  double incidence_noise_exponent = 1.0;
  double max_noise_incidence_deg = 85.0;  ///< deg, cap of the 1/cos growth, [0, 89.9]

  // ---- beam and echoes
  double beam_divergence_mrad = 0.3;  ///< mrad, full angle at 1/e^2, [0, 100]
  double beam_exit_diameter = 0.007;  ///< m, at the exit aperture, [0, 1]
  /// Sub-rays per pulse: 1 = a single ray; K >= 3 = centre + (K-1) on a ring at
  /// footprint_ring * beam radius, Gaussian-weighted. [1, 64]
  int footprint_rays = 1;
  double footprint_ring = 0.7;  ///< fraction of the 1/e^2 beam radius, (0, 2]
  /// m, sub-ray echoes closer than this in range merge into one echo whose range is their
  /// energy-weighted mean (a mixed pixel); farther apart they are separate echoes. [0, 100]
  double echo_separation = 0.5;
  std::string echo_mode = "strongest";  ///< which echo is reported: first | strongest | last
  int max_transmissions = 4;  ///< glass layers a ray may pass (Material::transmission), [0, 64]

  // ---- intensity and colour
  double intensity_attenuation = 0.01;  ///< 1/m, residual range fall-off of intensity, [0, 10]
  double intensity_noise = 0.01;        ///< 1 sigma, absolute, [0, 1]
  double ambient_light = 0.6;           ///< illumination from all directions, [0, 4]
  double top_light = 0.4;     ///< extra light on up-facing surfaces (ceiling lamps), [0, 4]
  double colour_noise = 2.0;  ///< sRGB levels, 1 sigma per channel, [0, 255]
  /// m, camera centre in the scanner frame; non-zero: colour comes from what the camera sees
  /// (parallax at occlusion edges, one extra ray per point).
  std::vector<double> camera_offset = {0.0, 0.0, 0.0};
  /// deg, the camera's rotation from its calibration (roll, pitch, yaw about the scanner's
  /// axes, each [-5, 5]): the colour of a point is what the camera sees along the calibrated
  /// direction turned by it (a residual of the camera-to-scanner calibration, or a bumped rig).
  /// Non-zero: one extra ray per point, as camera_offset.
  std::vector<double> camera_rpy_deg = {0.0, 0.0, 0.0};

  // ---- axes and mount
  double tilt_sigma_deg = 0.008;  ///< deg, per-scan levelling error, roll and pitch, [0, 10]
  /// deg, per-pulse beam-direction jitter, 1 sigma, [0, 1]. Not in the data sheet (0.0005 deg
  /// is its angular *resolution*, which would move points < 0.1 mm at 10 m); off by default.
  double angle_noise_deg = 0.0;
  /// deg, the instrument's residual axis errors after calibration (Lichti 2007, docs/realism.md):
  /// the beam is not perpendicular to the trunnion axis (collimation c: horizontal angle error
  /// c / cos(el)), the trunnion axis is not perpendicular to the vertical axis (i: i tan(el)),
  /// the elevation encoder's zero is off (vertical index v: el + v). The true beam carries them;
  /// points are reported along the encoder angles. [-1, 1] each; 0: an ideal instrument.
  double collimation_error_deg = 0.0;
  double trunnion_axis_error_deg = 0.0;
  double vertical_index_error_deg = 0.0;
  /// ppm, range-proportional error (distance-meter scale), [-1000, 1000]
  double range_scale_ppm = 0.0;
  /// m, extra range of a return at intensity 0, falling linearly to 0 at
  /// `low_signal_intensity`: the range walk of weak echoes (dark surfaces, grazing incidence;
  /// Zamecnikova et al. 2014). [-0.1, 0.1]
  double low_signal_range_bias = 0.0;
  double low_signal_intensity = 0.5;  ///< intensity at and above which there is none, (0, 1]
  /// Colour camera, per scan: exposure error, 1 sigma in stops (log2 of a gain on all three
  /// channels), and white balance, 1 sigma of the natural log of the red and blue gains (green
  /// fixed). Applied in linear light to the reported colour. [0, 4] and [0, 1]; 0: off.
  double exposure_sigma_stops = 0.0;
  double white_balance_sigma = 0.0;
  /// Daylight through the windows, in the units of ambient_light: a window of area A at
  /// distance r adds window_light A cos(a_w) cos(a_p) / (pi r^2) to a surface's light (a_w, a_p:
  /// the angles of the line between them to the window's and the surface's normals; the form
  /// factor of a small area), from the windows of the surface's own room, each as far as it is
  /// visible from the surface (soft shadows: one ray per window to a random point of its pane).
  /// [0, 20]; 0: off.
  double window_light = 0.0;
  /// stops, 1 sigma of the daylight's change from scan to scan (clouds, the time of day), [0, 4]
  double window_light_sigma_stops = 0.0;
  std::vector<double> mount_xyz = {0.0, 0.0, 1.4};      ///< m, scanner centre in base_link (X_BS)
  std::vector<double> mount_rpy_deg = {0.0, 0.0, 0.0};  ///< deg, X_BS rotation (roll, pitch, yaw)

  template <class V>
  void Visit(V& v) {
    v("name", name);
    v("azimuth_min_deg", azimuth_min_deg, Bounds{-360, 360});
    v("azimuth_span_deg", azimuth_span_deg, Bounds{1e-6, 360});
    v("elevation_max_deg", elevation_max_deg, Bounds{-90, 90});
    v("elevation_min_deg", elevation_min_deg, Bounds{-90, 90});
    v("step_deg", step_deg, Bounds{0.0024, 10});
    v("vertical_step_deg", vertical_step_deg, Bounds{0, 10});
    v("pulse_rate_hz", pulse_rate_hz, Bounds{1, 1e7});
    v("range_min", range_min, Bounds{0, 100});
    v("range_ref", range_ref, Bounds{0.1, 1e4});
    v("reflectance_ref", reflectance_ref, Bounds{0.001, 1});
    v("reflectance_exponent", reflectance_exponent, Bounds{0, 2});
    v("detection_sharpness", detection_sharpness, Bounds{0.5, 100});
    v("min_reflectance", min_reflectance, Bounds{0, 1});
    v("dropouts", dropouts);
    v("range_precision", range_precision, Bounds{0, 1});
    v("range_accuracy", range_accuracy, Bounds{0, 1});
    v("range_offset", range_offset, Bounds{-1, 1});
    v("incidence_noise_exponent", incidence_noise_exponent, Bounds{0, 4});
    v("max_noise_incidence_deg", max_noise_incidence_deg, Bounds{0, 89.9});
    v("beam_divergence_mrad", beam_divergence_mrad, Bounds{0, 100});
    v("beam_exit_diameter", beam_exit_diameter, Bounds{0, 1});
    v("footprint_rays", footprint_rays, Bounds{1, 64});
    v("footprint_ring", footprint_ring, Bounds{1e-6, 2});
    v("echo_separation", echo_separation, Bounds{0, 100});
    v("echo_mode", echo_mode);
    v("max_transmissions", max_transmissions, Bounds{0, 64});
    v("intensity_attenuation", intensity_attenuation, Bounds{0, 10});
    v("intensity_noise", intensity_noise, Bounds{0, 1});
    v("ambient_light", ambient_light, Bounds{0, 4});
    v("top_light", top_light, Bounds{0, 4});
    v("colour_noise", colour_noise, Bounds{0, 255});
    v("camera_offset", camera_offset, Bounds{-10, 10});
    v("camera_rpy_deg", camera_rpy_deg, Bounds{-5, 5});
    v("tilt_sigma_deg", tilt_sigma_deg, Bounds{0, 10});
    v("angle_noise_deg", angle_noise_deg, Bounds{0, 1});
    v("collimation_error_deg", collimation_error_deg, Bounds{-1, 1});
    v("trunnion_axis_error_deg", trunnion_axis_error_deg, Bounds{-1, 1});
    v("vertical_index_error_deg", vertical_index_error_deg, Bounds{-1, 1});
    v("range_scale_ppm", range_scale_ppm, Bounds{-1000, 1000});
    v("low_signal_range_bias", low_signal_range_bias, Bounds{-0.1, 0.1});
    v("low_signal_intensity", low_signal_intensity, Bounds{1e-3, 1});
    v("exposure_sigma_stops", exposure_sigma_stops, Bounds{0, 4});
    v("white_balance_sigma", white_balance_sigma, Bounds{0, 1});
    v("window_light", window_light, Bounds{0, 20});
    v("window_light_sigma_stops", window_light_sigma_stops, Bounds{0, 4});
    v("mount_xyz", mount_xyz, Bounds{-100, 100});
    v("mount_rpy_deg", mount_rpy_deg, Bounds{-360, 360});
  }

  /// Bounds plus cross-field rules; throws InputError naming the field.
  void Validate() const;
  /// The same parameters with every stochastic effect off (noise, bias, tilt, jitter,
  /// dropouts, intensity and colour noise, exposure and white balance). Glass still transmits
  /// with its probability; the instrument's fixed errors (axes, scale, range walk) stay.
  TlsParams NoiseFree() const;
};

/// Built-in profile by name ("riegl_vz400", "riegl_vz400_long_range"); InputError otherwise.
TlsParams TlsProfile(const std::string& name);
std::vector<std::string> TlsProfileNames();

}  // namespace mopad::sim
