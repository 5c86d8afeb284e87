// The mission's registration target (autonomy/registration_target.h): scans merged beside the
// owner give the map merged in place, bit for bit, and a bad pose is refused before it is
// queued.
#include "autonomy/registration_target.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "common/error.h"
#include "common/rng.h"
#include "perception/point_cloud_ops.h"

namespace mopad::autonomy {
namespace {

using perception::PointMap;
using perception::Points;

// One "scan" in its scanner frame: a floor patch and a wall 3 m ahead, with a few non-finite
// points (no returns), as a scanner's points are.
Points ScanOfACorner(std::uint64_t seed) {
  Points pts;
  CounterRng rng(seed, "test/corner");
  for (int i = 0; i < 30000; ++i) {
    const double a = rng.Uniform(-2.0, 2.0), b = rng.Uniform(0.0, 2.5);
    pts.emplace_back(rng.Bernoulli(0.5) ? Eigen::Vector3d(b, a, -0.6)
                                        : Eigen::Vector3d(3.0, a, b - 0.6));
  }
  pts.emplace_back(Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  return pts;
}

Eigen::Isometry3d Pose(double x, double y, double yaw) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = Eigen::Vector3d(x, y, 0.6);
  return X;
}

TEST(RegistrationTarget, MergedBesideTheOwnerEqualsMergedInPlace) {
  const perception::IcpParams icp;
  const Eigen::Isometry3d poses[3] = {Pose(0, 0, 0), Pose(0.8, 0.3, 0.4), Pose(1.5, -0.4, -0.9)};
  PointMap in_place(icp);
  RegistrationTarget target(icp);
  EXPECT_TRUE(target.Map().empty());
  for (int k = 0; k < 3; ++k) {
    const Points scan = ScanOfACorner(static_cast<std::uint64_t>(k));
    in_place.Add(perception::Transform(scan, poses[k]), poses[k].translation());
    target.Add(scan, poses[k]);
  }
  const PointMap& merged = target.Map();
  ASSERT_EQ(merged.size(), in_place.size());
  ASSERT_GT(merged.size(), 1000u);
  for (std::size_t i = 0; i < merged.size(); ++i) {
    ASSERT_EQ(merged.points()[i], in_place.points()[i]) << i;
    ASSERT_EQ(merged.normals()[i].valid, in_place.normals()[i].valid) << i;
    ASSERT_EQ(merged.normals()[i].n, in_place.normals()[i].n) << i;
    ASSERT_EQ(merged.views()[i], in_place.views()[i]) << i;
  }
  // The scans' origins went in with them: the free-space evidence is the same.
  const Points probe = perception::Transform(ScanOfACorner(7), Pose(0.2, 0.1, 0.2));
  EXPECT_TRUE(merged.has_origins());
  EXPECT_EQ(merged.CountInView(probe), in_place.CountInView(probe));
  EXPECT_EQ(merged.FreeSpaceViolation(probe), in_place.FreeSpaceViolation(probe));
}

TEST(RegistrationTarget, ANonFinitePoseIsRefusedBeforeItIsQueued) {
  RegistrationTarget target(perception::IcpParams{});
  target.Add(ScanOfACorner(1), Pose(0, 0, 0));
  const std::size_t before = target.Map().size();
  Eigen::Isometry3d bad = Pose(1, 0, 0);
  bad.translation().x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(target.Add(ScanOfACorner(2), bad), InputError);
  EXPECT_EQ(target.Map().size(), before);
}

TEST(RegistrationTarget, DestroyedWithAMergeInFlight) {
  // The destructor waits for the merge: no use of the freed map (ASan, TSan: scripts/sanitize.sh).
  auto target = std::make_unique<RegistrationTarget>(perception::IcpParams{});
  target->Add(ScanOfACorner(3), Pose(0, 0, 0));
  target.reset();
}

}  // namespace
}  // namespace mopad::autonomy
