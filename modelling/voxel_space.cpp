#include "modelling/voxel_space.h"

#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>

namespace mopad::modelling {

const char* ToString(VoxelLabel label) {
  switch (label) {
    case VoxelLabel::kUnseen:
      return "unseen";
    case VoxelLabel::kEmpty:
      return "empty";
    case VoxelLabel::kStructure:
      return "structure";
    case VoxelLabel::kOccludedStructure:
      return "occluded_structure";
    case VoxelLabel::kClutter:
      return "clutter";
    case VoxelLabel::kOpening:
      return "opening";
  }
  return "?";
}

VoxelSpace::VoxelSpace(const Vec3& origin, double size, int nx, int ny, int nz)
    : origin_(origin),
      size_(size),
      nx_(nx),
      ny_(ny),
      nz_(nz),
      flags_(static_cast<std::size_t>(nx) * ny * nz, 0) {}

Eigen::Vector3i VoxelSpace::VoxelOf(const Vec3& p) const {
  const Vec3 q = (p - origin_) / size_;
  return Eigen::Vector3i(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())),
                         static_cast<int>(std::floor(q.z())));
}

bool VoxelSpace::Occupied(const Vec3& p) const {
  const Eigen::Vector3i v = VoxelOf(p);
  if (!Contains(v.x(), v.y(), v.z())) return false;
  return (flags_[Index(v.x(), v.y(), v.z())] & kOccupied) != 0;
}

VoxelLabel VoxelSpace::Label(std::size_t index) const {
  const std::uint8_t f = flags_[index];
  const bool occ = f & kOccupied, passed = f & kPassed, structural = f & kStructural;
  if (structural) {
    if (f & kOpeningFace) return VoxelLabel::kOpening;
    if (occ) return VoxelLabel::kStructure;
    return passed ? VoxelLabel::kOpening : VoxelLabel::kOccludedStructure;
  }
  if (occ && (f & kInside)) return VoxelLabel::kClutter;
  if (passed) return VoxelLabel::kEmpty;
  return VoxelLabel::kUnseen;
}

std::array<std::int64_t, kVoxelLabelCount> VoxelSpace::LabelCounts() const {
  std::array<std::int64_t, kVoxelLabelCount> c{};
  for (std::size_t i = 0; i < flags_.size(); ++i) ++c[static_cast<int>(Label(i))];
  return c;
}

namespace {

// Amanatides & Woo traversal of the grid from a to b. Calls visit(index) for each voxel in
// order; stops when visit returns false, at b's voxel (not visited), when the ray leaves the
// grid, or before a voxel entered farther than `t_limit` (m from a) along the segment. The
// voxel's flat index is stepped with the voxel (a stride per axis), b's voxel compared by its
// index: the inner loop is a compare, a load and a step.
template <class Visit>
void Traverse(const Vec3& origin, double size, int nx, int ny, int nz, const Vec3& a, const Vec3& b,
              double t_limit, Visit&& visit) {
  const Vec3 d = b - a;
  const double len = d.norm();
  if (!(len > 1e-9)) return;
  const Vec3 dir = d / len;
  // Clip the segment to the grid box.
  const Vec3 lo = origin, hi = origin + size * Vec3(nx, ny, nz);
  double t0 = 0.0, t1 = len;
  for (int ax = 0; ax < 3; ++ax) {
    if (std::abs(dir[ax]) < 1e-12) {
      if (a[ax] < lo[ax] || a[ax] >= hi[ax]) return;
    } else {
      double ta = (lo[ax] - a[ax]) / dir[ax], tb = (hi[ax] - a[ax]) / dir[ax];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
  }
  if (t0 > t1 || t0 > t_limit) return;
  const double t_end = std::min(t1, t_limit);
  const Vec3 start = a + dir * (t0 + 1e-9);
  int v[3], step[3];
  const int n[3] = {nx, ny, nz};
  const std::ptrdiff_t stride[3] = {1, nx, static_cast<std::ptrdiff_t>(nx) * ny};
  std::ptrdiff_t index_step[3];
  double tmax[3], tdelta[3];
  // The voxel of b (so it can be excluded); none when it lies outside the grid.
  int vb[3];
  bool b_inside = true;
  for (int ax = 0; ax < 3; ++ax) {
    v[ax] = static_cast<int>(std::floor((start[ax] - origin[ax]) / size));
    v[ax] = std::min(std::max(v[ax], 0), n[ax] - 1);
    vb[ax] = static_cast<int>(std::floor((b[ax] - origin[ax]) / size));
    b_inside = b_inside && vb[ax] >= 0 && vb[ax] < n[ax];
    if (dir[ax] > 0) {
      step[ax] = 1;
      tmax[ax] = (origin[ax] + (v[ax] + 1) * size - a[ax]) / dir[ax];
      tdelta[ax] = size / dir[ax];
    } else if (dir[ax] < 0) {
      step[ax] = -1;
      tmax[ax] = (origin[ax] + v[ax] * size - a[ax]) / dir[ax];
      tdelta[ax] = -size / dir[ax];
    } else {
      step[ax] = 0;
      tmax[ax] = std::numeric_limits<double>::infinity();
      tdelta[ax] = std::numeric_limits<double>::infinity();
    }
    index_step[ax] = step[ax] * stride[ax];
  }
  std::size_t index = (static_cast<std::size_t>(v[2]) * ny + v[1]) * nx + v[0];
  const std::size_t index_b = b_inside ? (static_cast<std::size_t>(vb[2]) * ny + vb[1]) * nx + vb[0]
                                       : std::numeric_limits<std::size_t>::max();
  while (true) {
    if (index == index_b) return;
    if (!visit(index)) return;
    int ax = 0;
    if (tmax[1] < tmax[ax]) ax = 1;
    if (tmax[2] < tmax[ax]) ax = 2;
    if (tmax[ax] > t_end) return;
    v[ax] += step[ax];
    if (v[ax] < 0 || v[ax] >= n[ax]) return;
    index += index_step[ax];
    tmax[ax] += tdelta[ax];
  }
}

}  // namespace

void VoxelSpace::MarkPassed(const Vec3& a, const Vec3& b) {
  std::uint8_t* data = flags_.data();
  Traverse(origin_, size_, nx_, ny_, nz_, a, b, std::numeric_limits<double>::infinity(),
           [data](std::size_t index) {
             std::atomic_ref<std::uint8_t> f(data[index]);
             if (!(f.load(std::memory_order_relaxed) & kPassed))
               f.fetch_or(kPassed, std::memory_order_relaxed);
             return true;
           });
}

bool VoxelSpace::SegmentFree(const Vec3& a, const Vec3& b, double stop_short) const {
  bool free = true;
  const std::uint8_t* data = flags_.data();
  Traverse(origin_, size_, nx_, ny_, nz_, a, b, (b - a).norm() - stop_short,
           [&](std::size_t index) {
             if (!(data[index] & kOccupied)) return true;
             free = false;
             return false;
           });
  return free;
}

}  // namespace mopad::modelling
