// Steps 1-3 of SM5 on one SE (modelling/components.h): its images (the filled depth and colour
// at the local sample spacing, openings removed), the wall's background surface and colour, the
// candidate regions (casings of openings cut off), and the light its colours were measured in.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "common/srgb.h"
#include "modelling/component_features.h"
#include "modelling/components.h"
#include "common/statistics.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {

// CIE Lab of one RGB colour (0-255), as cv::cvtColor converts an image's pixels.
cv::Vec3d LabOf(double r, double g, double b) {
  cv::Mat px(1, 1, CV_32FC3, cv::Scalar(r / 255.0, g / 255.0, b / 255.0));
  cv::cvtColor(px, px, cv::COLOR_RGB2Lab);
  return cv::Vec3d(px.at<cv::Vec3f>(0, 0));
}

// The regions of `mask` (CV_8U) joined by a dilation of `grow` pixels: region i's box (the
// dilation taken off again; empty when the region was thinner than it) at i - 1, and, when
// `labels` is given, the joined mask's label image (0 = none, region i = i).
std::vector<cv::Rect> JoinedRegions(const cv::Mat& mask, int grow, cv::Mat* labels) {
  cv::Mat m;  // a new buffer when dilated: the caller's mask stays as it is
  if (grow > 0)
    cv::dilate(mask, m,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * grow + 1, 2 * grow + 1)));
  else
    m = mask;
  cv::Mat own_labels, stats, centroids;
  cv::Mat& l = labels ? *labels : own_labels;
  const int n = cv::connectedComponentsWithStats(m, l, stats, centroids, 8, CV_32S);
  std::vector<cv::Rect> out;
  for (int i = 1; i < n; ++i)
    out.emplace_back(stats.at<int>(i, cv::CC_STAT_LEFT) + grow,
                     stats.at<int>(i, cv::CC_STAT_TOP) + grow,
                     stats.at<int>(i, cv::CC_STAT_WIDTH) - 2 * grow,
                     stats.at<int>(i, cv::CC_STAT_HEIGHT) - 2 * grow);
  return out;
}

constexpr int kTile = 256;  // pixels, side of the tiles FillSe filters each level over

// The filled images at each pixel's own level (FillSe): the weight, depth and colour blurred at
// the pixel's sigma, and the seen pixels closed.
struct LevelFill {
  cv::Mat w, d, c, closed;  // CV_32F, CV_32F, CV_32FC3, CV_8U
};

// The filling at each pixel's own level: the weight, depth and colour blurred at its sigma and
// the seen pixels closed by about its sample spacing. Each level is filtered over the tiles
// holding its pixels, each tile grown by more than the filters' reach (4 sigma, and twice the
// closing's radius) with nothing beyond it (BORDER_ISOLATED), which at the tile's own pixels
// is the filter of the whole image: an unevenly sampled SE interleaves its levels, and a box
// per level covered most of the image at every level.
// `level`: each pixel's index into `sigmas` (-1: unseen); `tile_levels`: per tile of kTile x
// kTile pixels, tiles_c x tiles_r of them, the levels it holds (bit lv).
LevelFill FillAtOwnLevels(const cv::Mat& w, const cv::Mat& d, const cv::Mat& c,
                          const cv::Mat& seen8, const cv::Mat& level,
                          const std::vector<double>& sigmas,
                          const std::vector<std::uint32_t>& tile_levels, int tiles_c, int tiles_r,
                          const ComponentParams& p) {
  const int rows = w.rows, cols = w.cols;
  const int levels = static_cast<int>(sigmas.size());
  auto sigma_of = [&](int k) { return sigmas[static_cast<std::size_t>(k)]; };
  LevelFill out;
  out.w = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  out.d = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  out.c = cv::Mat(rows, cols, CV_32FC3, cv::Scalar(0, 0, 0));
  out.closed = cv::Mat(rows, cols, CV_8U, cv::Scalar(0));
  cv::Mat &fw = out.w, &fd = out.d, &fc = out.c, &fclosed = out.closed;
  std::vector<std::pair<int, int>> jobs;  // (level, tile)
  for (int lv = 0; lv < levels; ++lv)
    for (int t = 0; t < tiles_c * tiles_r; ++t)
      if (tile_levels[static_cast<std::size_t>(t)] & (1u << lv)) jobs.emplace_back(lv, t);
  // Jobs write disjoint pixels (one level per pixel, one tile per pixel): any thread order.
  tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t j) {
    const auto [lv, t] = jobs[j];
    const double s = sigma_of(lv);
    const int kd =
        std::max(3, 2 * static_cast<int>(std::ceil(0.75 * s / p.fill_spacing_share)) + 1);
    // The closing (a dilation, then an erosion of its result) reads up to 2 (kd / 2) away.
    const int m = std::max(static_cast<int>(std::ceil(4.0 * s)), 2 * (kd / 2)) + 2;
    const cv::Rect core = cv::Rect(t % tiles_c * kTile, t / tiles_c * kTile, kTile, kTile) &
                          cv::Rect(0, 0, cols, rows);
    const cv::Rect b = cv::Rect(core.x - m, core.y - m, core.width + 2 * m, core.height + 2 * m) &
                       cv::Rect(0, 0, cols, rows);
    cv::Mat tw, td, tc, tclosed;
    cv::GaussianBlur(w(b), tw, cv::Size(0, 0), s, s, cv::BORDER_CONSTANT | cv::BORDER_ISOLATED);
    cv::GaussianBlur(d(b), td, cv::Size(0, 0), s, s, cv::BORDER_CONSTANT | cv::BORDER_ISOLATED);
    cv::GaussianBlur(c(b), tc, cv::Size(0, 0), s, s, cv::BORDER_CONSTANT | cv::BORDER_ISOLATED);
    // Gaps narrower than about a sample spacing close; a shadow beside a protrusion stays open.
    cv::morphologyEx(seen8(b), tclosed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kd, kd)),
                     cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    for (int r = core.y; r < core.y + core.height; ++r)
      for (int k = core.x; k < core.x + core.width; ++k) {
        if (level.at<schar>(r, k) != lv) continue;
        const int rr = r - b.y, kk = k - b.x;
        fw.at<float>(r, k) = tw.at<float>(rr, kk);
        fd.at<float>(r, k) = td.at<float>(rr, kk);
        fc.at<cv::Vec3f>(r, k) = tc.at<cv::Vec3f>(rr, kk);
        fclosed.at<uchar>(r, k) = tclosed.at<uchar>(rr, kk);
      }
  });
  return out;
}

// Removes the openings, grown by opening_margin, from the SE's valid pixels and lists them.
void RemoveOpenings(const Orthoimage& im, const std::vector<DetectedOpening>& openings,
                    const ComponentParams& p, SeImages& se) {
  const int rows = im.Rows(), cols = im.Cols();
  for (const DetectedOpening& o : openings) {
    const auto a = im.PixelOf(o.u0 - p.opening_margin, o.v1 + p.opening_margin);
    const auto b = im.PixelOf(o.u1 + p.opening_margin, o.v0 - p.opening_margin);
    const int c0 = std::clamp(a[0], 0, cols), c1 = std::clamp(b[0] + 1, 0, cols);
    const int r0 = std::clamp(a[1], 0, rows), r1 = std::clamp(b[1] + 1, 0, rows);
    if (c1 > c0 && r1 > r0) {
      se.valid(cv::Rect(c0, r0, c1 - c0, r1 - r0)).setTo(0);
      se.openings.emplace_back(c0, r0, c1 - c0, r1 - r0);
    }
  }
}

}  // namespace

void FillSe(const Orthoimage& im, const std::vector<DetectedOpening>& openings,
            const ComponentParams& p, SeImages& se) {
  const int rows = im.Rows(), cols = im.Cols();
  const double pixel = im.Pixel();
  cv::Mat w(rows, cols, CV_32F, cv::Scalar(0)), d(rows, cols, CV_32F, cv::Scalar(0));
  cv::Mat n(rows, cols, CV_32F, cv::Scalar(0));
  cv::Mat c(rows, cols, CV_32FC3, cv::Scalar(0, 0, 0));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      const std::size_t i = im.Index(k, r);
      if (im.Count(i) == 0) continue;
      w.at<float>(r, k) = 1.0f;
      n.at<float>(r, k) = static_cast<float>(im.Count(i));
      d.at<float>(r, k) = im.FrontDepth(i);
      const auto rgb = im.Rgb(i);
      c.at<cv::Vec3f>(r, k) = cv::Vec3f(rgb[0], rgb[1], rgb[2]);
    }
  // Local density over the seen area (seen pixels closed by a 9 x 9 dilation): points per pixel
  // and the share of pixels holding points.
  cv::Mat seen8, area;
  w.convertTo(seen8, CV_8U, 255.0);
  cv::dilate(seen8, area, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(9, 9)));
  area.convertTo(area, CV_32F, 1.0 / 255.0);
  const double sw = p.density_window / pixel;
  cv::Mat area_b, n_b, w_b;
  cv::GaussianBlur(area, area_b, cv::Size(0, 0), sw, sw, cv::BORDER_CONSTANT);
  cv::GaussianBlur(n, n_b, cv::Size(0, 0), sw, sw, cv::BORDER_CONSTANT);
  cv::GaussianBlur(w, w_b, cv::Size(0, 0), sw, sw, cv::BORDER_CONSTANT);
  // Scale of each pixel: index into sigma_0 * sqrt(2)^k (pixels), -1 where nothing is seen.
  const double s0 = p.fill_sigma / pixel, s_max = std::max(s0, p.fill_sigma_max / pixel);
  const int levels = 1 + static_cast<int>(std::ceil(2.0 * std::log2(s_max / s0) - 1e-9));
  std::vector<double> sigmas;
  for (int k = 0; k < levels; ++k)
    sigmas.push_back(std::min(s_max, s0 * std::pow(std::sqrt(2.0), k)));
  auto sigma_of = [&](int k) { return sigmas[static_cast<std::size_t>(k)]; };
  cv::Mat level(rows, cols, CV_8S, cv::Scalar(-1));
  se.blur = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  se.spacing = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  cv::Mat share(rows, cols, CV_32F, cv::Scalar(0));
  // Each pixel's level, and per tile of kTile x kTile pixels the levels it holds (bit lv).
  const int tiles_c = (cols + kTile - 1) / kTile, tiles_r = (rows + kTile - 1) / kTile;
  std::vector<std::uint32_t> tile_levels(static_cast<std::size_t>(tiles_c) * tiles_r, 0);
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      const float a = area_b.at<float>(r, k);
      if (a < 1e-3f) continue;
      const double density = n_b.at<float>(r, k) / a;  // points per pixel
      if (density <= 0.0) continue;
      share.at<float>(r, k) = std::min(1.0f, w_b.at<float>(r, k) / a);
      se.spacing.at<float>(r, k) = static_cast<float>(pixel / std::sqrt(density));
      const double want = p.fill_spacing_share / std::sqrt(density);  // pixels
      int lv = 0;
      while (lv + 1 < levels && sigma_of(lv) < want) ++lv;
      level.at<schar>(r, k) = static_cast<schar>(lv);
      se.blur.at<float>(r, k) = static_cast<float>(sigma_of(lv));
      tile_levels[static_cast<std::size_t>(r / kTile) * tiles_c + k / kTile] |= 1u << lv;
    }
  const LevelFill filled =
      FillAtOwnLevels(w, d, c, seen8, level, sigmas, tile_levels, tiles_c, tiles_r, p);
  const cv::Mat &fw = filled.w, &fd = filled.d, &fc = filled.c, &fclosed = filled.closed;
  se.valid = cv::Mat(rows, cols, CV_8U, cv::Scalar(0));
  se.measured = cv::Mat(rows, cols, CV_8U, cv::Scalar(0));
  se.depth = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  se.rgb = cv::Mat(rows, cols, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      if (level.at<schar>(r, k) < 0) continue;
      const float wk = fw.at<float>(r, k);
      // Weight threshold relative to the weight a uniform sampling of this density gives: holes
      // between scan lines fill, shadows and unseen areas wider than a sample spacing stay
      // unknown.
      if (wk < static_cast<float>(p.fill_min_weight) * share.at<float>(r, k) || wk <= 0.0f ||
          !fclosed.at<uchar>(r, k))
        continue;
      se.valid.at<uchar>(r, k) = 255;
      // A pixel holding points keeps their front depth and mean colour; an empty one takes the
      // filter's estimate.
      const bool own = w.at<float>(r, k) > 0.0f;
      if (own) se.measured.at<uchar>(r, k) = 255;
      const std::size_t i = im.Index(k, r);
      se.depth.at<float>(r, k) = own ? im.FrontDepth(i) : fd.at<float>(r, k) / wk;
      const auto rgb = im.Rgb(i);
      const cv::Vec3f ck = own ? cv::Vec3f(rgb[0], rgb[1], rgb[2]) : fc.at<cv::Vec3f>(r, k) / wk;
      se.rgb.at<cv::Vec3b>(r, k) =
          cv::Vec3b(cv::saturate_cast<uchar>(ck[0]), cv::saturate_cast<uchar>(ck[1]),
                    cv::saturate_cast<uchar>(ck[2]));
    }
  RemoveOpenings(im, openings, p, se);
}

bool TouchesOpening(const SeImages& se, const cv::Rect& r) {
  const cv::Rect grown(r.x - 2, r.y - 2, r.width + 4, r.height + 4);
  for (const cv::Rect& o : se.openings)
    if ((grown & o).area() > 0) return true;
  return false;
}

void CutCasings(const SeImages& se, const ComponentParams& p, double pixel, int grow,
                cv::Mat& mask) {
  const int cut = static_cast<int>(std::lround(p.casing_cut / pixel));
  if (se.openings.empty() || cut <= 0) return;
  cv::Mat labels;
  const std::vector<cv::Rect> boxes = JoinedRegions(mask, grow, &labels);
  const int n = static_cast<int>(boxes.size()) + 1;
  std::vector<char> touches(static_cast<std::size_t>(n), 0);
  bool any = false;
  for (int i = 1; i < n; ++i) {
    const bool t = TouchesOpening(se, boxes[static_cast<std::size_t>(i - 1)]);
    touches[static_cast<std::size_t>(i)] = t;
    any = any || t;
  }
  if (!any) return;
  cv::Mat rest(mask.size(), CV_8U, cv::Scalar(0));  // the touching regions' pixels
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (mask.at<uchar>(r, c) && touches[static_cast<std::size_t>(labels.at<int>(r, c))]) {
        rest.at<uchar>(r, c) = 255;
        mask.at<uchar>(r, c) = 0;
      }
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  cv::Mat in_band(mask.size(), CV_8U, cv::Scalar(0));
  std::vector<cv::Rect> bands;
  for (const cv::Rect& o : se.openings) {
    bands.push_back(cv::Rect(o.x - cut, o.y - cut, o.width + 2 * cut, o.height + 2 * cut) & image);
    in_band(bands.back()).setTo(255);
  }
  // The trim's colour: the mean Lab of what the cut takes from each region.
  std::vector<cv::Vec3d> trim_lab(static_cast<std::size_t>(n), cv::Vec3d(0, 0, 0));
  std::vector<int> trim_count(static_cast<std::size_t>(n), 0);
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (rest.at<uchar>(r, c) && in_band.at<uchar>(r, c)) {
        const auto l = static_cast<std::size_t>(labels.at<int>(r, c));
        trim_lab[l] += cv::Vec3d(se.lab.at<cv::Vec3f>(r, c));
        ++trim_count[l];
        rest.at<uchar>(r, c) = 0;
      }
  // What the cut leaves of the trim is slivers along it (its edge blurred by the filling),
  // which would join a neighbour to the cut again: an opening removes what is thinner than
  // the cut. Where SM4's edge lies farther inside the opening than the margin, wider pieces of
  // the trim are left beside the cut (the casing, the wall in its shadow filled with its
  // colour): a piece touching the cut, or of the colour the cut took, is trim too.
  const int k = 2 * (cut / 2) + 1;
  cv::morphologyEx(rest, rest, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  cv::Mat piece_labels, piece_stats, piece_centroids;
  const int pieces =
      cv::connectedComponentsWithStats(rest, piece_labels, piece_stats, piece_centroids, 8, CV_32S);
  std::vector<cv::Vec3d> piece_lab(static_cast<std::size_t>(pieces), cv::Vec3d(0, 0, 0));
  std::vector<int> piece_count(static_cast<std::size_t>(pieces), 0);
  std::vector<int> origin(static_cast<std::size_t>(pieces), 0);  // the region it was part of
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (const int q = piece_labels.at<int>(r, c); q > 0) {
        piece_lab[static_cast<std::size_t>(q)] += cv::Vec3d(se.lab.at<cv::Vec3f>(r, c));
        ++piece_count[static_cast<std::size_t>(q)];
        origin[static_cast<std::size_t>(q)] = labels.at<int>(r, c);
      }
  std::vector<char> trim(static_cast<std::size_t>(pieces), 0);
  for (int q = 1; q < pieces; ++q) {
    const auto i = static_cast<std::size_t>(q);
    const cv::Rect r(piece_stats.at<int>(q, cv::CC_STAT_LEFT) - 2,
                     piece_stats.at<int>(q, cv::CC_STAT_TOP) - 2,
                     piece_stats.at<int>(q, cv::CC_STAT_WIDTH) + 4,
                     piece_stats.at<int>(q, cv::CC_STAT_HEIGHT) + 4);
    for (const cv::Rect& b : bands) trim[i] |= (r & b).area() > 0;
    const auto o = static_cast<std::size_t>(origin[i]);
    if (trim[i] || trim_count[o] == 0 || piece_count[i] == 0) continue;
    // Of the trim's colour, the wall's, or a mix of the two (the filling blends them):
    // within colour_delta_e of the segment joining them in Lab.
    const cv::Point mid(
        piece_stats.at<int>(q, cv::CC_STAT_LEFT) + piece_stats.at<int>(q, cv::CC_STAT_WIDTH) / 2,
        piece_stats.at<int>(q, cv::CC_STAT_TOP) + piece_stats.at<int>(q, cv::CC_STAT_HEIGHT) / 2);
    const cv::Vec3b w8 = se.wall_rgb.at<cv::Vec3b>(mid);
    const cv::Vec3d x = piece_lab[i] / piece_count[i], t = trim_lab[o] / trim_count[o];
    const cv::Vec3d w = LabOf(w8[0], w8[1], w8[2]);
    const double len2 = (w - t).dot(w - t);
    const double f = len2 > 0.0 ? std::clamp((x - t).dot(w - t) / len2, 0.0, 1.0) : 0.0;
    trim[i] = cv::norm(x - (t + f * (w - t))) <= p.colour_delta_e;
  }
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (rest.at<uchar>(r, c) && !trim[static_cast<std::size_t>(piece_labels.at<int>(r, c))])
        mask.at<uchar>(r, c) = 255;
}

void Background(const ComponentParams& p, double pixel, SeImages& se) {
  const int rows = se.depth.rows, cols = se.depth.cols;
  const int cell = std::max(1, static_cast<int>(std::lround(p.background_cell / pixel)));
  const int gr = (rows + cell - 1) / cell, gc = (cols + cell - 1) / cell;
  cv::Mat bd(gr, gc, CV_32F), bc(gr, gc, CV_32FC3);
  cv::Mat known(gr, gc, CV_8U, cv::Scalar(0));
  std::vector<float> all_d;
  std::array<std::vector<float>, 3> all_c;
  for (int i = 0; i < gr; ++i)
    for (int j = 0; j < gc; ++j) {
      std::vector<float> dv;
      std::array<std::vector<float>, 3> cv3;
      for (int r = i * cell; r < std::min(rows, (i + 1) * cell); ++r)
        for (int k = j * cell; k < std::min(cols, (j + 1) * cell); ++k) {
          const float dk = se.depth.at<float>(r, k);
          if (!se.valid.at<uchar>(r, k) || std::abs(dk) > p.surface_band) continue;
          dv.push_back(dk);
          for (int ch = 0; ch < 3; ++ch) cv3[ch].push_back(se.rgb.at<cv::Vec3b>(r, k)[ch]);
        }
      if (dv.size() < 8) continue;
      all_d.insert(all_d.end(), dv.begin(), dv.end());
      known.at<uchar>(i, j) = 1;
      bd.at<float>(i, j) = UpperMedian(dv);
      for (int ch = 0; ch < 3; ++ch) {
        all_c[ch].insert(all_c[ch].end(), cv3[ch].begin(), cv3[ch].end());
        bc.at<cv::Vec3f>(i, j)[ch] = UpperMedian(cv3[ch]);
      }
    }
  // A cell's median is the wall's only where the wall is most of the cell's surface layer: a
  // flush sign beside a removed door or window can be most of what is left of its cell, and
  // then the whole neighbourhood read the sign's colour as the wall's (the sign and the plain
  // wall around it both lost their contrast). So each cell's colour is taken again from its
  // pixels within colour_delta_e of the median of the known cells around it (3 x 3, per
  // channel: a minority cell does not move it), when at least 8 are; else that median.
  cv::Mat rgb_f;
  se.rgb.convertTo(rgb_f, CV_32FC3, 1.0 / 255.0);
  cv::cvtColor(rgb_f, se.lab, cv::COLOR_RGB2Lab);  // unknown pixels: the wall's, below
  if (gr * gc > 1) {
    cv::Mat refined = bc.clone();
    for (int i = 0; i < gr; ++i)
      for (int j = 0; j < gc; ++j) {
        if (!known.at<uchar>(i, j)) continue;
        std::array<std::vector<float>, 3> around;
        for (int a = std::max(0, i - 1); a <= std::min(gr - 1, i + 1); ++a)
          for (int b = std::max(0, j - 1); b <= std::min(gc - 1, j + 1); ++b)
            if (known.at<uchar>(a, b))
              for (int ch = 0; ch < 3; ++ch) around[ch].push_back(bc.at<cv::Vec3f>(a, b)[ch]);
        cv::Vec3f ref;
        for (int ch = 0; ch < 3; ++ch) ref[ch] = UpperMedian(around[ch]);
        const cv::Vec3f ref_lab(LabOf(ref[0], ref[1], ref[2]));
        std::array<std::vector<float>, 3> agree;
        for (int r = i * cell; r < std::min(rows, (i + 1) * cell); ++r)
          for (int k = j * cell; k < std::min(cols, (j + 1) * cell); ++k) {
            if (!se.valid.at<uchar>(r, k) || std::abs(se.depth.at<float>(r, k)) > p.surface_band)
              continue;
            if (cv::norm(se.lab.at<cv::Vec3f>(r, k) - ref_lab) > p.colour_delta_e) continue;
            for (int ch = 0; ch < 3; ++ch) agree[ch].push_back(se.rgb.at<cv::Vec3b>(r, k)[ch]);
          }
        for (int ch = 0; ch < 3; ++ch)
          refined.at<cv::Vec3f>(i, j)[ch] = agree[ch].size() >= 8 ? UpperMedian(agree[ch]) : ref[ch];
      }
    bc = refined;
  }
  float gd = 0.0f;
  cv::Vec3f gcol(200, 200, 200);
  if (!all_d.empty()) {
    gd = UpperMedian(all_d);
    for (int ch = 0; ch < 3; ++ch) gcol[ch] = UpperMedian(all_c[ch]);
  }
  for (int i = 0; i < gr; ++i)
    for (int j = 0; j < gc; ++j)
      if (!known.at<uchar>(i, j)) bd.at<float>(i, j) = gd, bc.at<cv::Vec3f>(i, j) = gcol;
  cv::Mat bd_full, bc_full;
  cv::resize(bd, bd_full, cv::Size(cols, rows), 0, 0, cv::INTER_LINEAR);
  cv::resize(bc, bc_full, cv::Size(cols, rows), 0, 0, cv::INTER_LINEAR);
  bc_full.convertTo(se.wall_rgb, CV_8UC3);
  se.wall_rgb.copyTo(se.rgb, ~se.valid);  // unknown pixels read as the wall (no contrast)
  cv::Mat wall_f, wall_lab;
  se.wall_rgb.convertTo(wall_f, CV_32FC3, 1.0 / 255.0);
  cv::cvtColor(wall_f, wall_lab, cv::COLOR_RGB2Lab);
  wall_lab.copyTo(se.lab, ~se.valid);
  se.highpass = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  se.delta_e = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      if (!se.valid.at<uchar>(r, k)) continue;
      se.highpass.at<float>(r, k) = se.depth.at<float>(r, k) - bd_full.at<float>(r, k);
      se.delta_e.at<float>(r, k) =
          static_cast<float>(cv::norm(se.lab.at<cv::Vec3f>(r, k) - wall_lab.at<cv::Vec3f>(r, k)));
    }
}

std::vector<cv::Rect> Regions(const cv::Mat& mask, int grow) {
  std::vector<cv::Rect> out = JoinedRegions(mask, grow, nullptr);
  out.erase(std::remove_if(out.begin(), out.end(),
                           [](const cv::Rect& r) { return r.width <= 0 || r.height <= 0; }),
            out.end());
  return out;
}

double SeLight(const SeImages& se, const std::vector<PathDetection>& depth, bool ceiling,
               const interfaces::ObjectModelCatalogue& cat, const ComponentParams& p) {
  if (p.light_min_pixels <= 0) return 1.0;
  std::vector<float> ratios;
  for (const PathDetection& d : depth) {
    const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(d.class_index)];
    if (d.score < p.single_depth_ncc || d.samples < p.min_depth_samples || !FrontFaceModel(m))
      continue;
    const int w = static_cast<int>(std::lround(d.col1 - d.col0));
    const int h = static_cast<int>(std::lround(d.row1 - d.row0));
    const int c0 = static_cast<int>(std::lround(d.col0)),
              r0 = static_cast<int>(std::lround(d.row0));
    if (w < 3 || h < 3) continue;
    cv::Mat model;
    cv::resize(MaybeFlip(ModelColour(m), ceiling), model, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    // Pixels whose 3 x 3 neighbourhood has their colour: no colour edge of the model.
    cv::Mat lo, hi;
    cv::erode(model, lo, cv::Mat());
    cv::dilate(model, hi, cv::Mat());
    const cv::Point mid(std::clamp(c0 + w / 2, 0, se.blur.cols - 1),
                        std::clamp(r0 + h / 2, 0, se.blur.rows - 1));
    const int edge = static_cast<int>(std::ceil(se.blur.at<float>(mid))) + 1;
    for (int r = edge; r < h - edge; ++r)
      for (int c = edge; c < w - edge; ++c) {
        const int rr = r0 + r, cc = c0 + c;
        if (rr < 0 || cc < 0 || rr >= se.rgb.rows || cc >= se.rgb.cols ||
            !se.measured.at<uchar>(rr, cc))
          continue;
        const cv::Vec3b a = lo.at<cv::Vec3b>(r, c), b = hi.at<cv::Vec3b>(r, c);
        if (std::max({b[0] - a[0], b[1] - a[1], b[2] - a[2]}) > 8) continue;
        const cv::Vec3b mc = model.at<cv::Vec3b>(r, c), sc = se.rgb.at<cv::Vec3b>(rr, cc);
        double lm = 0.0, ls = 0.0;
        for (int k = 0; k < 3; ++k)
          lm += SrgbToLinear(mc[k] / 255.0), ls += SrgbToLinear(sc[k] / 255.0);
        if (lm >= 0.3) ratios.push_back(static_cast<float>(ls / lm));
      }
  }
  if (ratios.size() < static_cast<std::size_t>(p.light_min_pixels)) return 1.0;
  return UpperMedian(ratios);
}

}  // namespace mopad::modelling::detail
