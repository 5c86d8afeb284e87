#include "perception/point_cloud_ops.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <string>
#include <unordered_map>
#include <utility>

#include "common/error.h"

namespace mopad::perception {
namespace {

constexpr std::int64_t kHalfRange = std::int64_t{1} << 20;  // cells per half axis

// nanoflann dataset adaptor over a point vector.
struct PointsAdaptor {
  const Points* pts = nullptr;
  std::size_t kdtree_get_point_count() const { return pts->size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*pts)[i][static_cast<int>(dim)];
  }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using Tree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                        PointsAdaptor, 3, std::uint32_t>;

// Result set for "nearest within a radius": the search prunes with the current best.
class NearestWithin {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;
  explicit NearestWithin(double max_dist_sq) : worst_(max_dist_sq) {}
  std::size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(double dist, std::uint32_t index) {
    if (dist < worst_) {
      worst_ = dist;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  double worstDist() const { return worst_; }
  bool found() const { return found_; }
  std::uint32_t index() const { return index_; }

 private:
  double worst_;
  std::uint32_t index_ = 0;
  bool found_ = false;
};

}  // namespace

Points ScanPoints(const interfaces::TlsScan& scan, const Eigen::Isometry3d& X_FS, double min_range,
                  double max_range) {
  if (!(min_range >= 0.0) || !(max_range > min_range)) {
    throw InputError("", "bad range limits for ScanPoints",
                     "[" + std::to_string(min_range) + ", " + std::to_string(max_range) + "]",
                     "0 <= min_range < max_range");
  }
  Points out;
  out.reserve(scan.points.size());
  for (const auto& p : scan.points) {
    if (!p.valid() || p.range < min_range || p.range > max_range) continue;
    out.push_back(X_FS * Eigen::Vector3d(p.x, p.y, p.z));
  }
  return out;
}

Points Transform(const Points& p_A, const Eigen::Isometry3d& X_BA) {
  Points out(p_A.size());
  for (std::size_t i = 0; i < p_A.size(); ++i) out[i] = X_BA * p_A[i];
  return out;
}

std::int64_t VoxelKey(const Eigen::Vector3d& p, double voxel_size) {
  std::int64_t packed = 0;
  for (int a = 0; a < 3; ++a) {
    const double c = std::floor(p[a] / voxel_size);
    if (!std::isfinite(c) || c < -static_cast<double>(kHalfRange) ||
        c >= static_cast<double>(kHalfRange)) {
      throw InputError("", "point outside the voxel grid", std::to_string(p[a]),
                       "finite and within +-" + std::to_string(kHalfRange * voxel_size) + " m");
    }
    packed = (packed << 21) | (static_cast<std::int64_t>(c) + kHalfRange);
  }
  return packed;
}

std::vector<VoxelCell> Voxelize(const Points& points, double voxel_size) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size)) {
    throw InputError("", "voxel size must be positive", std::to_string(voxel_size), "> 0");
  }
  // Accumulate in point order (so each cell's sum has a fixed summation order), then sort the
  // cells by key: the output never depends on the hash table's iteration order.
  std::unordered_map<std::int64_t, std::uint32_t> slot;
  slot.reserve(points.size() / 4 + 16);
  std::vector<VoxelCell> cells;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    const std::int64_t key = VoxelKey(p, voxel_size);
    const auto [it, inserted] = slot.try_emplace(key, static_cast<std::uint32_t>(cells.size()));
    if (inserted) {
      cells.emplace_back();
      cells.back().key = key;
    }
    VoxelCell& c = cells[it->second];
    c.sum += p;
    ++c.count;
  }
  std::sort(cells.begin(), cells.end(),
            [](const VoxelCell& x, const VoxelCell& y) { return x.key < y.key; });
  return cells;
}

std::vector<VoxelCell> MergeVoxels(const std::vector<VoxelCell>& a,
                                   const std::vector<VoxelCell>& b) {
  std::vector<VoxelCell> out;
  out.reserve(a.size() + b.size());
  std::size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    if (j == b.size() || (i < a.size() && a[i].key < b[j].key)) {
      out.push_back(a[i++]);
    } else if (i == a.size() || b[j].key < a[i].key) {
      out.push_back(b[j++]);
    } else {
      VoxelCell c = a[i++];
      c.sum += b[j].sum;
      c.count += b[j++].count;
      out.push_back(c);
    }
  }
  return out;
}

Points VoxelDownsample(const Points& points, double voxel_size) {
  const std::vector<VoxelCell> cells = Voxelize(points, voxel_size);
  Points out(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) out[i] = cells[i].Centroid();
  return out;
}

// ---- KdTree3 ---------------------------------------------------------------------------------

struct KdTree3::Impl {
  Points points;
  PointsAdaptor adaptor;
  std::unique_ptr<Tree> tree;
};

KdTree3::KdTree3(Points points) : impl_(std::make_unique<Impl>()) {
  impl_->points = std::move(points);
  impl_->adaptor.pts = &impl_->points;
  impl_->tree =
      std::make_unique<Tree>(3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->tree->buildIndex();
}
KdTree3::~KdTree3() = default;
KdTree3::KdTree3(KdTree3&&) noexcept = default;
KdTree3& KdTree3::operator=(KdTree3&&) noexcept = default;

const Points& KdTree3::points() const { return impl_->points; }
std::size_t KdTree3::size() const { return impl_->points.size(); }

std::int64_t KdTree3::Nearest(const Eigen::Vector3d& q, double max_distance,
                              double* dist_sq) const {
  if (impl_->points.empty()) return -1;
  NearestWithin result(max_distance * max_distance);
  impl_->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
  if (!result.found()) return -1;
  if (dist_sq) *dist_sq = result.worstDist();
  return result.index();
}

void KdTree3::Knn(const Eigen::Vector3d& q, int k, std::vector<std::uint32_t>& indices,
                  std::vector<double>& dist_sq) const {
  const std::size_t kk =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), impl_->points.size());
  indices.resize(kk);
  dist_sq.resize(kk);
  if (kk == 0) return;
  const std::size_t n = impl_->tree->knnSearch(q.data(), kk, indices.data(), dist_sq.data());
  indices.resize(n);
  dist_sq.resize(n);
}

// ---- normals -----------------------------------------------------------------------------------

namespace {

void CheckNormalArgs(int k, double max_radius, int min_neighbours) {
  if (k < 3 || min_neighbours < 3 || min_neighbours > k || !(max_radius > 0.0)) {
    throw InputError("", "bad normal estimation parameters",
                     "k=" + std::to_string(k) +
                         " min_neighbours=" + std::to_string(min_neighbours) +
                         " max_radius=" + std::to_string(max_radius),
                     "3 <= min_neighbours <= k, max_radius > 0");
  }
}

// PCA normal of point i from its k nearest neighbours within max_radius (a pure function of the
// tree's point set and i).
Normal NormalAt(const KdTree3& tree, std::size_t i, int k, double r2, int min_neighbours,
                const Eigen::Vector3d& viewpoint, std::vector<std::uint32_t>& idx,
                std::vector<double>& d2) {
  const Points& pts = tree.points();
  tree.Knn(pts[i], k, idx, d2);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int m = 0;
  for (std::size_t j = 0; j < idx.size() && d2[j] <= r2; ++j, ++m) mean += pts[idx[j]];  // sorted
  if (m < min_neighbours) return Normal{};
  mean /= m;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // about the mean (two passes: exact)
  for (int j = 0; j < m; ++j) {
    const Eigen::Vector3d d = pts[idx[j]] - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);
  const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = ev.sum();
  Normal out;
  out.n = es.eigenvectors().col(0).normalized();
  if (out.n.dot(viewpoint - pts[i]) < 0.0) out.n = -out.n;
  out.curvature = sum > 0.0 ? ev[0] / sum : 1.0;
  out.valid = out.n.allFinite() && sum > 0.0;
  return out.valid ? out : Normal{};
}

}  // namespace

std::vector<Normal> EstimateNormals(const KdTree3& tree, int k, double max_radius,
                                    int min_neighbours, const Eigen::Vector3d& viewpoint) {
  CheckNormalArgs(k, max_radius, min_neighbours);
  std::vector<Normal> normals(tree.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tree.size(), 256), [&](const auto& range) {
    std::vector<std::uint32_t> idx;
    std::vector<double> d2;
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      normals[i] =
          NormalAt(tree, i, k, max_radius * max_radius, min_neighbours, viewpoint, idx, d2);
  });
  return normals;
}

void EstimateNormalsAt(const KdTree3& tree, const std::vector<std::uint32_t>& which, int k,
                       double max_radius, int min_neighbours, const Eigen::Vector3d& viewpoint,
                       std::vector<Normal>& normals) {
  CheckNormalArgs(k, max_radius, min_neighbours);
  if (normals.size() != tree.size()) {
    throw InputError("", "normals and tree sizes differ", std::to_string(normals.size()),
                     std::to_string(tree.size()));
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, which.size(), 256), [&](const auto& range) {
    std::vector<std::uint32_t> idx;
    std::vector<double> d2;
    for (std::size_t w = range.begin(); w != range.end(); ++w)
      normals[which[w]] =
          NormalAt(tree, which[w], k, max_radius * max_radius, min_neighbours, viewpoint, idx, d2);
  });
}

}  // namespace mopad::perception
