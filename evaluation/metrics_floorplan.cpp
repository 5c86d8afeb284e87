#include "evaluation/metrics_floorplan.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "evaluation/hungarian.h"

namespace mopad::evaluation {
namespace {

void ValidateRoom(const Room& r, const std::string& what) {
  if (r.polygon.size() < 3) {
    throw InputError("", what + ": room polygon has too few vertices",
                     std::to_string(r.polygon.size()), ">= 3");
  }
  for (const Vec2& p : r.polygon) {
    if (!p.allFinite())
      throw InputError("", what + ": room vertex is not finite", "NaN/Inf", "finite");
  }
  if (std::abs(SignedArea(r.polygon)) < 1e-9) {
    throw InputError("", what + ": room polygon has zero area");
  }
}

// CCW corners with their interior angles (rad).
struct Corners {
  std::vector<Vec2> p;
  std::vector<double> interior;
};

Corners CornersOf(const Room& r, double collinear_tol) {
  Corners c;
  c.p = SimplifyPolygon(r.polygon, collinear_tol);
  if (SignedArea(c.p) < 0.0) std::reverse(c.p.begin(), c.p.end());
  const size_t n = c.p.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = c.p[(i + n - 1) % n] - c.p[i];
    const Vec2 b = c.p[(i + 1) % n] - c.p[i];
    // Interior angle of a CCW polygon at vertex i: angle from b to a, counter-clockwise.
    double ang = std::atan2(b.x() * a.y() - b.y() * a.x(), b.dot(a));
    if (ang < 0.0) ang += 2.0 * kPi;
    c.interior.push_back(ang);
  }
  return c;
}

}  // namespace

PrecisionRecall PrecisionRecall::From(int tp, int n_predicted, int n_truth) {
  PrecisionRecall s;
  s.tp = tp;
  s.n_predicted = n_predicted;
  s.n_truth = n_truth;
  s.precision = n_predicted > 0 ? static_cast<double>(tp) / n_predicted : 0.0;
  s.recall = n_truth > 0 ? static_cast<double>(tp) / n_truth : 0.0;
  s.f1 =
      s.precision + s.recall > 0.0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

FloorplanResult EvaluateFloorplan(const std::vector<Room>& predicted,
                                  const std::vector<Room>& truth, const FloorplanParams& params) {
  ValidateParams(params, "floorplan.");
  for (size_t i = 0; i < predicted.size(); ++i) {
    ValidateRoom(predicted[i], NameOf("predicted room", i, predicted[i].id));
  }
  for (size_t i = 0; i < truth.size(); ++i) {
    ValidateRoom(truth[i], NameOf("truth room", i, truth[i].id));
  }
  FloorplanResult res;
  const int nt = static_cast<int>(truth.size());
  const int np = static_cast<int>(predicted.size());
  Eigen::MatrixXd iou(nt, np), cost(nt, np);
  for (int t = 0; t < nt; ++t) {
    for (int p = 0; p < np; ++p) {
      iou(t, p) = PolygonIoU(predicted[p].polygon, truth[t].polygon);
      cost(t, p) = iou(t, p) > 0.0 ? 1.0 - iou(t, p) : kForbiddenCost;
    }
  }
  const std::vector<int> assign = SolveAssignment(cost);
  res.truth_room_iou.assign(nt, 0.0);
  int room_tp = 0;
  const double collinear = DegToRad(params.collinear_tolerance_deg);
  std::vector<Corners> pc(np), tc(nt);
  int n_pred_corners = 0, n_truth_corners = 0;
  for (int p = 0; p < np; ++p) {
    pc[p] = CornersOf(predicted[p], collinear);
    n_pred_corners += static_cast<int>(pc[p].p.size());
  }
  for (int t = 0; t < nt; ++t) {
    tc[t] = CornersOf(truth[t], collinear);
    n_truth_corners += static_cast<int>(tc[t].p.size());
  }
  std::vector<int> corner_tp(params.corner_thresholds.size(), 0);
  int angle_tp = 0;
  for (int t = 0; t < nt; ++t) {
    if (assign[t] < 0) continue;
    const int p = assign[t];
    RoomPair rp;
    rp.predicted = p;
    rp.truth = t;
    rp.predicted_id = predicted[p].id;
    rp.truth_id = truth[t].id;
    rp.iou = iou(t, p);
    rp.true_positive = rp.iou > params.room_iou_threshold;
    res.truth_room_iou[t] = rp.iou;
    res.room_pairs.push_back(rp);
    if (!rp.true_positive) continue;
    ++room_tp;
    const Corners& a = tc[t];
    const Corners& b = pc[p];
    Eigen::MatrixXd dc(a.p.size(), b.p.size());
    for (size_t i = 0; i < a.p.size(); ++i) {
      for (size_t j = 0; j < b.p.size(); ++j) dc(i, j) = (a.p[i] - b.p[j]).norm();
    }
    const std::vector<int> ca = SolveAssignment(dc);
    for (size_t i = 0; i < a.p.size(); ++i) {
      if (ca[i] < 0) continue;
      const double d = dc(i, ca[i]);
      for (size_t k = 0; k < params.corner_thresholds.size(); ++k) {
        if (d <= params.corner_thresholds[k]) ++corner_tp[k];
      }
      if (d <= params.angle_corner_threshold &&
          RadToDeg(std::abs(a.interior[i] - b.interior[ca[i]])) <= params.angle_tolerance_deg) {
        ++angle_tp;
      }
    }
  }
  double sum = 0.0;
  for (double v : res.truth_room_iou) sum += v;
  res.mean_truth_iou = nt > 0 ? sum / nt : 0.0;
  res.rooms = PrecisionRecall::From(room_tp, np, nt);
  for (size_t k = 0; k < params.corner_thresholds.size(); ++k) {
    res.corners.push_back({params.corner_thresholds[k],
                           PrecisionRecall::From(corner_tp[k], n_pred_corners, n_truth_corners)});
  }
  res.angles = PrecisionRecall::From(angle_tp, n_pred_corners, n_truth_corners);
  return res;
}

}  // namespace mopad::evaluation
