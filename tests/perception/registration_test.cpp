// Scan registration: point-cloud building blocks with analytic answers, and
// ICP of simulated 0.2 deg TLS scans of scenes/one_room.yaml against known true poses. The
// simulator and the scene generator make the input only; the registration never sees them.
#include "perception/registration.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>

#include "common/error.h"
#include "common/frames.h"
#include "common/params.h"
#include "common/rng.h"
#include "perception/point_cloud_ops.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/tls_params.h"
#include "sim/tls_scanner.h"

namespace mopad::perception {
namespace {

// ---- point-cloud operations ---------------------------------------------------------------------

TEST(PointCloudOps, VoxelDownsampleAveragesEachCellInKeyOrder) {
  const Points pts = {{0.31, 0.01, 0.01},
                      {0.05, 0.05, 0.05},
                      {0.02, 0.08, 0.02},
                      {0.39, 0.09, 0.09},
                      {std::nan(""), 0, 0}};
  const Points out = VoxelDownsample(pts, 0.1);
  ASSERT_EQ(out.size(), 2u);  // cells (0,0,0) and (3,0,0); the NaN point is skipped
  EXPECT_NEAR(out[0].x(), 0.035, 1e-12);
  EXPECT_NEAR(out[0].y(), 0.065, 1e-12);
  EXPECT_NEAR(out[1].x(), 0.35, 1e-12);
  EXPECT_NEAR(out[1].z(), 0.05, 1e-12);
  // Negative coordinates floor into their own cells.
  EXPECT_EQ(VoxelDownsample({{-0.01, 0, 0}, {0.01, 0, 0}}, 0.1).size(), 2u);
  EXPECT_THROW(VoxelDownsample(pts, 0.0), InputError);
  EXPECT_THROW(VoxelDownsample({{1e9, 0, 0}}, 0.01), InputError);
}

TEST(PointCloudOps, MergedVoxelsEqualVoxelsOfTheUnion) {
  Points a, b;
  CounterRng rng(7, "test/merge");
  for (int i = 0; i < 2000; ++i)
    a.emplace_back(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
  for (int i = 0; i < 1500; ++i)
    b.emplace_back(rng.Uniform(0, 2), rng.Uniform(-1, 1), rng.Uniform(-1, 1));
  Points all = a;
  all.insert(all.end(), b.begin(), b.end());
  const auto merged = MergeVoxels(Voxelize(a, 0.25), Voxelize(b, 0.25));
  const auto direct = Voxelize(all, 0.25);
  ASSERT_EQ(merged.size(), direct.size());
  for (std::size_t i = 0; i < merged.size(); ++i) {
    EXPECT_EQ(merged[i].key, direct[i].key);
    EXPECT_EQ(merged[i].count, direct[i].count);
    EXPECT_NEAR((merged[i].Centroid() - direct[i].Centroid()).norm(), 0.0, 1e-12);
  }
}

TEST(PointCloudOps, KdTreeNearestMatchesBruteForce) {
  Points pts;
  CounterRng rng(3, "test/kdtree");
  for (int i = 0; i < 3000; ++i)
    pts.emplace_back(rng.Uniform(0, 5), rng.Uniform(0, 5), rng.Uniform(0, 5));
  const KdTree3 tree(pts);
  for (int q = 0; q < 200; ++q) {
    const Eigen::Vector3d p(rng.Uniform(-1, 6), rng.Uniform(-1, 6), rng.Uniform(-1, 6));
    std::size_t best = 0;
    for (std::size_t i = 1; i < pts.size(); ++i)
      if ((pts[i] - p).squaredNorm() < (pts[best] - p).squaredNorm()) best = i;
    const double d = (pts[best] - p).norm();
    double d2 = 0;
    EXPECT_EQ(tree.Nearest(p, 10.0, &d2), static_cast<std::int64_t>(best));
    EXPECT_NEAR(std::sqrt(d2), d, 1e-12);
    EXPECT_EQ(tree.Nearest(p, 0.999 * d), -1);  // nothing within a smaller radius
  }
}

TEST(PointCloudOps, NormalsOfATiltedPlaneAndACorner) {
  // Plane z = 0.2 x on a 2 cm grid: normal (-0.2, 0, 1)/|.|, pointing to the viewpoint above.
  Points pts;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) pts.emplace_back(0.02 * i, 0.02 * j, 0.2 * 0.02 * i);
  const KdTree3 tree(pts);
  const auto normals = EstimateNormals(tree, 12, 0.1, 5, Eigen::Vector3d(0.5, 0.5, 10));
  const Eigen::Vector3d truth = Eigen::Vector3d(-0.2, 0, 1).normalized();
  for (std::size_t i = 0; i < pts.size(); i += 97) {
    ASSERT_TRUE(normals[i].valid);
    EXPECT_NEAR(normals[i].n.dot(truth), 1.0, 1e-9);
    EXPECT_LT(normals[i].curvature, 1e-9);
  }
  // An isolated point has too few neighbours within the radius.
  Points lonely = pts;
  lonely.emplace_back(10, 10, 10);
  const KdTree3 t2(lonely);
  EXPECT_FALSE(EstimateNormals(t2, 12, 0.1).back().valid);
  EXPECT_THROW(EstimateNormals(t2, 2, 0.1), InputError);
}

TEST(PointMap, IncrementalNormalsEqualAFullRecompute) {
  // Two overlapping batches on the floor and a wall, then a far-away batch: after each Add the
  // kept and recomputed normals equal EstimateNormals over the whole map.
  auto batch = [](std::uint64_t seed, double x0, double x1, int n) {
    Points pts;
    CounterRng rng(seed, "test/batch");
    for (int i = 0; i < n; ++i) {
      const double x = rng.Uniform(x0, x1), s = rng.Uniform(0, 3);
      pts.emplace_back(rng.Bernoulli(0.5) ? Eigen::Vector3d(x, s, 0.0)
                                          : Eigen::Vector3d(x, 3.0, s));
    }
    return pts;
  };
  IcpParams params;
  PointMap map(params);
  const Points batches[3] = {batch(1, 0, 4, 40000), batch(2, 3, 7, 40000), batch(3, 20, 22, 20000)};
  for (int b = 0; b < 3; ++b) {
    map.Add(batches[b]);
    const auto full =
        EstimateNormals(map.tree(), params.normal_neighbours, params.normal_radius, 5);
    ASSERT_EQ(full.size(), map.normals().size());
    for (std::size_t i = 0; i < full.size(); ++i) {
      ASSERT_EQ(full[i].valid, map.normals()[i].valid) << "batch " << b << " point " << i;
      ASSERT_EQ(full[i].n, map.normals()[i].n) << "batch " << b << " point " << i;
    }
    std::printf("  batch %d: %zu of %zu normals recomputed\n", b, map.last_normals_recomputed(),
                map.size());
  }
  // The far batch touched only its own cells (and their neighbourhood), not the first two.
  EXPECT_LT(map.last_normals_recomputed(), map.size() / 3);
}

// ---- simulated scans of one_room ----------------------------------------------------------------

double RotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return RadToDeg(Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle());
}
double TranslationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

struct SimScan {
  interfaces::TlsScan scan;
  Eigen::Isometry3d X_WS_true;
};

/// One room, 0.2 deg RIEGL VZ-400 profile with every noise source on; scans cached.
class Room {
 public:
  static Room& Get() {
    static Room room;
    return room;
  }
  const SimScan& Scan(int id, const Pose2& base) {
    auto it = scans_.find(id);
    if (it != scans_.end()) return it->second;
    sim::ScanRequest req;
    req.seed = 11;
    req.scan_id = static_cast<std::uint64_t>(id);
    req.X_WB = base.To3d();
    sim::TlsTruth truth;
    SimScan s;
    s.scan = scanner_->Scan(req, &truth);
    s.X_WS_true = truth.X_WS;
    return scans_.emplace(id, std::move(s)).first->second;
  }

 private:
  Room() {
    scenes::GeneratedScene g = scenes::Generate(
        scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/one_room.yaml"));
    truth_ = std::move(g.truth);
    world_ = std::make_unique<sim::EmbreeWorld>(std::move(g.scene), &truth_);
    scanner_ = std::make_unique<sim::TlsScanner>(*world_, sim::TlsProfile("riegl_vz400"));
  }
  scenes::GroundTruth truth_;
  std::unique_ptr<sim::EmbreeWorld> world_;
  std::unique_ptr<sim::TlsScanner> scanner_;
  std::map<int, SimScan> scans_;
};

// Base poses inside the 6 m x 4 m room (the desk stands at (4.5, 2.0)).
const Pose2 kBase[5] = {
    {1.5, 1.2, 0.3}, {3.2, 2.9, -1.2}, {2.2, 3.0, 2.5}, {5.2, 0.9, 0.8}, {1.0, 3.1, -2.8}};

/// The scan's own odometry prior, off by (0.15, -0.12, 0.03) m and 3 deg of yaw.
Eigen::Isometry3d PerturbedPrior(const interfaces::TlsScan& scan, double dx = 0.15,
                                 double dy = -0.12, double dyaw_deg = 3.0) {
  Eigen::Isometry3d prior = scan.X_MS_estimate;
  prior.linear() = Eigen::AngleAxisd(DegToRad(dyaw_deg), Eigen::Vector3d::UnitZ()) * prior.linear();
  prior.translation() += Eigen::Vector3d(dx, dy, 0.03);
  return prior;
}

/// A map of the given scans, each placed at its true pose (the first scan defines the map).
PointMap MapOf(std::initializer_list<int> ids, const IcpParams& params = {}) {
  PointMap map(params);
  for (int id : ids) {
    const SimScan& s = Room::Get().Scan(id, kBase[id]);
    map.Add(ScanPoints(s.scan, s.X_WS_true), s.X_WS_true.translation());
  }
  return map;
}

TEST(Registration, SecondScanInOneRoomWithinFiveMillimetres) {
  const PointMap map = MapOf({0});
  const SimScan& s1 = Room::Get().Scan(1, kBase[1]);
  const Eigen::Isometry3d prior = PerturbedPrior(s1.scan);
  ASSERT_GT(TranslationError(prior, s1.X_WS_true), 0.18);
  ASSERT_GT(RotationErrorDeg(prior, s1.X_WS_true), 2.9);
  const RegistrationResult r = RegisterScan(ScanPoints(s1.scan), map, prior, IcpParams{});
  std::printf("  %s\n  error %.2f mm, %.4f deg\n", r.message.c_str(),
              1e3 * TranslationError(r.X_MS, s1.X_WS_true), RotationErrorDeg(r.X_MS, s1.X_WS_true));
  EXPECT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.converged);
  // The last step is reported (the drive counts a creep below 10x the thresholds as converged).
  EXPECT_LT(r.last_step, IcpParams{}.min_delta_translation);
  EXPECT_LT(r.last_step_deg, IcpParams{}.min_delta_rotation_deg);
  EXPECT_FALSE(r.degenerate);
  EXPECT_EQ(r.information.size(), 4u);  // default 4 DoF: the prior's levelling is kept
  // Gravity in the scanner frame (row 2 of R_MS) is the prior's: only yaw changed.
  EXPECT_LT((prior.linear().row(2) - r.X_MS.linear().row(2)).norm(), 1e-12);
  EXPECT_GT(r.fitness, 0.8);
  EXPECT_LT(r.rmse, 0.01);
  EXPECT_LT(TranslationError(r.X_MS, s1.X_WS_true), 0.005);
  EXPECT_LT(RotationErrorDeg(r.X_MS, s1.X_WS_true), 0.05);
  EXPECT_NE(r.message.find("registration ok"), std::string::npos);
}

TEST(Registration, ThirdScanAgainstTwoAccumulatedWithinFiveMillimetres) {
  const PointMap map = MapOf({0, 1});
  const SimScan& s2 = Room::Get().Scan(2, kBase[2]);
  const Eigen::Isometry3d prior = PerturbedPrior(s2.scan, -0.14, 0.14, -3.0);
  const RegistrationResult r = RegisterScan(ScanPoints(s2.scan), map, prior, IcpParams{});
  std::printf("  %s\n  error %.2f mm, %.4f deg\n", r.message.c_str(),
              1e3 * TranslationError(r.X_MS, s2.X_WS_true), RotationErrorDeg(r.X_MS, s2.X_WS_true));
  EXPECT_TRUE(r.ok) << r.message;
  EXPECT_LT(TranslationError(r.X_MS, s2.X_WS_true), 0.005);
  EXPECT_LT(RotationErrorDeg(r.X_MS, s2.X_WS_true), 0.05);
}

TEST(Registration, MapPointsFarFromTheScanChangeNothing) {
  // The same two scans, and a copy of the first 60 m away (a room across the floor, added
  // without an origin): RegisterScan works on the map near the scan, with the same pairs, so
  // the result is the same to the bit; the message still counts the whole map.
  PointMap near_only = MapOf({0, 1});
  PointMap with_far = MapOf({0, 1});
  const SimScan& s0 = Room::Get().Scan(0, kBase[0]);
  Points far = ScanPoints(s0.scan, s0.X_WS_true);
  for (auto& p : far) p.x() += 60.0;
  with_far.Add(far);
  ASSERT_GT(with_far.size(), near_only.size() + 1000);
  const SimScan& s2 = Room::Get().Scan(2, kBase[2]);
  const Eigen::Isometry3d prior = PerturbedPrior(s2.scan, -0.14, 0.14, -3.0);
  const RegistrationResult a = RegisterScan(ScanPoints(s2.scan), near_only, prior, IcpParams{});
  const RegistrationResult b = RegisterScan(ScanPoints(s2.scan), with_far, prior, IcpParams{});
  EXPECT_TRUE(a.ok) << a.message;
  EXPECT_EQ(a.X_MS.matrix(), b.X_MS.matrix());
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(b.target_points, with_far.size());
}

TEST(Registration, WholeScanFromItsOwnEstimate) {
  // The TlsScan overload starts from X_MS_estimate (here the nominal, untilted pose; the true
  // scanner is tilted by the drawn levelling error) and honours the range gate.
  const PointMap map = MapOf({0});
  const SimScan& s2 = Room::Get().Scan(2, kBase[2]);
  const RegistrationResult r = RegisterScan(s2.scan, map, IcpParams{});
  EXPECT_TRUE(r.ok) << r.message;
  EXPECT_LT(TranslationError(r.X_MS, s2.X_WS_true), 0.005);
  EXPECT_LT(RotationErrorDeg(r.X_MS, s2.X_WS_true), 0.05);
  IcpParams far_only;
  far_only.min_range = 50.0;  // nothing in a 6 m room is that far: an empty source
  const RegistrationResult none = RegisterScan(s2.scan, map, far_only);
  EXPECT_FALSE(none.ok);
  EXPECT_NE(none.message.find("empty source"), std::string::npos) << none.message;
}

TEST(Registration, SixDofRecoversAMislevelledPriorThatFourDofKeeps) {
  // A prior tilted by 0.5 deg of roll (a badly levelled scanner): 6 DoF refines roll and pitch
  // too; 4 DoF (the default) trusts the prior's levelling and keeps that error.
  const PointMap map = MapOf({0});
  const SimScan& s3 = Room::Get().Scan(3, kBase[3]);
  Eigen::Isometry3d prior = PerturbedPrior(s3.scan);
  prior.linear() = prior.linear() *
                   Eigen::AngleAxisd(DegToRad(0.5), Eigen::Vector3d::UnitX()).toRotationMatrix();
  IcpParams p6;
  p6.dof = 6;
  const RegistrationResult r6 = RegisterScan(ScanPoints(s3.scan), map, prior, p6);
  EXPECT_TRUE(r6.ok) << r6.message;
  EXPECT_EQ(r6.information.size(), 6u);
  EXPECT_LT(TranslationError(r6.X_MS, s3.X_WS_true), 0.005);
  EXPECT_LT(RotationErrorDeg(r6.X_MS, s3.X_WS_true), 0.05);
  const RegistrationResult r4 = RegisterScan(ScanPoints(s3.scan), map, prior, IcpParams{});
  EXPECT_EQ(r4.information.size(), 4u);
  EXPECT_LT((prior.linear().row(2) - r4.X_MS.linear().row(2)).norm(), 1e-12);  // levelling kept
  EXPECT_GT(RotationErrorDeg(r4.X_MS, s3.X_WS_true), 0.45);
}

TEST(Registration, SourceFarFromTheMapIsReportedAsFailed) {
  const PointMap map = MapOf({0});
  const SimScan& s1 = Room::Get().Scan(1, kBase[1]);
  Eigen::Isometry3d prior = s1.scan.X_MS_estimate;
  prior.translation() += Eigen::Vector3d(30, 0, 0);
  const RegistrationResult r = RegisterScan(ScanPoints(s1.scan), map, prior, IcpParams{});
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.fitness, 0.5);
  EXPECT_NE(r.message.find("registration failed"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("correspondences"), std::string::npos) << r.message;
}

/// The pose turned by 180 deg about the vertical axis through the centre (3, 2) of one_room,
/// whose walls, floor and ceiling are symmetric under that turn (its contents are not).
Eigen::Isometry3d Twin(const Eigen::Isometry3d& X) {
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turn.translation() = Eigen::Vector3d(6.0, 4.0, 0.0);  // p -> (6 - x, 4 - y, z)
  return turn * X;
}

TEST(Registration, WildlyWrongPriorsAreReportedAsFailed) {
  // Priors 1.2 m and 35 or 90 deg off: 35 deg may be recovered (the basin is wide), but never
  // silently wrong; 90 deg cannot be recovered in a 6 m x 4 m room and must fail.
  const PointMap map = MapOf({0});
  const SimScan& s1 = Room::Get().Scan(1, kBase[1]);
  for (const auto& [dx, dyaw] :
       {std::pair{1.0, 35.0}, std::pair{-1.0, 90.0}, std::pair{1.0, -90.0}}) {
    const Eigen::Isometry3d prior = PerturbedPrior(s1.scan, dx, 0.6, dyaw);
    const RegistrationResult r = RegisterScan(ScanPoints(s1.scan), map, prior, IcpParams{});
    const double et = TranslationError(r.X_MS, s1.X_WS_true),
                 er = RotationErrorDeg(r.X_MS, s1.X_WS_true);
    std::printf("  prior off %.1f m / %.0f deg -> ok %d, error %.3f m %.2f deg: %s\n",
                std::hypot(dx, 0.6), dyaw, r.ok, et, er, r.message.c_str());
    if (r.ok) {
      EXPECT_LT(et, 0.01) << r.message;
      EXPECT_LT(er, 0.1) << r.message;
    } else {
      EXPECT_NE(r.message.find("registration failed"), std::string::npos);
    }
    if (std::abs(dyaw) >= 90.0) {
      EXPECT_FALSE(r.ok) << r.message;
    }
  }
}

TEST(Registration, SymmetricTwinPoseIsRejectedByTheFreeSpaceCheck) {
  // A prior near the 180 deg twin of the truth: ICP settles on the twin, where the room's shell
  // fits (fitness and rmse alone would pass it) but the desk, door and window land where the
  // map's scan saw empty space.
  const PointMap map = MapOf({1});
  const SimScan& s0 = Room::Get().Scan(0, kBase[0]);
  Eigen::Isometry3d prior = Twin(s0.X_WS_true);
  prior.translation() += Eigen::Vector3d(0.1, -0.1, 0.0);
  prior.linear() = Eigen::AngleAxisd(DegToRad(2.0), Eigen::Vector3d::UnitZ()) * prior.linear();
  const RegistrationResult r = RegisterScan(ScanPoints(s0.scan), map, prior, IcpParams{});
  std::printf("  %s\n  distance to the twin %.3f m, to the truth %.3f m\n", r.message.c_str(),
              TranslationError(r.X_MS, Twin(s0.X_WS_true)), TranslationError(r.X_MS, s0.X_WS_true));
  EXPECT_LT(TranslationError(r.X_MS, Twin(s0.X_WS_true)), 0.1);  // it did settle on the twin
  EXPECT_FALSE(r.ok) << r.message;
  EXPECT_GT(r.free_space_violation, IcpParams{}.max_free_space_violation) << r.message;
  EXPECT_NE(r.message.find("free-space violation"), std::string::npos) << r.message;
}

TEST(Registration, FreeSpaceViolationOfAWallSeenFromAnOrigin) {
  // One scan of the wall x = 5 (|y|, |z| <= 2) from the origin.
  Points wall;
  for (double y = -2; y <= 2; y += 0.02)
    for (double z = -2; z <= 2; z += 0.02) wall.emplace_back(5.0, y, z);
  PointMap map;
  map.Add(wall, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(map.FreeSpaceViolation({{3.0, 0.5, 0.2}, {4.0, -1.0, 1.0}}), 1.0);  // seen empty
  EXPECT_DOUBLE_EQ(map.FreeSpaceViolation({{5.0, 0.5, 0.2}, {7.0, 1.0, 0.0}}), 0.0);   // on, behind
  EXPECT_DOUBLE_EQ(map.FreeSpaceViolation({{-3.0, 0.0, 0.0}, {4.9, 0.0, 0.0}}),
                   0.0);  // no return; margin
  EXPECT_DOUBLE_EQ(map.FreeSpaceViolation({{3.0, 0.0, 0.0}, {-3.0, 0.0, 0.0}}), 0.5);
  PointMap no_origin;
  no_origin.Add(wall);
  EXPECT_DOUBLE_EQ(no_origin.FreeSpaceViolation({{3.0, 0.0, 0.0}}), 0.0);  // no evidence recorded
  EXPECT_THROW(map.Add(wall, Eigen::Vector3d(std::nan(""), 0, 0)), InputError);
}

TEST(PointMap, ViewsRecordTheSideEachCellWasSeenFrom) {
  // The two faces of a 0.2 m wall (x = 5 and x = 5.2), each scanned from its own room: every
  // cell's view sum points back to the room that saw it (IcpParams::same_side matches a scan's
  // points only with cells seen from their side); points added without an origin have none.
  Points face_a, face_b;
  for (double y = -1; y <= 1; y += 0.02)
    for (double z = -1; z <= 1; z += 0.02) {
      face_a.emplace_back(5.0, y, z);
      face_b.emplace_back(5.2, y, z);
    }
  PointMap map;
  map.Add(face_a, Eigen::Vector3d(2.0, 0.0, 0.0));
  map.Add(face_b, Eigen::Vector3d(8.0, 0.0, 0.0));
  ASSERT_EQ(map.views().size(), map.size());
  int toward_a = 0, toward_b = 0;
  for (std::size_t k = 0; k < map.size(); ++k) {
    const Eigen::Vector3f v = map.views()[k].normalized();
    if (map.points()[k].x() < 5.1) toward_a += v.x() < -0.5f;
    if (map.points()[k].x() > 5.1) toward_b += v.x() > 0.5f;
  }
  EXPECT_EQ(toward_a + toward_b, static_cast<int>(map.size()));
  PointMap no_origin;
  no_origin.Add(face_a);
  for (const auto& v : no_origin.views()) EXPECT_EQ(v.norm(), 0.0f);
}

TEST(Registration, LongCorridorIsFlaggedDegenerateAndKeepsThePriorAlongItsAxis) {
  // A synthetic 40 m x 2 m x 3 m corridor (walls, floor, ceiling; no ends): x is unobservable.
  Points corridor;
  for (double x = -20; x <= 20; x += 0.02) {
    for (double s = 0; s <= 3.0; s += 0.02) {
      corridor.emplace_back(x, -1.0, s);
      corridor.emplace_back(x, 1.0, s);
    }
    for (double y = -1.0; y <= 1.0; y += 0.02) {
      corridor.emplace_back(x, y, 0.0);
      corridor.emplace_back(x, y, 3.0);
    }
  }
  PointMap map;
  map.Add(corridor);
  Eigen::Isometry3d X_MS_true = Eigen::Isometry3d::Identity();
  X_MS_true.translation() = Eigen::Vector3d(0.3, 0.1, 1.4);
  Points source;  // the part within 15 m of the scanner, in its frame
  for (const auto& p : corridor)
    if ((p - X_MS_true.translation()).norm() < 15.0) source.push_back(X_MS_true.inverse() * p);
  Eigen::Isometry3d prior = X_MS_true;
  prior.translation() += Eigen::Vector3d(0.2, -0.1, 0.05);
  const RegistrationResult r = RegisterScan(source, map, prior, IcpParams{});
  EXPECT_TRUE(r.degenerate) << r.message;
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("degenerate"), std::string::npos) << r.message;
  EXPECT_GT(std::abs(r.weakest_direction[3]), 0.99) << r.message;        // along x
  EXPECT_NEAR(r.X_MS.translation().x(), prior.translation().x(), 0.01);  // frozen at the prior
  EXPECT_NEAR(r.X_MS.translation().y(), X_MS_true.translation().y(), 1e-3);
  EXPECT_NEAR(r.X_MS.translation().z(), X_MS_true.translation().z(), 1e-3);
}

TEST(Registration, CorridorResultEstimatesWhatItConstrainsAndCarriesThePriorElsewhere) {
  // The synthetic corridor above (x unobservable), with its map scan origin: the result's
  // constrained directions exclude x, its information along x is orders below that across,
  // and its covariance takes x from the prior while y and yaw come from the scan.
  Points corridor;
  for (double x = -20; x <= 20; x += 0.02) {
    for (double s = 0; s <= 3.0; s += 0.02) {
      corridor.emplace_back(x, -1.0, s);
      corridor.emplace_back(x, 1.0, s);
    }
    for (double y = -1.0; y <= 1.0; y += 0.02) {
      corridor.emplace_back(x, y, 0.0);
      corridor.emplace_back(x, y, 3.0);
    }
  }
  PointMap map;
  map.Add(corridor, Eigen::Vector3d(-2.0, 0.0, 1.4));
  Eigen::Isometry3d X_MS_true = Eigen::Isometry3d::Identity();
  X_MS_true.translation() = Eigen::Vector3d(0.3, 0.1, 1.4);
  Points source;
  for (const auto& p : corridor)
    if ((p - X_MS_true.translation()).norm() < 15.0) source.push_back(X_MS_true.inverse() * p);
  Eigen::Isometry3d prior = X_MS_true;
  prior.translation() += Eigen::Vector3d(0.2, -0.05, 0.02);
  prior.rotate(Eigen::AngleAxisd(DegToRad(1.0), Eigen::Vector3d::UnitZ()));
  const RegistrationResult r = RegisterScan(source, map, prior, IcpParams{});
  ASSERT_TRUE(r.degenerate) << r.message;
  EXPECT_TRUE(r.converged) << r.message;
  // Across the axis, height and yaw corrected; along it the prior kept.
  EXPECT_NEAR(r.X_MS.translation().x(), prior.translation().x(), 0.01) << r.message;
  EXPECT_NEAR(r.X_MS.translation().y(), X_MS_true.translation().y(), 2e-3) << r.message;
  EXPECT_NEAR(r.X_MS.translation().z(), X_MS_true.translation().z(), 2e-3) << r.message;
  const Eigen::Matrix3d dR = X_MS_true.linear().transpose() * r.X_MS.linear();
  EXPECT_LT(RadToDeg(Eigen::AngleAxisd(dR).angle()), 0.05) << r.message;
  // 4 DoF: rz, ty, tz constrained, tx not; roll and pitch not estimated.
  ASSERT_EQ(r.constrained_directions.cols(), 3) << r.message;
  for (Eigen::Index k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(r.constrained_directions(3, k)), 0.05) << k;  // no x in any
    EXPECT_EQ(r.constrained_directions(0, k), 0.0);
    EXPECT_EQ(r.constrained_directions(1, k), 0.0);
  }
  EXPECT_GT(r.information_matrix(4, 4), 1e4 * r.information_matrix(3, 3)) << r.message;
  EXPECT_GT(r.information_matrix(2, 2), 0.0);
  Eigen::Matrix<double, 6, 6> prior_cov = Eigen::Matrix<double, 6, 6>::Zero();
  prior_cov.diagonal() << 1e-8, 1e-8, 1e-4, 0.04, 0.04, 1e-4;  // 20 cm in x and y, 0.6 deg yaw
  const Eigen::Matrix<double, 6, 6> cov = RegistrationCovariance(r, prior_cov);
  EXPECT_NEAR(cov(3, 3), 0.04, 1e-3) << cov;  // x: the prior's
  EXPECT_LT(cov(4, 4), 1e-4 * 0.04) << cov;   // y: the scan's, far below the prior's
  EXPECT_LT(cov(2, 2), 1e-2 * 1e-4) << cov;   // yaw: the scan's
  EXPECT_NEAR(cov(0, 0), 1e-8, 1e-12);        // roll: not estimated, the prior's
  EXPECT_LT((cov - cov.transpose()).norm(), 1e-12);
  // The scan's own part is the inverse of its information where it constrains the pose.
  const Eigen::Matrix<double, 6, 6> own =
      RegistrationCovariance(r, Eigen::Matrix<double, 6, 6>::Zero());
  EXPECT_NEAR(own(3, 3), 0.0, 1e-9);
  EXPECT_NEAR(own(4, 4) * r.information_matrix(4, 4), 1.0, 0.2) << own;
  // Without information (a failed registration) the covariance is the prior's.
  EXPECT_EQ(RegistrationCovariance(RegistrationResult{}, prior_cov), prior_cov);
}

// ---- a doorway: the planes leave the along-wall offset free, the free space does not ----------

struct Box {
  Eigen::Vector3d lo, hi;
};

/// The first hit of every ray from `origin` (0.4 deg in azimuth and elevation, |el| <= 70 deg)
/// on the boxes, in the frame of `origin` (a scanner without noise, yaw 0).
Points CastScan(const std::vector<Box>& boxes, const Eigen::Vector3d& origin) {
  Points pts;
  const double step = DegToRad(0.4);
  for (double el = -DegToRad(70.0); el <= DegToRad(70.0); el += step)
    for (double az = 0.0; az < 2.0 * kPi; az += step) {
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      double best = 30.0;
      for (const Box& b : boxes) {
        double t0 = 0.0, t1 = best;
        for (int i = 0; i < 3 && t0 <= t1; ++i) {
          if (std::abs(d[i]) < 1e-12) {
            if (origin[i] < b.lo[i] || origin[i] > b.hi[i]) t0 = t1 + 1.0;
            continue;
          }
          double a = (b.lo[i] - origin[i]) / d[i], c = (b.hi[i] - origin[i]) / d[i];
          if (a > c) std::swap(a, c);
          t0 = std::max(t0, a);
          t1 = std::min(t1, c);
        }
        if (t0 <= t1 && t0 > 1e-6) best = std::min(best, t0);
      }
      if (best < 30.0) pts.push_back(best * d);
    }
  return pts;
}

/// Two 20 m long rooms on either side of a 0.2 m wall at x in [0, 0.2] with a 0.9 m x 2.1 m
/// door at y in [-0.45, 0.45]: through the door each room sees only planes parallel to the
/// wall (the far wall, floor, ceiling) and the door's jambs and lintel.
std::vector<Box> Doorway() {
  using V = Eigen::Vector3d;
  return {{V(-6, -10, -0.1), V(6, 10, 0)},        {V(-6, -10, 3), V(6, 10, 3.1)},
          {V(0, -10, 0), V(0.2, -0.45, 3)},       {V(0, 0.45, 0), V(0.2, 10, 3)},
          {V(0, -0.45, 2.1), V(0.2, 0.45, 3)},    {V(-6, -10, 0), V(-5.8, 10, 3)},
          {V(5.8, -10, 0), V(6, 10, 3)},          {V(-6, -10.2, 0), V(6, -10, 3)},
          {V(-6, 10, 0), V(6, 10.2, 3)}};
}

TEST(Registration, CountInViewKeepsPointsSomeMapScanCouldHaveSeen) {
  // One scan of the wall x = 5 (|y|, |z| <= 2) from the origin: in front of the wall and on it
  // is in view, behind it or where the scan had no return is not.
  Points wall;
  for (double y = -2; y <= 2; y += 0.02)
    for (double z = -2; z <= 2; z += 0.02) wall.emplace_back(5.0, y, z);
  PointMap map;
  EXPECT_FALSE(map.has_origins());
  map.Add(wall, Eigen::Vector3d::Zero());
  EXPECT_TRUE(map.has_origins());
  EXPECT_EQ(map.CountInView({{3.0, 0.5, 0.2}, {5.0, 0.5, 0.2}, {5.05, 0.0, 0.0}}), 3u);
  EXPECT_EQ(map.CountInView({{7.0, 1.0, 0.0}, {-3.0, 0.0, 0.0}, {5.0, 3.0, 0.0}}), 0u);
  PointMap no_origin;
  no_origin.Add(wall);
  EXPECT_EQ(no_origin.CountInView({{3.0, 0.5, 0.2}}), 0u);
}

TEST(Registration, FitnessCountsThePointsTheMapCouldHaveSeen) {
  // The map is one scan of room A (x < 0) of the doorway world; the new scan stands in room B
  // and sees room A only through the door. Most of its points lie where the map never looked:
  // they do not lower the fitness. A pose 0.3 m off across the wall puts points the map did
  // see where it saw nothing: the fitness there drops.
  const std::vector<Box> boxes = Doorway();
  const Eigen::Vector3d map_origin(-2.5, 0.0, 1.4), scan_origin(2.0, 0.3, 1.4);
  IcpParams icp;
  icp.same_side = true;
  PointMap map(icp);
  map.Add(Transform(CastScan(boxes, map_origin), Eigen::Isometry3d(Eigen::Translation3d(map_origin))),
          map_origin);
  const Points source = CastScan(boxes, scan_origin);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.translation() = scan_origin;
  const RegistrationResult r = RegisterScan(source, map, truth, icp);
  std::printf("  into new space: %s\n", r.message.c_str());
  EXPECT_LT(r.expected_overlap, 0.5) << r.message;
  EXPECT_LT(r.raw_fitness, 0.5) << r.message;
  EXPECT_GT(r.fitness, 0.9) << r.message;
  EXPECT_NEAR(r.raw_fitness, r.fitness * r.expected_overlap, 1e-9);
  // The same scan against a map that also holds room B: everything is in view.
  PointMap both(icp);
  both.Add(Transform(CastScan(boxes, map_origin), Eigen::Isometry3d(Eigen::Translation3d(map_origin))),
           map_origin);
  both.Add(Transform(source, truth), scan_origin);
  const RegistrationResult all = RegisterScan(source, both, truth, icp);
  EXPECT_GT(all.expected_overlap, 0.99) << all.message;
  EXPECT_GT(all.fitness, 0.95) << all.message;
  // A wrong pose, evaluated where it is (no ICP iterations): in-view points unmatched.
  IcpParams frozen = icp;
  frozen.max_iterations = 1;
  frozen.max_correspondence = {0.08};
  Eigen::Isometry3d off = truth;
  off.translation().y() += 0.3;
  off.rotate(Eigen::AngleAxisd(DegToRad(8.0), Eigen::Vector3d::UnitZ()));
  const RegistrationResult wrong = RegisterScan(source, both, off, frozen);
  // (The floor and ceiling still match: the drop is the walls and furniture, 1/3 of the points.)
  EXPECT_LT(wrong.fitness, all.fitness - 0.3) << wrong.message;
  EXPECT_GT(wrong.expected_overlap, 0.8) << wrong.message;
}

TEST(Registration, AWeakDirectionIsPlacedByTheFreeSpaceEvidence) {
  // The door scan 1.5 m in front of the door (room x > 0.2) is the map; the room's first scan
  // 1.3 m behind it (x < 0) has a prior 0.2 m off along the wall, as a localiser that drifted
  // in the passage gives. Point-to-plane leaves y weak at the result (the jambs and lintel are
  // a few points). The jambs of a scan placed off along y stand in the opening the door scan
  // looked through: the free space bounds the offset from both sides.
  const std::vector<Box> boxes = Doorway();
  const Eigen::Vector3d door_scan(1.5, 0.0, 1.4), entry(-1.3, 0.1, 1.4);
  IcpParams icp;  // the floor mission's entry-scan registration
  icp.same_side = true;
  icp.min_fitness = 0.15;
  icp.max_free_space_violation = 0.015;
  icp.max_correspondence = {0.3, 0.15, 0.08};
  PointMap map(icp);
  map.Add(Transform(CastScan(boxes, door_scan), Eigen::Isometry3d(Eigen::Translation3d(door_scan))),
          door_scan);
  const Points source = CastScan(boxes, entry);
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.translation() = entry;
  Eigen::Isometry3d prior = truth;
  prior.translation() += Eigen::Vector3d(0.005, 0.2, 0.0);
  RegistrationAcceptanceParams policy;  // the floor mission's entry-scan bounds
  policy.max_correction = 0.3;
  policy.max_correction_deg = 10.0;
  policy.gate_sigmas = 0.0;

  // Without the search ICP keeps the prior along the weak y (solution remapping), and the
  // jambs float in the opening the door scan looked through.
  const RegistrationResult stuck = RegisterScan(source, map, prior, icp);
  std::printf("  without the search: %s\n", stuck.message.c_str());
  EXPECT_TRUE(stuck.degenerate) << stuck.message;
  EXPECT_GT(std::abs(stuck.weakest_direction[4]), 0.9) << stuck.message;  // along y
  EXPECT_FALSE(stuck.weak_bounded);
  EXPECT_NEAR(stuck.X_MS.translation().y(), prior.translation().y(), 0.02) << stuck.message;
  const RegistrationDecision kept = AcceptRegistration(stuck, prior, icp, policy, 0.01);
  EXPECT_NEAR(kept.X_MS.translation().y(), prior.translation().y(), 0.02) << kept.message;

  // With the search the free space bounds y on both sides: the scan moves to the middle of the
  // evidence, and the policy uses the move (no slide rule).
  icp.weak_search = 0.3;
  const RegistrationResult moved = RegisterScan(source, map, prior, icp);
  std::printf("  with the search: %s\n", moved.message.c_str());
  EXPECT_TRUE(moved.weak_bounded) << moved.message;
  EXPECT_NEAR(moved.weak_offset * moved.weak_offset_direction.y(), -0.2, 0.03) << moved.message;
  EXPECT_NE(moved.message.find("moved"), std::string::npos) << moved.message;
  EXPECT_LT(moved.free_space_violation, stuck.free_space_violation) << moved.message;
  const RegistrationDecision used = AcceptRegistration(moved, prior, icp, policy, 0.01);
  EXPECT_TRUE(used.use) << used.message;
  EXPECT_NEAR(used.X_MS.translation().y(), truth.translation().y(), 0.02) << used.message;
  EXPECT_NEAR(used.X_MS.translation().x(), truth.translation().x(), 0.01) << used.message;

  // With a 1 m first stage the jambs pull the scan home before y turns weak at the result:
  // without the search that is a slide the policy undoes; with it, the evidence refutes the
  // prior and holds the result, which is used where it is.
  IcpParams wide = icp;
  wide.max_correspondence = {1.0, 0.5, 0.2, 0.08};
  wide.weak_search = 0.0;
  const RegistrationResult slid = RegisterScan(source, map, prior, wide);
  EXPECT_TRUE(slid.degenerate) << slid.message;
  EXPECT_NEAR(slid.X_MS.translation().y(), truth.translation().y(), 0.02) << slid.message;
  EXPECT_NEAR(AcceptRegistration(slid, prior, wide, policy, 0.01).X_MS.translation().y(),
              prior.translation().y(), 0.02);
  wide.weak_search = 0.3;
  const RegistrationResult pulled = RegisterScan(source, map, prior, wide);
  EXPECT_TRUE(pulled.weak_bounded) << pulled.message;
  EXPECT_EQ(pulled.weak_offset, 0.0) << pulled.message;
  const RegistrationDecision kept_pull = AcceptRegistration(pulled, prior, wide, policy, 0.01);
  EXPECT_TRUE(kept_pull.use) << kept_pull.message;
  EXPECT_NEAR(kept_pull.X_MS.translation().y(), truth.translation().y(), 0.02)
      << kept_pull.message;

  // A prior the evidence does not refute: the evidence does not decide, the result is used as
  // any degenerate one.
  const RegistrationResult held = RegisterScan(source, map, used.X_MS, icp);
  EXPECT_FALSE(held.weak_bounded) << held.message;
  EXPECT_EQ(held.weak_offset, 0.0) << held.message;
  EXPECT_NEAR(held.X_MS.translation().y(), truth.translation().y(), 0.02) << held.message;
  EXPECT_TRUE(AcceptRegistration(held, used.X_MS, icp, policy, 0.01).use);

  // No free space known (a map without scan origins): no evidence, no move.
  icp.weak_search = 0.3;
  PointMap blind(icp);
  blind.Add(map.points());
  const RegistrationResult none = RegisterScan(source, blind, prior, icp);
  EXPECT_FALSE(none.weak_bounded) << none.message;
  EXPECT_EQ(none.weak_offset, 0.0) << none.message;
  EXPECT_NEAR(none.X_MS.translation().y(), prior.translation().y(), 0.02) << none.message;
}

TEST(Registration, SameBytesWithOneAndTwoThreads) {
  const PointMap map = MapOf({0});
  const SimScan& s1 = Room::Get().Scan(1, kBase[1]);
  const Points src = ScanPoints(s1.scan);
  const Eigen::Isometry3d prior = PerturbedPrior(s1.scan);
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    PointMap m(IcpParams{});
    m.Add(map.points(), Room::Get().Scan(0, kBase[0]).X_WS_true.translation());
    return std::pair{RegisterScan(src, m, prior, IcpParams{}), m.normals()};
  };
  const auto [a, na] = run(1);
  const auto [b, nb] = run(2);
  EXPECT_EQ(std::memcmp(a.X_MS.matrix().data(), b.X_MS.matrix().data(), sizeof(double) * 16), 0);
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(a.rmse, b.rmse);
  EXPECT_EQ(a.free_space_violation, b.free_space_violation);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.message, b.message);
  ASSERT_EQ(na.size(), nb.size());
  for (std::size_t i = 0; i < na.size(); ++i) ASSERT_EQ(na[i].n, nb[i].n);
}

TEST(Registration, BadParamsAndInputsThrowInputError) {
  const PointMap map = MapOf({0});
  const Points src = {{1, 0, 0}};
  auto expect_bad = [&](auto tweak, const std::string& name) {
    IcpParams p;
    tweak(p);
    try {
      RegisterScan(src, map, Eigen::Isometry3d::Identity(), p);
      ADD_FAILURE() << "no InputError for " << name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  expect_bad([](IcpParams& p) { p.dof = 5; }, "dof");
  expect_bad([](IcpParams& p) { p.robust_kernel = "welsch"; }, "robust_kernel");
  expect_bad([](IcpParams& p) { p.max_correspondence.clear(); }, "max_correspondence");
  expect_bad([](IcpParams& p) { p.max_correspondence = {0.5, -0.1}; }, "max_correspondence");
  expect_bad([](IcpParams& p) { p.voxel_size = 0.0; }, "voxel_size");
  expect_bad([](IcpParams& p) { p.max_iterations = 0; }, "max_iterations");
  expect_bad([](IcpParams& p) { p.min_fitness = 1.5; }, "min_fitness");
  expect_bad([](IcpParams& p) { p.min_range = 50.0, p.max_range = 10.0; }, "min_range");
  Eigen::Isometry3d nan_prior = Eigen::Isometry3d::Identity();
  nan_prior.translation().x() = std::nan("");
  EXPECT_THROW(RegisterScan(src, map, nan_prior, IcpParams{}), InputError);
  IcpParams bad;
  bad.normal_neighbours = 1;
  EXPECT_THROW(PointMap{bad}, InputError);
  // An empty map is an outcome, not an exception.
  const RegistrationResult r =
      RegisterScan(src, PointMap{}, Eigen::Isometry3d::Identity(), IcpParams{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("empty map"), std::string::npos) << r.message;
}

TEST(Registration, ParamsRoundTripThroughYamlAndRejectUnknownKeys) {
  IcpParams p;
  p.dof = 4;
  p.max_correspondence = {0.3, 0.05};
  p.robust_kernel = "huber";
  const IcpParams q = LoadParams<IcpParams>(SaveParams(p), "icp.yaml");
  EXPECT_EQ(q.dof, 4);
  EXPECT_EQ(q.max_correspondence, p.max_correspondence);
  EXPECT_EQ(q.robust_kernel, "huber");
  EXPECT_THROW(LoadParams<IcpParams>(LoadYamlString("max_iteration: 3", "icp.yaml"), "icp.yaml"),
               InputError);
  EXPECT_THROW(LoadParams<IcpParams>(LoadYamlString("dof: 7", "icp.yaml"), "icp.yaml"), InputError);
}

// Figures only (no timing assertion): a 0.2 deg scan (~0.85 M points) of the 10 m x 9.4 m office
// R3 of scenes/office_5rooms.yaml against 1 and 4 accumulated scans (each added at its
// registered pose), including the source's range gate and voxel grid; and the map update.
TEST(RegistrationFigures, WallTimeOfOneScanAgainstOneAndFourScans) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  };
  scenes::GeneratedScene g = scenes::Generate(
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
  const scenes::GroundTruth truth = std::move(g.truth);
  const sim::EmbreeWorld world(std::move(g.scene), &truth);
  const sim::TlsScanner scanner(world, sim::TlsProfile("riegl_vz400"));
  const Pose2 base[5] = {{3, 12, 0}, {7, 16, 1}, {2, 17, 2}, {8, 11, -1}, {5, 14.5, 0.5}};
  std::vector<SimScan> scans;
  for (int k = 0; k < 5; ++k) {
    sim::ScanRequest req;
    req.seed = 5;
    req.scan_id = static_cast<std::uint64_t>(k);
    req.X_WB = base[k].To3d();
    sim::TlsTruth t;
    SimScan s;
    s.scan = scanner.Scan(req, &t);
    s.X_WS_true = t.X_WS;
    scans.push_back(std::move(s));
  }
  PointMap map;
  map.Add(ScanPoints(scans[0].scan, scans[0].X_WS_true), scans[0].X_WS_true.translation());
  for (int k = 1; k < 5; ++k) {
    const Points src = ScanPoints(scans[k].scan);
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    const RegistrationResult r =
        RegisterScan(src, map, PerturbedPrior(scans[k].scan, 0.1, 0.17, -3.0), IcpParams{});
    const double t_reg = seconds(t0),
                 cpu_reg = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    EXPECT_TRUE(r.ok) << r.message;
    EXPECT_LT(TranslationError(r.X_MS, scans[k].X_WS_true), 0.005);
    EXPECT_LT(RotationErrorDeg(r.X_MS, scans[k].X_WS_true), 0.05);
    const auto t1 = Clock::now();
    const std::clock_t c1 = std::clock();
    map.Add(Transform(src, r.X_MS), r.X_MS.translation());
    const double t_add = seconds(t1),
                 cpu_add = static_cast<double>(std::clock() - c1) / CLOCKS_PER_SEC;
    std::ifstream loadavg("/proc/loadavg");
    std::string load;
    std::getline(loadavg, load);
    std::printf("FIGURE machine load average: %s\n", load.c_str());
    std::printf(
        "FIGURE registration: scan %d (%zu points) vs %d accumulated scan(s): RegisterScan %.3f s "
        "(CPU %.3f s), then PointMap::Add %.3f s (CPU %.3f s, map %zu points); error %.2f mm %.4f "
        "deg; %s\n",
        k, src.size(), k, t_reg, cpu_reg, t_add, cpu_add, map.size(),
        1e3 * TranslationError(r.X_MS, scans[k].X_WS_true),
        RotationErrorDeg(r.X_MS, scans[k].X_WS_true), r.message.c_str());
  }
}

}  // namespace
}  // namespace mopad::perception
