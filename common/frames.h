#pragma once
// Frames and units. World frame is Z-up, REP-103 (x forward, y left, z up), metres, radians.
// Monogram names: X_WB is the pose of body B in world W; p_WP is point P in W.
// glTF is +Y up: kX_ZupFromYup is the one named conversion used by every loader and writer.

#include <Eigen/Geometry>
#include <cmath>

namespace mopad {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Pose3 = Eigen::Isometry3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

/// Rotation taking glTF's Y-up coordinates to our Z-up world: +90 deg about x
/// (glTF (x, y, z) -> world (x, -z, y)). Its inverse, -90 deg about x, is what a Z-up scene
/// writes as glTF node rotation, quaternion [-0.7071068, 0, 0, 0.7071068] in glTF's x,y,z,w.
inline Eigen::Matrix3d ZupFromYup() {
  Eigen::Matrix3d r;
  r << 1, 0, 0,  //
      0, 0, -1,  //
      0, 1, 0;
  return r;
}
inline Eigen::Matrix3d YupFromZup() { return ZupFromYup().transpose(); }

/// Planar pose (x, y, yaw) used by the base, odometry and navigation.
struct Pose2 {
  double x = 0.0;    ///< m
  double y = 0.0;    ///< m
  double yaw = 0.0;  ///< rad, CCW from +x

  Pose3 To3d(double z = 0.0) const {
    Pose3 p = Pose3::Identity();
    p.translation() = Vec3(x, y, z);
    p.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
    return p;
  }
};

/// Wraps an angle to (-pi, pi].
inline double WrapAngle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

}  // namespace mopad
