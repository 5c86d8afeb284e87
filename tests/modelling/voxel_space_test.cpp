// The voxel walk of VoxelSpace (modelling/voxel_space.h) against an independent oracle: each
// voxel's box met by the segment (slab test). Random grids, occupied voxels and segments, some
// starting or ending outside the grid; a segment grazing a voxel's edge exactly is a null set
// the random draws never hit.

#include "modelling/voxel_space.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/rng.h"

namespace mopad::modelling {
namespace {

// Entry distance (m from a) of the segment a -> b into voxel (i, j, k)'s box, or +inf when the
// segment misses it (or only touches it).
double EntryInto(const VoxelSpace& v, int i, int j, int k, const Vec3& a, const Vec3& b) {
  const Vec3 lo = v.Origin() + v.Size() * Vec3(i, j, k), hi = lo + Vec3::Constant(v.Size());
  const Vec3 d = b - a;
  const double len = d.norm();
  const Vec3 dir = d / len;
  double t0 = 0.0, t1 = len;
  for (int ax = 0; ax < 3; ++ax) {
    if (std::abs(dir[ax]) < 1e-12) {
      if (a[ax] < lo[ax] || a[ax] >= hi[ax]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (lo[ax] - a[ax]) / dir[ax], tb = (hi[ax] - a[ax]) / dir[ax];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1 ? t0 : std::numeric_limits<double>::infinity();
}

Eigen::Vector3i VoxelOfPoint(const VoxelSpace& v, const Vec3& p) {
  return ((p - v.Origin()) / v.Size()).array().floor().cast<int>();
}

TEST(VoxelSpace, SegmentFreeAndMarkPassedMeetTheVoxelsTheSegmentCrosses) {
  CounterRng rng(11, "voxel_walk", 0);
  int blocked = 0, free = 0, marked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int nx = 5 + static_cast<int>(rng.Below(20)), ny = 5 + static_cast<int>(rng.Below(20));
    const int nz = 3 + static_cast<int>(rng.Below(10));
    const double size = rng.Uniform(0.05, 0.3);
    const Vec3 origin(rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-1, 1));
    VoxelSpace v(origin, size, nx, ny, nz);
    for (std::size_t i = 0; i < v.VoxelCount(); ++i)
      if (rng.Uniform() < 0.03) v.MutableFlags(i) |= VoxelSpace::kOccupied;
    const Vec3 extent = size * Vec3(nx, ny, nz);
    auto point = [&] {  // in the grid's box grown by a quarter on each side
      return Vec3(origin + Vec3(rng.Uniform(-0.25, 1.25) * extent.x(),
                                rng.Uniform(-0.25, 1.25) * extent.y(),
                                rng.Uniform(-0.25, 1.25) * extent.z()));
    };
    for (int s = 0; s < 200; ++s) {
      const Vec3 a = point(), b = point();
      const double stop_short = rng.Uniform() < 0.5 ? 0.0 : rng.Uniform(0.0, 0.5);
      const double limit = (b - a).norm() - stop_short;
      const Eigen::Vector3i vb = VoxelOfPoint(v, b);
      // Oracle: an occupied voxel other than b's, entered no later than the limit.
      bool oracle_free = true;
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) {
            if (!(v.Flags(v.Index(i, j, k)) & VoxelSpace::kOccupied)) continue;
            if (Eigen::Vector3i(i, j, k) == vb) continue;
            if (EntryInto(v, i, j, k, a, b) <= limit) oracle_free = false;
          }
      EXPECT_EQ(v.SegmentFree(a, b, stop_short), oracle_free)
          << "trial " << trial << " segment " << s;
      (oracle_free ? free : blocked) += 1;
    }
    // MarkPassed: exactly the voxels the segment crosses before b's.
    VoxelSpace m(origin, size, nx, ny, nz);
    const Vec3 a = point(), b = point();
    m.MarkPassed(a, b);
    const Eigen::Vector3i vb = VoxelOfPoint(m, b);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const bool crossed = Eigen::Vector3i(i, j, k) != vb &&
                               std::isfinite(EntryInto(m, i, j, k, a, b));
          const bool passed = m.Flags(m.Index(i, j, k)) & VoxelSpace::kPassed;
          EXPECT_EQ(passed, crossed) << "trial " << trial << " voxel " << i << " " << j << " " << k;
          marked += passed;
        }
  }
  // Both answers occur often enough to mean something.
  EXPECT_GT(blocked, 1000);
  EXPECT_GT(free, 1000);
  EXPECT_GT(marked, 200);
}

}  // namespace
}  // namespace mopad::modelling
