#include "modelling/roi.h"

#include <cmath>

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
