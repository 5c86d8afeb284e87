#pragma once
// A TLS scan's ranges on a coarse angular grid, for telling a point of one scan that another
// scan saw through: something that was there when one scan looked and was gone when the other
// looked (a person walking, a door that swung). This is the visibility test of dynamic-point
// removal in multi-scan maps (Schauer and Nuechter 2018, "The Peopleremover"; Pomerleau et al.
// 2014; Kim and Kim 2020, "Remove, then Revert"): a point is transient when another scan's
// beam towards it ran on past it. docs/navigation.md, "People and other transients".
//
// Each cell of the coarse grid keeps the smallest range of the scan's returns in its block of
// pool x pool scan cells (no return: unknown), so a point is seen through only when every beam
// near its direction passed it: a depth edge, a grazing wall or a thin object in front keeps
// it. Robot side: sensor data only.
//
// Frames and units: the scan's own frame S (the scanner), its pose in the map M given; metres,
// radians.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "interfaces/tls_scan.h"

namespace mopad::perception {

class RangeImage {
 public:
  /// Cells of about `cell_rad` (rad) on a side: blocks of round(cell_rad / the scan's step)
  /// scan cells, at least 1. `X_MS` is the scan's pose in the map.
  RangeImage(const interfaces::TlsScan& scan, const Eigen::Isometry3d& X_MS,
             double cell_rad = 0.007);

  /// True when this scan's beams towards `p_M` (map) all ran on more than `margin` (m) beyond
  /// it: the cell of its direction and the eight around it hold returns and none nearer than
  /// |p| + margin. False where the scan has no returns, outside its field of view, and nearer
  /// than `min_range` (m) to the scanner.
  bool SeesThrough(const Eigen::Vector3d& p_M, double margin, double min_range = 0.5) const;

  const Eigen::Isometry3d& X_MS() const { return X_MS_; }
  std::size_t Bytes() const { return near_.size() * sizeof(float); }

 private:
  Eigen::Isometry3d X_MS_ = Eigen::Isometry3d::Identity(), X_SM_ = Eigen::Isometry3d::Identity();
  int rows_ = 0, columns_ = 0;
  double azimuth_min_ = 0.0, azimuth_step_ = 1.0, elevation_max_ = 0.0, elevation_step_ = 1.0;
  int pool_a_ = 1, pool_e_ = 1;  ///< scan cells per grid cell in azimuth and elevation
  bool full_turn_ = false;       ///< the columns close the circle
  std::vector<float> near_;      ///< rows_ x columns_, the smallest range; NaN: no return
};

}  // namespace mopad::perception
