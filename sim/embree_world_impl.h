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

  std::mutex error_mutex;
  std::string errors;  ///< recorded by Embree's error callback

  ~Impl();
  /// Re-traces a missed ray in the watertight scene; fills `out` on a hit.
  void RetraceMiss(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_near, float t_far,
                   RayHit* out) const;
  void ThrowIfError(const char* stage);
  void UpdateDoorTransform(DoorInstance& d);

  /// Fills `out` from Embree's hit fields (geomID must be valid).
  void Resolve(unsigned geom_id, unsigned prim_id, unsigned inst_id, float t, float u, float v,
               RayHit* out) const {
    out->t = t;
    out->triangle = prim_id;
    out->u = u;
    out->v = v;
    if (inst_id != RTC_INVALID_GEOMETRY_ID) {
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

/// Sets up an intersect context for coherent packets.
inline void InitCoherentContext(RTCIntersectContext* ctx) {
  rtcInitIntersectContext(ctx);
  ctx->flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

}  // namespace mopad::sim
