#pragma once
// A terrestrial laser scan as a real scanner reports it: an organised grid of returns in the
// scanner frame (x forward, y left, z up at the scanner's optical centre), with colour,
// intensity and timing. It carries no ground truth (no element ids, no true pose).

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace mopad::interfaces {

struct TlsPoint {
  float x = 0, y = 0, z = 0;  ///< m, scanner frame
  std::uint8_t r = 0, g = 0, b = 0;
  float intensity = 0;       ///< [0, 1], calibrated reflectance-like return strength
  float range = 0;           ///< m, measured; 0 = no return
  std::uint32_t row = 0;     ///< elevation index, 0 = top
  std::uint32_t column = 0;  ///< azimuth index
  double timestamp = 0;      ///< s, simulation time of the pulse
  bool valid() const { return range > 0.0f; }
};

struct TlsScan {
  std::uint64_t scan_id = 0;
  double start_time = 0.0;                           ///< s, simulation time
  std::uint32_t rows = 0;                            ///< elevation steps (top to bottom)
  std::uint32_t columns = 0;                         ///< azimuth steps (counter-clockwise from +x)
  double azimuth_min = 0.0, azimuth_step = 0.0;      ///< rad
  double elevation_max = 0.0, elevation_step = 0.0;  ///< rad, row r at elevation_max - r*step
  /// Calibrated mount of the scanner on the base (base_link -> tls); a robot knows this.
  Eigen::Isometry3d X_BS = Eigen::Isometry3d::Identity();
  /// The robot's own estimate of the scanner pose when the scan was taken (map frame), if the
  /// producer has one (e.g. `mopad scan --pose` or the localiser); identity otherwise.
  Eigen::Isometry3d X_MS_estimate = Eigen::Isometry3d::Identity();
  std::vector<TlsPoint> points;  ///< rows * columns, row-major; invalid cells have range 0

  const TlsPoint& at(std::uint32_t row, std::uint32_t col) const {
    return points[static_cast<std::size_t>(row) * columns + col];
  }
};

}  // namespace mopad::interfaces
