// Columns (RoomModel::DetectColumns): vertical floor-to-ceiling structures standing free inside
// the perimeter, each a convex plan footprint.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

void RoomModel::DetectColumns() {
  // Vertical structures inside the perimeter that reach from near the floor to just below the
  // ceiling: plan cells with points in the top slice, grouped; a group small enough and seen
  // over most of the height is a column; its footprint is the convex hull of its points.
  roi_.columns.clear();
  if (roi_.perimeter.size() < 3) return;
  Boundary outer;
  outer.AddLoop(roi_.perimeter, false, 0);
  const ColumnSearchParams& C = params_.columns;
  const double c = C.cell;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi_.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const int w = static_cast<int>(std::ceil((hi.x() - lo.x()) / c)) + 1;
  const int h = static_cast<int>(std::ceil((hi.y() - lo.y()) / c)) + 1;
  const int slices = C.slices;
  const double z0 = roi_.floor_z + C.floor_clearance, z1 = roi_.ceiling_z - C.ceiling_clearance;
  const double sh = (z1 - z0) / slices;
  if (sh <= 0) return;
  std::vector<std::uint16_t> mask(static_cast<std::size_t>(w) * h, 0);
  // Cells near the perimeter are wall; skip them (columns touching walls are pilasters, part of
  // the perimeter).
  cv::Mat inside = cv::Mat::zeros(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const Vec2 p = lo + c * Vec2(i + 0.5, j + 0.5);
      if (outer.Signed(p, nullptr, 0, nullptr) < -C.wall_clearance)
        inside.at<std::uint8_t>(j, i) = 1;
    }
  }
  for (const auto& p : work_points_) {
    if (p.z() < z0 || p.z() >= z1) continue;
    const int i = static_cast<int>((p.x() - lo.x()) / c),
              j = static_cast<int>((p.y() - lo.y()) / c);
    if (i < 0 || j < 0 || i >= w || j >= h || !inside.at<std::uint8_t>(j, i)) continue;
    const int s = std::min(slices - 1, static_cast<int>((p.z() - z0) / sh));
    mask[static_cast<std::size_t>(j) * w + i] |= static_cast<std::uint16_t>(1u << s);
  }
  cv::Mat top = cv::Mat::zeros(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      if (mask[static_cast<std::size_t>(j) * w + i] & (1u << (slices - 1)))
        top.at<std::uint8_t>(j, i) = 255;
    }
  }
  cv::dilate(top, top, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::Mat labels, stats, centroids;
  const int ncomp = cv::connectedComponentsWithStats(top, labels, stats, centroids, 8, CV_32S);
  const int max_cells = static_cast<int>(params_.column_max_size / c) + 2;
  for (int k = 1; k < ncomp; ++k) {
    const int bw = stats.at<int>(k, cv::CC_STAT_WIDTH), bh = stats.at<int>(k, cv::CC_STAT_HEIGHT);
    if (bw > max_cells || bh > max_cells) continue;
    const int bx = stats.at<int>(k, cv::CC_STAT_LEFT), by = stats.at<int>(k, cv::CC_STAT_TOP);
    std::uint16_t all = 0;
    for (int j = by; j < by + bh; ++j) {
      for (int i = bx; i < bx + bw; ++i) {
        if (labels.at<int>(j, i) == k) all |= mask[static_cast<std::size_t>(j) * w + i];
      }
    }
    if (__builtin_popcount(all) < params_.column_min_height_share * slices) continue;
    std::vector<cv::Point2f> pts;
    for (const auto& p : work_points_) {
      if (p.z() < z0 || p.z() >= z1) continue;
      const int i = static_cast<int>((p.x() - lo.x()) / c),
                j = static_cast<int>((p.y() - lo.y()) / c);
      if (i < 0 || j < 0 || i >= w || j >= h || labels.at<int>(j, i) != k) continue;
      pts.emplace_back(p.x(), p.y());
    }
    if (pts.size() < static_cast<std::size_t>(C.min_points)) continue;
    std::vector<cv::Point2f> hull, simple;
    cv::convexHull(pts, hull);
    cv::approxPolyDP(hull, simple, C.outline_tolerance, true);
    std::vector<Vec2> fp;
    for (const auto& p : simple) fp.emplace_back(p.x, p.y);
    if (fp.size() < 3 || std::abs(SignedArea(fp)) < C.min_area) continue;
    if (SignedArea(fp) < 0) std::reverse(fp.begin(), fp.end());
    roi_.columns.push_back(fp);
  }
}

}  // namespace mopad::modelling
