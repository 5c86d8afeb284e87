// AMCL on a synthetic two-room world: the LRF is simulated in the test by ray casting its own
// boxes; the map is what the robot built from scan points of the same boxes.
#include "perception/amcl.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>

#include "common/error.h"
#include "tests/perception/synthetic_world.h"

namespace mopad::perception {
namespace {

struct Err {
  double xy = 0, yaw = 0;
};
Err PoseError(const Pose2& a, const Pose2& b) {
  return {std::hypot(a.x - b.x, a.y - b.y), std::abs(WrapAngle(a.yaw - b.yaw))};
}

/// A robot driving through the test world: true unicycle motion, drifting odometry (scale
/// errors and noise of the test's own), a scan every step.
class Drive {
 public:
  Drive(const std::vector<testing::Box2>& world, const Pose2& start, std::uint64_t seed)
      : world_(world), truth_(start), seed_(seed) {}

  void Step(double v, double w, double dt = 0.1) {
    CounterRng rng(DeriveKey(seed_ ^ 0x5EED, step_++));
    const double ds = v * dt, dth = w * dt;
    truth_.x += ds * std::cos(truth_.yaw + 0.5 * dth);
    truth_.y += ds * std::sin(truth_.yaw + 0.5 * dth);
    truth_.yaw = WrapAngle(truth_.yaw + dth);
    // Odometry: +2 % distance, -2 % rotation, plus noise.
    const double ods = ds * 1.02 + 0.003 * std::sqrt(std::abs(ds)) * rng.Normal();
    const double odth = dth * 0.98 + 0.002 * std::sqrt(std::abs(ds)) * rng.Normal();
    Pose2& o = odom_.X_OB;
    o.x += ods * std::cos(o.yaw + 0.5 * odth);
    o.y += ods * std::sin(o.yaw + 0.5 * odth);
    o.yaw = WrapAngle(o.yaw + odth);
    odom_.timestamp += dt;
  }
  /// Drives toward (x, y) with a simple proportional law on the true pose.
  void GoTo(double x, double y, const std::function<void()>& after_step) {
    for (int k = 0; k < 2000; ++k) {
      const double dx = x - truth_.x, dy = y - truth_.y;
      if (std::hypot(dx, dy) < 0.05) return;
      const double err = WrapAngle(std::atan2(dy, dx) - truth_.yaw);
      const double w = std::clamp(2.0 * err, -1.0, 1.0);
      const double v = std::abs(err) < 0.4 ? std::min(0.4, std::hypot(dx, dy)) : 0.0;
      Step(v, w);
      after_step();
    }
  }
  interfaces::LrfScan Scan() const {
    return testing::SimulateScan(world_, truth_, seed_, step_, 0.01);
  }
  const Pose2& Truth() const { return truth_; }
  void Teleport(const Pose2& p) { truth_ = p; }
  const interfaces::Odometry& Odom() const { return odom_; }

 private:
  std::vector<testing::Box2> world_;
  Pose2 truth_;
  interfaces::Odometry odom_;
  std::uint64_t seed_;
  std::uint64_t step_ = 0;
};

Eigen::Matrix3d Cov(double sxy, double syaw) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal();
}

struct Fixture {
  std::vector<testing::Box2> world = testing::TwoRooms();
  OccupancyGrid map = testing::BuildGrid(world);
};

const Fixture& World() {
  static const Fixture f;
  return f;
}

/// The convergence scenario: small initial error, a short drive; returns the final filter.
Amcl RunConvergence(std::uint64_t seed, Err* final_error = nullptr) {
  const Pose2 start{2.5, 3.0, 0.2};
  Drive drive(World().world, start, 7);
  Amcl amcl(World().map, AmclParams{}, seed);
  amcl.SetInitialPose({2.65, 2.9, 0.2 + DegToRad(5.0)}, Cov(0.15, DegToRad(8.0)));
  auto update = [&] { amcl.Update(drive.Odom(), drive.Scan()); };
  update();
  drive.GoTo(3.5, 3.8, update);
  drive.GoTo(2.5, 4.0, update);
  drive.GoTo(2.0, 2.5, update);
  if (final_error) {
    *final_error = PoseError(amcl.Estimate().PoseAt(drive.Odom().X_OB), drive.Truth());
  }
  return amcl;
}

TEST(Amcl, ConvergesFromASmallInitialErrorToCentimetres) {
  Err e;
  const Amcl amcl = RunConvergence(42, &e);
  std::printf("[ AMCL     ] converged: error %.1f mm, %.2f deg; %s\n", 1000 * e.xy, RadToDeg(e.yaw),
              amcl.Estimate().message.c_str());
  EXPECT_LT(e.xy, 0.03);
  EXPECT_LT(e.yaw, DegToRad(1.0));
  EXPECT_EQ(amcl.Estimate().status, LocalisationStatus::kLocalised) << amcl.Estimate().message;
  EXPECT_GT(amcl.Estimate().n_eff, 1.0);
  EXPECT_LE(amcl.Estimate().particles, AmclParams{}.max_particles);
  EXPECT_LT(amcl.Estimate().particles, AmclParams{}.max_particles);  // KLD shrank the set
  EXPECT_LT(std::sqrt(amcl.Estimate().covariance(0, 0)), 0.05);
}

TEST(Amcl, TracksARobotThroughTheDoorWithDriftingOdometry) {
  const Pose2 start{1.5, 3.0, 0.0};
  Drive drive(World().world, start, 9);
  Amcl amcl(World().map, AmclParams{}, 3);
  amcl.SetInitialPose({1.55, 2.97, 0.02}, Cov(0.05, DegToRad(3.0)));
  double sum_sq = 0, max_xy = 0, max_yaw = 0, odom_max = 0;
  int n = 0;
  auto update = [&] {
    if (!amcl.Update(drive.Odom(), drive.Scan()).updated) return;
    const Err e = PoseError(amcl.Estimate().X_MB, drive.Truth());
    sum_sq += e.xy * e.xy;
    max_xy = std::max(max_xy, e.xy);
    max_yaw = std::max(max_yaw, e.yaw);
    if (getenv("AMCL_DEBUG"))
      std::printf("u %d truth %.2f %.2f %.2f err %.3f %.2f %s\n", n, drive.Truth().x,
                  drive.Truth().y, drive.Truth().yaw, e.xy, RadToDeg(e.yaw),
                  amcl.Estimate().message.c_str());
    const Pose2 raw = Compose(start, drive.Odom().X_OB);
    odom_max = std::max(odom_max, PoseError(raw, drive.Truth()).xy);
    ++n;
  };
  update();
  for (auto [x, y] : {std::pair{4.0, 3.0},
                      {6.5, 3.0},
                      {6.5, 1.5},
                      {8.3, 2.5},
                      {8.5, 5.0},
                      {8.3, 3.2},
                      {6.0, 3.1},
                      {3.0, 3.0},
                      {2.8, 2.0}}) {
    drive.GoTo(x, y, update);
  }
  const double rms = std::sqrt(sum_sq / n);
  std::printf(
      "[ AMCL     ] tracking over %d updates: RMS %.1f mm, max %.1f mm, max yaw %.2f deg "
      "(raw odometry drifted up to %.0f mm)\n",
      n, 1000 * rms, 1000 * max_xy, RadToDeg(max_yaw), 1000 * odom_max);
  EXPECT_GT(n, 100);
  EXPECT_LT(rms, 0.03);
  EXPECT_LT(max_xy, 0.08);
  EXPECT_LT(max_yaw, DegToRad(3.0));
  EXPECT_GT(odom_max, 0.2);  // the filter did real work
  EXPECT_EQ(amcl.Estimate().status, LocalisationStatus::kLocalised) << amcl.Estimate().message;
}

struct KidnapCase {
  Pose2 to;                                      // where the robot is carried
  std::vector<std::pair<double, double>> route;  // where it drives afterwards
};

class AmclKidnap : public ::testing::TestWithParam<KidnapCase> {};

TEST_P(AmclKidnap, IsDetectedAndTheFilterRelocalisesGlobally) {
  const KidnapCase kc = GetParam();
  Drive drive(World().world, {1.5, 3.0, 0.0}, 5);
  Amcl amcl(World().map, AmclParams{}, 8);
  amcl.SetInitialPose({1.5, 3.0, 0.0}, Cov(0.05, DegToRad(3.0)));
  bool lost = false;
  int updates_to_loss = -1, updates_to_relocalise = -1, updates = 0;
  auto update = [&] {
    const auto r = amcl.Update(drive.Odom(), drive.Scan());
    if (!r.updated) return;
    ++updates;
    if (r.lost_detected && !lost) {
      lost = true;
      updates_to_loss = updates;
    }
    if (lost && updates_to_relocalise < 0 &&
        amcl.Estimate().status == LocalisationStatus::kLocalised) {
      updates_to_relocalise = updates;
    }
  };
  update();
  drive.GoTo(3.0, 3.0, update);
  ASSERT_EQ(amcl.Estimate().status, LocalisationStatus::kLocalised);
  ASSERT_FALSE(lost);
  // Kidnap: the robot is carried away; odometry knows nothing.
  drive.Teleport(kc.to);
  updates = 0;
  // Keep moving (a lost robot rotates and creeps to gather evidence).
  for (auto [x, y] : kc.route) drive.GoTo(x, y, update);
  ASSERT_TRUE(lost) << amcl.Estimate().message;
  const Err e = PoseError(amcl.Estimate().PoseAt(drive.Odom().X_OB), drive.Truth());
  std::printf(
      "[ AMCL     ] kidnap to (%.1f, %.1f): detected after %d updates, re-localised after "
      "%d more; at the end: error %.1f mm, %.2f deg\n",
      kc.to.x, kc.to.y, updates_to_loss, updates_to_relocalise - updates_to_loss, 1000 * e.xy,
      RadToDeg(e.yaw));
  EXPECT_LE(updates_to_loss, 6);
  EXPECT_GT(updates_to_relocalise, 0);
  EXPECT_EQ(amcl.Estimate().status, LocalisationStatus::kLocalised) << amcl.Estimate().message;
  EXPECT_LT(e.xy, 0.03);
  EXPECT_LT(e.yaw, DegToRad(1.0));
}

// Readable names instead of gtest's byte dump of the parameter.
std::string KidnapCaseName(const ::testing::TestParamInfo<KidnapCase>& info) {
  static const char* kNames[] = {"IntoTheOtherRoom", "SameRoomTurnedAround",
                                 "NearTheDoorFacingTheWall"};
  return info.index < 3 ? kNames[info.index] : "Case" + std::to_string(info.index);
}

INSTANTIATE_TEST_SUITE_P(
    Destinations, AmclKidnap,
    ::testing::Values(
        // Into the other room (its walls mirror the first one's under a half turn).
        KidnapCase{{7.0, 2.0, 1.2}, {{7.5, 3.0}, {6.5, 3.5}, {8.0, 3.0}, {7.0, 1.8}, {6.0, 2.5}}},
        // Within the same room, turned around.
        KidnapCase{{3.5, 4.0, -2.5}, {{2.5, 3.5}, {3.5, 2.5}, {2.0, 2.0}, {3.0, 3.0}}},
        // Near the door, facing the wall.
        KidnapCase{{6.0, 4.5, 1.6}, {{6.0, 3.5}, {7.0, 3.0}, {6.0, 2.0}, {8.0, 2.5}}}),
    KidnapCaseName);

// Entering a room the map lacks through its door: the partition's east face (x = 5.1) is
// unknown while its west face (x = 5.0) is mapped. Beams on the east face, scored by their
// distance to the west face, pull the estimate back; unknown_endpoint_distance scores them as
// neutral misses instead (the office hall in mopad drive).
TEST(Amcl, BeamsOnUnmappedWallFacesDoNotPullTheEstimate) {
  const auto& world = World().world;
  std::vector<Eigen::Vector3d> pts;
  for (const auto& q : testing::ScanPoints(world, {0.0, 0.0}, {10.0, 6.0}))
    if (q.x() <= 5.02) pts.push_back(q);  // the west room and the partition's west face only
  OccupancyGrid map(OccupancyGridParams{}, {-0.5, -0.5}, 220, 140);
  map.InsertPoints(pts);
  double max_err[3] = {0, 0, 0};
  for (const int variant : {0, 1, 2}) {
    AmclParams p;
    p.unknown_endpoint_distance = variant ? 0.1 : 0.0;
    p.refine = variant == 2;
    Drive drive(world, {3.5, 3.0, 0.0}, 11);
    Amcl amcl(map, p, 5);
    amcl.SetInitialPose(drive.Truth(), Cov(0.01, DegToRad(0.5)));
    auto update = [&] {
      amcl.Update(drive.Odom(), drive.Scan());
      if (drive.Truth().x > 5.3)
        max_err[variant] =
            std::max(max_err[variant],
                     PoseError(amcl.Estimate().PoseAt(drive.Odom().X_OB), drive.Truth()).xy);
    };
    update();
    drive.GoTo(6.5, 3.0, update);
    drive.GoTo(6.8, 4.5, update);
  }
  std::printf(
      "[ AMCL     ] unmapped east room: max error %.1f mm plain, %.1f mm with neutral unknown "
      "endpoints, %.1f mm refined too\n",
      1000 * max_err[0], 1000 * max_err[1], 1000 * max_err[2]);
  // Plain: the filter is dragged metres off (measured 4.7 m); neutral: odometry-bound drift
  // while most beams end in the unknown room (measured 0.11 m; the test odometry has 2 %).
  EXPECT_GT(max_err[0], 0.5);
  EXPECT_LT(max_err[1], 0.15);
  // The refinement matches only beams on mapped returns (the partition's far face is not one).
  EXPECT_LT(max_err[2], 0.15);
}

// A straight corridor, 1.6 m wide, x in [0, length], with end walls when `ends`.
std::vector<testing::Box2> Corridor(double length, bool ends) {
  std::vector<testing::Box2> b = {{{-0.1, -0.1}, {length + 0.1, 0.0}},
                                  {{-0.1, 1.6}, {length + 0.1, 1.7}}};
  if (ends) {
    b.push_back({{-0.1, -0.1}, {0.0, 1.7}});
    b.push_back({{length, -0.1}, {length + 0.1, 1.7}});
  }
  return b;
}

OccupancyGrid CorridorMap(const std::vector<testing::Box2>& world, double length) {
  OccupancyGrid map(OccupancyGridParams{}, {-0.5, -0.5},
                    static_cast<int>(std::ceil((length + 1.0) / 0.05)), 56);
  map.InsertPoints(testing::ScanPoints(world, {0.0, 0.0}, {length, 1.6}));
  return map;
}

/// The navigator's filter: a wide hit sigma over few beams (robust, imprecise).
AmclParams WideFilter(bool refine) {
  AmclParams p;
  p.min_particles = 300;
  p.max_particles = 3000;
  p.recovery_alpha_slow = 0.0;
  p.unknown_endpoint_distance = 0.1;
  p.sigma_hit = 0.2;
  p.max_beams = 30;
  p.odom_alpha1 = 0.02;
  p.odom_alpha3 = 0.01;
  p.refine = refine;
  return p;
}

// Along a corridor only the end walls tell where the base is: a few of 30 beams, scored with a
// 0.2 m sigma, barely move the filter, so it lags the truth by the odometry's drift. Matching
// every beam holds the estimate to centimetres.
TEST(Amcl, RefinementHoldsTheEstimateAlongACorridorWithVisibleEnds) {
  const double length = 14.0;
  const auto world = Corridor(length, true);
  const OccupancyGrid map = CorridorMap(world, length);
  double max_err[2] = {0, 0};
  int refined = 0;
  for (const int variant : {0, 1}) {
    Drive drive(world, {1.0, 0.8, 0.0}, 21);
    Amcl amcl(map, WideFilter(variant == 1), 5);
    amcl.SetInitialPose(drive.Truth(), Cov(0.01, DegToRad(0.5)));
    auto update = [&] {
      if (!amcl.Update(drive.Odom(), drive.Scan()).updated) return;
      if (variant == 1 && amcl.Estimate().refined) ++refined;
      max_err[variant] =
          std::max(max_err[variant], PoseError(amcl.Estimate().X_MB, drive.Truth()).xy);
    };
    update();
    drive.GoTo(13.0, 0.8, update);
    drive.GoTo(2.0, 0.8, update);
  }
  std::printf(
      "[ AMCL     ] corridor with ends: max error %.1f mm filter only, %.1f mm refined "
      "(%d refinements)\n",
      1000 * max_err[0], 1000 * max_err[1], refined);
  EXPECT_GT(max_err[0], 0.06);  // the lag the refinement is for (the odometry has 2 %)
  EXPECT_LT(max_err[1], 0.03);
  EXPECT_GT(refined, 100);
}

// Without a visible end, nothing in the sweep says where along the corridor the base is: the
// refinement corrects across it and leaves the along-corridor position to the filter.
TEST(Amcl, RefinementLeavesDirectionsTheBeamsDoNotConstrain) {
  const double length = 60.0;  // the test LRF reaches 20 m
  const auto world = Corridor(length, false);
  const OccupancyGrid map = CorridorMap(world, length);
  const Pose2 truth{30.0, 0.8, 0.0};
  Amcl amcl(map, WideFilter(true), 5);
  amcl.SetInitialPose({30.1, 0.75, 0.0}, Cov(0.001, DegToRad(0.01)));
  interfaces::Odometry odom;
  ASSERT_TRUE(amcl.Update(odom, testing::SimulateScan(world, truth, 3, 0, 0.01)).updated);
  const LocalisationEstimate& e = amcl.Estimate();
  ASSERT_TRUE(e.refined) << e.message;
  EXPECT_NEAR(e.refinement.y, 0.05, 0.01);
  EXPECT_NEAR(e.refinement.x, 0.0, 0.005);
  EXPECT_NEAR(e.X_MB.y, truth.y, 0.01);
  EXPECT_NEAR(e.X_MB.x, 30.1, 0.01);
}

// A terrestrial scanner samples a far wall seen at a grazing angle in columns tens of cm
// apart, and its beams clear the cells between them: the map's wall is a dashed line. Those
// dashes are no feature along the wall: a sweep of the (continuous) corridor matched against
// them must not slide the estimate along it (each beam is measured along its own surface's
// normal, not towards the end of the nearest dash).
TEST(Amcl, RefinementDoesNotSlideAlongTheDashesOfASparselyMappedWall) {
  const double length = 60.0;
  const auto world = Corridor(length, false);
  OccupancyGrid map(OccupancyGridParams{}, {-0.5, -0.5},
                    static_cast<int>(std::ceil((length + 1.0) / 0.05)), 56);
  std::vector<Eigen::Vector3d> dashes;
  const double period = 0.4, dash = 0.1;
  for (const Eigen::Vector3d& q : testing::ScanPoints(world, {0.0, 0.0}, {length, 1.6}))
    if (std::fmod(q.x() + 10.0, period) < dash) dashes.push_back(q);
  map.InsertPoints(dashes);
  for (double x = dash; x < length; x += period) {
    map.FillBox({x + 0.01, -0.09}, {x + period - dash - 0.01, -0.01}, CellState::kFree);
    map.FillBox({x + 0.01, 1.61}, {x + period - dash - 0.01, 1.69}, CellState::kFree);
  }
  const Pose2 truth{30.0, 0.8, 0.0};
  interfaces::Odometry odom;
  for (const double offset : {0.06, 0.1, 0.16}) {
    Amcl amcl(map, WideFilter(true), 5);
    amcl.SetInitialPose({truth.x + offset, 0.75, 0.0}, Cov(0.001, DegToRad(0.01)));
    ASSERT_TRUE(amcl.Update(odom, testing::SimulateScan(world, truth, 3, 0, 0.01)).updated);
    const LocalisationEstimate& e = amcl.Estimate();
    ASSERT_TRUE(e.refined) << e.message;
    EXPECT_NEAR(e.refinement.y, 0.05, 0.01) << "offset " << offset;
    EXPECT_NEAR(e.refinement.x, 0.0, 0.005) << "offset " << offset;
  }
}

// A wide opening in a thick corridor wall, mapped from far down the corridor: the map holds
// the wall's corridor face (its last return a little short of the corner, as a terrestrial
// scanner's columns fall at a grazing angle) and the opening's floor seen through it, not the
// reveal the robot sees once past it, which faced away from the scanner. The beams on that
// unmapped reveal end nearest the corridor face's last returns, along the corridor, and the
// far jamb is too far to hold the estimate: matched to those returns they pull it along the
// corridor. Their surface crosses the mapped one, so they are no correspondence.
TEST(Amcl, RefinementDoesNotMatchAnUnmappedRevealToTheWallAcrossIt) {
  const double length = 60.0, jamb_w = 29.6, jamb_e = 33.0;
  const std::vector<testing::Box2> world = {{{-0.1, -0.3}, {jamb_w, 0.0}},
                                            {{jamb_e, -0.3}, {length + 0.1, 0.0}},
                                            {{-0.1, 1.6}, {length + 0.1, 1.7}}};
  std::vector<Eigen::Vector3d> seen;
  for (const Eigen::Vector3d& q : testing::ScanPoints(world, {0.0, 0.0}, {length, 1.6})) {
    const bool band = q.z() > 0.0;
    const bool west_reveal = std::abs(q.x() - jamb_w) < 1e-9 && q.y() < -1e-9;
    const bool short_of_corner = std::abs(q.y()) < 1e-9 && q.x() > jamb_w - 0.2 && q.x() <= jamb_w;
    if (!band || (!west_reveal && !short_of_corner)) seen.push_back(q);
  }
  OccupancyGrid map(OccupancyGridParams{}, {-0.5, -1.0},
                    static_cast<int>(std::ceil((length + 1.0) / 0.05)), 66);
  map.InsertPoints(seen);
  map.FillBox({jamb_w, -0.3}, {jamb_e, 0.0}, CellState::kFree);
  const Pose2 truth{jamb_w + 0.3, 0.4, 0.0};
  const interfaces::LrfScan scan = testing::SimulateScan(world, truth, 3, 0, 0.01);
  double shift[2] = {0, 0};
  for (const int variant : {0, 1}) {
    AmclParams p = WideFilter(true);
    if (variant == 0) p.refine_max_normal_angle_deg = 90.0;  // every pair matched
    Amcl amcl(map, p, 5);
    amcl.SetInitialPose(truth, Cov(0.001, DegToRad(0.01)));
    interfaces::Odometry odom;
    ASSERT_TRUE(amcl.Update(odom, scan).updated);
    const LocalisationEstimate& e = amcl.Estimate();
    shift[variant] = e.refined ? e.X_MB.x - truth.x : 0.0;
  }
  std::printf(
      "[ AMCL     ] unmapped reveal: along-corridor shift %.1f mm without the normal "
      "test, %.1f mm with it\n",
      1000 * shift[0], 1000 * shift[1]);
  // The pull the test is about, towards the wall face's returns (measured -12.8 mm).
  EXPECT_LT(shift[0], -0.008);
  EXPECT_LT(std::abs(shift[1]), 0.002);
}

TEST(Amcl, SameSeedGivesTheSameParticleBytesWithOneOrManyThreads) {
  auto bytes = [](const Amcl& a) {
    const auto& p = a.Particles();
    return std::vector<unsigned char>(reinterpret_cast<const unsigned char*>(p.data()),
                                      reinterpret_cast<const unsigned char*>(p.data() + p.size()));
  };
  std::vector<unsigned char> one, many, other;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = bytes(RunConvergence(42));
  }
  many = bytes(RunConvergence(42));
  other = bytes(RunConvergence(43));
  EXPECT_EQ(one, many);
  EXPECT_NE(one, other);
}

TEST(Amcl, DoesNotUpdateWithoutMotionAndReportsNotInitialised) {
  Amcl amcl(World().map, AmclParams{}, 1);
  interfaces::Odometry odom;
  const auto scan = testing::SimulateScan(World().world, {2.5, 3.0, 0.0}, 1, 0);
  EXPECT_FALSE(amcl.Update(odom, scan).updated);
  EXPECT_EQ(amcl.Estimate().status, LocalisationStatus::kNotInitialised);
  amcl.SetInitialPose({2.5, 3.0, 0.0}, Cov(0.02, 0.02));
  EXPECT_TRUE(amcl.Update(odom, scan).updated);   // first scan after initialisation
  EXPECT_FALSE(amcl.Update(odom, scan).updated);  // no motion
  EXPECT_TRUE(amcl.Update(odom, scan, true).updated);
}

TEST(Amcl, ParamsRoundTripAndValidation) {
  AmclParams p;
  p.sigma_hit = 0.07;
  EXPECT_EQ(LoadParams<AmclParams>(SaveParams(p), "a.yaml").sigma_hit, 0.07);
  AmclParams bad;
  bad.min_particles = 9000;
  EXPECT_THROW(bad.Validate(), InputError);
  EXPECT_THROW(Amcl(World().map, bad, 0), InputError);
  Amcl amcl(World().map, AmclParams{}, 0);
  EXPECT_THROW(amcl.SetInitialPose({}, -Eigen::Matrix3d::Identity()), InputError);
}

TEST(Pose2Math, ComposeAndInverse) {
  const Pose2 a{1.0, 2.0, 0.5}, b{-0.3, 0.7, -1.2};
  const Pose2 c = Compose(Inverse(a), Compose(a, b));
  EXPECT_NEAR(c.x, b.x, 1e-12);
  EXPECT_NEAR(c.y, b.y, 1e-12);
  EXPECT_NEAR(c.yaw, b.yaw, 1e-12);
}

}  // namespace
}  // namespace mopad::perception
