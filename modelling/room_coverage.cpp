// Coverage (RoomModel::UpdateFaces, UpdateCoverage): which RoI face cells the scans sensed or
// saw through (openings), and the sensed share of the estimated structural area.
#include <algorithm>
#include <cmath>

#include "modelling/room_model.h"

namespace mopad::modelling {
namespace {

// The beam to an outlier point is searched for its first perimeter crossing up to this multiple
// of the point's distance from the scanner.
constexpr double kFarthestCrossing = 2.0;

}  // namespace

void RoomModel::UpdateFaces() {
  if (roi_.empty()) return;
  for (auto& f : roi_.faces) {
    for (auto& c : f.cells) {
      if (c != FaceCell::kOff) c = FaceCell::kUnsensed;
    }
  }
  // Sensed: structural working points in their face's cell.
  for (std::size_t i = 0; i < work_points_.size(); ++i) {
    if (work_labels_[i] != PointLabel::kInlier || work_face_[i] < 0) continue;
    RoiFace& f = roi_.faces[work_face_[i]];
    const int c = f.CellIndexOf(work_points_[i].cast<double>());
    if (c >= 0 && f.cells[c] != FaceCell::kOff) f.cells[c] = FaceCell::kSensed;
  }
  // Openings: beams of outlier points cross the perimeter where there is no wall.
  const auto& P = roi_.perimeter;
  const int n = static_cast<int>(P.size());
  const double zf = roi_.floor_z, zc = roi_.ceiling_z;
  for (const auto& s : scans_) {
    const Vec3 o = s.origin;
    for (std::size_t i = s.begin; i < s.end; ++i) {
      if (labels_[i] != PointLabel::kOutlier) continue;
      const Vec3 p = points_[i].cast<double>();
      const Vec2 d = p.head<2>() - o.head<2>();
      double best_t = kFarthestCrossing;
      int best_e = -1;
      for (int e = 0; e < n; ++e) {
        const Vec2 a = P[e], b = P[(e + 1) % n];
        const Vec2 ab = b - a;
        const double den = d.x() * ab.y() - d.y() * ab.x();
        if (std::abs(den) < 1e-12) continue;
        const Vec2 ao = a - o.head<2>();
        const double t = (ao.x() * ab.y() - ao.y() * ab.x()) / den;
        const double u = (ao.x() * d.y() - ao.y() * d.x()) / den;
        if (t > 0 && t < best_t && u >= 0 && u <= 1) {
          best_t = t;
          best_e = e;
        }
      }
      if (best_e < 0) continue;
      const Vec3 q = o + best_t * (p - o);
      if (q.z() <= zf || q.z() >= zc) continue;
      RoiFace& f = roi_.faces[2 + best_e];
      const int c = f.CellIndexOf(q);
      if (c >= 0 && f.cells[c] == FaceCell::kUnsensed) f.cells[c] = FaceCell::kOpening;
    }
  }
  for (auto& f : roi_.faces) {
    double on = 0.0, sensed = 0.0;
    for (std::size_t c = 0; c < f.cells.size(); ++c) {
      if (f.cells[c] == FaceCell::kOff) continue;
      on += f.cell_area[c];
      if (f.cells[c] == FaceCell::kSensed) sensed += f.cell_area[c];
    }
    f.sensed_share = on > 0 ? sensed / on : 0.0;
    f.structural = f.sensed_share >= params_.structural_share && sensed > 0;
  }
}

void RoomModel::UpdateCoverage() {
  CoverageFigures f;
  f.scans = ScanCount();
  double on = 0.0;
  for (const auto& face : roi_.faces) {
    for (std::size_t c = 0; c < face.cells.size(); ++c) {
      switch (face.cells[c]) {
        case FaceCell::kOff:
          break;
        case FaceCell::kUnsensed:
          on += face.cell_area[c];
          break;
        case FaceCell::kSensed:
          on += face.cell_area[c];
          f.sensed_area += face.cell_area[c];
          break;
        case FaceCell::kOpening:
          f.opening_area += face.cell_area[c];
          break;
      }
    }
  }
  f.total_area = on;
  f.ratio = on > 0 ? f.sensed_area / on : 0.0;
  const double prev = coverage_.empty() ? 0.0 : coverage_.back().sensed_area;
  f.increment = on > 0 ? (f.sensed_area - prev) / on : 0.0;
  f.observable_ratio = f.ratio;
  coverage_.push_back(f);
}

void CoverageFigures::SetHiddenArea(double area) {
  hidden_area = std::clamp(area, 0.0, std::max(0.0, total_area - sensed_area));
  const double observable = total_area - hidden_area;
  observable_ratio = observable > 0.0 ? sensed_area / observable : 0.0;
}

}  // namespace mopad::modelling
