// The detail pass's planning (autonomy/detail_pass.h) on walls built in code: which SE cells are
// too sparse or too grazing, and where (and at which step) the extra scan goes.

#include "autonomy/detail_pass.h"

#include <gtest/gtest.h>

#include <cmath>

#include "autonomy/exploration.h"
#include "autonomy/room_scan.h"
#include "common/error.h"
#include "common/params.h"

namespace mopad::autonomy {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A 3 m x 2.5 m wall in the plane y = 5, facing the room at y < 5.
DetailSurface Wall(double width = 3.0) {
  DetailSurface s;
  s.name = "wall_1";
  s.origin = Vec3(0.0, 5.0, 0.0);
  s.u = Vec3::UnitX();
  s.v = Vec3::UnitZ();
  s.n = -Vec3::UnitY();
  s.width = width;
  s.height = 2.5;
  return s;
}

// Points every 2 cm over the surface, all from scan `scan` (the analysis counts which scans saw
// a cell; the density is analytic).
void AddPoints(const DetailSurface& s, std::uint16_t scan, std::vector<Eigen::Vector3f>& pts,
               std::vector<std::uint16_t>& idx) {
  for (double u = 0.01; u < s.width; u += 0.02)
    for (double v = 0.01; v < s.height; v += 0.02) {
      pts.push_back((s.origin + u * s.u + v * s.v).cast<float>());
      idx.push_back(scan);
    }
}

std::vector<DetailCell> Analyse(const DetailSurface& wall, const Vec3& scanner, double step_deg,
                                const DetailPassParams& p = {}) {
  std::vector<Eigen::Vector3f> pts;
  std::vector<std::uint16_t> idx;
  AddPoints(wall, 0, pts, idx);
  DetailScans scans;
  scans.origins = {scanner};
  scans.step_rad = {step_deg * kDeg};
  return AnalyseDetailCells(pts, idx, scans, {wall}, p);
}

DetailView View() {
  DetailView v;
  v.ref_step_rad = 0.2 * kDeg;
  v.seconds_at_ref = 3.0;  // ~900k rays at 300 kHz
  return v;
}

double DeficientArea(const std::vector<DetailCell>& cells) {
  double a = 0.0;
  for (const DetailCell& c : cells) a += c.deficient ? c.area : 0.0;
  return a;
}

TEST(DetailPass, DensityIsTheScannersAnalyticSpacingAtNormalIncidence) {
  // Scanner 3 m in front of the wall's centre at the cell's height: spacing = r x step.
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(1.5, 2.0, 1.375), 0.2, p);
  ASSERT_EQ(cells.size(), 12u * 10u);  // 3 m / 0.25 x 2.5 m / 0.25
  // The cell whose centre is (1.625, 5, 1.375): r = sqrt(3^2 + 0.125^2).
  bool checked = false;
  for (const DetailCell& c : cells)
    if (std::abs(c.centre.x() - 1.625) < 1e-9 && std::abs(c.centre.z() - 1.375) < 1e-9) {
      const double r = std::hypot(3.0, 0.125);
      const double cos_a = 3.0 / r;
      EXPECT_NEAR(c.Spacing(), r * 0.2 * kDeg / std::sqrt(cos_a), 1e-6);
      EXPECT_NEAR(c.incidence, std::acos(cos_a), 1e-9);
      checked = true;
    }
  EXPECT_TRUE(checked);
}

TEST(DetailPass, AWallAlreadyDenseGetsNoDetailScan) {
  // 1.5 m in front at a 0.05 deg step: ~1.3 mm spacing, every cell within 55 deg.
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(1.5, 3.5, 1.4), 0.05, p);
  ASSERT_FALSE(cells.empty());
  EXPECT_EQ(DeficientArea(cells), 0.0);
  const std::vector<DetailCandidate> cands{{Vec2(1.5, 3.0), 1.4, 0.1 * kDeg, 0.5}};
  const DetailPlan plan = PlanDetailScan(cells, {wall}, cands, View(), p, {});
  EXPECT_FALSE(plan.found) << plan.message;
  EXPECT_EQ(plan.deficient_area, 0.0);
}

TEST(DetailPass, AWallSeenOnlyAtGrazingIncidenceGetsADetailScanInFrontOfIt) {
  // Seen only from 6 m to its left, 0.5 m off its plane: every cell beyond 80 deg.
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(-6.0, 4.5, 1.4), 0.2, p);
  ASSERT_FALSE(cells.empty());
  for (const DetailCell& c : cells) EXPECT_TRUE(c.deficient);
  EXPECT_NEAR(DeficientArea(cells), 3.0 * 2.5, 1e-9);
  // Candidates: where it stands (no drive), 2 m in front of the wall's middle (7 m drive),
  // each at the room step and the fine step.
  std::vector<DetailCandidate> cands;
  for (const double step : {0.2, 0.1}) {
    cands.push_back({Vec2(-6.0, 4.5), 1.4, step * kDeg, 0.0});
    cands.push_back({Vec2(1.5, 3.0), 1.4, step * kDeg, 7.0});
  }
  const DetailPlan plan = PlanDetailScan(cells, {wall}, cands, View(), p, {});
  ASSERT_TRUE(plan.found) << plan.message;
  EXPECT_EQ(cands[plan.chosen].base, Vec2(1.5, 3.0)) << plan.message;
  EXPECT_GE(plan.gain_area, 0.8 * 3.0 * 2.5) << plan.message;
}

TEST(DetailPass, ASparseWallFacedSquarelyGetsAFinerStepFromWhereTheRobotStands) {
  // 5 m in front at 0.2 deg: ~1.75 cm spacing, incidence fine. A 0.1 deg scan from the same
  // spot halves the spacing without a drive; driving to 2 m gives the same but costs the drive.
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(1.5, 0.0, 1.4), 0.2, p);
  ASSERT_GT(DeficientArea(cells), 0.9 * 3.0 * 2.5);
  std::vector<DetailCandidate> cands;
  for (const double step : {0.2, 0.1}) {
    cands.push_back({Vec2(1.5, 0.0), 1.4, step * kDeg, 0.0});
    cands.push_back({Vec2(1.5, 3.0), 1.4, step * kDeg, 3.0});
  }
  const DetailPlan plan = PlanDetailScan(cells, {wall}, cands, View(), p, {});
  ASSERT_TRUE(plan.found) << plan.message;
  EXPECT_EQ(cands[plan.chosen].base, Vec2(1.5, 0.0)) << plan.message;
  EXPECT_NEAR(cands[plan.chosen].step_rad, 0.1 * kDeg, 1e-12) << plan.message;
}

TEST(DetailPass, ARepeatScanFromTheSamePlaceAtTheSameStepIsNoCandidate) {
  // 5 m in front at 0.2 deg; the only candidates stand there: at 0.2 deg (its rays would land
  // on the first scan's samples) and at 0.1 deg (new samples between them).
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(1.5, 0.0, 1.4), 0.2, p);
  DetailScans taken;
  taken.origins = {Vec3(1.5, 0.0, 1.4)};
  taken.step_rad = {0.2 * kDeg};
  const std::vector<DetailCandidate> same{{Vec2(1.5, 0.0), 1.4, 0.2 * kDeg, 0.0}};
  EXPECT_FALSE(PlanDetailScan(cells, {wall}, same, View(), p, taken).found);
  const std::vector<DetailCandidate> finer{{Vec2(1.5, 0.0), 1.4, 0.1 * kDeg, 0.0}};
  EXPECT_TRUE(PlanDetailScan(cells, {wall}, finer, View(), p, taken).found);
}

TEST(DetailPass, ACandidateWhoseViewIsBlockedIsNotChosen) {
  const DetailSurface wall = Wall();
  DetailPassParams p;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(-6.0, 4.5, 1.4), 0.2, p);
  const std::vector<DetailCandidate> cands{{Vec2(1.5, 3.0), 1.4, 0.1 * kDeg, 3.0},
                                           {Vec2(1.5, 2.0), 1.4, 0.1 * kDeg, 4.0}};
  // Something stands between the nearer candidate and the wall.
  const LineOfSight blocked_from_first = [](const Vec3& scanner, const Vec3&) {
    return scanner.y() < 2.5;
  };
  const DetailPlan plan = PlanDetailScan(cells, {wall}, cands, View(), p, {}, blocked_from_first);
  ASSERT_TRUE(plan.found) << plan.message;
  EXPECT_EQ(plan.chosen, 1) << plan.message;
}

TEST(DetailPass, TooLittleDeficientAreaPlansNothing) {
  // A 0.5 m wide strip, grazing: 1.25 m2 deficient, below a 2 m2 floor.
  const DetailSurface wall = Wall(0.5);
  DetailPassParams p;
  p.min_gain_area = 2.0;
  const std::vector<DetailCell> cells = Analyse(wall, Vec3(-6.0, 4.5, 1.4), 0.2, p);
  const std::vector<DetailCandidate> cands{{Vec2(0.25, 3.0), 1.4, 0.1 * kDeg, 3.0}};
  const DetailPlan plan = PlanDetailScan(cells, {wall}, cands, View(), p, {});
  EXPECT_FALSE(plan.found) << plan.message;
  EXPECT_NEAR(plan.deficient_area, 1.25, 1e-9);
}

TEST(DetailPass, PointsSeenFromBehindTheFaceDoNotCount) {
  // A scanner behind the wall (another room's scan through the wall's plane) sees none of it.
  const DetailSurface wall = Wall();
  EXPECT_TRUE(Analyse(wall, Vec3(1.5, 7.0, 1.4), 0.2).empty());
}

TEST(DetailPass, ParamsVisitEveryField) {
  EXPECT_TRUE(FieldsMissingFromVisit(DetailPassParams{}).empty());
}

// Every field of the robot side's params is in its Visit() list (common/params.h).
TEST(AutonomyParams, EveryFieldIsInTheFieldList) {
  for (const auto& m : FieldsMissingFromVisit(RoomScanParams{}, "room.")) ADD_FAILURE() << m;
  for (const auto& m : FieldsMissingFromVisit(NavigatorParams{}, "navigator.")) ADD_FAILURE() << m;
  for (const auto& m : FieldsMissingFromVisit(ExplorationParams{}, "exploration."))
    ADD_FAILURE() << m;
}

TEST(DetailPass, TheRoomLoopLoadsItsParamsUnderDetailAndRejectsTypos) {
  const auto p = LoadParams<RoomScanParams>(
      LoadYamlString("detail: {enabled: true, fine_step_deg: 0.05, max_scans: 1}", "t.yaml"),
      "t.yaml");
  EXPECT_TRUE(p.detail.enabled);
  EXPECT_EQ(p.detail.fine_step_deg, 0.05);
  EXPECT_EQ(p.detail.max_scans, 1);
  EXPECT_TRUE(RoomScanParams{}.detail.enabled);  // on by default (docs/room-scanning.md)
  EXPECT_THROW(
      LoadParams<RoomScanParams>(LoadYamlString("detail: {max_scan: 1}", "t.yaml"), "t.yaml"),
      InputError);
}

}  // namespace
}  // namespace mopad::autonomy
