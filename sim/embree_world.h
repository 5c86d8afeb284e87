#pragma once
// The ray-casting world: a loaded Scene in Embree, with every door leaf as an instance that can
// swing about its hinge during a mission.
//
// Frames and units: everything in the world frame W (Z-up, metres), as the Scene. Distances are
// along unit ray directions, in metres.
//
// Door leaves: parts with element_class kDoorLeaf whose element_id names a door Opening of the
// GroundTruth become one Embree instance per opening. The Scene holds the leaf at the opening's
// modelled angle (Opening::opening_angle); SetDoorAngle(id, lambda) rotates the leaf about the
// hinge axis (Opening::hinge_point, hinge_axis) by lambda - opening_angle. Without a matching
// opening a leaf is static geometry.
//
// Movers: moving occluders (people walking, sim/people.h), each a set of parts in its own frame
// (x forward, z up, origin on the floor) instanced into a scene of their own, which every query
// traces after the building. Their parts take part indices after the scene's (Part, PartCount)
// and their ids element indices after the scene's; they are in no truth of the building. A
// track (SetMoverTrack) places them over a time span with up to 129 poses each, which Embree
// interpolates per ray by the ray's time (motion blur): a query at time t sees each mover where
// the track puts it at t. Without movers, a query traces the building alone.
//
// Embree stays behind a pimpl (no Embree header here). Its error callback only records; the
// constructor and SetDoorAngle check after every commit and throw std::runtime_error.
// Every ray sets mask = 0xFFFFFFFF: Debian's Embree is built with ray masks.
//
// Thread-safety: const queries may run concurrently from any number of threads. SetDoorAngle,
// AddMovers and SetMoverTrack mutate the acceleration structures and must not overlap any query.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::sim {

/// Result of one ray query. A miss has part == -1 and t == +inf.
struct RayHit {
  float t = std::numeric_limits<float>::infinity();  ///< m along the unit direction
  std::int32_t part = -1;                            ///< index into Scene::parts, -1 = miss
  std::uint32_t triangle = 0;                        ///< index into that part's triangles
  float u = 0, v = 0;  ///< barycentrics of vertices 1 and 2 (Embree's convention)
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  ///< unit geometric normal, world frame,
                                                     ///< (v1-v0)x(v2-v0) orientation
  std::int32_t door = -1;  ///< door index (see DoorIds) when a leaf was hit, else -1
  bool hit() const { return part >= 0; }
};

/// A moving occluder: its parts in its own frame (x forward, y left, z up, origin on the floor);
/// their `material` indexes `materials`.
struct MoverModel {
  std::string id;  ///< its element id, e.g. "person_1"
  std::vector<scenes::MeshPart> parts;
  std::vector<scenes::Material> materials;
};

/// A mover's pose on the floor at one time step: position (m, world frame) and heading (rad).
struct MoverPose {
  double x = 0.0, y = 0.0, yaw = 0.0;
};

/// Options for building the world.
struct WorldOptions {
  /// Trace everything with Embree's robust (watertight) intersector. ~35 % slower packets.
  bool robust = false;
  /// Keep the fast intersector but re-trace every miss against a robust copy of the scene (one
  /// more BVH; misses are few indoors). Without it, a ray aimed exactly at an edge shared by two
  /// parts (a room corner seen along a grid azimuth) can slip between them and leave a closed
  /// room.
  bool watertight_misses = true;
};

class EmbreeWorld {
 public:
  /// Builds the world. `truth` (may be null) supplies door hinges. Throws InputError on
  /// non-finite vertices or out-of-range indices, std::runtime_error on Embree failures.
  explicit EmbreeWorld(scenes::Scene scene, const scenes::GroundTruth* truth = nullptr,
                       WorldOptions options = {});
  ~EmbreeWorld();
  EmbreeWorld(EmbreeWorld&&) noexcept;
  EmbreeWorld& operator=(EmbreeWorld&&) noexcept;
  EmbreeWorld(const EmbreeWorld&) = delete;
  EmbreeWorld& operator=(const EmbreeWorld&) = delete;

  const scenes::Scene& scene() const;

  /// Ids of the doors that can swing, in index order (RayHit::door indexes this).
  const std::vector<std::string>& DoorIds() const;
  /// Sets the opening angle lambda (rad) of door `id`. Throws InputError for an unknown id.
  /// Not thread-safe with queries.
  void SetDoorAngle(const std::string& id, double angle_rad);
  /// Current opening angle of door `id` (rad).
  double DoorAngle(const std::string& id) const;

  /// Adds moving occluders, once, before any scanner or LRF is made on this world (they read
  /// the part tables when made). Each stands at the origin until SetMoverTrack. Throws
  /// InputError for a mover without triangles, a bad part or an id the scene already uses.
  void AddMovers(std::vector<MoverModel> movers);
  std::size_t MoverCount() const;
  /// Where the movers are over [t0, t1] (s): track[i] holds mover i's K poses at
  /// t0 + k (t1 - t0) / (K - 1), K in [1, 129] and the same for all (K = 1: standing). Between
  /// poses a mover moves on a straight line and turns by the shorter arc. Not thread-safe with
  /// queries. Throws std::invalid_argument for a track that does not fit.
  void SetMoverTrack(double t0, double t1, const std::vector<std::vector<MoverPose>>& track);
  /// The pose of mover `i` at time `t` (s) on the current track (t clamped to its span).
  MoverPose MoverAt(std::size_t i, double t) const;
  /// A query's time for the movers, in Embree's [0, 1] over the current track's span.
  float TrackTime(double t) const;
  /// Part `p` of the world: the scene's (p < scene().parts.size()) or a mover's.
  const scenes::MeshPart& Part(std::int32_t p) const;
  std::int32_t PartCount() const;
  /// The material of part `p` (a mover's from its own list); nullptr = the default grey.
  const scenes::Material* MaterialOf(std::int32_t p) const;

  /// Element ids of the scene in first-appearance order of the parts ("" is not listed);
  /// ElementIndex(part) indexes this table, -1 for parts without an id.
  const std::vector<std::string>& ElementIds() const;
  std::int32_t ElementIndex(std::int32_t part) const;

  /// One ray, world frame. `direction` must be unit length. Reports the first surface with
  /// t in [t_near, t_far]; movers where they are at `time` (s; the default: the track's start).
  RayHit Intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                   float t_near = 0.0f, float t_far = std::numeric_limits<float>::infinity(),
                   double time = -std::numeric_limits<double>::infinity()) const;
  /// Many rays, traced in 16-wide packets in the given order (keep neighbouring rays adjacent
  /// for speed). Sizes of all spans must match. Movers where they are at `time` (s).
  void IntersectMany(std::span<const Eigen::Vector3f> origins,
                     std::span<const Eigen::Vector3f> directions, float t_near, float t_far,
                     std::span<RayHit> hits,
                     double time = -std::numeric_limits<double>::infinity()) const;

  /// Internal state (Embree handles); only sim/*.cpp can use it.
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mopad::sim
