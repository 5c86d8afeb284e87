#include "modelling/components.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "common/error.h"
#include "common/srgb.h"
#include "modelling/component_features.h"
#include "modelling/sample_fit.h"

namespace mopad::modelling {
namespace {

// The SE images of steps 1-3, all rows x cols of the orthoimage.
struct SeImages {
  cv::Mat valid;     // CV_8U, 255 = known and outside the openings
  cv::Mat depth;     // CV_32F, m, filled J^_D
  cv::Mat rgb;       // CV_8UC3, filled J^_C (RGB)
  cv::Mat lab;       // CV_32FC3, J^_C in CIE Lab
  cv::Mat highpass;  // CV_32F, m, depth minus its wall background (0 where not valid)
  cv::Mat wall_rgb;  // CV_8UC3, local wall colour
  cv::Mat delta_e;   // CV_32F, Lab distance to the local wall colour (0 where not valid)
  cv::Mat blur;      // CV_32F, pixels, sigma of the filling at each pixel (0 where unseen)
  cv::Mat spacing;   // CV_32F, m, local sample spacing (pixel / sqrt(points per pixel); 0 unseen)
  cv::Mat measured;  // CV_8U, 255 = the pixel holds points (not filled)
  std::vector<cv::Rect> openings;  // the removed openings (grown by opening_margin), pixels
};

float Median(std::vector<float>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Step 1: normalised convolution of the imaged pixels, openings removed, at the LOCAL sample
// spacing. One SE is sampled very unevenly (a wall 1 m from a scan and 8 m from it, the band
// near the floor at grazing incidence): a filter sized by the SE's typical spacing leaves the
// sparse parts full of holes, which splits a component into fragments. So the spacing is
// measured per pixel (points per pixel over the seen area in a Gaussian window of
// `density_window`), each pixel is filled at the smallest of a ladder of sigmas (ratio sqrt 2)
// reaching fill_spacing_share of its spacing, and its weight is compared with the local share
// of pixels holding points (the weight a uniform sampling gives there).
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
  constexpr int kTile = 256;
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
  // The filling at each pixel's own level: the weight, depth and colour blurred at its sigma and
  // the seen pixels closed by about its sample spacing. Each level is filtered over the tiles
  // holding its pixels, each tile grown by more than the filters' reach (4 sigma, and twice the
  // closing's radius) with nothing beyond it (BORDER_ISOLATED), which at the tile's own pixels
  // is the filter of the whole image: an unevenly sampled SE interleaves its levels, and a box
  // per level covered most of the image at every level.
  cv::Mat fw(rows, cols, CV_32F, cv::Scalar(0)), fd(rows, cols, CV_32F, cv::Scalar(0));
  cv::Mat fc(rows, cols, CV_32FC3, cv::Scalar(0, 0, 0)), fclosed(rows, cols, CV_8U, cv::Scalar(0));
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

// A candidate region that touches a removed opening (within 2 pixels) is the rest of the
// opening's casing or trim beyond the removal margin (a door casing is often wider than the
// margin, and SM4's edges are known to a centimetre or two), not a component on the wall.
bool TouchesOpening(const SeImages& se, const cv::Rect& r) {
  const cv::Rect grown(r.x - 2, r.y - 2, r.width + 4, r.height + 4);
  for (const cv::Rect& o : se.openings)
    if ((grown & o).area() > 0) return true;
  return false;
}

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

// The casing is cut off, not the region with it: in a candidate mask (connected after a
// dilation of `grow` pixels, as Regions joins it), a region touching a removed opening loses
// its pixels within casing_cut of that opening, and what stays apart from it (a sign or a
// switch beside a door, joined to the casing by the scan's blur) is a candidate of its own.
// Regions that touch no opening are left as they are.
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
  const int pieces = cv::connectedComponentsWithStats(rest, piece_labels, piece_stats,
                                                      piece_centroids, 8, CV_32S);
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
    const cv::Point mid(piece_stats.at<int>(q, cv::CC_STAT_LEFT) +
                            piece_stats.at<int>(q, cv::CC_STAT_WIDTH) / 2,
                        piece_stats.at<int>(q, cv::CC_STAT_TOP) +
                            piece_stats.at<int>(q, cv::CC_STAT_HEIGHT) / 2);
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

// Steps 2-3: the low-frequency wall surface (depth and colour medians of the surface layer per
// background cell, bilinear), the depth high-pass and the colour distance.
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
      bd.at<float>(i, j) = Median(dv);
      for (int ch = 0; ch < 3; ++ch) {
        all_c[ch].insert(all_c[ch].end(), cv3[ch].begin(), cv3[ch].end());
        bc.at<cv::Vec3f>(i, j)[ch] = Median(cv3[ch]);
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
        for (int ch = 0; ch < 3; ++ch) ref[ch] = Median(around[ch]);
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
          refined.at<cv::Vec3f>(i, j)[ch] = agree[ch].size() >= 8 ? Median(agree[ch]) : ref[ch];
      }
    bc = refined;
  }
  float gd = 0.0f;
  cv::Vec3f gcol(200, 200, 200);
  if (!all_d.empty()) {
    gd = Median(all_d);
    for (int ch = 0; ch < 3; ++ch) gcol[ch] = Median(all_c[ch]);
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

// Candidate boxes: connected components of `mask` (CV_8U), as [c0, r0, c1, r1) pixel boxes.
std::vector<cv::Rect> Regions(const cv::Mat& mask, int grow) {
  std::vector<cv::Rect> out = JoinedRegions(mask, grow, nullptr);
  out.erase(std::remove_if(out.begin(), out.end(),
                           [](const cv::Rect& r) { return r.width <= 0 || r.height <= 0; }),
            out.end());
  return out;
}

bool MountsOn(const interfaces::ObjectModel& m, bool ceiling) {
  return ceiling ? m.mounting == interfaces::Mounting::kCeiling
                 : m.mounting == interfaces::Mounting::kWall;
}

// The class's box can be the candidate: extent within tolerance (colour blobs may be smaller:
// a part of the model differs from the wall), plus `spread` metres on each side.
bool SizeFits(const cv::Rect& r, double pixel, const interfaces::ObjectModel& m,
              const ComponentParams& p, double min_share, double spread = 0.0) {
  const double w = r.width * pixel, h = r.height * pixel;
  auto fits = [&](double x, double size) {
    return x <= size * (1.0 + p.size_tolerance) + p.size_slack + 2.0 * spread &&
           x >= std::max(0.0, min_share * size - p.size_slack);
  };
  return fits(w, m.width) && fits(h, m.height);
}

// A template match: its score and the template's centre in unpadded pixel coordinates.
struct Peak {
  double score = -2.0;
  double col = 0.0, row = 0.0;
};
// The best entry of a matchTemplate result over the window `win` (padded coordinates), with
// its sub-pixel position (a parabola through the maximum and its two neighbours, per axis,
// where they are scored) as the template's centre in unpadded pixel coordinates.
Peak PeakOf(const cv::Mat& res, const cv::Rect& win, const cv::Mat& templ, int pad) {
  Peak peak;
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(res, nullptr, &best, nullptr, &at);
  if (!std::isfinite(best) || best < -1.5) return peak;
  peak.score = best;
  auto vertex = [](float l, float c, float r) {
    const double den = l - 2.0 * c + r;
    return l > -1.5f && r > -1.5f && den < -1e-9 ? std::clamp(0.5 * (l - r) / den, -0.5, 0.5)
                                                  : 0.0;
  };
  double dx = 0.0, dy = 0.0;
  if (at.x > 0 && at.x + 1 < res.cols)
    dx = vertex(res.at<float>(at.y, at.x - 1), res.at<float>(at.y, at.x),
                res.at<float>(at.y, at.x + 1));
  if (at.y > 0 && at.y + 1 < res.rows)
    dy = vertex(res.at<float>(at.y - 1, at.x), res.at<float>(at.y, at.x),
                res.at<float>(at.y + 1, at.x));
  peak.col = win.x + at.x + dx + 0.5 * templ.cols - pad;
  peak.row = win.y + at.y + dy + 0.5 * templ.rows - pad;
  return peak;
}

// NCC of `templ` over the window around `r` in `image` (both padded by `pad` pixels of
// `image_padded`): best score and the template's centre in unpadded pixel coordinates.
Peak MatchAround(const cv::Mat& image_padded, int pad, const cv::Mat& templ, const cv::Rect& r,
                 int margin) {
  const int wx = std::max(0, (templ.cols - r.width) / 2) + margin;
  const int wy = std::max(0, (templ.rows - r.height) / 2) + margin;
  cv::Rect win(r.x + pad - wx, r.y + pad - wy, r.width + 2 * wx, r.height + 2 * wy);
  win &= cv::Rect(0, 0, image_padded.cols, image_padded.rows);
  Peak peak;
  if (win.width < templ.cols || win.height < templ.rows) return peak;
  cv::Mat res;
  cv::matchTemplate(image_padded(win), templ, res, cv::TM_CCOEFF_NORMED);
  return PeakOf(res, win, templ, pad);
}

// NCC of `templ` over the KNOWN pixels only (`known_padded` nonzero), with the template centred
// at every place in `centres` (unpadded pixels: the template's centre pixel ranges over it);
// places where less than `min_known` of the template is known score -2. From six plain
// correlations: with M the mask, I the image and T the template, the sums over the known
// pixels n = M*1, sI = MI*1, sII = MI^2*1, sT = M*T, sTT = M*T^2, sIT = MI*T give
// (sIT - sI sT / n) / sqrt((sII - sI^2 / n)(sTT - sT^2 / n)).
Peak MaskedMatch(const cv::Mat& image_padded, const cv::Mat& known_padded, int pad,
                 const cv::Mat& templ, const cv::Rect& centres, double min_known) {
  cv::Rect win(centres.x + pad - templ.cols / 2, centres.y + pad - templ.rows / 2,
               centres.width + templ.cols - 1, centres.height + templ.rows - 1);
  win &= cv::Rect(0, 0, image_padded.cols, image_padded.rows);
  if (win.width < templ.cols || win.height < templ.rows) return Peak{};
  // Centimetres: the sums of squares keep their precision in float.
  cv::Mat m, mi, mii, t, tt;
  known_padded(win).convertTo(m, CV_32F, 1.0 / 255.0);
  image_padded(win).convertTo(mi, CV_32F, 100.0);
  mi = mi.mul(m);
  mii = mi.mul(mi);
  templ.convertTo(t, CV_32F, 100.0);
  tt = t.mul(t);
  const cv::Mat ones = cv::Mat::ones(templ.size(), CV_32F);
  cv::Mat n, si, sii, st, stt, sit;
  cv::matchTemplate(m, ones, n, cv::TM_CCORR);
  cv::matchTemplate(mi, ones, si, cv::TM_CCORR);
  cv::matchTemplate(mii, ones, sii, cv::TM_CCORR);
  cv::matchTemplate(m, t, st, cv::TM_CCORR);
  cv::matchTemplate(m, tt, stt, cv::TM_CCORR);
  cv::matchTemplate(mi, t, sit, cv::TM_CCORR);
  cv::Mat res(n.size(), CV_32F, cv::Scalar(-2.0f));
  const double need = std::max(1.0, min_known * templ.total());
  for (int r = 0; r < res.rows; ++r)
    for (int c = 0; c < res.cols; ++c) {
      const double k = std::round(n.at<float>(r, c));
      if (k < need) continue;
      const double vi = sii.at<float>(r, c) - si.at<float>(r, c) * si.at<float>(r, c) / k;
      const double vt = stt.at<float>(r, c) - st.at<float>(r, c) * st.at<float>(r, c) / k;
      if (vi <= 1e-6 * k || vt <= 1e-6 * k) continue;
      const double cov = sit.at<float>(r, c) - si.at<float>(r, c) * st.at<float>(r, c) / k;
      res.at<float>(r, c) = static_cast<float>(std::clamp(cov / std::sqrt(vi * vt), -1.0, 1.0));
    }
  return PeakOf(res, win, templ, pad);
}

PathDetection BoxAt(int k, const interfaces::ObjectModel& m, double pixel, const Peak& pk) {
  PathDetection d;
  d.class_index = k;
  d.col0 = pk.col - 0.5 * m.width / pixel;
  d.col1 = pk.col + 0.5 * m.width / pixel;
  d.row0 = pk.row - 0.5 * m.height / pixel;
  d.row1 = pk.row + 0.5 * m.height / pixel;
  d.score = pk.score;
  return d;
}

double OverlapOfSmaller(const PathDetection& a, const PathDetection& b) {
  const double w = std::min(a.col1, b.col1) - std::max(a.col0, b.col0);
  const double h = std::min(a.row1, b.row1) - std::max(a.row0, b.row0);
  if (w <= 0 || h <= 0) return 0.0;
  const double aa = (a.col1 - a.col0) * (a.row1 - a.row0);
  const double ab = (b.col1 - b.col0) * (b.row1 - b.row0);
  return w * h / std::max(1e-12, std::min(aa, ab));
}

// Keeps the best of same-class detections that overlap by more than half (several candidate
// regions of one object reach the same peak).
void Dedupe(std::vector<PathDetection>& d) {
  std::stable_sort(d.begin(), d.end(), [](const PathDetection& a, const PathDetection& b) {
    return a.score > b.score;
  });
  std::vector<PathDetection> kept;
  for (const PathDetection& x : d) {
    bool dup = false;
    for (const PathDetection& y : kept)
      dup = dup || (x.class_index == y.class_index && OverlapOfSmaller(x, y) > 0.5);
    if (!dup) kept.push_back(x);
  }
  d = std::move(kept);
}

cv::Mat MaybeFlip(cv::Mat m, bool ceiling) {
  if (ceiling) cv::flip(m, m, 0);
  return m;
}

}  // namespace

namespace {

// A detection's box in whole pixels, clipped to the SE image.
cv::Rect BoxRect(const SeImages& se, const PathDetection& d) {
  return cv::Rect(static_cast<int>(std::floor(d.col0)), static_cast<int>(std::floor(d.row0)),
                  static_cast<int>(std::ceil(d.col1 - d.col0)),
                  static_cast<int>(std::ceil(d.row1 - d.row0))) &
         cv::Rect(0, 0, se.highpass.cols, se.highpass.rows);
}

// Measured protrusion of a box: the `quantile` of the high-pass depth over its known pixels (m);
// NaN when less than 30 % of the box is known.
double BoxProtrusion(const SeImages& se, const PathDetection& d, double quantile = 0.95) {
  const cv::Rect box = BoxRect(se, d);
  std::vector<float> h;
  for (int r = box.y; r < box.y + box.height; ++r)
    for (int c = box.x; c < box.x + box.width; ++c)
      if (se.valid.at<uchar>(r, c)) h.push_back(se.highpass.at<float>(r, c));
  if (h.empty() || h.size() < 0.3 * std::max(1, box.area()))
    return std::numeric_limits<double>::quiet_NaN();
  const auto q =
      h.begin() + static_cast<std::ptrdiff_t>(quantile * static_cast<double>(h.size() - 1));
  std::nth_element(h.begin(), q, h.end());
  return *q;
}

// Measured samples (pixels holding points, not filled) in `box` (within the image)
// protruding more than protrusion_min.
int ProtrudingSamplesIn(const SeImages& se, const cv::Rect& box, const ComponentParams& p) {
  int n = 0;
  for (int r = box.y; r < box.y + box.height; ++r)
    for (int c = box.x; c < box.x + box.width; ++c)
      n += se.measured.at<uchar>(r, c) && se.highpass.at<float>(r, c) > p.protrusion_min;
  return n;
}

// The same in a detection's box.
int ProtrudingSamples(const SeImages& se, const PathDetection& d, const ComponentParams& p) {
  return ProtrudingSamplesIn(se, BoxRect(se, d), p);
}

// The measured protrusion inside a box agrees with the class (ComponentParams::
// depth_consistency); true when too little of the box is known to tell.
bool DepthAgrees(const SeImages& se, const PathDetection& d, const interfaces::ObjectModel& m,
                 const ComponentParams& p) {
  // A protruding class: its top (95th percentile) stands out, even when it covers part of the
  // box, and not by much more than the class's depth (a chair's back or a sill is no switch):
  // within a factor 1 / depth_consistency either way. A flush class: most of the box (the
  // median) lies on the wall, neither proud of it nor behind it (a window's reveal or a recess
  // seen past a removed opening's margin); a top percentile would read the range noise of a
  // grazing view, or a neighbour's edge, as a protrusion.
  const double flush = 2.0 * p.protrusion_min;
  if (m.depth >= flush) {
    const double top = BoxProtrusion(se, d, 0.95);
    return !std::isfinite(top) ||
           (top >= p.depth_consistency * m.depth && top * p.depth_consistency <= m.depth);
  }
  const double mid = BoxProtrusion(se, d, 0.5);
  return !std::isfinite(mid) || std::abs(mid) < flush;
}

// Support from the geometry for a colour-only instance (step 4) of a protruding class: the
// measured samples of the box protruding more than protrusion_min, when the box's protrusion
// is known (DepthAgrees has checked it against the class's depth), is the object's own, not
// part of a larger one (a radiator, a box it is painted on: under a fifth of the measured ring
// of template_pad around the box protrudes; the ring begins two filling sigmas out, past the
// spread of the object's own edges, which reach 2 sigma for a 19 cm deep extinguisher), and
// at least half of the box differs from the wall's colour (colour_delta_e: the object's colour
// is evidence, not only its pattern); else 0.
int SupportingSamples(const SeImages& se, const PathDetection& d, const interfaces::ObjectModel& m,
                      double pixel, const ComponentParams& p) {
  if (m.depth < 2.0 * p.protrusion_min || !std::isfinite(BoxProtrusion(se, d, 0.95))) return 0;
  const cv::Rect in = BoxRect(se, d);
  const int e = static_cast<int>(
      std::ceil(2.0 * se.blur.at<float>(in.y + in.height / 2, in.x + in.width / 2)));
  const cv::Rect spread(in.x - e, in.y - e, in.width + 2 * e, in.height + 2 * e);
  const int g = std::max(1, static_cast<int>(std::lround(p.template_pad / pixel))) + e;
  const cv::Rect out = cv::Rect(in.x - g, in.y - g, in.width + 2 * g, in.height + 2 * g) &
                       cv::Rect(0, 0, se.valid.cols, se.valid.rows);
  int ring = 0, proud = 0, known = 0, coloured = 0, samples = 0;
  for (int r = out.y; r < out.y + out.height; ++r)
    for (int c = out.x; c < out.x + out.width; ++c) {
      const bool measured = se.measured.at<uchar>(r, c) != 0;
      const bool protrudes = se.highpass.at<float>(r, c) > p.protrusion_min;
      if (in.contains({c, r})) {
        samples += measured && protrudes;
        if (!se.valid.at<uchar>(r, c)) continue;
        ++known;
        coloured += se.delta_e.at<float>(r, c) > p.colour_delta_e;
      } else if (measured && !spread.contains({c, r})) {
        ++ring;
        proud += protrudes;
      }
    }
  return ring > 0 && proud < 0.2 * ring && coloured >= 0.5 * known ? samples : 0;
}

// Two classes of one outline family, the second a longer version of the first (a four-gang
// socket of a single one): the same depth (within 25 %) and one side (within 10 %), the other
// side at least 1.3 times as long.
bool Extends(const interfaces::ObjectModel& longer, const interfaces::ObjectModel& m) {
  auto same = [](double a, double b, double tol) { return std::abs(a - b) <= tol * b; };
  return longer.mounting == m.mounting && same(longer.depth, m.depth, 0.25) &&
         ((same(longer.height, m.height, 0.1) && longer.width >= 1.3 * m.width) ||
          (same(longer.width, m.width, 0.1) && longer.height >= 1.3 * m.height));
}

// A depth detection cut short by a hidden part (furniture before the wall): where the measured
// protrusion goes on past the detection's box (beyond the filling's blur) and a longer class
// of its family, placed over the box, matches the KNOWN pixels (MaskedMatch, at least
// masked_known_min of its template known) at least as well as the detection's own class does
// there, the detection becomes the longer class (the best such). The unknown part neither
// refutes nor supports the longer class; the protrusion past the box refutes the shorter one.
// A single socket in its own shadow has no protrusion past its box and stays as it is. The
// evidence (score) stays at most the detection's own: a match that ignores the unknown part
// must not outrank, across classes, one that had to explain it.
void ExtendTruncated(const SeImages& se, const cv::Mat& hp_padded, const cv::Mat& known_padded,
                     int pad, double pixel, const interfaces::ObjectModelCatalogue& cat,
                     const ComponentParams& p, const std::function<const cv::Mat&(int)>& templ,
                     PathDetection& d) {
  const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(d.class_index)];
  std::vector<int> longer;
  for (int k = 0; k < static_cast<int>(cat.models.size()); ++k)
    if (Extends(cat.models[static_cast<std::size_t>(k)], m)) longer.push_back(k);
  const cv::Rect own = BoxRect(se, d);
  if (longer.empty() || own.area() <= 0) return;
  const cv::Point mid(own.x + own.width / 2, own.y + own.height / 2);
  const Peak self = MaskedMatch(hp_padded, known_padded, pad, templ(d.class_index),
                                cv::Rect(mid.x, mid.y, 1, 1), p.masked_known_min);
  // Past the box: outside it grown by the filling's blur there (an edge's spread) + 1 pixel.
  const int blur = static_cast<int>(std::ceil(se.blur.at<float>(mid.y, mid.x))) + 1;
  const cv::Rect near(own.x - blur, own.y - blur, own.width + 2 * blur, own.height + 2 * blur);
  const int margin = static_cast<int>(std::ceil(p.search_margin / pixel));
  PathDetection best = d;
  double best_ncc = self.score;
  for (const int k : longer) {
    const interfaces::ObjectModel& l = cat.models[static_cast<std::size_t>(k)];
    // Centres of the longer box that keep the detection's box inside it (and the margin).
    const int ex = static_cast<int>(std::ceil(0.5 * (l.width - m.width) / pixel)) + margin;
    const int ey = static_cast<int>(std::ceil(0.5 * (l.height - m.height) / pixel)) + margin;
    const Peak pk = MaskedMatch(hp_padded, known_padded, pad, templ(k),
                                cv::Rect(mid.x - ex, mid.y - ey, 2 * ex + 1, 2 * ey + 1),
                                p.masked_known_min);
    if (pk.score < std::max(p.depth_ncc_min, best_ncc)) continue;
    const PathDetection e = BoxAt(k, l, pixel, pk);
    if (OverlapOfSmaller(d, e) <= p.max_class_overlap) continue;  // not the same object
    const cv::Rect box = BoxRect(se, e);
    const int past = ProtrudingSamplesIn(se, box, p) - ProtrudingSamplesIn(se, box & near, p);
    if (past < p.extend_samples) continue;
    best = e, best_ncc = pk.score;
  }
  if (best.class_index == d.class_index) return;
  const interfaces::ObjectModel& l = cat.models[static_cast<std::size_t>(best.class_index)];
  best.ncc = best_ncc;
  const double top = BoxProtrusion(se, best);
  const double agree =
      std::isfinite(top) && top > 0.0 ? std::min(top, l.depth) / std::max(top, l.depth) : 0.5;
  best.score = std::min(d.score, best_ncc * agree);
  best.samples = ProtrudingSamples(se, best, p);
  d = best;
}

// The class's depth model (a height map of its front face) is what an oblique scan sees of
// it: it stands off the wall less than it is wide and tall. An object deeper than that (a
// fire extinguisher) is seen mostly by its sides, whose front-most points fall across and
// beyond its outline.
bool FrontFaceModel(const interfaces::ObjectModel& m) {
  return m.depth < std::min(m.width, m.height);
}

// A depth detection's place: the peak of its class's NCC over the known pixels only
// (MaskedMatch, at least masked_known_min of the template known) within search_margin of where
// the plain NCC put it. The plain NCC reads what no scan saw (a shadow, a part hidden by
// furniture) as wall and pulls the template away from it; the known pixels alone do not. The
// score stays the plain NCC's: the place changes, not the evidence. Only for classes whose
// depth model is a front face (FrontFaceModel): the known pixels of a deeper object's sides
// misled as much as the unknown ones (two extinguishers on random floors 6 and 10 moved from
// 3.5-3.9 cm off to over 5 cm).
void PlaceByKnownPixels(const cv::Mat& hp_padded, const cv::Mat& known_padded, int pad,
                        double pixel, const ComponentParams& p, const cv::Mat& templ,
                        PathDetection& d) {
  const double col = 0.5 * (d.col0 + d.col1), row = 0.5 * (d.row0 + d.row1);
  const int r = static_cast<int>(std::ceil(p.search_margin / pixel));
  const int c0 = static_cast<int>(std::floor(col)), r0 = static_cast<int>(std::floor(row));
  const Peak pk = MaskedMatch(hp_padded, known_padded, pad, templ,
                              cv::Rect(c0 - r, r0 - r, 2 * r + 1, 2 * r + 1), p.masked_known_min);
  if (pk.score < -1.0) return;
  const double dc = pk.col - col, dr = pk.row - row;
  d.col0 += dc, d.col1 += dc, d.row0 += dr, d.row1 += dr;
}

// An unknown area whose rim is protruding pixels alone (no wall pixel on it, not at the image
// border, not in a removed opening) lies inside an object: samples too sparse there for the filling
// (the gaps between a radiator's fins, seen from close by at a slant, hold a point in several
// centimetres while its fins' sides hold many), wider than gap_close. It takes the mean protrusion
// of its rim and counts as known. Read as wall it perforated the object, and the NCC fell below its
// floor.
void FillEnclosedHoles(const std::vector<cv::Rect>& openings, double protrusion_min, cv::Mat& hp,
                       cv::Mat& known) {
  cv::Mat labels;
  const int n = cv::connectedComponents(~known, labels, 8, CV_32S);
  if (n <= 1) return;
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  std::vector<int> count(static_cast<std::size_t>(n), 0);
  std::vector<char> open(static_cast<std::size_t>(n), 0);
  for (const cv::Rect& o : openings) {
    const cv::Rect in = o & cv::Rect(0, 0, hp.cols, hp.rows);
    for (int r = in.y; r < in.y + in.height; ++r)
      for (int c = in.x; c < in.x + in.width; ++c)
        open[static_cast<std::size_t>(labels.at<int>(r, c))] = 1;
  }
  const int rows = hp.rows, cols = hp.cols;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l > 0) {
        if (r == 0 || c == 0 || r == rows - 1 || c == cols - 1)
          open[static_cast<std::size_t>(l)] = 1;
        continue;
      }
      // A known pixel: the unknown areas beside it have it on their rim.
      const float h = hp.at<float>(r, c);
      const bool proud = h > protrusion_min;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
          const int k = labels.at<int>(rr, cc);
          if (k <= 0) continue;
          if (!proud) open[static_cast<std::size_t>(k)] = 1;
          sum[static_cast<std::size_t>(k)] += h;
          ++count[static_cast<std::size_t>(k)];
        }
    }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l <= 0 || open[static_cast<std::size_t>(l)] || count[static_cast<std::size_t>(l)] == 0)
        continue;
      hp.at<float>(r, c) =
          static_cast<float>(sum[static_cast<std::size_t>(l)] / count[static_cast<std::size_t>(l)]);
      known.at<uchar>(r, c) = 255;
    }
}

// Step 2 on one SE.
std::vector<PathDetection> DepthPath(const SeImages& se, double pixel, bool ceiling,
                                     const interfaces::ObjectModelCatalogue& cat,
                                     const ComponentParams& p) {
  // An unknown pixel in a gap narrower than gap_close between protruding ones takes their
  // protrusion (a grey closing of the high-pass depth, on unknown pixels only): the wall
  // behind a radiator's fins or in an extinguisher's own shadow is hidden by the object, not a
  // hole in it, and read as wall it broke the object into fragments no class fitted and pulled
  // the NCC down. A shadow wider than gap_close stays unknown.
  cv::Mat hp = se.highpass.clone(), known;
  const int gap = 2 * static_cast<int>(std::lround(0.5 * p.gap_close / pixel)) + 1;
  if (gap >= 3) {
    cv::Mat closed;
    cv::morphologyEx(se.highpass, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(gap, gap)));
    closed.copyTo(hp, ~se.valid);
    known = se.valid | (hp > p.protrusion_min);
  } else {
    known = se.valid.clone();
  }
  FillEnclosedHoles(se.openings, p.protrusion_min, hp, known);
  cv::Mat mask = (hp > p.protrusion_min) & known;
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  CutCasings(se, p, pixel, 0, mask);
  const std::vector<cv::Rect> regions = Regions(mask, 0);
  const int pad = static_cast<int>(std::ceil((1.2 + p.template_pad * 2 + p.search_margin) / pixel));
  cv::Mat padded;
  cv::copyMakeBorder(hp, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
  std::map<int, cv::Mat> templates;
  auto templ = [&](int k) -> const cv::Mat& {
    auto it = templates.find(k);
    if (it == templates.end())
      it = templates
               .emplace(k, MaybeFlip(ModelDepthOnWall(cat.models[static_cast<std::size_t>(k)],
                                                      p.template_pad, pixel),
                                     ceiling))
               .first;
    return it->second;
  };
  std::vector<PathDetection> out;
  const int margin = static_cast<int>(std::ceil(p.search_margin / pixel));
  for (const cv::Rect& r : regions) {
    if (r.area() * pixel * pixel < p.min_region_area || TouchesOpening(se, r)) continue;
    // The filling blurs a protrusion's edges: a step of depth H crosses protrusion_min
    // sigma x Phi^-1(1 - protrusion_min / H) outside the object, about one sigma for a 4 cm
    // socket. Where the wall is sparsely sampled (sigma up to fill_sigma_max) an 8 cm high
    // four-gang socket made a 15 cm high region that no class of its size fitted.
    const double spread = se.blur.at<float>(r.y + r.height / 2, r.x + r.width / 2) * pixel;
    for (int k = 0; k < static_cast<int>(cat.models.size()); ++k) {
      const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(k)];
      if (!MountsOn(m, ceiling) || m.depth < 1.5 * p.protrusion_min) continue;
      if (!SizeFits(r, pixel, m, p, 1.0 - p.size_tolerance, spread)) continue;
      const Peak pk = MatchAround(padded, pad, templ(k), r, margin);
      if (pk.score < p.depth_ncc_min) continue;
      PathDetection d = BoxAt(k, m, pixel, pk);
      d.ncc = pk.score;
      // NCC ignores the amplitude: a 12 mm switch and a 40 mm socket correlate alike. The
      // score weighs the NCC by how well the measured protrusion matches the class's depth.
      const double top = BoxProtrusion(se, d);
      const double agree =
          std::isfinite(top) && top > 0.0 ? std::min(top, m.depth) / std::max(top, m.depth) : 0.5;
      d.score = pk.score * agree;
      d.samples = ProtrudingSamples(se, d, p);
      out.push_back(d);
    }
  }
  if (p.masked_known_min > 0.0 && !out.empty()) {
    cv::Mat known_padded;
    cv::copyMakeBorder(known, known_padded, pad, pad, pad, pad, cv::BORDER_CONSTANT,
                       cv::Scalar(0));
    for (PathDetection& d : out)
      ExtendTruncated(se, padded, known_padded, pad, pixel, cat, p, templ, d);
    for (PathDetection& d : out)
      if (FrontFaceModel(cat.models[static_cast<std::size_t>(d.class_index)]))
        PlaceByKnownPixels(padded, known_padded, pad, pixel, p, templ(d.class_index), d);
  }
  Dedupe(out);
  return out;
}

// Two classes of one mounting whose widths and heights agree within 10 %.
bool SameSize(const interfaces::ObjectModel& a, const interfaces::ObjectModel& b) {
  return a.mounting == b.mounting && std::abs(a.width - b.width) <= 0.1 * a.width &&
         std::abs(a.height - b.height) <= 0.1 * a.height;
}

// The colour box of class m centred at (col, row): RGB bytes in the model's orientation.
std::vector<std::uint8_t> ColourBox(const cv::Mat& rgb_padded, int pad, const PathDetection& d,
                                    bool ceiling, int* w, int* h) {
  *w = std::max(2, static_cast<int>(std::lround(d.col1 - d.col0)));
  *h = std::max(2, static_cast<int>(std::lround(d.row1 - d.row0)));
  const int c0 = static_cast<int>(std::lround(0.5 * (d.col0 + d.col1) - 0.5 * *w)) + pad;
  const int r0 = static_cast<int>(std::lround(0.5 * (d.row0 + d.row1) - 0.5 * *h)) + pad;
  cv::Rect box(c0, r0, *w, *h);
  box &= cv::Rect(0, 0, rgb_padded.cols, rgb_padded.rows);
  cv::Mat crop = MaybeFlip(rgb_padded(box).clone(), ceiling);
  *w = crop.cols, *h = crop.rows;
  return std::vector<std::uint8_t>(crop.data, crop.data + crop.total() * 3);
}

// A depth detection whose colour contradicts its class: the perceptron reads the box as a
// component (its best class beats "none") but no class of this one's size among its likely
// ones (colour_score_min of the best), e.g. a white socket's box taken by depth for a red
// fire alarm switch of nearly its shape. A box the perceptron reads as plain wall (a
// radiator of the wall's colour) does not contradict.
bool ColourContradicts(const SeImages& se, double pixel, bool ceiling, const PathDetection& d,
                       const ComponentRecogniser& rec, const ComponentParams& p) {
  const interfaces::ObjectModelCatalogue& cat = rec.Catalogue();
  const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(d.class_index)];
  const int pad = static_cast<int>(std::ceil(std::max(m.width, m.height) / pixel)) + 2;
  cv::Mat rgb_padded;
  const cv::Rect win = cv::Rect(static_cast<int>(std::floor(d.col0)) - pad,
                                static_cast<int>(std::floor(d.row0)) - pad,
                                static_cast<int>(std::ceil(d.col1 - d.col0)) + 2 * pad,
                                static_cast<int>(std::ceil(d.row1 - d.row0)) + 2 * pad) &
                       cv::Rect(0, 0, se.rgb.cols, se.rgb.rows);
  if (win.area() == 0) return false;
  cv::copyMakeBorder(se.rgb(win), rgb_padded, pad, pad, pad, pad, cv::BORDER_REPLICATE);
  PathDetection local = d;
  local.col0 -= win.x, local.col1 -= win.x, local.row0 -= win.y, local.row1 -= win.y;
  int w = 0, h = 0;
  const std::vector<std::uint8_t> box = ColourBox(rgb_padded, pad, local, ceiling, &w, &h);
  if (w < 2 || h < 2) return false;
  const std::vector<float> s = rec.Score(box, w, h, m.width, m.height);
  const float best = *std::max_element(s.begin(), s.end() - 1);
  if (best <= s.back()) return false;
  float sk = 0.0f;
  for (std::size_t j = 0; j + 1 < s.size(); ++j)
    if (SameSize(m, cat.models[j])) sk = std::max(sk, s[j]);
  return sk < p.colour_score_min * best;
}

// The light the SE's colours were measured in, as a factor of the light of the catalogue's
// colour images (linear RGB): the median ratio of measured to model colour over the measured
// pixels of the front faces of the SE's confident depth detections (depth-only instance
// floors: score and measured samples; FrontFaceModel classes), inside their boxes by the
// filling's blur + 1 pixel and away from the model's own colour edges (its 3 x 3 neighbourhood
// within 8 levels per channel), where the model is not dark (mean linear >= 0.1: a ratio of
// small numbers).
// 1 (the catalogue's colours as they are) with fewer than light_min_pixels. The composite
// template puts a model beside the wall colour the scan measured: in the scanner's light (0.6
// of full on the vertical faces of the default scenes) a white socket on a white wall shows
// no outline, while the unlit model's plate stood out and its NCC sat on the socket's lit top
// edge, 5 cm high.
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
  return Median(ratios);
}

// The points an SE image was built from (map frame) as samples in its pixels
// (modelling/sample_fit.h).
SeSamples SeSamplesOf(const Orthoimage& image, const OrthoPoints& points) {
  CheckOrthoPoints(points);
  const PatchFrame& f = image.Frame();
  std::vector<Eigen::Vector3f> uvd;
  uvd.reserve(points.points->size());
  for (const Eigen::Vector3f& q : *points.points) {
    const Vec3 x = q.cast<double>();
    const Vec2 uv = f.ToUv(x);
    uvd.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()),
                     static_cast<float>(f.Depth(x)));
  }
  return SeSamples(image, uvd, *points.colours);
}

// Step 7: an instance's box moved to where its class's model best explains the SE's samples
// (FitOnSamples): a protruding class by its depth model (its height map), a flush one by its
// colour face, relit by the SE's light (SeLight), on the local wall colour.
void PlaceOnSamples(const SeSamples& samples, const SeImages& se, const interfaces::ObjectModel& m,
                    bool ceiling, double pixel, double light, const ComponentParams& p,
                    PathDetection& b) {
  const double col = 0.5 * (b.col0 + b.col1), row = 0.5 * (b.row0 + b.row1);
  const cv::Point mid(std::clamp(static_cast<int>(col), 0, se.spacing.cols - 1),
                      std::clamp(static_cast<int>(row), 0, se.spacing.rows - 1));
  const double spacing = se.spacing.at<float>(mid);
  if (!(spacing > 0.0)) return;  // nothing seen there
  SampleModel model;
  model.pixel = m.pixel_size;
  model.width = m.width;
  model.height = m.height;
  model.protrusion = m.depth;
  if (m.depth >= 2.0 * p.protrusion_min) {
    model.depth = MaybeFlip(ModelDepth(m), ceiling);
  } else {
    model.wall_rgb = se.wall_rgb.at<cv::Vec3b>(mid);
    model.colour_rgb =
        MaybeFlip(ModelColourOnWall(m, model.wall_rgb, 0.0, m.pixel_size, light), ceiling);
  }
  const SampleFit fit = FitOnSamples(samples, model, col, row, pixel, spacing, p);
  if (!fit.fitted) return;
  b.col0 += fit.dcol, b.col1 += fit.dcol;
  b.row0 += fit.drow, b.row1 += fit.drow;
}

// Step 3 on one SE.
std::vector<PathDetection> ColourPath(const SeImages& se, double pixel, bool ceiling, double light,
                                      const ComponentRecogniser& rec, const ComponentParams& p) {
  const interfaces::ObjectModelCatalogue& cat = rec.Catalogue();
  cv::Mat mask = (se.delta_e > p.colour_delta_e) & se.valid;
  const int grow = static_cast<int>(std::lround(p.colour_merge / pixel));
  CutCasings(se, p, pixel, grow, mask);
  const std::vector<cv::Rect> blobs = Regions(mask, grow);
  const int pad = static_cast<int>(std::ceil((1.2 + p.template_pad * 2 + p.search_margin) / pixel));
  cv::Mat lab_padded, rgb_padded;
  cv::copyMakeBorder(se.lab, lab_padded, pad, pad, pad, pad, cv::BORDER_REPLICATE);
  cv::copyMakeBorder(se.rgb, rgb_padded, pad, pad, pad, pad, cv::BORDER_REPLICATE);
  const int margin = static_cast<int>(std::ceil(p.search_margin / pixel));
  std::vector<PathDetection> out;
  for (const cv::Rect& r : blobs) {
    if (TouchesOpening(se, r)) continue;  // a blob of any size: where to search, not the object
    const cv::Point mid(r.x + r.width / 2, r.y + r.height / 2);
    const cv::Vec3b wall = se.wall_rgb.at<cv::Vec3b>(mid);
    const double sigma = p.template_blur_share * se.blur.at<float>(mid);
    for (int k = 0; k < static_cast<int>(cat.models.size()); ++k) {
      const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(k)];
      if (!MountsOn(m, ceiling) || !SizeFits(r, pixel, m, p, p.colour_min_extent)) continue;
      // Matched filter: the template degraded as the scan degraded the blob (the filling's
      // sigma there), so that a small, faint model is compared with what a scan makes of it.
      auto match = [&](double template_pad, double lit) {
        cv::Mat t_rgb = MaybeFlip(ModelColourOnWall(m, wall, template_pad, pixel, lit), ceiling),
                t_f, t_lab;
        t_rgb.convertTo(t_f, CV_32FC3, 1.0 / 255.0);
        if (sigma > 0.0)
          cv::GaussianBlur(t_f, t_f, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
        cv::cvtColor(t_f, t_lab, cv::COLOR_RGB2Lab);
        return MatchAround(lab_padded, pad, t_lab, r, margin);
      };
      Peak pk = match(p.template_pad, 1.0);
      bool inner_used = false;
      // The padded template holds the model's colours (the catalogue's) beside the wall's
      // measured colour, so its outline is only as right as the two agree. A flush plate whose
      // colour the scan renders as its wall's (a white built-in socket on a light wall) shows
      // no outline in the scan although its template has one; its inner pattern (cup and
      // holes) still shows. So a flush class is also matched without the padding; that peak
      // counts when it is higher and reaches inner_ncc_min (fewer pixels and no outline: a
      // higher floor for the same rate of chance matches).
      if (m.depth < 2.0 * p.protrusion_min) {
        const Peak inner = match(0.0, 1.0);
        if (inner.score > pk.score && inner.score >= p.inner_ncc_min) pk = inner, inner_used = true;
      }
      if (pk.score < p.colour_ncc_min) continue;
      // The place is the peak of the model relit by the SE's light (SeLight). The floors stay
      // those of the catalogue's colours: relit, a white model on a white wall is its inner
      // pattern alone, and as a detector it took chance matches at shelf edges and radiator
      // fins (office seeds 1-5: FP 11 -> 18).
      if (light != 1.0) {
        const Peak at = match(inner_used ? 0.0 : p.template_pad, light);
        if (at.score >= p.colour_ncc_min) pk.col = at.col, pk.row = at.row;
      }
      PathDetection d = BoxAt(k, m, pixel, pk);
      if (!DepthAgrees(se, d, m, p)) continue;
      int w = 0, h = 0;
      const std::vector<std::uint8_t> box = ColourBox(rgb_padded, pad, d, ceiling, &w, &h);
      const std::vector<float> s = rec.Score(box, w, h, m.width, m.height);
      // The box is a component (its best class beats "none") and class k's size is among the
      // perceptron's likely ones: its pattern holds global colour statistics and the box size,
      // not the pictogram, so classes of one size (e.g. signs with different pictograms on the
      // same colours) are told apart by the NCC of their colour models (step 5), not by it.
      float sk = 0.0f;
      for (std::size_t j = 0; j + 1 < s.size(); ++j)
        if (SameSize(m, cat.models[j])) sk = std::max(sk, s[j]);
      const float best = *std::max_element(s.begin(), s.end() - 1);
      if (best <= s.back() || sk < p.colour_score_min * best) continue;
      d.score = best;
      d.ncc = pk.score;
      d.samples = SupportingSamples(se, d, m, pixel, p);
      out.push_back(d);
    }
  }
  Dedupe(out);
  return out;
}

// x's projection onto the frame's plane lies within `margin` of its extent.
bool OverExtent(const PatchFrame& f, const Vec3& x, double margin) {
  const Vec2 uv = f.ToUv(x);
  return uv.x() >= -margin && uv.y() >= -margin && uv.x() <= f.width + margin &&
         uv.y() <= f.height + margin;
}

// The box that places an instance: its depth detection's when depth found it, else its
// colour detection's.
const PathDetection& InstanceBox(const ConsensusInstance& c,
                                 const std::vector<PathDetection>& colour,
                                 const std::vector<PathDetection>& depth) {
  return c.depth >= 0 ? depth[static_cast<std::size_t>(c.depth)]
                      : colour[static_cast<std::size_t>(c.colour)];
}

// An instance of the equipment `sign`'s class marks lies below it on the SE (overlapping it
// along u).
bool MarkedBelow(const PathDetection& sign, const std::vector<PathDetection>& colour,
                 const std::vector<PathDetection>& depth,
                 const interfaces::ObjectModelCatalogue& cat,
                 const std::vector<ConsensusInstance>& instances) {
  const std::string& marks = cat.models[static_cast<std::size_t>(sign.class_index)].marks;
  if (marks.empty()) return false;
  for (const ConsensusInstance& q : instances) {
    if (cat.models[static_cast<std::size_t>(q.class_index)].class_name != marks) continue;
    const PathDetection& b = InstanceBox(q, colour, depth);
    const bool along = std::min(b.col1, sign.col1) > std::max(b.col0, sign.col0);
    if (along && 0.5 * (b.row0 + b.row1) > sign.row1) return true;  // rows run downwards
  }
  return false;
}

// Step 6's support: flags the colour detections of marking classes left out of `instances`
// whose marked equipment is an instance below them; true when it flagged any.
bool MarkSupport(const std::vector<PathDetection>& depth,
                 const interfaces::ObjectModelCatalogue& cat,
                 const std::vector<ConsensusInstance>& instances,
                 std::vector<PathDetection>& colour) {
  std::vector<bool> used(colour.size(), false);
  for (const ConsensusInstance& c : instances)
    if (c.colour >= 0) used[static_cast<std::size_t>(c.colour)] = true;
  bool any = false;
  for (std::size_t i = 0; i < colour.size(); ++i) {
    if (used[i] || colour[i].marked) continue;
    if (MarkedBelow(colour[i], colour, depth, cat, instances)) colour[i].marked = any = true;
  }
  return any;
}

// Location signs of one size and colours differ only in their pictograms, which a scan a few
// metres away does not resolve (the colour NCCs of the look-alike classes then differ by
// chance). What a sign marks does: a colour-only instance whose class marks no equipment found
// below it on this SE (overlapping it along u) takes a look-alike class, detected on the same
// box by the colour path, whose marked equipment is there (interfaces::ObjectModel::marks: the
// catalogue's relation, a robot's knowledge of the objects, not of the scene).
void ApplyMarks(const std::vector<PathDetection>& colour, const std::vector<PathDetection>& depth,
                const interfaces::ObjectModelCatalogue& cat,
                std::vector<ConsensusInstance>& instances) {
  for (ConsensusInstance& c : instances) {
    if (c.colour < 0 || c.depth >= 0) continue;
    const PathDetection& sign = colour[static_cast<std::size_t>(c.colour)];
    if (MarkedBelow(sign, colour, depth, cat, instances)) continue;
    for (std::size_t j = 0; j < colour.size(); ++j) {
      const PathDetection& alt = colour[j];
      if (alt.class_index == c.class_index ||
          !SameSize(cat.models[static_cast<std::size_t>(alt.class_index)],
                    cat.models[static_cast<std::size_t>(c.class_index)]) ||
          OverlapOfSmaller(alt, sign) < 0.5 || !MarkedBelow(alt, colour, depth, cat, instances))
        continue;
      c.class_index = alt.class_index;
      c.colour = static_cast<int>(j);
      break;
    }
  }
}

}  // namespace

void ComponentParams::Validate() const { ValidateParams(*this, "components."); }

const char* ToString(FoundBy f) {
  switch (f) {
    case FoundBy::kColourAndDepth:
      return "colour+depth";
    case FoundBy::kColour:
      return "colour";
    case FoundBy::kDepth:
      return "depth";
  }
  return "?";
}

double CoherenceAlpha(const PathDetection& c, const PathDetection& d) {
  const double w = std::min(c.col1, d.col1) - std::max(c.col0, d.col0);
  const double h = std::min(c.row1, d.row1) - std::max(c.row0, d.row0);
  if (w <= 0 || h <= 0) return 0.0;
  const double ew = std::max(c.col1, d.col1) - std::min(c.col0, d.col0);
  const double eh = std::max(c.row1, d.row1) - std::min(c.row0, d.row0);
  return std::clamp(w * h / (ew * eh), 0.0, 1.0);
}

std::vector<ConsensusInstance> Consensus(const std::vector<PathDetection>& colour,
                                         const std::vector<PathDetection>& depth,
                                         const ComponentParams& p) {
  std::vector<ConsensusInstance> out;
  std::vector<int> classes;
  for (const auto& d : colour) classes.push_back(d.class_index);
  for (const auto& d : depth) classes.push_back(d.class_index);
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  for (int k : classes) {
    // R(O): rows = colour detections of k, columns = depth detections of k.
    std::vector<int> rows, cols;
    for (int i = 0; i < static_cast<int>(colour.size()); ++i)
      if (colour[static_cast<std::size_t>(i)].class_index == k) rows.push_back(i);
    for (int j = 0; j < static_cast<int>(depth.size()); ++j)
      if (depth[static_cast<std::size_t>(j)].class_index == k) cols.push_back(j);
    std::vector<std::vector<double>> R(rows.size(), std::vector<double>(cols.size(), 0.0));
    for (std::size_t a = 0; a < rows.size(); ++a)
      for (std::size_t b = 0; b < cols.size(); ++b)
        R[a][b] = CoherenceAlpha(colour[static_cast<std::size_t>(rows[a])],
                                 depth[static_cast<std::size_t>(cols[b])]);
    std::vector<bool> row_used(rows.size(), false), col_used(cols.size(), false);
    std::vector<ConsensusInstance> pairs;
    while (true) {  // iterated maximum over the remaining entries
      double best = -1.0;
      std::size_t ba = 0, bb = 0;
      for (std::size_t a = 0; a < rows.size(); ++a)
        for (std::size_t b = 0; b < cols.size(); ++b)
          if (!row_used[a] && !col_used[b] && R[a][b] > best) best = R[a][b], ba = a, bb = b;
      if (best < std::max(p.min_pair_alpha, 1e-9)) break;
      row_used[ba] = col_used[bb] = true;
      pairs.push_back({k, rows[ba], cols[bb], best});
    }
    out.insert(out.end(), pairs.begin(), pairs.end());
    auto overlaps_pair = [&](const PathDetection& d, bool is_colour) {
      for (const auto& q : pairs) {
        const PathDetection& o = is_colour ? colour[static_cast<std::size_t>(q.colour)]
                                           : depth[static_cast<std::size_t>(q.depth)];
        if (OverlapOfSmaller(d, o) > 0.0) return true;
      }
      return false;
    };
    for (std::size_t a = 0; a < rows.size(); ++a) {
      const PathDetection& d = colour[static_cast<std::size_t>(rows[a])];
      // A colour detection whose box's protrusion supports its class (ColourPath: the
      // object's own, of a colour unlike the wall) on min_depth_samples measured samples needs
      // only the colour path's NCC floor: seen along a corridor an extinguisher leaves depth
      // fragments its template does not match, and its colour NCC stays under
      // single_colour_ncc.
      const bool supported = d.samples >= std::max(1, p.min_depth_samples) || d.marked;
      if (!row_used[a] && d.score >= p.single_colour_score &&
          (d.ncc >= p.single_colour_ncc || supported) && !overlaps_pair(d, true))
        out.push_back({k, rows[a], -1, 0.5});
    }
    for (std::size_t b = 0; b < cols.size(); ++b) {
      const PathDetection& d = depth[static_cast<std::size_t>(cols[b])];
      if (!col_used[b] && d.score >= p.single_depth_ncc && d.samples >= p.min_depth_samples &&
          !overlaps_pair(d, false))
        out.push_back({k, -1, cols[b], 0.5});
    }
  }
  // Step 5: across classes, the larger rank keeps an overlap. Rank = max(alpha, 0.5) x the
  // evidence for the class: the depth score where depth found it (NCC x protrusion agreement:
  // the colour of small white components hardly tells them apart), else the colour NCC (the
  // perceptron's score says "a component", the model template says which). A pair ranks at
  // least as a single path: two boxes that disagree still both saw the object.
  auto rank = [&](const ConsensusInstance& c) {
    const double evidence = c.depth >= 0 ? depth[static_cast<std::size_t>(c.depth)].score
                                         : colour[static_cast<std::size_t>(c.colour)].ncc;
    return std::max(c.alpha, 0.5) * evidence;
  };
  std::stable_sort(out.begin(), out.end(),
                   [&](const auto& a, const auto& b) { return rank(a) > rank(b); });
  std::vector<ConsensusInstance> kept;
  for (const auto& c : out) {
    const PathDetection& bc = InstanceBox(c, colour, depth);
    bool clash = false;
    for (const auto& q : kept)
      clash = clash || OverlapOfSmaller(bc, InstanceBox(q, colour, depth)) > p.max_class_overlap;
    if (!clash) kept.push_back(c);
  }
  return kept;
}

std::vector<DetectedComponent> DetectSeComponents(const Orthoimage& image, const std::string& host,
                                                  bool ceiling,
                                                  const std::vector<DetectedOpening>& openings,
                                                  const ComponentRecogniser& recogniser,
                                                  const ComponentParams& params,
                                                  const OrthoPoints* samples) {
  params.Validate();
  if (!recogniser.Trained())
    throw InputError("", "component recogniser is not trained", "untrained", "a trained one");
  std::vector<DetectedComponent> out;
  if (image.Cols() < 4 || image.Rows() < 4) return out;
  SeImages se;
  std::vector<DetectedOpening> mine;
  for (const auto& o : openings)
    if (o.host == host) mine.push_back(o);
  FillSe(image, mine, params, se);
  Background(params, image.Pixel(), se);
  const auto& cat = recogniser.Catalogue();
  std::vector<PathDetection> depth = DepthPath(se, image.Pixel(), ceiling, cat, params);
  depth.erase(std::remove_if(depth.begin(), depth.end(),
                             [&](const PathDetection& d) {
                               return ColourContradicts(se, image.Pixel(), ceiling, d, recogniser,
                                                        params);
                             }),
              depth.end());
  const double light = SeLight(se, depth, ceiling, cat, params);
  std::vector<PathDetection> colour =
      ColourPath(se, image.Pixel(), ceiling, light, recogniser, params);
  std::vector<ConsensusInstance> instances = Consensus(colour, depth, params);
  if (!ceiling && MarkSupport(depth, cat, instances, colour))
    instances = Consensus(colour, depth, params);
  if (!ceiling) ApplyMarks(colour, depth, cat, instances);
  const SeSamples placing = params.place_on_samples && samples && !instances.empty()
                                ? SeSamplesOf(image, *samples)
                                : SeSamples();
  for (const ConsensusInstance& c : instances) {
    const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(c.class_index)];
    PathDetection b = InstanceBox(c, colour, depth);
    if (!placing.Empty()) PlaceOnSamples(placing, se, m, ceiling, image.Pixel(), light, params, b);
    DetectedComponent d;
    d.class_name = m.class_name;
    d.host = host;
    d.u = image.ColU(0.5 * (b.col0 + b.col1));
    d.v = image.RowV(0.5 * (b.row0 + b.row1));
    d.centre = image.Frame().ToMap(d.u, d.v, 0.0);
    d.normal = image.Frame().n;
    d.size = Vec3(m.width, m.height, m.depth);
    d.alpha = c.alpha;
    d.found_by = c.colour >= 0 && c.depth >= 0 ? FoundBy::kColourAndDepth
                 : c.depth >= 0                ? FoundBy::kDepth
                                               : FoundBy::kColour;
    d.depth_score = c.depth >= 0 ? depth[static_cast<std::size_t>(c.depth)].score : 0.0;
    d.colour_score = c.colour >= 0 ? colour[static_cast<std::size_t>(c.colour)].score : 0.0;
    out.push_back(d);
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.u != b.u ? a.u < b.u : a.v < b.v; });
  return out;
}

std::vector<std::size_t> SePointIndices(const StructuralModel& sm3, std::size_t se,
                                        const std::vector<Eigen::Vector3f>& points,
                                        const ComponentParams& params) {
  if (se >= sm3.patches.size())
    throw InputError("", "SE index out of range", std::to_string(se),
                     "< " + std::to_string(sm3.patches.size()));
  std::vector<PatchFrame> frames;
  for (const StructuralPatch& patch : sm3.patches) frames.push_back(PatchFrame::Of(patch));
  const PatchFrame& frame = frames[se];
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3 x = points[k].cast<double>();
    if (std::abs(frame.Depth(x)) > params.band || !OverExtent(frame, x, 0.0)) continue;
    bool other = false;
    for (std::size_t j = 0; j < frames.size() && !other; ++j)
      other = j != se && std::abs(frames[j].Depth(x)) <= params.surface_band &&
              OverExtent(frames[j], x, params.band);
    if (!other) out.push_back(k);
  }
  return out;
}

Sm5Model DetectComponents(const StructuralModel& sm3, const Sm4Model& sm4,
                          const OrthoPoints& points, const ComponentRecogniser& recogniser,
                          const ComponentParams& params) {
  params.Validate();
  if (!recogniser.Trained())
    throw InputError("", "component recogniser is not trained", "untrained", "a trained one");
  Sm5Model out;
  out.room = sm3.room;
  CheckOrthoPoints(points);  // of it, points and colours are used here, not the rays
  OrthoimageParams op;
  op.band = params.band;
  op.finest_pixel = op.coarsest_pixel = params.pixel;
  op.max_pixels = params.max_image_pixels;
  std::vector<std::size_t> ses;  // indices into sm3.patches
  for (std::size_t j = 0; j < sm3.patches.size(); ++j) {
    const PatchFrame f = PatchFrame::Of(sm3.patches[j]);
    if (sm3.patches[j].patch_class == PatchClass::kFloor ||
        (f.width / params.pixel) * (f.height / params.pixel) > params.max_image_pixels)
      continue;
    ses.push_back(j);
  }
  // One task per SE (each reads only its own image, the shared points and the trained
  // recogniser), gathered in SE order: the same bytes on any number of threads.
  std::vector<std::vector<DetectedComponent>> found(ses.size());
  tbb::parallel_for(std::size_t{0}, ses.size(), [&](std::size_t i) {
    const std::size_t se = ses[i];
    std::vector<Eigen::Vector3f> own_points;
    std::vector<std::array<std::uint8_t, 3>> own_colours;
    for (const std::size_t k : SePointIndices(sm3, se, *points.points, params)) {
      own_points.push_back((*points.points)[k]);
      own_colours.push_back((*points.colours)[k]);
    }
    OrthoPoints own;
    own.points = &own_points;
    own.colours = &own_colours;
    const Orthoimage image =
        BuildOrthoimage(own, PatchFrame::Of(sm3.patches[se]), op, params.pixel);
    const bool ceiling = sm3.patches[se].patch_class == PatchClass::kCeiling;
    found[i] = DetectSeComponents(image, sm3.patches[se].id, ceiling, sm4.openings, recogniser,
                                  params, &own);
  });
  for (auto& f : found)
    for (DetectedComponent& d : f) out.components.push_back(std::move(d));
  for (std::size_t i = 0; i < out.components.size(); ++i)
    out.components[i].id = "bsc_" + std::to_string(i + 1);
  return out;
}

}  // namespace mopad::modelling
