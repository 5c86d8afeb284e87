// The per-point labels (RoomModel::Classify, LabelAll): inlier on the floor, the ceiling, a
// perimeter wall or a column; outlier outside the perimeter; clutter the rest.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {
namespace {

// The boundary's lookup raster (RoomModel::Boundary::BuildRaster). Its cells only speed up the
// lookups: a point's label does not depend on them.
constexpr double kRasterCell = 0.1;    // m, raster cell
constexpr double kRasterMargin = 0.5;  // m, the raster reaches this beyond reveal_depth
// m, the exact distance is looked up within max(reveal_depth, wall_tolerance) + this of the
// boundary (the farthest the rule reads it).
constexpr double kNearSlack = 0.05;

}  // namespace

namespace {

struct Classified {
  PointLabel label = PointLabel::kNone;
  int face = -1;
};

}  // namespace

// The per-point rule (see the header and docs/room-scanning.md).
static Classified ClassifyWith(const RoomModelParams& P, const Roi& roi,
                               const RoomModel::Boundary* bnd, const Vec3& p) {
  Classified out;
  if (roi.empty()) return out;
  const double zf = roi.floor_z, zc = roi.CeilingAt(p.head<2>());
  int seg = -1;
  const double sd = bnd->Lookup(p.head<2>(), &seg);
  const double dzf = std::abs(p.z() - zf), dzc = std::abs(p.z() - zc);
  if (p.z() < zf - P.plane_tolerance || p.z() > zc + P.plane_tolerance) {
    out.label = PointLabel::kOutlier;
    return out;
  }
  if (sd > P.wall_tolerance) {
    const bool column = seg >= 0 && bnd->segs[seg].column;
    const bool in_reveal =
        sd <= P.reveal_depth && p.z() > zf + P.plane_tolerance && p.z() < zc - P.plane_tolerance;
    out.label = (column || in_reveal) ? PointLabel::kClutter : PointLabel::kOutlier;
    return out;
  }
  if (sd >= -P.wall_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = seg >= 0 ? bnd->segs[seg].face : -1;
    const double asd = std::abs(sd);
    if (dzf <= P.plane_tolerance && dzf < asd) out.face = 0;
    if (dzc <= P.plane_tolerance && dzc < asd) out.face = 1;
    return out;
  }
  if (dzf <= P.plane_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = 0;
  } else if (dzc <= P.plane_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = 1;
  } else {
    out.label = PointLabel::kClutter;
  }
  return out;
}

PointLabel RoomModel::Classify(const Vec3& p_M) const {
  if (roi_.empty() || !boundary_) return PointLabel::kNone;
  return ClassifyWith(params_, roi_, boundary_.get(), p_M).label;
}

void RoomModel::LabelAll() {
  boundary_.reset();
  if (roi_.empty()) return;
  auto b = std::make_shared<Boundary>();
  b->AddLoop(roi_.perimeter, false, 2);
  int face = 2 + static_cast<int>(roi_.perimeter.size());
  for (const auto& c : roi_.columns) {
    b->AddLoop(c, true, face);
    face += static_cast<int>(c.size());
  }
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi_.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double m = params_.reveal_depth + kRasterMargin;
  b->BuildRaster(lo - Vec2(m, m), hi + Vec2(m, m), kRasterCell,
                 std::max(params_.reveal_depth, params_.wall_tolerance) + kNearSlack);
  boundary_ = b;
  const Boundary* bp = b.get();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        labels_[i] =
                            ClassifyWith(params_, roi_, bp, points_[i].cast<double>()).label;
                      }
                    });
  work_labels_.resize(work_points_.size());
  work_face_.resize(work_points_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work_points_.size(), 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        const Classified c =
                            ClassifyWith(params_, roi_, bp, work_points_[i].cast<double>());
                        work_labels_[i] = c.label;
                        work_face_[i] = c.face;
                      }
                    });
}

}  // namespace mopad::modelling
