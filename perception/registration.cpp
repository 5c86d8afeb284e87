#include "perception/registration.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <unordered_set>
#include <utility>

#include "common/error.h"
#include "common/format.h"
#include "common/frames.h"

namespace mopad::perception {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

constexpr std::size_t kBlock = 1024;  // points per reduction block (fixed: determinism)

enum class Kernel { kNone, kHuber, kTukey, kCauchy };

Kernel ParseKernel(const std::string& name) {
  if (name == "none") return Kernel::kNone;
  if (name == "huber") return Kernel::kHuber;
  if (name == "tukey") return Kernel::kTukey;
  if (name == "cauchy") return Kernel::kCauchy;
  throw InputError("", "parameter 'robust_kernel' unknown", "'" + name + "'",
                   "none | huber | tukey | cauchy");
}

// IRLS weight of a residual r for kernel scale k.
double KernelWeight(Kernel kernel, double r, double k) {
  const double a = std::abs(r);
  switch (kernel) {
    case Kernel::kNone:
      return 1.0;
    case Kernel::kHuber:
      return a <= k ? 1.0 : k / a;
    case Kernel::kTukey: {
      if (a >= k) return 0.0;
      const double u = 1.0 - (r / k) * (r / k);
      return u * u;
    }
    case Kernel::kCauchy:
      return 1.0 / (1.0 + (r / k) * (r / k));
  }
  return 1.0;
}

// Sums of one correspondence pass (per block, then reduced in block order).
struct Accum {
  Mat6 H = Mat6::Zero();    // sum w J J^T, J = [(p - c) x n; n]
  Vec6 g = Vec6::Zero();    // sum w J r
  double weight = 0.0;      // sum w
  double lever2 = 0.0;      // sum w |p - c|^2
  double r2 = 0.0;          // sum r^2 (unweighted) over planar matches
  std::size_t matched = 0;  // source points with a map point within the distance
  std::size_t planar = 0;   // of which the map point has a usable normal
  void Add(const Accum& o) {
    H += o.H;
    g += o.g;
    weight += o.weight;
    lever2 += o.lever2;
    r2 += o.r2;
    matched += o.matched;
    planar += o.planar;
  }
};

Accum Correspond(const Points& src, const Eigen::Isometry3d& T, const Eigen::Vector3d& c,
                 const PointMap& map, double max_dist, Kernel kernel, double kernel_scale,
                 double max_curvature, bool same_side) {
  const std::size_t blocks = (src.size() + kBlock - 1) / kBlock;
  std::vector<Accum> partial(blocks);
  const Points& q = map.points();
  const std::vector<Normal>& normals = map.normals();
  const std::vector<Eigen::Vector3f>& views = map.views();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      Accum& acc = partial[b];
      const std::size_t end = std::min(src.size(), (b + 1) * kBlock);
      for (std::size_t i = b * kBlock; i < end; ++i) {
        const Eigen::Vector3d p = T * src[i];
        const std::int64_t j = map.tree().Nearest(p, max_dist);
        if (j < 0) continue;
        const Normal& nm = normals[static_cast<std::size_t>(j)];
        // A map point seen from the other side of its plane is another surface (the other face
        // of a wall): no correspondence.
        if (same_side && nm.valid) {
          const Eigen::Vector3d view = views[static_cast<std::size_t>(j)].cast<double>();
          if (nm.n.dot(view) * nm.n.dot(T.translation() - p) < 0.0) continue;
        }
        ++acc.matched;
        if (!nm.valid || nm.curvature > max_curvature) continue;
        ++acc.planar;
        const double r = nm.n.dot(p - q[static_cast<std::size_t>(j)]);
        acc.r2 += r * r;
        const double w = KernelWeight(kernel, r, kernel_scale);
        if (w <= 0.0) continue;
        const Eigen::Vector3d arm = p - c;
        Vec6 J;
        J.head<3>() = arm.cross(nm.n);
        J.tail<3>() = nm.n;
        acc.H.noalias() += w * J * J.transpose();
        acc.g.noalias() += (w * r) * J;
        acc.weight += w;
        acc.lever2 += w * arm.squaredNorm();
      }
    }
  });
  Accum total;
  for (const Accum& a : partial) total.Add(a);
  return total;
}

// The Gauss-Newton system restricted to the active DoF, in homogeneous units (rotation scaled by
// the RMS lever arm L) and normalised by the total weight. idx maps reduced -> full parameters.
struct Reduced {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  std::vector<int> idx;
  double lever = 1.0;
};

Reduced Reduce(const Accum& a, int dof) {
  Reduced red;
  red.idx = dof == 6 ? std::vector<int>{0, 1, 2, 3, 4, 5} : std::vector<int>{2, 3, 4, 5};
  red.lever = a.weight > 0.0 ? std::max(std::sqrt(a.lever2 / a.weight), 1e-3) : 1.0;
  const int n = static_cast<int>(red.idx.size());
  red.H.resize(n, n);
  red.g.resize(n);
  for (int r = 0; r < n; ++r) {
    const double sr = red.idx[r] < 3 ? 1.0 / red.lever : 1.0;
    red.g[r] = a.g[red.idx[r]] * sr / a.weight;
    for (int c = 0; c < n; ++c) {
      const double sc = red.idx[c] < 3 ? 1.0 / red.lever : 1.0;
      red.H(r, c) = a.H(red.idx[r], red.idx[c]) * sr * sc / a.weight;
    }
  }
  return red;
}

}  // namespace

void IcpParams::Validate() const {
  ValidateParams(*this);
  if (dof != 4 && dof != 6) {
    throw InputError("", "parameter 'dof' must be 4 or 6", std::to_string(dof), "4 | 6");
  }
  ParseKernel(robust_kernel);
  if (max_correspondence.empty()) {
    throw InputError("", "parameter 'max_correspondence' is empty", "[]", "one distance per stage");
  }
  if (!(min_range < max_range)) {
    throw InputError("", "parameter 'min_range' must be below 'max_range'",
                     std::to_string(min_range) + " >= " + std::to_string(max_range),
                     "min_range < max_range");
  }
}

// ---- PointMap ----------------------------------------------------------------------------------

// Nearest return per direction bin of one added scan, seen from its origin.
struct RangeImage {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  int n_az = 0, n_el = 0;
  double bin = 0.0;             // rad
  std::vector<float> nearest;   // n_el * n_az, +inf = no return
  std::vector<float> farthest;  // idem, 0 = no return
  float reach = 0.0f;           // m, the farthest return of all bins
  // Bin of direction d (non-zero), or -1.
  std::int64_t Bin(const Eigen::Vector3d& d, double r) const {
    const int a = std::clamp(static_cast<int>((std::atan2(d.y(), d.x()) + kPi) / bin), 0, n_az - 1);
    const int e = std::clamp(
        static_cast<int>((std::asin(std::clamp(d.z() / r, -1.0, 1.0)) + 0.5 * kPi) / bin), 0,
        n_el - 1);
    return static_cast<std::int64_t>(e) * n_az + a;
  }
};

struct PointMap::Impl {
  IcpParams params;
  std::vector<VoxelCell> cells;
  Points centroids;                    // per cell
  std::vector<Normal> normals;
  std::vector<Eigen::Vector3f> views;  // per merged cell, as PointMap::views()
  std::vector<std::shared_ptr<const RangeImage>> images;  // shared with Local maps
  std::size_t last_recomputed = 0;
  // Over `centroids`, built on first use after a change: an Add needs only the trees of the
  // neighbourhoods it touches, a registration only that of the map near its scan (Local).
  mutable std::unique_ptr<KdTree3> tree;
  mutable std::mutex tree_mutex;
};

PointMap::PointMap(const IcpParams& params) : impl_(std::make_unique<Impl>()) {
  params.Validate();
  impl_->params = params;
}
PointMap::~PointMap() = default;
PointMap::PointMap(PointMap&&) noexcept = default;
PointMap& PointMap::operator=(PointMap&&) noexcept = default;

void PointMap::Add(const Points& points_M) { AddCells(points_M, nullptr); }

void PointMap::AddCells(const Points& points_M, const Eigen::Vector3d* origin_M) {
  const IcpParams& p = impl_->params;
  const std::vector<VoxelCell> fresh = Voxelize(points_M, p.voxel_size);
  if (fresh.empty()) return;
  // Per fresh cell: the unit vectors from its points towards the scan origin, summed in point
  // order.
  std::vector<Eigen::Vector3f> fresh_views(fresh.size(), Eigen::Vector3f::Zero());
  if (origin_M) {
    for (const auto& q : points_M) {
      if (!q.allFinite()) continue;
      const std::int64_t key = VoxelKey(q, p.voxel_size);
      const auto it =
          std::lower_bound(fresh.begin(), fresh.end(), key,
                           [](const VoxelCell& cell, std::int64_t k) { return cell.key < k; });
      const Eigen::Vector3d d = *origin_M - q;
      if (d.norm() > 1e-9)
        fresh_views[static_cast<std::size_t>(it - fresh.begin())] += d.normalized().cast<float>();
    }
  }
  std::vector<Eigen::Vector3f> merged_views;
  merged_views.reserve(impl_->views.size() + fresh.size());
  // Merge the key-sorted cell lists, remembering which cells changed (old and new centroids).
  const std::vector<VoxelCell>& old = impl_->cells;
  std::vector<VoxelCell> merged;
  merged.reserve(old.size() + fresh.size());
  std::vector<std::int64_t> from_old;  // per merged cell: index in `old`, or -1 if new
  std::vector<char> changed;
  Points moved;  // centroids (before and after) of changed cells
  std::size_t i = 0, j = 0;
  while (i < old.size() || j < fresh.size()) {
    if (j == fresh.size() || (i < old.size() && old[i].key < fresh[j].key)) {
      merged_views.push_back(impl_->views[i]);
      merged.push_back(old[i]);
      from_old.push_back(static_cast<std::int64_t>(i++));
      changed.push_back(0);
      continue;
    }
    if (i < old.size() && old[i].key == fresh[j].key) {
      moved.push_back(old[i].Centroid());
      VoxelCell c = old[i];
      c.sum += fresh[j].sum;
      c.count += fresh[j].count;
      merged.push_back(c);
      merged_views.push_back(impl_->views[i] + fresh_views[j]);
      from_old.push_back(static_cast<std::int64_t>(i++));
    } else {
      merged.push_back(fresh[j]);
      merged_views.push_back(fresh_views[j]);
      from_old.push_back(-1);
    }
    moved.push_back(merged.back().Centroid());
    changed.push_back(1);
    ++j;
  }
  Points centroids(merged.size());
  for (std::size_t k = 0; k < merged.size(); ++k) centroids[k] = merged[k].Centroid();
  // A normal depends only on the points within normal_radius of its point (EstimateNormals), so
  // only cells that changed or lie within the radius of a changed centroid are recomputed:
  // those in the 27 coarse cells (edge = radius) around a coarse cell holding a moved centroid.
  // Their neighbours within the radius lie in the 27 coarse cells around theirs: the tree the
  // normals are computed on holds only those (the same neighbours as the whole map's).
  const double g = p.normal_radius;
  constexpr std::int64_t kX = std::int64_t{1} << 42, kY = std::int64_t{1} << 21;
  auto dilate = [&](const std::unordered_set<std::int64_t>& keys) {
    std::unordered_set<std::int64_t> out;
    for (const std::int64_t key : keys)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) out.insert(key + dx * kX + dy * kY + dz);
    return out;
  };
  std::unordered_set<std::int64_t> seeds;
  for (const auto& c : moved) seeds.insert(VoxelKey(c, g));
  const std::unordered_set<std::int64_t> dirty = dilate(seeds);
  const std::unordered_set<std::int64_t> reach = dilate(dirty);
  // Every cell of `reach` lies within three coarse cells of a moved centroid: cells outside
  // that box keep their normals without a look-up.
  Eigen::AlignedBox3d near_moved;
  for (const auto& c : moved) near_moved.extend(c);
  near_moved.min().array() -= 3.0 * g;
  near_moved.max().array() += 3.0 * g;
  std::vector<Normal> normals(merged.size());
  std::vector<std::uint32_t> which, local_of_which;
  Points local_points;
  for (std::size_t k = 0; k < merged.size(); ++k) {
    if (!changed[k] && !near_moved.contains(centroids[k])) {
      normals[k] = impl_->normals[static_cast<std::size_t>(from_old[k])];
      continue;
    }
    const std::int64_t key = VoxelKey(centroids[k], g);
    const bool recompute = changed[k] || dirty.count(key);
    if (!recompute) normals[k] = impl_->normals[static_cast<std::size_t>(from_old[k])];
    if (!reach.count(key)) continue;
    if (recompute) {
      which.push_back(static_cast<std::uint32_t>(k));
      local_of_which.push_back(static_cast<std::uint32_t>(local_points.size()));
    }
    local_points.push_back(centroids[k]);
  }
  const KdTree3 local_tree(std::move(local_points));
  std::vector<Normal> local_normals(local_tree.size());
  EstimateNormalsAt(local_tree, local_of_which, p.normal_neighbours, p.normal_radius,
                    std::min(5, p.normal_neighbours), Eigen::Vector3d::Zero(), local_normals);
  for (std::size_t w = 0; w < which.size(); ++w) normals[which[w]] = local_normals[local_of_which[w]];
  impl_->cells = std::move(merged);
  impl_->centroids = std::move(centroids);
  impl_->normals = std::move(normals);
  impl_->views = std::move(merged_views);
  impl_->last_recomputed = which.size();
  std::lock_guard<std::mutex> lock(impl_->tree_mutex);
  impl_->tree.reset();
}

PointMap PointMap::Local(const Points& points_M, double distance) const {
  PointMap out(impl_->params);
  Impl& o = *out.impl_;
  const Impl& m = *impl_;
  o.images = m.images;
  if (points_M.empty() || !(distance > 0.0) || !std::isfinite(distance)) return out;
  // Tiles of edge `distance` holding a point, and their 26 neighbours: every map cell within
  // `distance` of a point lies in one of them.
  constexpr std::int64_t kX = std::int64_t{1} << 42, kY = std::int64_t{1} << 21;
  std::unordered_set<std::int64_t> tiles;
  Eigen::AlignedBox3d box;
  for (const auto& p : points_M) {
    if (!p.allFinite()) continue;
    box.extend(p);
    const std::int64_t key = VoxelKey(p, distance);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) tiles.insert(key + dx * kX + dy * kY + dz);
  }
  if (box.isEmpty()) return out;
  box.min().array() -= 2.0 * distance;
  box.max().array() += 2.0 * distance;
  for (std::size_t k = 0; k < m.centroids.size(); ++k) {
    if (!box.contains(m.centroids[k]) || !tiles.count(VoxelKey(m.centroids[k], distance)))
      continue;
    o.cells.push_back(m.cells[k]);
    o.centroids.push_back(m.centroids[k]);
    o.normals.push_back(m.normals[k]);
    o.views.push_back(m.views[k]);
  }
  return out;
}

std::size_t PointMap::last_normals_recomputed() const { return impl_->last_recomputed; }

void PointMap::Add(const Points& points_M, const Eigen::Vector3d& origin_M) {
  if (!origin_M.allFinite())
    throw InputError("", "scan origin is not finite", "", "a finite point");
  AddCells(points_M, &origin_M);
  RangeImage img;
  img.origin = origin_M;
  img.bin = DegToRad(impl_->params.free_space_bin_deg);
  img.n_az = static_cast<int>(std::ceil(2.0 * kPi / img.bin));
  img.n_el = static_cast<int>(std::ceil(kPi / img.bin)) + 1;
  img.nearest.assign(static_cast<std::size_t>(img.n_az) * img.n_el,
                     std::numeric_limits<float>::infinity());
  img.farthest.assign(img.nearest.size(), 0.0f);
  for (const auto& p : points_M) {
    const Eigen::Vector3d d = p - origin_M;
    const double r = d.norm();
    if (!std::isfinite(r) || r < 1e-6) continue;
    const auto b = static_cast<std::size_t>(img.Bin(d, r));
    img.nearest[b] = std::min(img.nearest[b], static_cast<float>(r));
    img.farthest[b] = std::max(img.farthest[b], static_cast<float>(r));
    img.reach = std::max(img.reach, static_cast<float>(r));
  }
  impl_->images.push_back(std::make_shared<const RangeImage>(std::move(img)));
}

namespace {

/// How many of `points` some range image holds `seen(image, bin, range)` for: one walk over the
/// points and images for both the free-space check and the expected overlap.
template <class Seen>
/// `seen` holds only where the range is at most reach_scale * farthest + reach_margin of its
/// bin, so images whose every return is nearer are skipped without a look (scans of far rooms).
std::size_t CountSeenByAnyImage(const Points& points,
                                const std::vector<std::shared_ptr<const RangeImage>>& images,
                                double reach_scale, double reach_margin, Seen seen) {
  std::size_t n = 0;
  for (const auto& p : points) {
    for (const auto& image : images) {
      const RangeImage& img = *image;
      const Eigen::Vector3d d = p - img.origin;
      const double r = d.norm();
      if (!(r > 1e-6) || r > reach_scale * img.reach + reach_margin) continue;
      if (seen(img, static_cast<std::size_t>(img.Bin(d, r)), r)) {
        ++n;
        break;
      }
    }
  }
  return n;
}

}  // namespace

double PointMap::FreeSpaceViolation(const Points& points_M) const {
  if (points_M.empty() || impl_->images.empty()) return 0.0;
  const double margin = impl_->params.free_space_margin;
  const std::size_t violating = CountSeenByAnyImage(
      points_M, impl_->images, 1.0, 0.0, [&](const RangeImage& img, std::size_t b, double r) {
        const double nearest = img.nearest[b];
        // Evidence only from bins that saw one surface squarely (range spread within the
        // margin): grazing floors and depth edges spread over a bin and would accuse good
        // points. Also skips empty bins (inf).
        return img.farthest[b] - nearest <= margin && r < nearest - margin - 0.02 * nearest;
      });
  return static_cast<double>(violating) / static_cast<double>(points_M.size());
}

std::size_t PointMap::CountInView(const Points& points_M) const {
  const double margin = impl_->params.free_space_margin;
  return CountSeenByAnyImage(points_M, impl_->images, 1.02, margin,
                             [&](const RangeImage& img, std::size_t b, double r) {
                               const double farthest = img.farthest[b];
                               return farthest > 0.0 && r <= farthest + margin + 0.02 * farthest;
                             });
}

bool PointMap::has_origins() const { return !impl_->images.empty(); }

bool PointMap::empty() const { return impl_->centroids.empty(); }
std::size_t PointMap::size() const { return impl_->centroids.size(); }
const Points& PointMap::points() const { return impl_->centroids; }
const std::vector<Normal>& PointMap::normals() const { return impl_->normals; }
const std::vector<Eigen::Vector3f>& PointMap::views() const { return impl_->views; }
const KdTree3& PointMap::tree() const {
  std::lock_guard<std::mutex> lock(impl_->tree_mutex);
  if (!impl_->tree) impl_->tree = std::make_unique<KdTree3>(impl_->centroids);
  return *impl_->tree;
}
const IcpParams& PointMap::params() const { return impl_->params; }

// ---- ICP
// -----------------------------------------------------------------------------------------

namespace {

// The source for ICP: range gate, then voxel centroids in the scanner frame.
Points GatedSource(const Points& source_S, const IcpParams& params) {
  Points gated;
  gated.reserve(source_S.size());
  const double rmin2 = params.min_range * params.min_range,
               rmax2 = params.max_range * params.max_range;
  for (const auto& p : source_S) {
    const double r2 = p.squaredNorm();
    if (std::isfinite(r2) && r2 >= rmin2 && r2 <= rmax2) gated.push_back(p);
  }
  return VoxelDownsample(gated, params.source_voxel_size);
}

// One Gauss-Newton step from the accumulated system `a`, solved in the eigenbasis; directions
// with too little information keep the prior (solution remapping, Zhang et al. 2016). The step
// turns about the current source centroid c: p -> R (p - c) + c + dt.
Eigen::Isometry3d GaussNewtonStep(const Accum& a, const Eigen::Vector3d& c, const IcpParams& params,
                                  double* step_translation, double* step_angle) {
  const Reduced red = Reduce(a, params.dof);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(red.H);
  const Eigen::VectorXd ev = es.eigenvalues();
  const Eigen::VectorXd proj = es.eigenvectors().transpose() * red.g;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(red.H.rows());
  const double floor_ev = std::max(params.degeneracy_threshold, 1e-9);
  for (int k = 0; k < ev.size(); ++k) {
    if (ev[k] >= floor_ev) y -= es.eigenvectors().col(k) * (proj[k] / ev[k]);
  }
  Vec6 x = Vec6::Zero();
  for (int k = 0; k < static_cast<int>(red.idx.size()); ++k) {
    x[red.idx[k]] = red.idx[k] < 3 ? y[k] / red.lever : y[k];
  }
  const Eigen::Vector3d w = x.head<3>(), dt = x.tail<3>();
  const double angle = w.norm();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (angle > 0.0) R = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = R;
  step.translation() = c - R * c + dt;
  *step_translation = dt.norm();
  *step_angle = angle;
  return step;
}

// Share of `src` (scanner frame) that, placed by T, has no map point within `dist` and lies
// where a map scan saw empty space. Only such points can float in observed empty space
// (matched ones lie on known surfaces; near depth edges they would only add noise).
double ViolationAt(const Points& src, const Eigen::Isometry3d& T, const PointMap& target,
                   double dist) {
  Points unmatched;
  for (const auto& p : src) {
    const Eigen::Vector3d q = T * p;
    if (target.tree().Nearest(q, dist) < 0) unmatched.push_back(q);
  }
  return target.FreeSpaceViolation(unmatched) * static_cast<double>(unmatched.size()) /
         static_cast<double>(src.size());
}

// The free-space search along a degenerate result's weak direction (IcpParams::weak_search):
// the violation of the offsets along the unit horizontal `u`; the least violating run of them
// around the best one, [lo, hi] in m, and whether both its ends lie inside the range (bounded).
struct WeakEvidence {
  bool bounded = false;
  double lo = 0.0, hi = 0.0;
};
WeakEvidence WeakDirectionEvidence(const Points& src, const Eigen::Isometry3d& T,
                                   const PointMap& target, const IcpParams& params,
                                   const Eigen::Vector3d& u) {
  WeakEvidence e;
  const int n = static_cast<int>(std::floor(params.weak_search / params.weak_search_step + 1e-9));
  if (n < 1) return e;
  std::vector<double> v(static_cast<std::size_t>(2 * n + 1));
  for (int k = -n; k <= n; ++k) {
    Eigen::Isometry3d Ts = T;
    Ts.translation() += (k * params.weak_search_step) * u;
    v[static_cast<std::size_t>(k + n)] =
        ViolationAt(src, Ts, target, params.max_correspondence.back());
  }
  const auto best = std::min_element(v.begin(), v.end());
  const double limit = *best + params.weak_search_tolerance;
  auto lo = best, hi = best;
  while (lo != v.begin() && *(lo - 1) <= limit) --lo;
  while (hi + 1 != v.end() && *(hi + 1) <= limit) ++hi;
  e.bounded = lo != v.begin() && hi + 1 != v.end();
  e.lo = (static_cast<int>(lo - v.begin()) - n) * params.weak_search_step;
  e.hi = (static_cast<int>(hi - v.begin()) - n) * params.weak_search_step;
  return e;
}

// Health at the result (res.X_MS), with the last stage's distance and no kernel: fitness,
// rmse, free-space violation, the information's eigenvalues and degeneracy.
void AssessRegistration(const Points& src, const Eigen::Vector3d& src_centroid,
                        const PointMap& target, const IcpParams& params, RegistrationResult& res) {
  const Eigen::Isometry3d& T = res.X_MS;
  const double last_dist = params.max_correspondence.back();
  const Eigen::Vector3d c = T * src_centroid;
  const Accum fin = Correspond(src, T, c, target, last_dist, Kernel::kNone, 1.0,
                               params.max_normal_curvature, params.same_side);
  const double n_src = static_cast<double>(src.size());
  res.raw_fitness = static_cast<double>(fin.matched) / n_src;
  res.rmse = fin.planar > 0 ? std::sqrt(fin.r2 / static_cast<double>(fin.planar)) : 0.0;
  // Free space and expected overlap: only points without a map point within the last stage's
  // distance can float in observed empty space or lie where no map scan looked (matched ones
  // lie on known surfaces).
  Points unmatched;
  for (const auto& p : src) {
    const Eigen::Vector3d q = T * p;
    if (target.tree().Nearest(q, last_dist) < 0) unmatched.push_back(q);
  }
  res.free_space_violation = target.FreeSpaceViolation(unmatched) *
                             static_cast<double>(unmatched.size()) / n_src;
  const double unseen = target.has_origins() ? static_cast<double>(unmatched.size() -
                                                                   target.CountInView(unmatched))
                                             : 0.0;
  res.expected_overlap = (n_src - unseen) / n_src;
  res.fitness = n_src - unseen > 0.0 ? static_cast<double>(fin.matched) / (n_src - unseen) : 0.0;
  res.information_matrix.setZero();
  res.constrained_directions.resize(6, 0);
  if (fin.planar >= 12 && fin.weight > 0.0) {
    const Reduced red = Reduce(fin, params.dof);
    const int n = static_cast<int>(red.idx.size());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(red.H);
    res.information.assign(es.eigenvalues().data(),
                           es.eigenvalues().data() + es.eigenvalues().size());
    for (int k = 0; k < n; ++k) {
      res.weakest_direction[red.idx[k]] = es.eigenvectors()(k, 0);
    }
    res.degenerate = res.information.front() < params.degeneracy_threshold;
    // Information in physical units: the unweighted Hessian of the estimated DoF over the
    // residual variance (at least 1 mm: a perfect fit is not infinite information).
    const double var = std::max(res.rmse * res.rmse, 1e-6);
    for (int r = 0; r < n; ++r)
      for (int q = 0; q < n; ++q)
        res.information_matrix(red.idx[r], red.idx[q]) = fin.H(red.idx[r], red.idx[q]) / var;
    // The constrained directions: eigenvectors of the normalised information (homogeneous
    // units) at or above the threshold, mapped back to radians and metres and renormalised.
    std::vector<Vec6> strong;
    for (int k = 0; k < n; ++k) {
      if (es.eigenvalues()[k] < params.degeneracy_threshold) continue;
      Vec6 v = Vec6::Zero();
      for (int i = 0; i < n; ++i)
        v[red.idx[i]] = red.idx[i] < 3 ? es.eigenvectors()(i, k) / red.lever
                                       : es.eigenvectors()(i, k);
      strong.push_back(v.normalized());
    }
    res.constrained_directions.resize(6, static_cast<Eigen::Index>(strong.size()));
    for (std::size_t k = 0; k < strong.size(); ++k)
      res.constrained_directions.col(static_cast<Eigen::Index>(k)) = strong[k];
  } else {
    res.information.assign(params.dof, 0.0);
    res.degenerate = true;
  }
}

// res.ok and the one-line message: every reason it is not ok, then the figures.
void ExplainRegistration(const std::string& failure, double last_dt, double last_dr,
                         const IcpParams& params, RegistrationResult& res) {
  std::vector<std::string> why;
  if (!failure.empty())
    why.push_back(failure);
  else if (!res.converged)
    why.push_back("not converged in " + std::to_string(params.max_iterations) +
                  " iterations of the last stage (step " + FormatNumbers("%.2g", last_dt) + " m, " +
                  FormatNumbers("%.2g", RadToDeg(last_dr)) + " deg)");
  if (res.fitness < params.min_fitness) {
    why.push_back("fitness " + FormatNumbers("%.3f", res.fitness) + " < min_fitness " +
                  FormatNumbers("%.3f", params.min_fitness));
  }
  if (res.rmse > params.max_rmse) {
    why.push_back("rmse " + FormatNumbers("%.4f", res.rmse) + " m > max_rmse " +
                  FormatNumbers("%.4f", params.max_rmse));
  }
  if (res.free_space_violation > params.max_free_space_violation) {
    why.push_back("free-space violation " + FormatNumbers("%.3f", res.free_space_violation) +
                  " > " + FormatNumbers("%.3f", params.max_free_space_violation) +
                  " (source points where the map saw empty space)");
  }
  if (res.degenerate) {
    const Vec6& d = res.weakest_direction;
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "degenerate: information %.3g < %.3g along (rx %.2f ry %.2f rz %.2f tx %.2f ty "
                  "%.2f tz %.2f)",
                  res.information.front(), params.degeneracy_threshold, d[0], d[1], d[2], d[3],
                  d[4], d[5]);
    why.push_back(buf);
  }
  res.ok = why.empty();
  char figures[400];
  std::snprintf(figures, sizeof figures,
                "fitness %.3f (%.3f of all points, expected overlap %.3f), rmse %.2f mm, "
                "free-space violation %.4f, %d iterations, last step %.2g m / %.2g deg, "
                "min information %.3g, %zu source / %zu map points",
                res.fitness, res.raw_fitness, res.expected_overlap, res.rmse * 1e3,
                res.free_space_violation, res.iterations, last_dt,
                RadToDeg(last_dr), res.information.empty() ? 0.0 : res.information.front(),
                res.source_points, res.target_points);
  if (res.ok) {
    res.message = std::string("registration ok: ") + figures;
  } else {
    std::string reasons;
    for (const auto& w : why) reasons += (reasons.empty() ? "" : "; ") + w;
    res.message = "registration failed: " + reasons + " (" + figures + ")";
  }
}

}  // namespace

RegistrationResult RegisterScan(const Points& source_S, const PointMap& map,
                                const Eigen::Isometry3d& prior_X_MS, const IcpParams& params) {
  params.Validate();
  if (!prior_X_MS.matrix().allFinite()) {
    throw InputError("", "registration prior is not finite", "", "a finite pose");
  }
  const Kernel kernel = ParseKernel(params.robust_kernel);
  RegistrationResult res;
  res.X_MS = prior_X_MS;
  const Points src = GatedSource(source_S, params);
  res.source_points = src.size();
  res.target_points = map.size();
  // The map near what the scan saw: within the widest correspondence distance, the
  // weak-direction search and kLocalMapSlack of its points at the prior. No map point farther
  // can pair with a source point (the same pairs as the whole map) while the correction moves
  // no source point farther than the slack.
  Points at_prior;
  at_prior.reserve(src.size());
  for (const auto& p : src) at_prior.push_back(prior_X_MS * p);
  const double reach = *std::max_element(params.max_correspondence.begin(),
                                         params.max_correspondence.end()) +
                       params.weak_search + kLocalMapSlack;
  const PointMap target = map.Local(at_prior, reach);  // may be empty: then no correspondences
  if (src.empty() || map.empty()) {
    res.message = std::string("registration failed: empty ") + (src.empty() ? "source" : "map") +
                  " (" + std::to_string(src.size()) + " source / " + std::to_string(map.size()) +
                  " map points)";
    return res;
  }
  Eigen::Vector3d src_centroid = Eigen::Vector3d::Zero();
  for (const auto& p : src) src_centroid += p;
  src_centroid /= static_cast<double>(src.size());

  // Coarse-to-fine stages of point-to-plane Gauss-Newton, from `first` on.
  Eigen::Isometry3d T = prior_X_MS;
  const double min_dt = params.min_delta_translation;
  const double min_dr = DegToRad(params.min_delta_rotation_deg);
  double last_dt = 0.0, last_dr = 0.0;
  bool stage_converged = false;
  std::string failure;
  auto run_stages = [&](std::size_t first) {
    for (std::size_t stage = first; stage < params.max_correspondence.size() && failure.empty();
         ++stage) {
      const double dist = params.max_correspondence[stage];
      const double scale = params.kernel_scale_ratio * dist;
      stage_converged = false;
      for (int it = 0; it < params.max_iterations; ++it) {
        const Eigen::Vector3d c = T * src_centroid;
        const Accum a = Correspond(src, T, c, target, dist, kernel, scale,
                                   params.max_normal_curvature, params.same_side);
        if (a.planar < 12 || a.weight <= 0.0) {
          failure = "only " + std::to_string(a.planar) + " correspondences within " +
                    FormatNumbers("%.3g", dist) + " m";
          break;
        }
        T = GaussNewtonStep(a, c, params, &last_dt, &last_dr) * T;
        T.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
        ++res.iterations;
        if (last_dt < min_dt && last_dr < min_dr) {
          stage_converged = true;
          break;
        }
      }
    }
    res.X_MS = T;
    res.converged = failure.empty() && stage_converged;
    res.last_step = last_dt;
    res.last_step_deg = RadToDeg(last_dr);
    AssessRegistration(src, src_centroid, target, params, res);
  };
  run_stages(0);
  // A weak horizontal translation: the planes leave it free, the free space may not. The
  // evidence decides only where it refutes the prior (bounded on both sides, the prior outside
  // the least violating offsets): a result among them keeps its place (the few points that
  // constrain the direction, a door's jambs, pulled it there), one outside moves to their
  // middle. Where the prior fits the evidence too, the acceptance's slide rule judges.
  if (failure.empty() && res.degenerate && params.weak_search > 0.0) {
    Eigen::Vector3d w = res.weakest_direction.tail<3>();
    w.z() = 0.0;
    if (w.norm() > 0.9) {
      const Eigen::Vector3d u = w.normalized();
      const WeakEvidence e = WeakDirectionEvidence(src, T, target, params, u);
      const double at_prior = (prior_X_MS.translation() - T.translation()).dot(u);
      const double half = 0.5 * params.weak_search_step;
      if (e.bounded && (at_prior < e.lo - half || at_prior > e.hi + half)) {
        res.weak_bounded = true;
        if (e.lo > 0.0 || e.hi < 0.0) {
          const double s = 0.5 * (e.lo + e.hi);
          T.translation() += s * u;
          const std::size_t n = params.max_correspondence.size();
          run_stages(n >= 2 ? n - 2 : 0);
          res.weak_offset = s;
          res.weak_offset_direction = u;
        }
      }
    }
  }
  ExplainRegistration(failure, last_dt, last_dr, params, res);
  if (res.weak_offset != 0.0)
    res.message += FormatNumbers("; moved %.3f m along its weak direction to the middle of the "
                                 "free-space evidence",
                                 res.weak_offset);
  else if (res.weak_bounded)
    res.message += "; its place along the weak direction within the free-space evidence, the "
                   "prior outside it";
  return res;
}

RegistrationResult RegisterScan(const interfaces::TlsScan& scan, const PointMap& target,
                                const IcpParams& params) {
  params.Validate();
  return RegisterScan(
      ScanPoints(scan, Eigen::Isometry3d::Identity(), params.min_range, params.max_range), target,
      scan.X_MS_estimate, params);
}

Eigen::Matrix<double, 6, 6> RegistrationCovariance(const RegistrationResult& r,
                                                   const Eigen::Matrix<double, 6, 6>& prior_cov) {
  const Eigen::Index k = r.constrained_directions.cols();
  if (k == 0) return prior_cov;
  // Orthonormal basis of the constrained subspace (the directions are orthogonal in the
  // normalised units, not necessarily after the lever scaling) and of its complement.
  Eigen::HouseholderQR<Eigen::Matrix<double, 6, Eigen::Dynamic>> qr(r.constrained_directions);
  const Mat6 Q = qr.householderQ() * Mat6::Identity();
  const Eigen::Matrix<double, 6, Eigen::Dynamic> S = Q.leftCols(k);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> W = Q.rightCols(6 - k);
  // The scan's covariance in its constrained subspace: (S^T I S)^-1.
  const Eigen::MatrixXd info_s = S.transpose() * r.information_matrix * S;
  const Eigen::MatrixXd cov_s = info_s.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
  const Eigen::MatrixXd cov_w = W.transpose() * prior_cov * W;
  return S * cov_s * S.transpose() + W * cov_w * W.transpose();
}

RegistrationDecision AcceptRegistration(const RegistrationResult& r,
                                        const Eigen::Isometry3d& prior_X_MS, const IcpParams& icp,
                                        const RegistrationAcceptanceParams& policy,
                                        double prior_sigma) {
  RegistrationDecision d;
  // A degenerate result creeps along its weak direction, where nothing holds it; what it
  // moved along that direction is the slide rule's (below).
  d.creeping = policy.creeping_step_factor > 0.0 && !r.converged && r.iterations > 0 &&
               r.last_step <= policy.creeping_step_factor * icp.min_delta_translation &&
               r.last_step_deg <= policy.creeping_step_factor * icp.min_delta_rotation_deg;
  const bool fits = (r.converged || d.creeping) && r.fitness >= icp.min_fitness &&
                    r.rmse <= icp.max_rmse &&
                    r.free_space_violation <= icp.max_free_space_violation;
  d.X_MS = r.X_MS;
  bool slid = false;
  if (r.degenerate && !r.weak_bounded) {
    // The weak direction's translation (map frame, as the ICP's steps): how far the result
    // moved along it from the prior (with free-space evidence on both sides, where the
    // evidence put it: no slide).
    const Eigen::Vector3d w = r.weakest_direction.tail<3>();
    if (w.norm() > 0.5) {
      const Eigen::Vector3d u = w.normalized();
      d.weak_slide = (r.X_MS.translation() - prior_X_MS.translation()).dot(u);
      if (std::abs(d.weak_slide) > policy.max_weak_slide) {
        d.X_MS.translation() -= d.weak_slide * u;
        slid = true;
      }
    }
  }
  const Eigen::Isometry3d dX = prior_X_MS.inverse() * d.X_MS;
  d.correction = dX.translation().head<2>().norm();
  d.correction_deg = std::abs(std::atan2(dX.linear()(1, 0), dX.linear()(0, 0))) * 180.0 / kPi;
  const bool gated = policy.gate_sigmas > 0.0 && (r.degenerate || !policy.trust_constrained);
  d.gate = gated ? std::clamp(policy.gate_sigmas * prior_sigma, policy.min_gate,
                              std::max(policy.min_gate, policy.max_correction))
                 : policy.max_correction;
  d.within_bounds = d.correction <= d.gate && d.correction_deg <= policy.max_correction_deg;
  const bool flaw_accepted = fits && ((r.degenerate && policy.accept_degenerate) || d.creeping);
  d.use = (r.ok || flaw_accepted) && d.within_bounds;
  char figures[160];
  std::snprintf(figures, sizeof figures,
                "; correction %.3f m / %.3f deg, prior sigma %.3f m, gate %.3f m", d.correction,
                d.correction_deg, prior_sigma, d.gate);
  const std::string slide_note =
      slid ? FormatNumbers("; slid %.3f m along its weak direction: the prior kept along it",
                           d.weak_slide)
           : "";
  d.message = std::string(d.use ? "" : "refused, prior kept: ") +
              (d.creeping && fits ? "converged but for a creep below the step limit: " : "") +
              r.message + figures + slide_note + (d.within_bounds ? "" : " (too large)");
  return d;
}

}  // namespace mopad::perception
