#include "io/tum.h"

#include <cmath>
#include <cstdio>

namespace mopad::io {

std::string TumLine(double t, const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.rotation());
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", t,
                X.translation().x(), X.translation().y(), X.translation().z(), q.x(), q.y(), q.z(),
                q.w());
  return buf;
}

std::string TumLinePlanar(double t, double x, double y, double yaw) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.3f %.6f %.6f 0.000000 0.000000 0.000000 %.9f %.9f\n", t, x, y,
                std::sin(0.5 * yaw), std::cos(0.5 * yaw));
  return buf;
}

}  // namespace mopad::io
