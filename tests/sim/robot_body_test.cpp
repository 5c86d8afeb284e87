// Robot body: the kinematic differential-drive base over Bullet collision queries and its
// drifting wheel odometry. Tiny worlds built in code with analytic answers.
#include "sim/robot_body.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "common/error.h"
#include "common/params.h"

namespace mopad::sim {
namespace {

struct Mesh {
  std::vector<Eigen::Vector3f> v;
  std::vector<std::uint32_t> i;
  void Quad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
            const Eigen::Vector3f& d) {
    const auto base = static_cast<std::uint32_t>(v.size());
    v.insert(v.end(), {a, b, c, d});
    i.insert(i.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  /// Axis-aligned closed box.
  void Box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
    const float x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
    Quad({x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0});
    Quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1});
    Quad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1});
    Quad({x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1});
    Quad({x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1});
    Quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1});
  }
  /// A large floor at z = 0 (must never count as contact).
  void Floor() { Quad({-20, -20, 0}, {20, -20, 0}, {20, 20, 0}, {-20, 20, 0}); }
};

void Drive(RobotBody& body, double v, double w, double seconds, double dt = 0.01) {
  const int n = static_cast<int>(std::lround(seconds / dt));
  for (int k = 0; k < n; ++k) body.Step({v, w}, dt);
}

TEST(RobotBody, DrivesStraightWithTheAccelerationRampOverTheFloor) {
  Mesh m;
  m.Floor();
  RobotBodyParams p;
  RobotBody body(p, m.v, m.i, {}, 1);
  Drive(body, 0.5, 0.0, 4.0);
  // Ramp 0.5 s at 1 m/s^2 (0.125 m) then 3.5 s at 0.5 m/s (1.75 m).
  EXPECT_NEAR(body.TruePose().x, 1.875, 1e-6);
  EXPECT_NEAR(body.TruePose().y, 0.0, 1e-9);
  EXPECT_NEAR(body.LinearSpeed(), 0.5, 1e-12);
  EXPECT_EQ(body.ContactCount(), 0);
  EXPECT_EQ(body.BlockedSteps(), 0);
}

TEST(RobotBody, TurnsInPlaceAtTheCommandedRate) {
  RobotBodyParams p;
  p.max_angular_acceleration = 2.0;
  RobotBody body(p, {}, {}, {}, 1);
  Drive(body, 0.0, 1.0, 1.0);  // ramp 0.5 s at 2 rad/s^2 (0.25 rad) then 0.5 s at 1 rad/s
  EXPECT_NEAR(body.TruePose().yaw, 0.75, 1e-6);
  EXPECT_NEAR(body.TruePose().x, 0.0, 1e-12);
}

TEST(RobotBody, ClampsSpeedsAccelerationsAndWheelSpeeds) {
  RobotBodyParams p;
  RobotBody body(p, {}, {}, {}, 1);
  body.Step({10.0, 0.0}, 0.01);
  EXPECT_NEAR(body.LinearSpeed(), p.max_linear_acceleration * 0.01, 1e-12);
  Drive(body, 10.0, 0.0, 2.0);
  EXPECT_NEAR(body.LinearSpeed(), p.max_linear_speed, 1e-12);
  // Full speed and full turn rate exceed the outer wheel's limit: both are scaled down.
  Drive(body, 10.0, 10.0, 3.0);
  const double wheel = std::abs(body.LinearSpeed()) + 0.5 * p.wheel_base * body.AngularSpeed();
  EXPECT_LE(wheel, p.max_linear_speed + 1e-9);
  EXPECT_GT(body.AngularSpeed(), 0.5);
}

TEST(RobotBody, StopsAtAWallAndCountsOneContact) {
  Mesh m;
  m.Floor();
  m.Box({3.0f, -5.0f, 0.0f}, {3.1f, 5.0f, 2.5f});
  RobotBodyParams p;
  RobotBody body(p, m.v, m.i, {}, 1);
  Drive(body, 0.6, 0.0, 10.0);
  const double front = body.TruePose().x + 0.5 * p.footprint_length;
  EXPECT_LE(front, 3.0 + p.contact_tolerance + 1e-3);
  EXPECT_GE(front, 3.0 - p.max_substep_translation - 0.01);
  EXPECT_EQ(body.ContactCount(), 1);  // pushing on is the same contact
  EXPECT_GT(body.BlockedSteps(), 10);
  ASSERT_EQ(body.Contacts().size(), 1u);
  EXPECT_GT(body.Contacts()[0].impulse, 0.0);
  EXPECT_DOUBLE_EQ(body.LinearSpeed(), 0.0);
  // Backing off frees the base; a second approach is a second contact.
  Drive(body, -0.3, 0.0, 2.0);
  EXPECT_LT(body.TruePose().x + 0.5 * p.footprint_length, 2.8);
  Drive(body, 0.6, 0.0, 3.0);
  EXPECT_EQ(body.ContactCount(), 2);
}

TEST(RobotBody, NoTunnellingThroughAZeroThicknessWallAtMaxSpeedAndLongSteps) {
  Mesh m;
  m.Quad({2.0f, -5.0f, 0.0f}, {2.0f, 5.0f, 0.0f}, {2.0f, 5.0f, 2.0f}, {2.0f, -5.0f, 2.0f});
  RobotBodyParams p;
  p.max_linear_speed = 3.0;
  p.max_linear_acceleration = 20.0;
  RobotBody body(p, m.v, m.i, {}, 1);
  for (int k = 0; k < 20; ++k) body.Step({3.0, 0.0}, 0.2);  // 0.6 m per step at full speed
  EXPECT_LT(body.TruePose().x + 0.5 * p.footprint_length, 2.0 + 0.01);
  EXPECT_EQ(body.ContactCount(), 1);
}

TEST(RobotBody, RotatingIntoAnObstacleIsBlockedToo) {
  Mesh m;
  // A post beside the base's front-left corner: turning left sweeps the corner into it.
  m.Box({0.2f, 0.27f, 0.0f}, {0.3f, 0.4f, 1.0f});
  RobotBodyParams p;
  RobotBody body(p, m.v, m.i, {}, 1);
  EXPECT_FALSE(body.InCollision(body.TruePose()));
  Drive(body, 0.0, 1.0, 2.0);
  EXPECT_EQ(body.ContactCount(), 1);
  EXPECT_LT(body.TruePose().yaw, 0.5);
}

TEST(RobotBody, DoorLeafBlocksUntilItIsOpened) {
  Mesh m;
  m.Floor();
  m.Box({3.0f, -5.0f, 0.0f}, {3.1f, -0.5f, 2.5f});  // wall with a 1 m gap at |y| < 0.5
  m.Box({3.0f, 0.5f, 0.0f}, {3.1f, 5.0f, 2.5f});
  RobotBodyParams p;
  RobotBody body(p, m.v, m.i, {}, 1);
  Eigen::Isometry3d closed = Eigen::Isometry3d::Identity();
  closed.translation() = Eigen::Vector3d(3.05, 0.0, 1.0);
  const int leaf = body.AddDoorLeaf({0.02, 0.5, 1.0}, closed);
  Drive(body, 0.5, 0.0, 8.0);
  EXPECT_NEAR(body.TruePose().x + 0.3, 3.03, 0.03);
  EXPECT_EQ(body.ContactCount(), 1);
  // Open the leaf by 90 degrees about its hinge at y = 0.5: it now lies along x at y ~ 0.5.
  Eigen::Isometry3d open = Eigen::Isometry3d::Identity();
  open.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  open.translation() = Eigen::Vector3d(3.6, 0.48, 1.0);
  body.SetDoorLeafPose(leaf, open);
  Drive(body, 0.5, 0.0, 4.0);
  EXPECT_GT(body.TruePose().x, 4.0);
  EXPECT_EQ(body.ContactCount(), 1);
  EXPECT_THROW(body.SetDoorLeafPose(7, open), InputError);
}

TEST(RobotBody, OdometryWithoutErrorsFollowsTheTruth) {
  RobotBodyParams p;
  RobotBody body(p, {}, {}, {1.0, 2.0, 0.5}, 3);
  Drive(body, 0.4, 0.3, 6.0);
  Drive(body, 0.2, -0.6, 3.0);
  // odom starts at identity: compare against the truth relative to the start.
  const Pose2 t = body.TruePose();
  const double c = std::cos(-0.5), s = std::sin(-0.5);
  const double dx = t.x - 1.0, dy = t.y - 2.0;
  const Pose2& o = body.Odometry().X_OB;
  EXPECT_NEAR(o.x, c * dx - s * dy, 1e-5);  // midpoint rule vs exact arcs
  EXPECT_NEAR(o.y, s * dx + c * dy, 1e-5);
  EXPECT_NEAR(WrapAngle(o.yaw - (t.yaw - 0.5)), 0.0, 1e-9);
  EXPECT_NEAR(body.Odometry().timestamp, 9.0, 1e-9);
  EXPECT_NEAR(body.Odometry().v, 0.2, 1e-9);
}

TEST(RobotBody, WheelRadiusErrorScalesDistance) {
  RobotBodyParams p;
  p.odometry.left_radius_error = p.odometry.right_radius_error = 0.02;
  RobotBody body(p, {}, {}, {}, 3);
  Drive(body, 0.5, 0.0, 5.0);
  EXPECT_NEAR(body.Odometry().X_OB.x, 1.02 * body.TruePose().x, 1e-6);
}

TEST(RobotBody, TrackWidthErrorScalesRotation) {
  RobotBodyParams p;
  p.odometry.track_width_error = 0.05;
  RobotBody body(p, {}, {}, {}, 3);
  Drive(body, 0.0, 0.5, 3.0);
  EXPECT_NEAR(body.Odometry().X_OB.yaw, body.TruePose().yaw / 1.05, 1e-6);
}

TEST(RobotBody, UnequalRadiiMakeStraightDrivingCurve) {
  RobotBodyParams p;
  p.odometry.right_radius_error = 0.01;
  RobotBody body(p, {}, {}, {}, 3);
  Drive(body, 0.5, 0.0, 10.0);
  // Believed yaw error = (dr - dl)/b = 0.01 * distance / wheel_base.
  EXPECT_NEAR(body.Odometry().X_OB.yaw, 0.01 * body.TruePose().x / p.wheel_base, 1e-3);
}

double SlipErrorRms(double seconds) {
  double sum = 0.0;
  const int seeds = 24;
  for (int seed = 0; seed < seeds; ++seed) {
    RobotBodyParams p;
    p.odometry.slip_sigma = 0.01;
    RobotBody body(p, {}, {}, {}, static_cast<std::uint64_t>(seed));
    Drive(body, 0.5, 0.0, seconds, 0.02);
    const double ex = body.Odometry().X_OB.x - body.TruePose().x;
    const double ey = body.Odometry().X_OB.y - body.TruePose().y;
    sum += ex * ex + ey * ey;
  }
  return std::sqrt(sum / seeds);
}

TEST(RobotBody, SlipDriftGrowsWithDistance) {
  const double short_run = SlipErrorRms(4.0);  // ~1.9 m
  const double long_run = SlipErrorRms(16.0);  // ~7.9 m
  EXPECT_GT(short_run, 0.0);
  EXPECT_GT(long_run, 2.0 * short_run);  // heading random walk: error grows faster than sqrt(d)
  EXPECT_LT(long_run, 1.0);
}

TEST(RobotBody, SameSeedSameBytesDifferentSeedDifferentOdometry) {
  auto run = [](std::uint64_t seed) {
    Mesh m;
    m.Floor();
    m.Box({2.0f, -5.0f, 0.0f}, {2.1f, 5.0f, 2.5f});
    RobotBodyParams p;
    p.odometry.slip_sigma = 0.02;
    p.odometry.track_width_error = 0.01;
    RobotBody body(p, m.v, m.i, {}, seed);
    std::vector<double> log;
    for (int k = 0; k < 800; ++k) {
      body.Step({0.5, 0.3 * std::sin(0.01 * k)}, 0.01);
      const auto& o = body.Odometry();
      const auto& t = body.TruePose();
      log.insert(log.end(), {o.X_OB.x, o.X_OB.y, o.X_OB.yaw, t.x, t.y, t.yaw});
    }
    return log;
  };
  const auto a = run(11), b = run(11), c = run(12);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(double)), 0);
}

TEST(RobotBody, ParamsRoundTripThroughYamlAndRejectBadValues) {
  RobotBodyParams p;
  p.footprint_length = 0.7;
  p.odometry.slip_sigma = 0.005;
  const YAML::Node node = SaveParams(p);
  const auto q = LoadParams<RobotBodyParams>(node, "test.yaml");
  EXPECT_EQ(q.footprint_length, 0.7);
  EXPECT_EQ(q.odometry.slip_sigma, 0.005);
  const auto bad = LoadYamlString("max_linear_speed: -1\n", "bad.yaml");
  EXPECT_THROW(LoadParams<RobotBodyParams>(bad, "bad.yaml"), InputError);
  const auto typo = LoadYamlString("odometry: {slip_sigm: 0.1}\n", "typo.yaml");
  EXPECT_THROW(LoadParams<RobotBodyParams>(typo, "typo.yaml"), InputError);
  RobotBodyParams flat;
  flat.body_height = 0.02;
  EXPECT_THROW(flat.Validate(), InputError);
  EXPECT_THROW(RobotBody(flat, {}, {}, {}, 0), InputError);
  EXPECT_THROW(RobotBody(RobotBodyParams{}, {{0, 0, 0}}, {0, 0, 5}, {}, 0), InputError);
}

}  // namespace
}  // namespace mopad::sim
