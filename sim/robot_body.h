#pragma once
// The robot's physical base in the simulator: a differential-drive body that moves over the
// static scene's collision mesh and among door leaves, and the drifting wheel odometry that is
// the robot's only proprioception.
//
// Model. The base is velocity-controlled, as a real base with motor speed loops is: commanded
// (v, w) are clamped to the speed limits (and to the per-wheel speed limit), then slewed by the
// acceleration limits, then integrated exactly along circular arcs. Collision uses Bullet's
// btCollisionWorld with a *kinematic* box (no btDiscreteDynamicsWorld): each step is split into
// sub-steps of at most `max_substep_translation` / `max_substep_rotation`, and the box is tested
// for penetration against the static btBvhTriangleMeshShape and the door-leaf boxes at every
// sub-step. A sub-step that would penetrate is rejected and the base stops (a bumper stop):
// speeds drop to zero and a contact is counted. Because a sub-step is far shorter than the
// box, a thin (even zero-thickness) wall cannot be skipped at any speed (no tunnelling), and
// since nothing is solved iteratively the result is a pure function of the inputs
// (deterministic, unlike a dynamics solver's contact impulses). The price: no sliding along
// walls and no pushing of objects — a collision is a failure to be counted, not a manoeuvre.
//
// Frames: world (W, the scene frame, Z up, floor at z = 0; it coincides with the robot's map
// frame only by the simulator's choice), base_link (B, REP-105: origin at the middle of the
// wheel axle on the floor, x forward). Odometry is reported in the odom frame (O), which starts
// at the base's initial pose. Units SI.
//
// Truth: TruePose() is ground truth. Only the simulator loop and the evaluator may read it; the
// robot gets Odometry(). Not thread-safe: one body per thread.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/odometry.h"

namespace mopad::sim {

/// Wheel-odometry error model. Encoders measure each wheel's rotation; the robot converts it to
/// travel with a *believed* wheel radius and track width that differ from the true ones by the
/// scale errors below, and the wheels slip on the floor (random walk in travel).
struct WheelOdometryParams {
  double left_radius_error = 0.0;   ///< believed / true left wheel radius - 1, [-0.1, 0.1]
  double right_radius_error = 0.0;  ///< believed / true right wheel radius - 1, [-0.1, 0.1]
  double track_width_error = 0.0;   ///< believed / true wheel base - 1, [-0.1, 0.1]
  double slip_sigma = 0.0;          ///< m/sqrt(m), per-wheel travel std after 1 m, [0, 0.1]

  template <class V>
  void Visit(V& v) {
    v("left_radius_error", left_radius_error, Bounds{-0.1, 0.1});
    v("right_radius_error", right_radius_error, Bounds{-0.1, 0.1});
    v("track_width_error", track_width_error, Bounds{-0.1, 0.1});
    v("slip_sigma", slip_sigma, Bounds{0.0, 0.1});
  }
};

struct RobotBodyParams {
  double footprint_length = 0.6;    ///< m, box extent along base_link x, [0.1, 3]
  double footprint_width = 0.5;     ///< m, box extent along base_link y, [0.1, 3]
  double footprint_offset_x = 0.0;  ///< m, box centre ahead of the axle centre, [-1, 1]
  double ground_clearance = 0.03;  ///< m, bottom of the collision box above the floor, [0.005, 0.5]
  double body_height = 1.0;        ///< m, top of the collision box above the floor, (clearance, 3]
  double mass = 60.0;              ///< kg; kinematic model: used for contact impulses, [1, 1000]
  double wheel_base = 0.45;        ///< m, distance between the wheels' contact points, [0.1, 2]
  double wheel_radius = 0.1;       ///< m, true wheel radius, [0.02, 0.5]
  double max_linear_speed = 0.6;   ///< m/s, also the per-wheel speed limit, [0.05, 3]
  double max_angular_speed = 1.5;  ///< rad/s, [0.1, 10]
  double max_linear_acceleration = 1.0;   ///< m/s^2, [0.05, 20]
  double max_angular_acceleration = 3.0;  ///< rad/s^2, [0.1, 50]
  double max_substep_translation = 0.02;  ///< m, collision sub-step length, [0.001, 0.1]
  double max_substep_rotation = 0.02;     ///< rad, collision sub-step rotation, [0.001, 0.2]
  double contact_tolerance = 0.001;       ///< m, penetration that counts as contact, [0, 0.05]
  WheelOdometryParams odometry;

  template <class V>
  void Visit(V& v) {
    v("footprint_length", footprint_length, Bounds{0.1, 3.0});
    v("footprint_width", footprint_width, Bounds{0.1, 3.0});
    v("footprint_offset_x", footprint_offset_x, Bounds{-1.0, 1.0});
    v("ground_clearance", ground_clearance, Bounds{0.005, 0.5});
    v("body_height", body_height, Bounds{0.01, 3.0});
    v("mass", mass, Bounds{1.0, 1000.0});
    v("wheel_base", wheel_base, Bounds{0.1, 2.0});
    v("wheel_radius", wheel_radius, Bounds{0.02, 0.5});
    v("max_linear_speed", max_linear_speed, Bounds{0.05, 3.0});
    v("max_angular_speed", max_angular_speed, Bounds{0.1, 10.0});
    v("max_linear_acceleration", max_linear_acceleration, Bounds{0.05, 20.0});
    v("max_angular_acceleration", max_angular_acceleration, Bounds{0.1, 50.0});
    v("max_substep_translation", max_substep_translation, Bounds{0.001, 0.1});
    v("max_substep_rotation", max_substep_rotation, Bounds{0.001, 0.2});
    v("contact_tolerance", contact_tolerance, Bounds{0.0, 0.05});
    v("odometry", odometry);
  }
  /// ValidateParams plus cross-field checks (body_height > ground_clearance); InputError.
  void Validate() const;
};

/// Integrates drifting wheel odometry from the wheels' true travel. Noise is keyed by
/// (seed, "sim/wheel_odometry", step index), so a run is reproducible.
class WheelOdometry {
 public:
  /// `true_wheel_base` is the physical track width (m); the believed one is scaled by the error.
  WheelOdometry(const WheelOdometryParams& params, double true_wheel_base, std::uint64_t seed);

  /// Adds one step: true ground travel of each wheel (m) over `dt` (s), ending at `timestamp`.
  void Integrate(double left_travel, double right_travel, double dt, double timestamp);
  /// Odometry reading: base_link in odom, starting at the identity.
  const interfaces::Odometry& Reading() const { return reading_; }

 private:
  WheelOdometryParams params_;
  double true_wheel_base_;
  std::uint64_t seed_;
  std::uint64_t step_ = 0;
  interfaces::Odometry reading_;
};

/// One contact: the base was stopped by an obstacle.
struct ContactEvent {
  double time = 0.0;     ///< s, simulation time
  Pose2 X_WB;            ///< true pose where the base stopped
  double speed = 0.0;    ///< m/s, linear speed just before the stop
  double impulse = 0.0;  ///< N s, mass * speed (the bumper's momentum to absorb)
};

/// Result of one Step.
struct BodyStepResult {
  bool blocked = false;  ///< a sub-step was rejected (contact)
  int substeps = 0;      ///< collision sub-steps taken
  double v = 0.0;        ///< m/s, actual forward speed at the end of the step
  double w = 0.0;        ///< rad/s, actual yaw rate at the end of the step
};

class RobotBody {
 public:
  /// `vertices` (world frame, m) and `triangles` (3 indices each, into `vertices`) form the
  /// static collision mesh; it may be empty. Throws InputError for invalid params or indices.
  RobotBody(const RobotBodyParams& params, const std::vector<Eigen::Vector3f>& vertices,
            const std::vector<std::uint32_t>& triangles, const Pose2& X_WB_start,
            std::uint64_t seed);
  ~RobotBody();
  RobotBody(const RobotBody&) = delete;
  RobotBody& operator=(const RobotBody&) = delete;
  RobotBody(RobotBody&&) noexcept;
  RobotBody& operator=(RobotBody&&) noexcept;

  /// Adds a door leaf: a box of `half_extents` (m) with its centre and axes at `X_WD`. Returns
  /// its id for SetDoorLeafPose.
  int AddDoorLeaf(const Eigen::Vector3d& half_extents, const Eigen::Isometry3d& X_WD);
  /// Moves a leaf (e.g. a door opening); throws InputError for an unknown id.
  void SetDoorLeafPose(int id, const Eigen::Isometry3d& X_WD);

  /// Advances simulation time by `dt` (s, > 0) under the command.
  BodyStepResult Step(const interfaces::VelocityCommand& cmd, double dt);

  /// Ground truth: base_link in world. For the simulator and the evaluator only.
  const Pose2& TruePose() const { return X_WB_; }
  /// Moves the base without motion (kidnapping tests); odometry does not see it.
  void Teleport(const Pose2& X_WB);
  /// True if the footprint box penetrates the mesh or a leaf at `X_WB` (beyond the tolerance).
  bool InCollision(const Pose2& X_WB) const;

  /// The robot's proprioception: drifting wheel odometry (odom frame).
  const interfaces::Odometry& Odometry() const { return odometry_.Reading(); }

  double Time() const { return time_; }       ///< s, simulation time
  double LinearSpeed() const { return v_; }   ///< m/s, actual
  double AngularSpeed() const { return w_; }  ///< rad/s, actual
  /// Contact events: a stop by an obstacle counts once until the base has moved 5 cm or
  /// turned 0.1 rad away from where it was stopped.
  int ContactCount() const { return contact_count_; }
  int BlockedSteps() const { return blocked_steps_; }  ///< steps in which motion was stopped
  const std::vector<ContactEvent>& Contacts() const { return contacts_; }
  const RobotBodyParams& Params() const { return params_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  RobotBodyParams params_;
  Pose2 X_WB_;
  double v_ = 0.0, w_ = 0.0, time_ = 0.0;
  static constexpr double kContactReleaseDistance = 0.05;  // m, ends a contact episode
  static constexpr double kContactReleaseAngle = 0.1;      // rad, ends a contact episode
  bool in_contact_ = false;
  Pose2 stop_pose_;
  int contact_count_ = 0, blocked_steps_ = 0;
  std::vector<ContactEvent> contacts_;
  WheelOdometry odometry_;
};

}  // namespace mopad::sim
