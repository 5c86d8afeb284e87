// SM5's template matching and box measures (modelling/components.h), shared by its depth and
// colour paths: which classes a region may be, NCC peaks (plain and over the known pixels only),
// detection boxes, their protrusion and supporting samples.
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/statistics.h"
#include "modelling/components.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {}  // namespace

bool MountsOn(const interfaces::ObjectModel& m, bool ceiling) {
  return ceiling ? m.mounting == interfaces::Mounting::kCeiling
                 : m.mounting == interfaces::Mounting::kWall;
}

bool SizeFits(const cv::Rect& r, double pixel, const interfaces::ObjectModel& m,
              const ComponentParams& p, double min_share, double spread) {
  const double w = r.width * pixel, h = r.height * pixel;
  auto fits = [&](double x, double size) {
    return x <= size * (1.0 + p.size_tolerance) + p.size_slack + 2.0 * spread &&
           x >= std::max(0.0, min_share * size - p.size_slack);
  };
  return fits(w, m.width) && fits(h, m.height);
}

Peak PeakOf(const cv::Mat& res, const cv::Rect& win, const cv::Mat& templ, int pad) {
  Peak peak;
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(res, nullptr, &best, nullptr, &at);
  if (!std::isfinite(best) || best < -1.5) return peak;
  peak.score = best;
  auto vertex = [](float l, float c, float r) {
    const double den = l - 2.0 * c + r;
    return l > -1.5f && r > -1.5f && den < -1e-9 ? std::clamp(0.5 * (l - r) / den, -0.5, 0.5) : 0.0;
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

cv::Rect BoxRect(const SeImages& se, const PathDetection& d) {
  return cv::Rect(static_cast<int>(std::floor(d.col0)), static_cast<int>(std::floor(d.row0)),
                  static_cast<int>(std::ceil(d.col1 - d.col0)),
                  static_cast<int>(std::ceil(d.row1 - d.row0))) &
         cv::Rect(0, 0, se.highpass.cols, se.highpass.rows);
}

double BoxProtrusion(const SeImages& se, const PathDetection& d, double quantile) {
  const cv::Rect box = BoxRect(se, d);
  std::vector<float> h;
  for (int r = box.y; r < box.y + box.height; ++r)
    for (int c = box.x; c < box.x + box.width; ++c)
      if (se.valid.at<uchar>(r, c)) h.push_back(se.highpass.at<float>(r, c));
  if (h.empty() || h.size() < 0.3 * std::max(1, box.area()))
    return std::numeric_limits<double>::quiet_NaN();
  return Quantile(std::move(h), quantile);
}

int ProtrudingSamplesIn(const SeImages& se, const cv::Rect& box, const ComponentParams& p) {
  int n = 0;
  for (int r = box.y; r < box.y + box.height; ++r)
    for (int c = box.x; c < box.x + box.width; ++c)
      n += se.measured.at<uchar>(r, c) && se.highpass.at<float>(r, c) > p.protrusion_min;
  return n;
}

int ProtrudingSamples(const SeImages& se, const PathDetection& d, const ComponentParams& p) {
  return ProtrudingSamplesIn(se, BoxRect(se, d), p);
}

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

bool FrontFaceModel(const interfaces::ObjectModel& m) {
  return m.depth < std::min(m.width, m.height);
}

bool SameSize(const interfaces::ObjectModel& a, const interfaces::ObjectModel& b) {
  return a.mounting == b.mounting && std::abs(a.width - b.width) <= 0.1 * a.width &&
         std::abs(a.height - b.height) <= 0.1 * a.height;
}

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

}  // namespace mopad::modelling::detail
