// EmbreeWorld's movers (sim/embree_world.h): moving occluders in a scene of their own, each a
// motion-blurred instance whose track Embree interpolates by the ray's time.

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "common/frames.h"
#include "sim/embree_world.h"
#include "sim/embree_world_impl.h"

namespace mopad::sim {

namespace {

// Linear interpolation of a track at Embree time `time` in [0, 1]: position and (unwrapped)
// heading, as Embree interpolates a quaternion decomposition about one axis.
MoverPose Interpolate(const std::vector<MoverPose>& track, float time) {
  if (track.size() < 2) return track.empty() ? MoverPose{} : track.front();
  const double f =
      std::clamp(static_cast<double>(time), 0.0, 1.0) * static_cast<double>(track.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(f), track.size() - 2);
  const double a = f - static_cast<double>(k);
  const MoverPose& p = track[k];
  const MoverPose& q = track[k + 1];
  return {p.x + a * (q.x - p.x), p.y + a * (q.y - p.y), p.yaw + a * (q.yaw - p.yaw)};
}

}  // namespace

void EmbreeWorld::AddMovers(std::vector<MoverModel> movers) {
  Impl& w = *impl_;
  if (w.movers) throw std::logic_error("EmbreeWorld::AddMovers: the world has its movers already");
  if (movers.empty()) return;
  const std::string where = w.scene.source.empty() ? "scene" : w.scene.source;
  w.movers = rtcNewScene(w.device);
  rtcSetSceneFlags(w.movers, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(w.movers, RTC_BUILD_QUALITY_LOW);
  for (std::size_t i = 0; i < movers.size(); ++i) {
    MoverModel& model = movers[i];
    const std::string what = "mover '" + model.id + "'";
    if (model.id.empty()) throw InputError(where, "a mover without an id");
    if (std::find(w.element_ids.begin(), w.element_ids.end(), model.id) != w.element_ids.end())
      throw InputError(where, what + ": its id is an element of the scene already");
    MoverInstance m;
    m.id = model.id;
    m.child = rtcNewScene(w.device);
    const auto element = static_cast<std::int32_t>(w.element_ids.size());
    w.element_ids.push_back(model.id);
    const int material_base = static_cast<int>(w.mover_materials.size());
    w.mover_materials.insert(w.mover_materials.end(), model.materials.begin(),
                             model.materials.end());
    std::size_t triangles = 0;
    for (std::size_t k = 0; k < model.parts.size(); ++k) {
      scenes::MeshPart& part = model.parts[k];
      ValidatePart(part, model.materials.size(), where, what + " part " + std::to_string(k));
      if (part.triangles.empty()) continue;
      triangles += part.triangles.size();
      part.element_id = model.id;
      if (part.material >= 0) part.material += material_base;
      const auto index = static_cast<std::int32_t>(w.scene.parts.size() + w.mover_parts.size());
      RTCGeometry g = MakeTriangleGeometry(w.device, part);
      const unsigned id = rtcAttachGeometry(m.child, g);
      rtcReleaseGeometry(g);
      if (id >= m.child_geom_to_part.size()) m.child_geom_to_part.resize(id + 1, -1);
      m.child_geom_to_part[id] = index;
      AppendNormals(part, &w);
      w.part_element.push_back(element);
      w.mover_parts.push_back(std::move(part));
    }
    if (triangles == 0) {
      rtcReleaseScene(m.child);
      throw InputError(where, what + " has no triangles");
    }
    rtcCommitScene(m.child);
    m.instance = rtcNewGeometry(w.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(m.instance, m.child);
    m.track.assign(1, MoverPose{});
    const unsigned id = rtcAttachGeometry(w.movers, m.instance);
    rtcReleaseGeometry(m.instance);  // the scene holds it; the handle stays valid
    if (id != i) throw std::logic_error("EmbreeWorld::AddMovers: unexpected instance id");
    w.mover_list.push_back(std::move(m));
  }
  SetMoverTrack(0.0, 0.0, std::vector<std::vector<MoverPose>>(movers.size(), {MoverPose{}}));
}

std::size_t EmbreeWorld::MoverCount() const { return impl_->mover_list.size(); }

void EmbreeWorld::SetMoverTrack(double t0, double t1,
                                const std::vector<std::vector<MoverPose>>& track) {
  Impl& w = *impl_;
  if (track.size() != w.mover_list.size())
    throw std::invalid_argument("SetMoverTrack: one track per mover");
  const std::size_t steps = track.empty() ? 1 : track.front().size();
  if (steps < 1 || steps > RTC_MAX_TIME_STEP_COUNT || !std::isfinite(t0) || !std::isfinite(t1) ||
      t1 < t0 || (steps > 1 && !(t1 > t0)))
    throw std::invalid_argument("SetMoverTrack: 1-129 poses over a span t0 <= t1 (t0 < t1 for 2+)");
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (track[i].size() != steps)
      throw std::invalid_argument("SetMoverTrack: every mover needs the same number of poses");
    MoverInstance& m = w.mover_list[i];
    m.track = track[i];
    for (std::size_t k = 0; k < steps; ++k) {
      MoverPose& p = m.track[k];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.yaw))
        throw std::invalid_argument("SetMoverTrack: a pose is not finite");
      if (k > 0) {  // the shorter arc from the pose before
        const double prev = m.track[k - 1].yaw;
        p.yaw = prev + std::remainder(p.yaw - prev, 2.0 * kPi);
      }
    }
    rtcSetGeometryTimeStepCount(m.instance, static_cast<unsigned>(steps));
    for (std::size_t k = 0; k < steps; ++k) {
      const MoverPose& p = m.track[k];
      RTCQuaternionDecomposition qd;
      rtcInitQuaternionDecomposition(&qd);
      rtcQuaternionDecompositionSetQuaternion(&qd, static_cast<float>(std::cos(0.5 * p.yaw)), 0.f,
                                              0.f, static_cast<float>(std::sin(0.5 * p.yaw)));
      rtcQuaternionDecompositionSetTranslation(&qd, static_cast<float>(p.x),
                                               static_cast<float>(p.y), 0.f);
      rtcSetGeometryTransformQuaternion(m.instance, static_cast<unsigned>(k), &qd);
    }
    rtcCommitGeometry(m.instance);
  }
  w.track_t0 = t0;
  w.track_t1 = t1;
  if (w.movers) rtcCommitScene(w.movers);
  w.ThrowIfError("mover update");
}

float EmbreeWorld::TrackTime(double t) const {
  const Impl& w = *impl_;
  if (!(w.track_t1 > w.track_t0) || !(t > w.track_t0)) return 0.0f;
  if (t >= w.track_t1) return 1.0f;
  return static_cast<float>((t - w.track_t0) / (w.track_t1 - w.track_t0));
}

MoverPose EmbreeWorld::MoverAt(std::size_t i, double t) const {
  return Interpolate(impl_->mover_list.at(i).track, TrackTime(t));
}

Eigen::Matrix3f EmbreeWorld::Impl::MoverRotation(std::size_t mover, float time) const {
  const double yaw = Interpolate(mover_list[mover].track, time).yaw;
  return Eigen::AngleAxisf(static_cast<float>(yaw), Eigen::Vector3f::UnitZ()).toRotationMatrix();
}

const scenes::MeshPart& EmbreeWorld::Part(std::int32_t p) const {
  const auto n = static_cast<std::int32_t>(impl_->scene.parts.size());
  return p < n ? impl_->scene.parts.at(static_cast<std::size_t>(p))
               : impl_->mover_parts.at(static_cast<std::size_t>(p - n));
}

std::int32_t EmbreeWorld::PartCount() const {
  return static_cast<std::int32_t>(impl_->scene.parts.size() + impl_->mover_parts.size());
}

const scenes::Material* EmbreeWorld::MaterialOf(std::int32_t p) const {
  const int m = Part(p).material;
  if (m < 0) return nullptr;
  const bool mover = p >= static_cast<std::int32_t>(impl_->scene.parts.size());
  return mover ? &impl_->mover_materials.at(static_cast<std::size_t>(m))
               : &impl_->scene.materials.at(static_cast<std::size_t>(m));
}

void EmbreeWorld::Impl::TraceMovers1(RTCRayHit* rh) const {
  if (!movers) return;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(movers, &ctx, rh);
  if (rh->hit.geomID != RTC_INVALID_GEOMETRY_ID) rh->hit.instID[0] += kMoverInst;
}

void EmbreeWorld::Impl::TraceMovers16(const int* valid, RTCIntersectContext* ctx,
                                      RTCRayHit16* rh) const {
  if (!movers) return;
  alignas(64) RTCRayHit16 m;
  m.ray = rh->ray;
  for (int j = 0; j < 16; ++j) {
    m.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
    m.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
  }
  rtcIntersect16(valid, movers, ctx, &m);
  for (int j = 0; j < 16; ++j) {
    if (!valid[j] || m.hit.geomID[j] == RTC_INVALID_GEOMETRY_ID) continue;
    rh->ray.tfar[j] = m.ray.tfar[j];
    rh->hit.geomID[j] = m.hit.geomID[j];
    rh->hit.primID[j] = m.hit.primID[j];
    rh->hit.instID[0][j] = kMoverInst + m.hit.instID[0][j];
    rh->hit.u[j] = m.hit.u[j];
    rh->hit.v[j] = m.hit.v[j];
    rh->hit.Ng_x[j] = m.hit.Ng_x[j];
    rh->hit.Ng_y[j] = m.hit.Ng_y[j];
    rh->hit.Ng_z[j] = m.hit.Ng_z[j];
  }
}

}  // namespace mopad::sim
