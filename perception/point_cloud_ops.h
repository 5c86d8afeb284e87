#pragma once
// Point-cloud building blocks for registration and maps: scan -> points, voxel-grid
// downsampling, a 3D kd-tree (nanoflann, kept out of this header) and PCA normals.
//
// Determinism: every function returns the same bytes for the same input, whatever the number
// of TBB threads — voxel output is ordered by voxel key (x-major), per-point work is
// independent and reductions run in a fixed order.
// Units: metres; frames are whatever frame the caller's points are in.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "interfaces/tls_scan.h"

namespace mopad::perception {

using Points = std::vector<Eigen::Vector3d>;

/// The valid returns of `scan` with range in [min_range, max_range], mapped by `X_FS` (scanner
/// frame S to the caller's frame F), in grid order (row-major). InputError on bad bounds.
Points ScanPoints(const interfaces::TlsScan& scan,
                  const Eigen::Isometry3d& X_FS = Eigen::Isometry3d::Identity(),
                  double min_range = 0.0, double max_range = 1e9);

/// Applies X_BA to every point (A -> B).
Points Transform(const Points& p_A, const Eigen::Isometry3d& X_BA);

/// One occupied voxel: integer cell, sum of its points and their count.
struct VoxelCell {
  std::int64_t key = 0;  ///< packed cell index (VoxelKey), the sort order
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::uint32_t count = 0;
  Eigen::Vector3d Centroid() const { return sum / static_cast<double>(count); }
};

/// Packs the cell of `p` (floor(p / voxel_size)) into 64 bits (21 bits per axis, cells within
/// +-2^20 of the origin). InputError for non-finite points or points out of that range.
std::int64_t VoxelKey(const Eigen::Vector3d& p, double voxel_size);

/// Voxel cells of `points` sorted by key; non-finite points are skipped. InputError if
/// voxel_size <= 0.
std::vector<VoxelCell> Voxelize(const Points& points, double voxel_size);

/// Merges two key-sorted cell lists (sums and counts of equal keys add), keeping the order.
std::vector<VoxelCell> MergeVoxels(const std::vector<VoxelCell>& a,
                                   const std::vector<VoxelCell>& b);

/// One point per occupied voxel: the centroid of its points, in voxel-key order.
Points VoxelDownsample(const Points& points, double voxel_size);

/// Exact nearest-neighbour queries over a fixed point set (nanoflann kd-tree, L2). Keeps a copy
/// of the points. Const queries are thread-safe.
class KdTree3 {
 public:
  explicit KdTree3(Points points);
  ~KdTree3();
  KdTree3(KdTree3&&) noexcept;
  KdTree3& operator=(KdTree3&&) noexcept;
  KdTree3(const KdTree3&) = delete;
  KdTree3& operator=(const KdTree3&) = delete;

  const Points& points() const;
  std::size_t size() const;
  /// Index of the nearest point within `max_distance` (squared distance in `dist_sq`), or -1.
  std::int64_t Nearest(const Eigen::Vector3d& q, double max_distance,
                       double* dist_sq = nullptr) const;
  /// Up to k nearest points, closest first; a pure function of the point set and the query.
  void Knn(const Eigen::Vector3d& q, int k, std::vector<std::uint32_t>& indices,
           std::vector<double>& dist_sq) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A surface normal from PCA of a point's neighbourhood.
struct Normal {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  ///< unit; zero if invalid
  double curvature = 1.0;  ///< lambda_min / (sum of eigenvalues): 0 plane, 1/3 isotropic
  bool valid = false;      ///< at least `min_neighbours` points within max_radius
};

/// PCA normals of `tree`'s points from their k nearest neighbours within `max_radius` (the
/// point itself included); valid with at least `min_neighbours` (>= 3) of them. Normals point
/// towards `viewpoint` (n . (viewpoint - p) >= 0). Parallel over points, deterministic.
std::vector<Normal> EstimateNormals(const KdTree3& tree, int k, double max_radius,
                                    int min_neighbours = 5,
                                    const Eigen::Vector3d& viewpoint = Eigen::Vector3d::Zero());
/// The same for the points `which` only: normals[which[i]] is (re)computed, the others are
/// left as they are (normals.size() must equal tree.size()). Used for incremental map updates.
void EstimateNormalsAt(const KdTree3& tree, const std::vector<std::uint32_t>& which, int k,
                       double max_radius, int min_neighbours, const Eigen::Vector3d& viewpoint,
                       std::vector<Normal>& normals);

}  // namespace mopad::perception
