#include "modelling/voxel_space.h"

#include <atomic>
#include <cmath>
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

// Amanatides & Woo traversal of the grid from a to b. Calls visit(index, t_enter) for each
// voxel in order, with t in metres from a; stops when visit returns false, at b's voxel
// (not visited unless `include_last`), or when the ray leaves the grid.
template <class Visit>
void Traverse(const Vec3& origin, double size, int nx, int ny, int nz, const Vec3& a, const Vec3& b,
              Visit&& visit) {
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
  if (t0 > t1) return;
  const Vec3 start = a + dir * (t0 + 1e-9);
  int v[3], n[3] = {nx, ny, nz}, step[3];
  double tmax[3], tdelta[3];
  // The voxel of b (so it can be excluded).
  int vb[3];
  for (int ax = 0; ax < 3; ++ax) {
    v[ax] = static_cast<int>(std::floor((start[ax] - origin[ax]) / size));
    v[ax] = std::min(std::max(v[ax], 0), n[ax] - 1);
    vb[ax] = static_cast<int>(std::floor((b[ax] - origin[ax]) / size));
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
  }
  double t = t0;
  while (true) {
    if (v[0] == vb[0] && v[1] == vb[1] && v[2] == vb[2]) return;
    const std::size_t index = (static_cast<std::size_t>(v[2]) * ny + v[1]) * nx + v[0];
    if (!visit(index, t)) return;
    int ax = 0;
    if (tmax[1] < tmax[ax]) ax = 1;
    if (tmax[2] < tmax[ax]) ax = 2;
    t = tmax[ax];
    if (t > t1) return;
    v[ax] += step[ax];
    if (v[ax] < 0 || v[ax] >= n[ax]) return;
    tmax[ax] += tdelta[ax];
  }
}

}  // namespace

void VoxelSpace::MarkPassed(const Vec3& a, const Vec3& b) {
  std::uint8_t* data = flags_.data();
  Traverse(origin_, size_, nx_, ny_, nz_, a, b, [data](std::size_t index, double) {
    std::atomic_ref<std::uint8_t> f(data[index]);
    if (!(f.load(std::memory_order_relaxed) & kPassed))
      f.fetch_or(kPassed, std::memory_order_relaxed);
    return true;
  });
}

bool VoxelSpace::SegmentFree(const Vec3& a, const Vec3& b, double stop_short) const {
  const double limit = (b - a).norm() - stop_short;
  bool free = true;
  const std::uint8_t* data = flags_.data();
  Traverse(origin_, size_, nx_, ny_, nz_, a, b, [&](std::size_t index, double t) {
    if (t > limit) return false;
    if (data[index] & kOccupied) {
      free = false;
      return false;
    }
    return true;
  });
  return free;
}

}  // namespace mopad::modelling
