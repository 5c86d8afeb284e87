#pragma once
// The voxel space of a room's RoI (paper §3.1 step (5)): a dense grid of cubes labelled by
// visibility (a beam passed through / something was hit / never seen) and by the structural
// condition (the voxel holds part of a RoI face: one voxel layer per face, the layer containing
// it, as the evaluator's truth DSM3 — set by RoomModel). Labels are DSM3's six (§3.2: opening,
// structure, occluded structure, clutter, empty, unseen), so the same grid extends to DSM3.
//
// Frame: map, metres. Voxel (i, j, k) covers origin + [i, i+1) * size (etc.); the z origin is
// aligned so the floor lies in the middle of layer 0's upper neighbour band (see RoomModel).
// Not thread-safe for writes; const queries may run concurrently.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "common/frames.h"

namespace mopad::modelling {

/// DSM3-compatible voxel labels (values are stable; written to files).
enum class VoxelLabel : std::uint8_t {
  kUnseen = 0,             ///< no beam passed, nothing hit, not on a RoI face
  kEmpty = 1,              ///< a beam passed through, nothing hit
  kStructure = 2,          ///< on a RoI face and hit (sensed structural element)
  kOccludedStructure = 3,  ///< on a RoI face, never seen
  kClutter = 4,            ///< hit, inside the RoI, not on a face
  kOpening = 5,            ///< on a RoI face, beams passed through it, nothing hit
};
constexpr int kVoxelLabelCount = 6;
const char* ToString(VoxelLabel label);

class VoxelSpace {
 public:
  /// Flag bits per voxel.
  /// kOpeningFace: a structural voxel inside a recognised opening (SM4, MarkOpeningVoxels in
  /// modelling/openings.h); it reads as opening whatever it holds (a closed leaf, glass).
  enum : std::uint8_t {
    kOccupied = 1,
    kPassed = 2,
    kStructural = 4,
    kInside = 8,
    kOpeningFace = 16
  };

  VoxelSpace() = default;
  /// An all-unseen grid of nx * ny * nz voxels of edge `size` (m) from `origin`.
  VoxelSpace(const Vec3& origin, double size, int nx, int ny, int nz);

  const Vec3& Origin() const { return origin_; }
  double Size() const { return size_; }
  int Nx() const { return nx_; }
  int Ny() const { return ny_; }
  int Nz() const { return nz_; }
  std::size_t VoxelCount() const { return flags_.size(); }
  bool empty() const { return flags_.empty(); }

  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < nx_ && j < ny_ && k < nz_;
  }
  std::size_t Index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * ny_ + j) * nx_ + i;
  }
  Eigen::Vector3i VoxelOf(const Vec3& p_M) const;
  Vec3 Centre(int i, int j, int k) const {
    return origin_ + size_ * Vec3(i + 0.5, j + 0.5, k + 0.5);
  }
  std::uint8_t Flags(std::size_t index) const { return flags_[index]; }
  std::uint8_t& MutableFlags(std::size_t index) { return flags_[index]; }
  const std::vector<std::uint8_t>& FlagData() const { return flags_; }
  bool Occupied(const Vec3& p_M) const;

  /// Label of one voxel from its flags (see VoxelLabel).
  VoxelLabel Label(std::size_t index) const;
  /// Voxel count per label, indexed by the label's value.
  std::array<std::int64_t, kVoxelLabelCount> LabelCounts() const;

  /// Marks every voxel the segment a -> b passes through *before* the voxel containing b as
  /// passed (3D DDA, Amanatides & Woo 1987); clipped to the grid. Safe to call concurrently
  /// from several threads (the flag is only ever set, through atomic stores).
  void MarkPassed(const Vec3& a, const Vec3& b);
  /// True if the segment a -> b meets no occupied voxel, ignoring voxels entered after
  /// distance |b - a| - stop_short from a. Parts outside the grid count as free.
  bool SegmentFree(const Vec3& a, const Vec3& b, double stop_short) const;

 private:
  Vec3 origin_ = Vec3::Zero();
  double size_ = 0.1;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint8_t> flags_;
};

}  // namespace mopad::modelling
