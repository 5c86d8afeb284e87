#pragma once
// A 2D laser range finder sweep (like sensor_msgs/LaserScan): ranges in the sensor's x-y plane,
// counter-clockwise from angle_min. A reading of range_max or beyond means "no return".

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace mopad::interfaces {

struct LrfScan {
  std::string frame;  ///< e.g. "lrf_base", "lrf_top"
  std::uint64_t seq = 0;
  double timestamp = 0.0;          ///< s, simulation time
  double angle_min = 0.0;          ///< rad
  double angle_increment = 0.0;    ///< rad
  double range_min = 0.0;          ///< m
  double range_max = 0.0;          ///< m; readings >= range_max are no-return
  std::vector<float> ranges;       ///< m
  std::vector<float> intensities;  ///< [0, 1], may be empty
  Eigen::Isometry3d X_BL = Eigen::Isometry3d::Identity();  ///< calibrated mount on base_link
};

}  // namespace mopad::interfaces
