#include "modelling/roi.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/polygon.h"

namespace mopad::modelling {

const char* ToString(FaceKind kind) {
  switch (kind) {
    case FaceKind::kFloor:
      return "floor";
    case FaceKind::kCeiling:
      return "ceiling";
    case FaceKind::kWall:
      return "wall";
    case FaceKind::kColumn:
      return "column";
  }
  return "?";
}

int RoiFace::CellIndexOf(const Vec3& p_M) const {
  const Vec3 d = p_M - origin;
  const int iu = static_cast<int>(std::floor(d.dot(u_axis) / cell));
  const int iv = static_cast<int>(std::floor(d.dot(v_axis) / cell));
  if (iu < 0 || iv < 0 || iu >= nu || iv >= nv) return -1;
  return iv * nu + iu;
}

double Roi::CeilingAt(const Vec2& p) const {
  if (slopes.empty()) return ceiling_z;
  double z = level_ceiling ? ceiling_z : std::numeric_limits<double>::infinity();
  for (const auto& s : slopes) z = std::min(z, s.ZAt(p));
  return z;
}

bool Roi::ContainsPlan(const Vec2& p) const {
  if (empty() || !PointInPolygon(p, perimeter)) return false;
  for (const auto& c : columns) {
    if (PointInPolygon(p, c)) return false;
  }
  return true;
}

double Roi::Volume() const {
  if (empty()) return 0.0;
  double a = std::abs(SignedArea(perimeter));
  for (const auto& c : columns) a -= std::abs(SignedArea(c));
  return a * (ceiling_z - floor_z);
}

}  // namespace mopad::modelling
