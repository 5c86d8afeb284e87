// The room model's scans: AddScan (the full-resolution cloud, every point tagged with its
// azimuth column), the working cloud, and the floor and ceiling heights; the other steps of
// AddScan live in room_outline.cpp, room_perimeter.cpp, room_columns.cpp, room_roi.cpp,
// room_labels.cpp, room_coverage.cpp and room_voxels.cpp.
#include "modelling/room_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

using detail::kGapBit;
using detail::kRayCastBit;

const char* ToString(PointLabel label) {
  switch (label) {
    case PointLabel::kNone:
      return "none";
    case PointLabel::kInlier:
      return "inlier";
    case PointLabel::kOutlier:
      return "outlier";
    case PointLabel::kClutter:
      return "clutter";
  }
  return "?";
}

namespace {

std::int64_t VoxelKey(const Eigen::Vector3f& p, double size) {
  const auto q = [size](float v) {
    return static_cast<std::int64_t>(std::floor(static_cast<double>(v) / size)) + (1 << 20);
  };
  return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
}

}  // namespace

RoomModel::RoomModel(RoomModelParams params)
    : params_(params), colour_reference_(params_.colour_alignment) {
  params_.Validate();
}

LabelCounts RoomModel::CountLabels() const {
  LabelCounts c;
  for (PointLabel l : labels_) {
    switch (l) {
      case PointLabel::kNone:
        ++c.none;
        break;
      case PointLabel::kInlier:
        ++c.inlier;
        break;
      case PointLabel::kOutlier:
        ++c.outlier;
        break;
      case PointLabel::kClutter:
        ++c.clutter;
        break;
    }
  }
  return c;
}

void RoomModel::AddScan(const interfaces::TlsScan& scan, const Pose3& X_MS) {
  const std::string where = "scan " + std::to_string(scan.scan_id);
  if (static_cast<std::size_t>(scan.rows) * scan.columns != scan.points.size()) {
    throw InputError(where, "scan grid and point count disagree",
                     std::to_string(scan.points.size()),
                     std::to_string(scan.rows) + " x " + std::to_string(scan.columns));
  }
  if (!X_MS.matrix().allFinite()) throw InputError(where, "scanner pose is not finite");
  if (scans_.size() >= 65535) throw InputError(where, "too many scans in one room", "", "< 65535");

  ScanRecord rec;
  rec.begin = points_.size();
  rec.origin = X_MS.translation();
  const Eigen::Matrix3f R = X_MS.linear().cast<float>();
  const Eigen::Vector3f T = X_MS.translation().cast<float>();
  const auto scan_no = static_cast<std::uint16_t>(scans_.size());
  // Column by column, top row first: the perimeter trace walks each column in this order.
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    std::int64_t prev_row = -1;
    for (std::uint32_t r = 0; r < scan.rows; ++r) {
      const interfaces::TlsPoint& p = scan.at(r, c);
      if (!p.valid()) continue;
      const Eigen::Vector3f q = R * Eigen::Vector3f(p.x, p.y, p.z) + T;
      if (!q.allFinite()) continue;
      points_.push_back(q);
      colours_.push_back({p.r, p.g, p.b});
      intensity_.push_back(p.intensity);
      scan_index_.push_back(scan_no);
      std::uint32_t tag = c;
      if (r % params_.ray_stride == 0 && c % params_.ray_stride == 0) tag |= kRayCastBit;
      if (static_cast<std::int64_t>(r) - prev_row > params_.outline.gap_rows) tag |= kGapBit;
      column_index_.push_back(tag);
      prev_row = r;
    }
  }
  rec.end = points_.size();
  if (rec.end == rec.begin) throw InputError(where, "scan has no valid return");
  colour_gains_.push_back(colour_reference_.Align(points_, colours_, rec.begin, rec.end));
  rec.columns = scan.columns;
  rec.azimuth_min = scan.azimuth_min;
  rec.azimuth_step = scan.azimuth_step;
  rec.R_MS = X_MS.linear();
  if (!scan.X_BS.isApprox(Eigen::Isometry3d::Identity()))
    rec.base_z = (X_MS * scan.X_BS.inverse()).translation().z();
  rec.min_range = std::numeric_limits<double>::infinity();
  double up_slope = 0.0;
  for (const auto& p : scan.points) {
    if (!p.valid()) continue;
    rec.min_range = std::min(rec.min_range, static_cast<double>(p.range));
    const double h = std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
    if (p.z > 0.0f)
      up_slope = h > 0.0 ? std::max(up_slope, p.z / h) : std::numeric_limits<double>::infinity();
  }
  rec.max_up_slope = up_slope > 0.0 ? up_slope : std::numeric_limits<double>::infinity();
  labels_.resize(points_.size(), PointLabel::kNone);
  scans_.push_back(rec);
  scan_poses_.push_back(X_MS);
  scan_steps_.push_back(std::max(scan.azimuth_step, scan.elevation_step));

  UpdateWorkingCloud(rec.begin, rec.end);
  if (!structure_frozen_) {
    const double old_ceiling = roi_.ceiling_z;
    EstimateHeights();
    const bool slopes_moved = DetectSlopes();
    const bool retrace = scans_.size() == 1 || slopes_moved ||
                         std::abs(roi_.ceiling_z - old_ceiling) > params_.outline.retrace_change;
    for (std::size_t s = retrace ? 0 : scans_.size() - 1; s < scans_.size(); ++s) {
      TraceOutline(scans_[s]);
    }
    BuildPerimeter();
    DetectColumns();
    BuildRoi();
  }
  LabelAll();
  UpdateFaces();
  UpdateVoxels(true);
  UpdateCoverage();
}

void RoomModel::UpdateWorkingCloud(std::size_t begin, std::size_t end) {
  const double v = params_.working_voxel;
  for (std::size_t i = begin; i < end; ++i) {
    const std::int64_t key = VoxelKey(points_[i], v);
    auto [it, inserted] = work_slot_.try_emplace(key, static_cast<std::uint32_t>(work_sum_.size()));
    if (inserted) {
      work_sum_.push_back(Vec3::Zero());
      work_count_.push_back(0);
    }
    work_sum_[it->second] += points_[i].cast<double>();
    ++work_count_[it->second];
  }
  work_points_.resize(work_sum_.size());
  for (std::size_t k = 0; k < work_sum_.size(); ++k) {
    work_points_[k] = (work_sum_[k] / work_count_[k]).cast<float>();
  }
}

void RoomModel::EstimateHeights() {
  // Z-histogram of the working cloud (area-like weights: one count per working voxel). Floor:
  // the lowest strong peak below the scanners; ceiling: the highest strong peak above them
  // that is over them (heights.ceiling_over_scanner).
  double zs = 0.0;
  for (const auto& s : scans_) zs += s.origin.z();
  zs /= static_cast<double>(scans_.size());
  const HeightSearchParams& H = params_.heights;
  const double bin = params_.histogram_bin;
  const double lo = zs - H.search_range, hi = zs + H.search_range;
  const int n = static_cast<int>((hi - lo) / bin);
  std::vector<double> hist(n, 0.0);
  for (const auto& p : work_points_) {
    const int b = static_cast<int>(std::floor((p.z() - lo) / bin));
    if (b >= 0 && b < n) hist[b] += 1.0;
  }
  std::vector<double> sm(n, 0.0);
  for (int b = 1; b + 1 < n; ++b) sm[b] = 0.25 * hist[b - 1] + 0.5 * hist[b] + 0.25 * hist[b + 1];
  const int mid = static_cast<int>((zs - lo) / bin);
  const int guard = static_cast<int>(H.scanner_guard / bin);
  auto pick = [&](int b0, int b1, bool lowest) {
    double m = 0.0;
    for (int b = b0; b < b1; ++b) m = std::max(m, sm[b]);
    if (m <= 0.0) return -1;
    // Strong local maxima (at least peak_share of the highest); the extreme one wins.
    int best = -1;
    for (int b = std::max(b0, 1); b < std::min(b1, n - 1); ++b) {
      if (sm[b] >= H.peak_share * m && sm[b] >= sm[b - 1] && sm[b] >= sm[b + 1]) {
        if (best < 0 || !lowest) best = b;
        if (lowest) break;
      }
    }
    return best;
  };
  int bf = pick(0, std::max(1, mid - guard), true);
  // The floor the robot stands on, where the scans carry their mount: the lowest strong peak
  // when it lies within floor_from_base of it, else the strong peak nearest it within that,
  // else that floor itself (below).
  double base_z = 0.0;
  int with_base = 0;
  for (const auto& s : scans_)
    if (std::isfinite(s.base_z)) base_z += s.base_z, ++with_base;
  const bool floor_known = with_base > 0 && H.floor_from_base > 0.0;
  bool floor_unseen = false;
  if (floor_known) base_z /= with_base;
  if (floor_known && (bf < 0 || std::abs(lo + (bf + 0.5) * bin - base_z) > H.floor_from_base)) {
    const int b1 = std::max(1, mid - guard);
    double m = 0.0;
    for (int b = 0; b < b1; ++b) m = std::max(m, sm[b]);
    int near = -1;
    double near_d = H.floor_from_base;
    for (int b = 1; b < std::min(b1, n - 1); ++b) {
      const double d = std::abs(lo + (b + 0.5) * bin - base_z);
      if (m > 0.0 && sm[b] >= H.peak_share * m && sm[b] >= sm[b - 1] && sm[b] >= sm[b + 1] &&
          d <= near_d) {
        near = b;
        near_d = d;
      }
    }
    bf = near;
    floor_unseen = near < 0;
  }
  int bc = pick(std::min(n - 1, mid + guard), n, false);
  // The highest strong peak is the ceiling unless it is not over the scanners (another room's,
  // seen through a door): then the highest strong peak that is. Over a scanner: its points
  // within reach of the scanner's blind disc lie in at least ceiling_sectors of the eight
  // azimuth sectors around it (the next room's ceiling seen through a door beside the scanner
  // is also within reach, but in the one or two sectors the door spans).
  const auto over_scanner = [&](int b) {
    const double c = lo + (b + 0.5) * bin;
    constexpr double kSector = 2.0 * kPi / 8.0;
    for (const auto& s : scans_) {
      const double dz = c - s.origin.z();
      const double rmin = std::isfinite(s.min_range) ? s.min_range : 0.0;
      const double blind = std::max(std::sqrt(std::max(0.0, rmin * rmin - dz * dz)),
                                    dz > 0.0 ? dz / s.max_up_slope : 0.0);
      const double reach = blind + H.ceiling_over_scanner;
      unsigned sectors = 0;
      for (const auto& p : work_points_) {
        if (std::abs(p.z() - c) > H.refine_bins * bin) continue;
        const double dx = p.x() - s.origin.x(), dy = p.y() - s.origin.y();
        if (dx * dx + dy * dy > reach * reach) continue;
        const int k = static_cast<int>(std::floor((std::atan2(dy, dx) + kPi) / kSector));
        const unsigned bit = 1u << std::clamp(k, 0, 7);
        if ((sectors & bit) == 0 && std::popcount(sectors |= bit) >= H.ceiling_sectors) return true;
      }
    }
    return false;
  };
  if (bc >= 0 && !over_scanner(bc)) {
    const int b0 = std::min(n - 1, mid + guard);
    double m = 0.0;
    for (int b = b0; b < n; ++b) m = std::max(m, sm[b]);
    for (int b = bc - 1; b >= std::max(b0, 1); --b) {
      if (b + 1 < n && sm[b] >= H.peak_share * m && sm[b] >= sm[b - 1] && sm[b] >= sm[b + 1] &&
          over_scanner(b)) {
        bc = b;
        break;
      }
    }
  }
  auto refine = [&](int b) {
    const double c = lo + (b + 0.5) * bin;
    double sum = 0.0, cnt = 0.0;
    for (const auto& p : work_points_) {
      if (std::abs(p.z() - c) <= H.refine_bins * bin) {
        sum += p.z();
        cnt += 1.0;
      }
    }
    return cnt > 0 ? sum / cnt : c;
  };
  roi_.floor_z = bf >= 0 ? refine(bf) : floor_unseen ? base_z : zs - H.fallback_offset;
  roi_.ceiling_z = bc >= 0 ? refine(bc) : zs + H.fallback_offset;
}

}  // namespace mopad::modelling
