#pragma once
// TUM trajectory files (`t tx ty tz qx qy qz qw`, one pose per line; the format of the TUM RGB-D
// benchmark tools and evo): the robot's trajectories and scan poses. Deterministic text.

#include <Eigen/Geometry>
#include <string>

namespace mopad::io {

/// One line for a 3D pose: time with microseconds, position to the micrometre, the quaternion
/// (x, y, z, w) to 1e-9.
std::string TumLine(double t, const Eigen::Isometry3d& X);
/// One line for a planar pose (x, y, yaw in rad; z = 0, rotation about z): time with
/// milliseconds (control steps), position to the micrometre, the quaternion to 1e-9.
std::string TumLinePlanar(double t, double x, double y, double yaw);

}  // namespace mopad::io
