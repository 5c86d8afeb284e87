#include "evaluation/scan_eval.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "common/error.h"
#include "scenes/element_class.h"
#include "scenes/geometry.h"

namespace mopad::evaluation {

PoseError RegistrationError(const Pose3& X_MS_estimated, const Pose3& X_MS_true) {
  PoseError e;
  e.translation = (X_MS_estimated.translation() - X_MS_true.translation()).norm();
  const Eigen::Matrix3d dR = X_MS_estimated.linear().transpose() * X_MS_true.linear();
  // Angle from the trace, robust near 0 and 180 via atan2 of the axis norm.
  const Eigen::Vector3d axis(dR(2, 1) - dR(1, 2), dR(0, 2) - dR(2, 0), dR(1, 0) - dR(0, 1));
  e.rotation_deg = RadToDeg(std::atan2(0.5 * axis.norm(), 0.5 * (dR.trace() - 1.0)));
  return e;
}

Pose3 TrueScannerPoseInMap(const Pose3& X_WM, const sim::TlsTruth& truth) {
  return X_WM.inverse() * truth.X_WS;
}

PoseError ScanRegistrationError(const Pose3& X_MS_estimated, const Pose3& X_WM,
                                const sim::TlsTruth& truth) {
  return RegistrationError(X_MS_estimated, TrueScannerPoseInMap(X_WM, truth));
}

std::string_view ToString(Sm1Label label) {
  switch (label) {
    case Sm1Label::kNone:
      return "none";
    case Sm1Label::kInlier:
      return "inlier";
    case Sm1Label::kOutlier:
      return "outlier";
    case Sm1Label::kClutter:
      return "clutter";
  }
  return "none";
}

std::vector<Sm1Label> TruthLabels(const interfaces::TlsScan& scan, const sim::TlsTruth& truth,
                                  const scenes::GroundTruth& ground_truth, const std::string& room,
                                  const LabelTruthParams& params) {
  ValidateParams(params, "label_truth.");
  if (scan.rows != truth.rows || scan.columns != truth.columns ||
      scan.points.size() != truth.points.size() ||
      scan.points.size() != static_cast<std::size_t>(scan.rows) * scan.columns) {
    throw InputError("", "scan and truth grids differ",
                     std::to_string(scan.rows) + "x" + std::to_string(scan.columns) + " scan",
                     std::to_string(truth.rows) + "x" + std::to_string(truth.columns) + " truth");
  }
  const scenes::Room* r = ground_truth.FindRoom(room);
  if (!r) throw InputError("", "unknown room", "'" + room + "'", "a room of the ground truth");
  // Truth element table index -> structural element of this room.
  std::set<std::string> own;
  for (const scenes::StructuralElement& e : ground_truth.elements) {
    if (scenes::IsStructural(e.element_class) &&
        std::find(e.rooms.begin(), e.rooms.end(), room) != e.rooms.end()) {
      own.insert(e.id);
    }
  }
  std::vector<std::uint8_t> is_own(truth.element_ids.size(), 0);
  for (std::size_t k = 0; k < truth.element_ids.size(); ++k)
    is_own[k] = own.count(truth.element_ids[k]) ? 1 : 0;

  std::vector<Sm1Label> out(scan.points.size(), Sm1Label::kNone);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const interfaces::TlsPoint& p = scan.points[i];
    if (!p.valid()) continue;
    const sim::TlsPointTruth& t = truth.points[i];
    if (t.flags & sim::kTruthTransmitted) {
      out[i] = Sm1Label::kOutlier;
      continue;
    }
    const auto cls = static_cast<scenes::ElementClass>(t.element_class);
    if (t.element >= 0 && static_cast<std::size_t>(t.element) < is_own.size() &&
        is_own[t.element] && scenes::IsStructural(cls)) {
      out[i] = Sm1Label::kInlier;
      continue;
    }
    Eigen::Vector3d p_S(p.x, p.y, p.z);
    if (t.true_range > 0.0f && p_S.norm() > 0)
      p_S = p_S.normalized() * static_cast<double>(t.true_range);
    const Eigen::Vector3d p_W = truth.X_WS * p_S;
    const Eigen::Vector2d q(p_W.x(), p_W.y());
    const bool outside = !scenes::PointInPolygon(q, r->polygon) &&
                         scenes::DistanceToBoundary(q, r->polygon) > params.outside_margin;
    out[i] = outside ? Sm1Label::kOutlier : Sm1Label::kClutter;
  }
  return out;
}

std::vector<Sm1Label> InPlyOrder(const interfaces::TlsScan& scan,
                                 const std::vector<Sm1Label>& grid) {
  if (grid.size() != scan.points.size()) {
    throw InputError("", "label grid does not match the scan", std::to_string(grid.size()),
                     std::to_string(scan.points.size()));
  }
  std::vector<Sm1Label> out;
  for (std::uint32_t c = 0; c < scan.columns; ++c)
    for (std::uint32_t r = 0; r < scan.rows; ++r) {
      const std::size_t i = static_cast<std::size_t>(r) * scan.columns + c;
      if (scan.points[i].valid()) out.push_back(grid[i]);
    }
  return out;
}

void LabelAccuracy::Add(const LabelAccuracy& o) {
  points += o.points;
  correct += o.correct;
  unlabelled += o.unlabelled;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) confusion[a][b] += o.confusion[a][b];
}

LabelAccuracy CompareLabels(std::span<const Sm1Label> truth,
                            std::span<const std::uint8_t> estimated) {
  if (truth.size() != estimated.size()) {
    throw InputError("", "label counts differ", std::to_string(estimated.size()) + " estimated",
                     std::to_string(truth.size()) + " (one per truth label)");
  }
  LabelAccuracy acc;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const std::uint8_t e = estimated[i];
    if (e > 3)
      throw InputError("", "label out of range at point " + std::to_string(i), std::to_string(e),
                       "0..3");
    const int t = static_cast<int>(truth[i]);
    if (t == 0) continue;
    ++acc.points;
    if (e == 0) {
      ++acc.unlabelled;
      continue;
    }
    ++acc.confusion[t - 1][e - 1];
    if (e == t) ++acc.correct;
  }
  return acc;
}

LabelAccuracy CompareLabels(std::span<const Sm1Label> truth, std::span<const Sm1Label> estimated) {
  std::vector<std::uint8_t> e(estimated.size());
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = static_cast<std::uint8_t>(estimated[i]);
  return CompareLabels(truth, e);
}

std::string LabelAccuracyToJson(const LabelAccuracy& a) {
  nlohmann::ordered_json j;
  j["points"] = a.points;
  j["correct"] = a.correct;
  j["unlabelled"] = a.unlabelled;
  j["accuracy"] = std::round(a.Accuracy() * 1e6) / 1e6;
  j["confusion"] = nlohmann::ordered_json::array();
  for (const auto& row : a.confusion) j["confusion"].push_back({row[0], row[1], row[2]});
  return j.dump(2) + "\n";
}

}  // namespace mopad::evaluation
