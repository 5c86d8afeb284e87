#pragma once
// Wheel odometry and velocity commands: the robot's proprioception and actuation.

#include "common/frames.h"

namespace mopad::interfaces {

/// Integrated wheel odometry: pose of base_link in the odom frame. Drifts; never the true pose.
struct Odometry {
  double timestamp = 0.0;  ///< s
  Pose2 X_OB;              ///< base_link in odom
  double v = 0.0;          ///< m/s, measured forward speed
  double w = 0.0;          ///< rad/s, measured yaw rate
};

/// Commanded body velocity (like geometry_msgs/Twist restricted to the plane).
struct VelocityCommand {
  double v = 0.0;  ///< m/s, forward
  double w = 0.0;  ///< rad/s, CCW
};

}  // namespace mopad::interfaces
