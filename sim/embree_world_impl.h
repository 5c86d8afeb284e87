#pragma once
// Internal to sim/: the Embree side of EmbreeWorld. Never include from a public header.

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <mutex>
#include <string>
#include <vector>

#include "sim/embree_world.h"

namespace mopad::sim {

struct DoorInstance {
  std::string id;
  Eigen::Vector3d hinge_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d hinge_axis = Eigen::Vector3d::UnitZ();
  double modelled_angle = 0.0;  ///< rad, the angle the Scene geometry is at
  double angle = 0.0;           ///< rad, current
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();  ///< modelled -> current
  RTCScene child = nullptr;
  RTCGeometry instance = nullptr;
  unsigned instance_geom_id = RTC_INVALID_GEOMETRY_ID;
  std::vector<std::int32_t> child_geom_to_part;
};

/// A mover (EmbreeWorld::AddMovers): a child scene of its parts, instanced into `movers` with a
/// motion-blurred transform.
struct MoverInstance {
  std::string id;
  RTCScene child = nullptr;
  RTCGeometry instance = nullptr;
  std::vector<std::int32_t> child_geom_to_part;
  std::vector<MoverPose> track;  ///< the current track's poses, headings unwrapped
};

/// instID of a mover's hit in a packet after TraceMovers16: kMoverInst + mover index (top-level
/// instance ids are door leaves, far below).
inline constexpr unsigned kMoverInst = 0x40000000u;

struct EmbreeWorld::Impl {
  scenes::Scene scene;
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  /// The same geometries under RTC_SCENE_FLAG_ROBUST (watertight): rays that miss `top` are
  /// re-traced here, so a ray through a shared edge of two parts cannot slip out of a closed
  /// room. Null when WorldOptions::watertight_misses is off (or `top` is itself robust).
  RTCScene robust = nullptr;
  std::vector<std::int32_t> geom_to_part;  ///< top-level geomID -> part (-1: an instance)
  std::vector<std::int32_t> geom_to_door;  ///< top-level geomID -> door (-1: static)
  std::vector<DoorInstance> doors;
  std::vector<std::string> door_ids;
  std::vector<std::string> element_ids;
  std::vector<std::int32_t> part_element;
  std::vector<Eigen::Vector3f> normals;  ///< unit triangle normals of all parts, flattened
  std::vector<std::uint32_t>
      first_triangle;  ///< per part: index of its first triangle in `normals`
  /// Movers: their own scene (null without), their parts (part index scene.parts.size() + k)
  /// and materials, and the current track's span (s).
  RTCScene movers = nullptr;
  std::vector<MoverInstance> mover_list;
  std::vector<scenes::MeshPart> mover_parts;
  std::vector<scenes::Material> mover_materials;
  double track_t0 = 0.0, track_t1 = 0.0;

  std::mutex error_mutex;
  std::string errors;  ///< recorded by Embree's error callback

  ~Impl();
  /// Re-traces a missed ray in the watertight scene; fills `out` on a hit.
  void RetraceMiss(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_near, float t_far,
                   RayHit* out) const;
  void ThrowIfError(const char* stage);
  void UpdateDoorTransform(DoorInstance& d);

  /// Traces the valid lanes of a packet (its rays, tnear, tfar and time as they are) against
  /// the movers; where a mover is nearer than the packet's tfar (its hit, or its far limit after
  /// a miss), the lane takes the mover's hit (tfar, geomID, primID, u, v, Ng, and instID
  /// kMoverInst + mover). Nothing without movers.
  void TraceMovers16(const int* valid, RTCIntersectContext* ctx, RTCRayHit16* rh) const;
  /// One ray against the movers alone; a mover's hit gets instID kMoverInst + mover.
  void TraceMovers1(RTCRayHit* rh) const;

  /// The part a hit is on, and its door (-1: none) (geomID must be valid).
  std::int32_t PartOfHit(unsigned geom_id, unsigned inst_id, std::int32_t* door) const {
    *door = -1;
    if (inst_id == RTC_INVALID_GEOMETRY_ID) return geom_to_part[geom_id];
    if (inst_id >= kMoverInst) return mover_list[inst_id - kMoverInst].child_geom_to_part[geom_id];
    *door = geom_to_door[inst_id];
    return doors[static_cast<std::size_t>(*door)].child_geom_to_part[geom_id];
  }
  /// The unit world normal of triangle `prim_id` of the part a hit is on; `time` is the ray's
  /// (Embree's [0, 1]), which places a mover.
  Eigen::Vector3f NormalOfHit(std::int32_t part, unsigned prim_id, unsigned inst_id,
                              std::int32_t door, float time) const {
    const Eigen::Vector3f& n = normals[first_triangle[static_cast<std::size_t>(part)] + prim_id];
    if (door >= 0) return doors[static_cast<std::size_t>(door)].rotation * n;
    if (inst_id != RTC_INVALID_GEOMETRY_ID && inst_id >= kMoverInst)
      return MoverRotation(inst_id - kMoverInst, time) * n;
    return n;
  }
  Eigen::Matrix3f MoverRotation(std::size_t mover, float time) const;

  /// Fills `out` from Embree's hit fields (geomID must be valid); `time` is the ray's.
  void Resolve(unsigned geom_id, unsigned prim_id, unsigned inst_id, float t, float u, float v,
               RayHit* out, float time = 0.0f) const {
    out->t = t;
    out->triangle = prim_id;
    out->u = u;
    out->v = v;
    if (inst_id != RTC_INVALID_GEOMETRY_ID && inst_id >= kMoverInst) {
      out->door = -1;
      out->part = mover_list[inst_id - kMoverInst].child_geom_to_part[geom_id];
      out->normal = NormalOfHit(out->part, prim_id, inst_id, -1, time);
    } else if (inst_id != RTC_INVALID_GEOMETRY_ID) {
      const std::int32_t d = geom_to_door[inst_id];
      const DoorInstance& door = doors[static_cast<std::size_t>(d)];
      out->door = d;
      out->part = door.child_geom_to_part[geom_id];
      out->normal =
          door.rotation * normals[first_triangle[static_cast<std::size_t>(out->part)] + prim_id];
    } else {
      out->door = -1;
      out->part = geom_to_part[geom_id];
      out->normal = normals[first_triangle[static_cast<std::size_t>(out->part)] + prim_id];
    }
  }
};

/// Building blocks of EmbreeWorld (sim/embree_world.cpp), shared with the movers.
void ValidatePart(const scenes::MeshPart& p, std::size_t materials, const std::string& where,
                  const std::string& what);
RTCGeometry MakeTriangleGeometry(RTCDevice device, const scenes::MeshPart& p);
/// Appends the unit normals of `p`'s triangles (+z for a degenerate one) and its first index.
void AppendNormals(const scenes::MeshPart& p, EmbreeWorld::Impl* w);

/// Sets up an intersect context for coherent packets.
inline void InitCoherentContext(RTCIntersectContext* ctx) {
  rtcInitIntersectContext(ctx);
  ctx->flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

}  // namespace mopad::sim
