#pragma once
// The registration target of a mission, S(t-1): every registered scan, with each new scan
// merged beside what the robot does next (docs/performance.md).
//
// Merging a registered scan into the map (voxel cells, the normals near them, its range image)
// costs a few tenths of a second, and nothing needs the merged map until the next scan is
// registered: the model update, the next best scan and the drive come between. So Add hands
// the merge to a TBB task (the worker thread takes it, or the owner when it next asks for the
// map) and Map() waits for it. The map is the one merged in place: the merges run one at a
// time in the order of the Adds, and PointMap::Add is deterministic whatever thread runs it.
//
// Robot side. Not thread-safe: one owner calls Add and Map.

#include <memory>

#include <Eigen/Geometry>

#include "perception/registration.h"

namespace mopad::autonomy {

class RegistrationTarget {
 public:
  /// An empty target with the map parameters of `icp` (validated: InputError).
  explicit RegistrationTarget(const perception::IcpParams& icp);
  ~RegistrationTarget();  ///< waits for a merge still running (its error is dropped)
  RegistrationTarget(const RegistrationTarget&) = delete;
  RegistrationTarget& operator=(const RegistrationTarget&) = delete;

  /// Merges the scan's points `points_S` (scanner frame) registered at `X_MS` (the scanner in
  /// the map; its translation is the scan's origin, PointMap::Add with an origin) and returns
  /// at once. Throws InputError for a non-finite pose before anything is queued.
  void Add(perception::Points points_S, const Eigen::Isometry3d& X_MS);
  /// The map with every Add so far merged: waits for the merge in flight, and throws what it
  /// threw.
  const perception::PointMap& Map();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::autonomy
