#include "perception/range_image.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mopad::perception {

namespace {
constexpr double kTwoPi = 6.283185307179586;
}

RangeImage::RangeImage(const interfaces::TlsScan& scan, const Eigen::Isometry3d& X_MS,
                       double cell_rad)
    : X_MS_(X_MS), X_SM_(X_MS.inverse()) {
  if (scan.rows == 0 || scan.columns == 0 || !(scan.azimuth_step > 0.0) ||
      !(scan.elevation_step > 0.0) || scan.points.size() != std::size_t{scan.rows} * scan.columns)
    return;  // no grid: sees through nothing
  const int pa = std::max(1, static_cast<int>(std::lround(cell_rad / scan.azimuth_step)));
  const int pe = std::max(1, static_cast<int>(std::lround(cell_rad / scan.elevation_step)));
  rows_ = (static_cast<int>(scan.rows) + pe - 1) / pe;
  columns_ = (static_cast<int>(scan.columns) + pa - 1) / pa;
  azimuth_min_ = scan.azimuth_min;
  elevation_max_ = scan.elevation_max;
  azimuth_step_ = scan.azimuth_step;
  elevation_step_ = scan.elevation_step;
  pool_a_ = pa;
  pool_e_ = pe;
  // Columns cover the circle when one more step would repeat the first.
  full_turn_ = (scan.columns + 1) * scan.azimuth_step >= kTwoPi - 1e-9;
  near_.assign(static_cast<std::size_t>(rows_) * columns_, std::numeric_limits<float>::quiet_NaN());
  for (std::uint32_t r = 0; r < scan.rows; ++r)
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const interfaces::TlsPoint& p = scan.at(r, c);
      if (!p.valid()) continue;
      float& v = near_[static_cast<std::size_t>(static_cast<int>(r) / pe) * columns_ +
                       static_cast<int>(c) / pa];
      if (!(v <= p.range)) v = p.range;  // NaN or farther: this one
    }
}

bool RangeImage::SeesThrough(const Eigen::Vector3d& p_M, double margin, double min_range) const {
  if (near_.empty()) return false;
  const Eigen::Vector3d p = X_SM_ * p_M;
  const double r = p.norm();
  if (!(r >= min_range)) return false;
  double az = std::atan2(p.y(), p.x()) - azimuth_min_;
  az -= kTwoPi * std::floor(az / kTwoPi);  // [0, 2 pi)
  const double el = std::asin(std::clamp(p.z() / r, -1.0, 1.0));
  // The nearest scan cell, then its block.
  const double u = std::floor(az / azimuth_step_ + 0.5),
               v = std::floor((elevation_max_ - el) / elevation_step_ + 0.5);
  const int c = static_cast<int>(std::floor(u / pool_a_));
  const int rw = static_cast<int>(std::floor(v / pool_e_));
  const float need = static_cast<float>(r + margin);
  for (int dr = -1; dr <= 1; ++dr) {
    const int row = rw + dr;
    if (row < 0 || row >= rows_) return false;
    for (int dc = -1; dc <= 1; ++dc) {
      int col = c + dc;
      if (full_turn_) col = ((col % columns_) + columns_) % columns_;
      if (col < 0 || col >= columns_) return false;
      const float v = near_[static_cast<std::size_t>(row) * columns_ + col];
      if (!(v > need)) return false;  // nearer, or no return (NaN): no proof
    }
  }
  return true;
}

}  // namespace mopad::perception
