#include "sim/robot_body.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/rng.h"

namespace mopad::sim {

void RobotBodyParams::Validate() const {
  ValidateParams(*this, "robot_body.");
  if (body_height <= ground_clearance + 0.01) {
    throw InputError("", "parameter 'robot_body.body_height' must exceed ground_clearance + 0.01",
                     std::to_string(body_height), "> " + std::to_string(ground_clearance + 0.01));
  }
}

// --- Wheel odometry ---------------------------------------------------------------------------

WheelOdometry::WheelOdometry(const WheelOdometryParams& params, double true_wheel_base,
                             std::uint64_t seed)
    : params_(params), true_wheel_base_(true_wheel_base), seed_(seed) {}

void WheelOdometry::Integrate(double left_travel, double right_travel, double dt,
                              double timestamp) {
  CounterRng rng(seed_, "sim/wheel_odometry", step_++);
  // Slip: a random walk in each wheel's travel whose variance grows with distance, so the error
  // does not depend on the step length.
  const double nl = rng.Normal(), nr = rng.Normal();
  const double slip_l = params_.slip_sigma * std::sqrt(std::abs(left_travel)) * nl;
  const double slip_r = params_.slip_sigma * std::sqrt(std::abs(right_travel)) * nr;
  // Encoder ticks are (travel + slip) / r_true; the robot multiplies by its believed radius.
  const double dl = (left_travel + slip_l) * (1.0 + params_.left_radius_error);
  const double dr = (right_travel + slip_r) * (1.0 + params_.right_radius_error);
  const double believed_base = true_wheel_base_ * (1.0 + params_.track_width_error);
  const double ds = 0.5 * (dl + dr);
  const double dth = (dr - dl) / believed_base;
  Pose2& p = reading_.X_OB;
  const double mid = p.yaw + 0.5 * dth;  // second-order (midpoint) integration
  p.x += ds * std::cos(mid);
  p.y += ds * std::sin(mid);
  p.yaw = WrapAngle(p.yaw + dth);
  reading_.timestamp = timestamp;
  reading_.v = dt > 0.0 ? ds / dt : 0.0;
  reading_.w = dt > 0.0 ? dth / dt : 0.0;
}

// --- Bullet collision world -------------------------------------------------------------------

namespace {

/// Records the deepest penetration (most negative distance) of one contact query.
struct DeepestContact : btCollisionWorld::ContactResultCallback {
  double min_distance = 0.0;
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                           const btCollisionObjectWrapper*, int, int) override {
    min_distance = std::min(min_distance, static_cast<double>(cp.getDistance()));
    return 0;
  }
};

/// Exact unicycle motion over time t at constant (v, w).
Pose2 Advance(const Pose2& p, double v, double w, double t) {
  Pose2 q = p;
  const double dth = w * t;
  if (std::abs(dth) < 1e-9) {
    q.x += v * t * std::cos(p.yaw + 0.5 * dth);
    q.y += v * t * std::sin(p.yaw + 0.5 * dth);
  } else {
    const double r = v / w;
    q.x += r * (std::sin(p.yaw + dth) - std::sin(p.yaw));
    q.y -= r * (std::cos(p.yaw + dth) - std::cos(p.yaw));
  }
  q.yaw = WrapAngle(p.yaw + dth);
  return q;
}

}  // namespace

struct RobotBody::Impl {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};

  // Static mesh (Bullet references the arrays, so they live here).
  std::vector<float> mesh_vertices;
  std::vector<int> mesh_indices;
  std::unique_ptr<btTriangleIndexVertexArray> mesh_array;
  std::unique_ptr<btBvhTriangleMeshShape> mesh_shape;
  std::unique_ptr<btCollisionObject> mesh_object;

  struct Leaf {
    std::unique_ptr<btBoxShape> shape;
    std::unique_ptr<btCollisionObject> object;
  };
  std::vector<Leaf> leaves;

  std::unique_ptr<btBoxShape> body_shape;
  std::unique_ptr<btCollisionObject> body_object;
  double body_centre_z = 0.0;
  double footprint_offset_x = 0.0;

  ~Impl() {
    if (mesh_object) world.removeCollisionObject(mesh_object.get());
    for (auto& l : leaves) world.removeCollisionObject(l.object.get());
  }

  /// Deepest penetration (m, >= 0) of the body box at pose `p`.
  double Penetration(const Pose2& p) {
    btTransform t;
    t.setIdentity();
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    t.setOrigin(btVector3(static_cast<btScalar>(p.x + c * footprint_offset_x),
                          static_cast<btScalar>(p.y + s * footprint_offset_x),
                          static_cast<btScalar>(body_centre_z)));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), static_cast<btScalar>(p.yaw)));
    body_object->setWorldTransform(t);
    DeepestContact cb;
    world.contactTest(body_object.get(), cb);
    return -cb.min_distance;
  }
};

RobotBody::RobotBody(const RobotBodyParams& params, const std::vector<Eigen::Vector3f>& vertices,
                     const std::vector<std::uint32_t>& triangles, const Pose2& X_WB_start,
                     std::uint64_t seed)
    : impl_(std::make_unique<Impl>()),
      params_(params),
      X_WB_(X_WB_start),
      odometry_(params.odometry, params.wheel_base, seed) {
  params_.Validate();
  if (triangles.size() % 3 != 0) {
    throw InputError("", "robot body mesh: index count is not a multiple of 3",
                     std::to_string(triangles.size()), "3 * triangles");
  }
  Impl& m = *impl_;
  if (!triangles.empty()) {
    m.mesh_vertices.reserve(vertices.size() * 3);
    for (const auto& v : vertices) {
      if (!v.allFinite()) throw InputError("", "robot body mesh: non-finite vertex");
      m.mesh_vertices.insert(m.mesh_vertices.end(), {v.x(), v.y(), v.z()});
    }
    m.mesh_indices.reserve(triangles.size());
    for (std::uint32_t i : triangles) {
      if (i >= vertices.size()) {
        throw InputError("", "robot body mesh: vertex index out of range", std::to_string(i),
                         "< " + std::to_string(vertices.size()));
      }
      m.mesh_indices.push_back(static_cast<int>(i));
    }
    m.mesh_array = std::make_unique<btTriangleIndexVertexArray>(
        static_cast<int>(triangles.size() / 3), m.mesh_indices.data(), 3 * sizeof(int),
        static_cast<int>(vertices.size()), m.mesh_vertices.data(), 3 * sizeof(float));
    m.mesh_shape = std::make_unique<btBvhTriangleMeshShape>(m.mesh_array.get(), true);
    m.mesh_object = std::make_unique<btCollisionObject>();
    m.mesh_object->setCollisionShape(m.mesh_shape.get());
    m.world.addCollisionObject(m.mesh_object.get());
  }
  const double hz = 0.5 * (params_.body_height - params_.ground_clearance);
  m.body_centre_z = params_.ground_clearance + hz;
  m.footprint_offset_x = params_.footprint_offset_x;
  m.body_shape = std::make_unique<btBoxShape>(
      btVector3(static_cast<btScalar>(0.5 * params_.footprint_length),
                static_cast<btScalar>(0.5 * params_.footprint_width), static_cast<btScalar>(hz)));
  // A small margin keeps the box's reported distances close to its true faces.
  m.body_shape->setMargin(0.005f);
  m.body_object = std::make_unique<btCollisionObject>();
  m.body_object->setCollisionShape(m.body_shape.get());
}

RobotBody::~RobotBody() = default;
RobotBody::RobotBody(RobotBody&&) noexcept = default;
RobotBody& RobotBody::operator=(RobotBody&&) noexcept = default;

int RobotBody::AddDoorLeaf(const Eigen::Vector3d& half_extents, const Eigen::Isometry3d& X_WD) {
  if (!(half_extents.array() > 0.0).all() || !half_extents.allFinite()) {
    throw InputError("", "door leaf half extents must be positive", "", "> 0");
  }
  Impl::Leaf leaf;
  leaf.shape = std::make_unique<btBoxShape>(btVector3(static_cast<btScalar>(half_extents.x()),
                                                      static_cast<btScalar>(half_extents.y()),
                                                      static_cast<btScalar>(half_extents.z())));
  leaf.shape->setMargin(0.002f);
  leaf.object = std::make_unique<btCollisionObject>();
  leaf.object->setCollisionShape(leaf.shape.get());
  impl_->world.addCollisionObject(leaf.object.get());
  impl_->leaves.push_back(std::move(leaf));
  const int id = static_cast<int>(impl_->leaves.size()) - 1;
  SetDoorLeafPose(id, X_WD);
  return id;
}

void RobotBody::SetDoorLeafPose(int id, const Eigen::Isometry3d& X_WD) {
  if (id < 0 || id >= static_cast<int>(impl_->leaves.size())) {
    throw InputError("", "unknown door leaf id", std::to_string(id),
                     "[0, " + std::to_string(impl_->leaves.size()) + ")");
  }
  const Eigen::Quaterniond q(X_WD.linear());
  const Eigen::Vector3d t = X_WD.translation();
  btTransform bt;
  bt.setOrigin(btVector3(static_cast<btScalar>(t.x()), static_cast<btScalar>(t.y()),
                         static_cast<btScalar>(t.z())));
  bt.setRotation(btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()),
                              static_cast<btScalar>(q.z()), static_cast<btScalar>(q.w())));
  auto* obj = impl_->leaves[static_cast<std::size_t>(id)].object.get();
  obj->setWorldTransform(bt);
  impl_->world.updateSingleAabb(obj);
}

bool RobotBody::InCollision(const Pose2& X_WB) const {
  return impl_->Penetration(X_WB) > params_.contact_tolerance;
}

void RobotBody::Teleport(const Pose2& X_WB) {
  X_WB_ = X_WB;
  v_ = w_ = 0.0;
  in_contact_ = false;
}

BodyStepResult RobotBody::Step(const interfaces::VelocityCommand& cmd, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw InputError("", "RobotBody::Step: dt must be positive", std::to_string(dt), "> 0");
  }
  const RobotBodyParams& p = params_;
  // 1. Speed limits, including the per-wheel limit (scale both down to keep the curvature).
  double v_cmd =
      std::isfinite(cmd.v) ? std::clamp(cmd.v, -p.max_linear_speed, p.max_linear_speed) : 0.0;
  double w_cmd =
      std::isfinite(cmd.w) ? std::clamp(cmd.w, -p.max_angular_speed, p.max_angular_speed) : 0.0;
  const double wheel = std::abs(v_cmd) + 0.5 * p.wheel_base * std::abs(w_cmd);
  if (wheel > p.max_linear_speed) {
    const double k = p.max_linear_speed / wheel;
    v_cmd *= k;
    w_cmd *= k;
  }
  // 2. Acceleration limits.
  const double v_new =
      v_ + std::clamp(v_cmd - v_, -p.max_linear_acceleration * dt, p.max_linear_acceleration * dt);
  const double w_new = w_ + std::clamp(w_cmd - w_, -p.max_angular_acceleration * dt,
                                       p.max_angular_acceleration * dt);
  // Trapezoidal speed over the step; integrate at the mean speeds.
  const double v_mean = 0.5 * (v_ + v_new), w_mean = 0.5 * (w_ + w_new);

  // 3. Sub-stepped collision checking.
  BodyStepResult result;
  const int n = std::max(
      1, static_cast<int>(std::ceil(std::max(std::abs(v_mean * dt) / p.max_substep_translation,
                                             std::abs(w_mean * dt) / p.max_substep_rotation))));
  const double h = dt / n;
  double current_pen = impl_->Penetration(X_WB_);
  double travelled_t = 0.0;
  for (int i = 0; i < n; ++i) {
    const Pose2 next = Advance(X_WB_, v_mean, w_mean, h);
    const double pen = impl_->Penetration(next);
    ++result.substeps;
    // Reject a sub-step that starts a contact or deepens an existing one (e.g. a leaf closed
    // onto the base): moving out of a contact is allowed.
    if (pen > p.contact_tolerance && pen > current_pen + 1e-6) {
      result.blocked = true;
      break;
    }
    X_WB_ = next;
    current_pen = pen;
    travelled_t += h;
  }

  // 4. Odometry sees the wheels' true travel (a stopped base stalls its wheels).
  const double ds = v_mean * travelled_t, dth = w_mean * travelled_t;
  const double half_base = 0.5 * p.wheel_base;
  time_ += dt;
  odometry_.Integrate(ds - dth * half_base, ds + dth * half_base, dt, time_);

  if (in_contact_) {
    // A contact episode ends once the base has left the place where it was stopped, so that
    // creeping on against the same obstacle is one contact, not one per step.
    const double moved = std::hypot(X_WB_.x - stop_pose_.x, X_WB_.y - stop_pose_.y);
    const double turned = std::abs(WrapAngle(X_WB_.yaw - stop_pose_.yaw));
    if (moved > kContactReleaseDistance || turned > kContactReleaseAngle) in_contact_ = false;
  }
  if (result.blocked) {
    ++blocked_steps_;
    if (!in_contact_) {
      ++contact_count_;
      contacts_.push_back({time_, X_WB_, std::abs(v_mean), p.mass * std::abs(v_mean)});
    }
    in_contact_ = true;
    stop_pose_ = X_WB_;
    v_ = w_ = 0.0;
  } else {
    v_ = v_new;
    w_ = w_new;
  }
  result.v = v_;
  result.w = w_;
  return result;
}

}  // namespace mopad::sim
