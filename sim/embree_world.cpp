#include "sim/embree_world.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "common/error.h"
#include "sim/embree_world_impl.h"

namespace mopad::sim {

namespace {

void ErrorCallback(void* user, RTCError code, const char* str) {
  auto* impl = static_cast<EmbreeWorld::Impl*>(user);
  std::lock_guard<std::mutex> lock(impl->error_mutex);
  impl->errors +=
      "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (str ? str : "") + "; ";
}

}  // namespace

void ValidatePart(const scenes::MeshPart& p, std::size_t materials, const std::string& where,
                  const std::string& what) {
  for (const auto& v : p.positions) {
    if (!v.allFinite()) throw InputError(where, what + " has a non-finite vertex");
  }
  const int n = static_cast<int>(p.positions.size());
  for (const auto& t : p.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= n) {
      throw InputError(where, what + " has a triangle index out of range",
                       std::to_string(t.minCoeff()) + ".." + std::to_string(t.maxCoeff()),
                       "[0, " + std::to_string(n) + ")");
    }
  }
  if (!p.uvs.empty() && p.uvs.size() != p.positions.size()) {
    throw InputError(where, what + " has a UV count different from its vertex count",
                     std::to_string(p.uvs.size()), std::to_string(p.positions.size()));
  }
  if (p.material < -1 || p.material >= static_cast<int>(materials)) {
    throw InputError(where, what + " has a material index out of range", std::to_string(p.material),
                     "-1 or [0, " + std::to_string(materials) + ")");
  }
}

RTCGeometry MakeTriangleGeometry(RTCDevice device, const scenes::MeshPart& p) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.positions.size()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), p.triangles.size()));
  if (vb && ib) {
    for (std::size_t i = 0; i < p.positions.size(); ++i)
      std::memcpy(vb + 3 * i, p.positions[i].data(), 12);
    for (std::size_t i = 0; i < p.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = static_cast<unsigned>(p.triangles[i][k]);
  }
  rtcCommitGeometry(g);
  return g;
}

void AppendNormals(const scenes::MeshPart& p, EmbreeWorld::Impl* w) {
  w->first_triangle.push_back(static_cast<std::uint32_t>(w->normals.size()));
  for (const auto& tri : p.triangles) {
    const Eigen::Vector3f& a = p.positions[tri[0]];
    const Eigen::Vector3f& b = p.positions[tri[1]];
    const Eigen::Vector3f& c = p.positions[tri[2]];
    const Eigen::Vector3d n = (b - a).cast<double>().cross((c - a).cast<double>());
    const double len = n.norm();
    w->normals.push_back(len > 0 ? Eigen::Vector3f((n / len).cast<float>())
                                 : Eigen::Vector3f::UnitZ());
  }
}

EmbreeWorld::Impl::~Impl() {
  for (auto& d : doors) {
    if (d.child) rtcReleaseScene(d.child);
  }
  for (auto& m : mover_list) {
    if (m.child) rtcReleaseScene(m.child);
  }
  if (movers) rtcReleaseScene(movers);
  if (robust) rtcReleaseScene(robust);
  if (top) rtcReleaseScene(top);
  if (device) rtcReleaseDevice(device);
}

namespace {

// One ray for rtcIntersect1. Debian's Embree is built with ray masks: mask 0 hits nothing.
RTCRayHit MakeRayHit(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_near,
                     float t_far) {
  RTCRayHit rh;
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

void EmbreeWorld::Impl::RetraceMiss(const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                                    float t_near, float t_far, RayHit* out) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = MakeRayHit(o, d, t_near, t_far);
  rtcIntersect1(robust, &ctx, &rh);
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    Resolve(rh.hit.geomID, rh.hit.primID, rh.hit.instID[0], rh.ray.tfar, rh.hit.u, rh.hit.v, out);
  }
}

void EmbreeWorld::Impl::ThrowIfError(const char* stage) {
  std::lock_guard<std::mutex> lock(error_mutex);
  if (!errors.empty()) {
    const std::string msg = std::string("Embree failed during ") + stage + ": " + errors;
    errors.clear();
    throw std::runtime_error(msg);
  }
}

void EmbreeWorld::Impl::UpdateDoorTransform(DoorInstance& d) {
  const Eigen::AngleAxisd rot(d.angle - d.modelled_angle, d.hinge_axis);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(d.hinge_point);
  T.rotate(rot);
  T.translate(-d.hinge_point);
  d.rotation = rot.toRotationMatrix().cast<float>();
  float xfm[12];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) xfm[3 * c + r] = static_cast<float>(T.matrix()(r, c));
  rtcSetGeometryTransform(d.instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  rtcCommitGeometry(d.instance);
}

namespace {

// Element table in first-appearance order (deterministic).
void IndexElements(EmbreeWorld::Impl* w) {
  const auto& parts = w->scene.parts;
  std::unordered_map<std::string, std::int32_t> element_index;
  w->part_element.assign(parts.size(), -1);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& id = parts[i].element_id;
    if (id.empty()) continue;
    auto [it, inserted] =
        element_index.emplace(id, static_cast<std::int32_t>(w->element_ids.size()));
    if (inserted) w->element_ids.push_back(id);
    w->part_element[i] = it->second;
  }
}

// Unit normal of every triangle, flattened part by part.
void ComputeNormals(EmbreeWorld::Impl* w) {
  for (const auto& p : w->scene.parts) AppendNormals(p, w);
}

// The device (errors recorded by ErrorCallback), the top scene and, when misses are re-traced,
// the watertight scene.
void CreateScenes(const WorldOptions& options, EmbreeWorld::Impl* w) {
  w->device = rtcNewDevice(nullptr);
  if (!w->device) {
    throw std::runtime_error("cannot create Embree device (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(w->device, ErrorCallback, w);
  w->top = rtcNewScene(w->device);
  rtcSetSceneFlags(w->top, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(w->top, RTC_BUILD_QUALITY_HIGH);
  if (options.watertight_misses && !options.robust) {
    w->robust = rtcNewScene(w->device);
    rtcSetSceneFlags(w->robust, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(w->robust, RTC_BUILD_QUALITY_HIGH);
  }
}

// Which parts are swinging door leaves: per part its door index, -1 for static parts. Fills
// w->doors and w->door_ids from the truth's openings.
std::vector<std::int32_t> FindDoorLeaves(const scenes::GroundTruth* truth, EmbreeWorld::Impl* w) {
  const auto& parts = w->scene.parts;
  std::vector<std::int32_t> part_door(parts.size(), -1);
  if (truth) {
    std::unordered_map<std::string, std::int32_t> door_index;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const auto& p = parts[i];
      if (p.element_class != scenes::ElementClass::kDoorLeaf || p.triangles.empty()) continue;
      const scenes::Opening* o = truth->FindOpening(p.element_id);
      if (!o || o->type != scenes::OpeningType::kDoor) continue;
      auto [it, inserted] =
          door_index.emplace(p.element_id, static_cast<std::int32_t>(w->doors.size()));
      if (inserted) {
        DoorInstance d;
        d.id = o->id;
        d.hinge_point = o->hinge_point;
        const double axis_norm = o->hinge_axis.norm();
        if (!(axis_norm > 0) || !o->hinge_point.allFinite() || !std::isfinite(o->opening_angle)) {
          throw InputError(w->scene.source, "door '" + o->id + "' has an invalid hinge");
        }
        d.hinge_axis = o->hinge_axis / axis_norm;
        d.modelled_angle = d.angle = o->opening_angle;
        w->doors.push_back(std::move(d));
        w->door_ids.push_back(o->id);
      }
      part_door[i] = it->second;
    }
  }
  return part_door;
}

// Static geometry, one Embree geometry per part (geomID -> part).
void AttachStaticParts(const std::vector<std::int32_t>& part_door, EmbreeWorld::Impl* w) {
  const auto& parts = w->scene.parts;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].triangles.empty() || part_door[i] >= 0) continue;
    RTCGeometry g = MakeTriangleGeometry(w->device, parts[i]);
    const unsigned id = rtcAttachGeometry(w->top, g);
    if (w->robust) rtcAttachGeometryByID(w->robust, g, id);  // same ids: same lookup tables
    rtcReleaseGeometry(g);
    if (id >= w->geom_to_part.size()) {
      w->geom_to_part.resize(id + 1, -1);
      w->geom_to_door.resize(id + 1, -1);
    }
    w->geom_to_part[id] = static_cast<std::int32_t>(i);
  }
}

// Door leaves: a child scene per door, instanced into the top scene.
void AttachDoorLeaves(const std::vector<std::int32_t>& part_door, EmbreeWorld::Impl* w) {
  const auto& parts = w->scene.parts;
  for (std::size_t d = 0; d < w->doors.size(); ++d) {
    DoorInstance& door = w->doors[d];
    door.child = rtcNewScene(w->device);
    rtcSetSceneBuildQuality(door.child, RTC_BUILD_QUALITY_HIGH);
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (part_door[i] != static_cast<std::int32_t>(d)) continue;
      RTCGeometry g = MakeTriangleGeometry(w->device, parts[i]);
      const unsigned id = rtcAttachGeometry(door.child, g);
      rtcReleaseGeometry(g);
      if (id >= door.child_geom_to_part.size()) door.child_geom_to_part.resize(id + 1, -1);
      door.child_geom_to_part[id] = static_cast<std::int32_t>(i);
    }
    rtcCommitScene(door.child);
    door.instance = rtcNewGeometry(w->device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(door.instance, door.child);
    rtcSetGeometryTimeStepCount(door.instance, 1);
    w->UpdateDoorTransform(door);
    door.instance_geom_id = rtcAttachGeometry(w->top, door.instance);
    if (w->robust) rtcAttachGeometryByID(w->robust, door.instance, door.instance_geom_id);
    rtcReleaseGeometry(door.instance);  // the scene holds it; the handle stays valid
    if (door.instance_geom_id >= w->geom_to_part.size()) {
      w->geom_to_part.resize(door.instance_geom_id + 1, -1);
      w->geom_to_door.resize(door.instance_geom_id + 1, -1);
    }
    w->geom_to_door[door.instance_geom_id] = static_cast<std::int32_t>(d);
  }
}

}  // namespace

EmbreeWorld::EmbreeWorld(scenes::Scene scene, const scenes::GroundTruth* truth,
                         WorldOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.scene = std::move(scene);
  const std::string where = w.scene.source.empty() ? "scene" : w.scene.source;
  for (std::size_t i = 0; i < w.scene.parts.size(); ++i)
    ValidatePart(w.scene.parts[i], w.scene.materials.size(), where,
                 "part " + std::to_string(i) + " ('" + w.scene.parts[i].name + "')");
  IndexElements(&w);
  ComputeNormals(&w);
  CreateScenes(options, &w);
  const std::vector<std::int32_t> part_door = FindDoorLeaves(truth, &w);
  AttachStaticParts(part_door, &w);
  AttachDoorLeaves(part_door, &w);
  rtcCommitScene(w.top);
  if (w.robust) rtcCommitScene(w.robust);
  w.ThrowIfError("scene build");
}

EmbreeWorld::~EmbreeWorld() = default;
EmbreeWorld::EmbreeWorld(EmbreeWorld&&) noexcept = default;
EmbreeWorld& EmbreeWorld::operator=(EmbreeWorld&&) noexcept = default;

const scenes::Scene& EmbreeWorld::scene() const { return impl_->scene; }
const std::vector<std::string>& EmbreeWorld::DoorIds() const { return impl_->door_ids; }
const std::vector<std::string>& EmbreeWorld::ElementIds() const { return impl_->element_ids; }

std::int32_t EmbreeWorld::ElementIndex(std::int32_t part) const {
  if (part < 0 || part >= static_cast<std::int32_t>(impl_->part_element.size())) return -1;
  return impl_->part_element[static_cast<std::size_t>(part)];
}

void EmbreeWorld::SetDoorAngle(const std::string& id, double angle_rad) {
  for (auto& d : impl_->doors) {
    if (d.id != id) continue;
    if (!std::isfinite(angle_rad)) throw InputError("", "door '" + id + "' angle is not finite");
    d.angle = angle_rad;
    impl_->UpdateDoorTransform(d);
    rtcCommitScene(impl_->top);
    if (impl_->robust) rtcCommitScene(impl_->robust);
    impl_->ThrowIfError("door update");
    return;
  }
  throw InputError("", "unknown door id '" + id + "'", "",
                   "a door leaf with a hinge in the ground truth");
}

double EmbreeWorld::DoorAngle(const std::string& id) const {
  for (const auto& d : impl_->doors)
    if (d.id == id) return d.angle;
  throw InputError("", "unknown door id '" + id + "'");
}

RayHit EmbreeWorld::Intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                              float t_near, float t_far, double time) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = MakeRayHit(origin, direction, t_near, t_far);
  rtcIntersect1(impl_->top, &ctx, &rh);
  RayHit out;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    impl_->Resolve(rh.hit.geomID, rh.hit.primID, rh.hit.instID[0], rh.ray.tfar, rh.hit.u, rh.hit.v,
                   &out);
  } else if (impl_->robust) {
    impl_->RetraceMiss(origin, direction, t_near, t_far, &out);
  }
  if (impl_->movers) {
    RTCRayHit m = MakeRayHit(origin, direction, t_near, out.hit() ? out.t : t_far);
    m.ray.time = TrackTime(time);
    impl_->TraceMovers1(&m);
    if (m.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      impl_->Resolve(m.hit.geomID, m.hit.primID, m.hit.instID[0], m.ray.tfar, m.hit.u, m.hit.v,
                     &out, m.ray.time);
    }
  }
  return out;
}

void EmbreeWorld::IntersectMany(std::span<const Eigen::Vector3f> origins,
                                std::span<const Eigen::Vector3f> directions, float t_near,
                                float t_far, std::span<RayHit> hits, double time) const {
  if (origins.size() != directions.size() || origins.size() != hits.size()) {
    throw std::invalid_argument("EmbreeWorld::IntersectMany: span sizes differ");
  }
  RTCIntersectContext ctx;
  InitCoherentContext(&ctx);
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  const float mover_time = impl_->movers ? TrackTime(time) : 0.0f;
  for (std::size_t i0 = 0; i0 < origins.size(); i0 += 16) {
    const std::size_t n = std::min<std::size_t>(16, origins.size() - i0);
    for (std::size_t k = 0; k < 16; ++k) {
      const std::size_t i = i0 + std::min(k, n - 1);
      valid[k] = k < n ? -1 : 0;
      rh.ray.org_x[k] = origins[i].x();
      rh.ray.org_y[k] = origins[i].y();
      rh.ray.org_z[k] = origins[i].z();
      rh.ray.dir_x[k] = directions[i].x();
      rh.ray.dir_y[k] = directions[i].y();
      rh.ray.dir_z[k] = directions[i].z();
      rh.ray.tnear[k] = t_near;
      rh.ray.tfar[k] = t_far;
      rh.ray.time[k] = mover_time;
      rh.ray.mask[k] = 0xFFFFFFFFu;
      rh.ray.id[k] = static_cast<unsigned>(k);
      rh.ray.flags[k] = 0;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, impl_->top, &ctx, &rh);
    for (std::size_t k = 0; k < n; ++k) {
      RayHit& out = hits[i0 + k];
      out = RayHit{};
      if (rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) {
        impl_->Resolve(rh.hit.geomID[k], rh.hit.primID[k], rh.hit.instID[0][k], rh.ray.tfar[k],
                       rh.hit.u[k], rh.hit.v[k], &out);
      } else if (impl_->robust) {
        impl_->RetraceMiss(origins[i0 + k], directions[i0 + k], t_near, t_far, &out);
        if (out.hit()) rh.ray.tfar[k] = out.t;
      }
    }
    if (!impl_->movers) continue;
    impl_->TraceMovers16(valid, &ctx, &rh);
    for (std::size_t k = 0; k < n; ++k) {
      const unsigned inst = rh.hit.instID[0][k];
      if (inst == RTC_INVALID_GEOMETRY_ID || inst < kMoverInst) continue;
      impl_->Resolve(rh.hit.geomID[k], rh.hit.primID[k], rh.hit.instID[0][k], rh.ray.tfar[k],
                     rh.hit.u[k], rh.hit.v[k], &hits[i0 + k], mover_time);
    }
  }
}

}  // namespace mopad::sim
