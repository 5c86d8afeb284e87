// Steps 1-2 of SM4 on one wall (modelling/openings.h): the wall area (each pixel classified by
// its depth and colour), the edge images of J_C, J_D and the evidence mask, and their straight
// lines.
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "modelling/openings.h"
#include "modelling/openings_internal.h"

namespace mopad::modelling {

WallArea SegmentWallArea(const Orthoimage& img, const OpeningParams& p) {
  WallArea out;
  const std::size_t n = static_cast<std::size_t>(img.Cols()) * img.Rows();
  // Colour seeds: pixels on the plane, binned 8x8x8; the mode bin and its 26 neighbours.
  std::vector<int> hist(512, 0);
  auto bin_of = [](const std::array<std::uint8_t, 3>& c) {
    return std::array<int, 3>{c[0] / 32, c[1] / 32, c[2] / 32};
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (img.Count(i) == 0 || std::abs(img.Depth(i)) > p.flush_depth) continue;
    const auto b = bin_of(img.Rgb(i));
    ++hist[(b[0] * 8 + b[1]) * 8 + b[2]];
  }
  const int mode = static_cast<int>(std::max_element(hist.begin(), hist.end()) - hist.begin());
  const std::array<int, 3> mb{mode / 64, (mode / 8) % 8, mode % 8};
  std::array<double, 3> sum{0, 0, 0};
  double k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (img.Count(i) == 0 || std::abs(img.Depth(i)) > p.flush_depth) continue;
    const auto b = bin_of(img.Rgb(i));
    if (std::abs(b[0] - mb[0]) > 1 || std::abs(b[1] - mb[1]) > 1 || std::abs(b[2] - mb[2]) > 1)
      continue;
    for (int c = 0; c < 3; ++c) sum[c] += img.Rgb(i)[c];
    ++k;
  }
  if (k > 0)
    for (int c = 0; c < 3; ++c) out.wall_rgb[c] = sum[c] / k;
  out.classes.assign(n, OrthoClass::kOccluded);
  out.through_no_return.assign(n, 0);
  std::size_t wall = 0;
  const double tol2 = p.colour_tolerance * p.colour_tolerance;
  for (std::size_t i = 0; i < n; ++i) {
    if (img.Count(i) == 0) {
      out.classes[i] =
          img.Passed(i) > img.Blocked(i) ? OrthoClass::kThrough : OrthoClass::kOccluded;
      out.through_no_return[i] =
          out.classes[i] == OrthoClass::kThrough && img.PassedNoReturn(i) == img.Passed(i);
      continue;
    }
    const double d = img.Depth(i);
    if (d < -p.recess_depth) {
      out.classes[i] = OrthoClass::kRecessed;
    } else if (d > p.flush_depth) {
      out.classes[i] = OrthoClass::kProtruding;
    } else {
      double e2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double dc = img.Rgb(i)[c] - out.wall_rgb[c];
        e2 += dc * dc;
      }
      out.classes[i] = (k > 0 && e2 <= tol2) ? OrthoClass::kWall : OrthoClass::kOffColour;
      if (out.classes[i] == OrthoClass::kWall) ++wall;
    }
  }
  out.wall_share = n > 0 ? static_cast<double>(wall) / n : 0.0;
  // A seen-through pixel is weak (no-return only) unless a ray that returned from beyond the
  // plane passed within through_window of it: a doorway's sparse dropouts sit among returns
  // from the room behind, a dark occluder's do not.
  const int cols = img.Cols(), rows = img.Rows();
  cv::Mat strong(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = img.Index(c, r);
      if (img.Passed(i) > img.PassedNoReturn(i)) strong.at<std::uint8_t>(r, c) = 1;
    }
  const int win = 2 * static_cast<int>(std::lround(0.5 * p.through_window / img.Pixel())) + 1;
  cv::dilate(strong, strong, cv::Mat::ones(win, win, CV_8U));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (strong.at<std::uint8_t>(r, c)) out.through_no_return[img.Index(c, r)] = 0;
  return out;
}

namespace detail {
namespace {

// Runs of `on(i, j)` along j for each i, gaps <= gap bridged, length >= min_len, merged when
// parallel within 2 pixels and overlapping; the longest max_lines, ordered by position.
template <class On>
std::vector<Line> FindLines(int n_i, int n_j, On on, int gap, int min_len, int max_lines) {
  std::vector<Line> raw;
  for (int i = 0; i < n_i; ++i) {
    int start = -1, last = -1;
    for (int j = 0; j <= n_j; ++j) {
      const bool o = j < n_j && on(i, j);
      if (o) {
        if (start < 0)
          start = j;
        else if (j - last - 1 > gap) {
          if (last - start + 1 >= min_len) raw.push_back({double(i), start, last});
          start = j;
        }
        last = j;
      }
    }
    if (start >= 0 && last - start + 1 >= min_len) raw.push_back({double(i), start, last});
  }
  // Merge (raw is ordered by position, then extent).
  std::vector<Line> merged;
  std::vector<double> weight;
  for (const Line& l : raw) {
    bool done = false;
    for (std::size_t m = merged.size(); m-- > 0;) {
      Line& g = merged[m];
      if (l.pos - g.pos > 2.0) break;
      if (l.a > g.b + gap || l.b < g.a - gap) continue;
      const double w0 = weight[m], w1 = l.Length();
      g.pos = (g.pos * w0 + l.pos * w1) / (w0 + w1);
      g.a = std::min(g.a, l.a), g.b = std::max(g.b, l.b);
      weight[m] = w0 + w1;
      done = true;
      break;
    }
    if (!done) merged.push_back(l), weight.push_back(l.Length());
  }
  std::stable_sort(merged.begin(), merged.end(),
                   [](const Line& x, const Line& y) { return x.Length() > y.Length(); });
  if (static_cast<int>(merged.size()) > max_lines) merged.resize(max_lines);
  std::sort(merged.begin(), merged.end(), [](const Line& x, const Line& y) {
    return std::tie(x.pos, x.a, x.b) < std::tie(y.pos, y.a, y.b);
  });
  return merged;
}

// Where each line's step lies across it, to a fraction of a pixel: the vertex of the parabola
// through the gradient across the line (summed along its extent) at the strongest of the
// columns (rows) pos-1..pos+1 and its two neighbours. Canny marks one pixel of a step, and of a
// step between two pixels (both with the same gradient) the first: its centre is half a pixel
// off the step, which the vertex puts back on it (a two-point plateau has its vertex between
// them); a step inside a mixed pixel keeps that pixel's centre. `grad`: |d/dcol| for vertical
// lines, |d/drow| for horizontal ones.
void LocateEdges(std::vector<Line>& lines, const cv::Mat& grad, bool vertical) {
  const int n_across = vertical ? grad.cols : grad.rows;
  const int n_along = vertical ? grad.rows : grad.cols;
  for (Line& l : lines) {
    const auto profile = [&](int i) {
      if (i < 0 || i >= n_across) return 0.0;
      double s = 0.0;
      for (int j = std::max(0, l.a); j <= std::min(n_along - 1, l.b); ++j)
        s += vertical ? grad.at<float>(j, i) : grad.at<float>(i, j);
      return s;
    };
    const int c = static_cast<int>(std::lround(l.pos));
    int peak = c;
    for (int i = c - 1; i <= c + 1; ++i)
      if (profile(i) > profile(peak)) peak = i;
    const double s0 = profile(peak - 1), s1 = profile(peak), s2 = profile(peak + 1);
    const double den = s0 - 2.0 * s1 + s2;
    // Within the peak pixel (+-0.49: the line's pixel stays the peak's, see LinePixel).
    const double d = den < 0.0 ? std::clamp(0.5 * (s0 - s2) / den, -0.49, 0.49) : 0.0;
    l.edge = peak + 0.5 + d;
  }
}

cv::Mat ClassMask(const WallArea& area, int cols, int rows, std::initializer_list<OrthoClass> cs) {
  cv::Mat m(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const OrthoClass k = area.classes[static_cast<std::size_t>(r) * cols + c];
      for (OrthoClass x : cs)
        if (k == x) m.at<std::uint8_t>(r, c) = 1;
    }
  return m;
}

}  // namespace

WallEdges BuildWallEdges(const Orthoimage& img, const WallArea& area, const OpeningParams& p) {
  const int cols = img.Cols(), rows = img.Rows();
  const double px = img.Pixel();
  const cv::Vec3b wall_bgr(static_cast<std::uint8_t>(std::lround(area.wall_rgb[0])),
                           static_cast<std::uint8_t>(std::lround(area.wall_rgb[1])),
                           static_cast<std::uint8_t>(std::lround(area.wall_rgb[2])));
  cv::Mat colour(rows, cols, CV_8UC3, cv::Scalar(wall_bgr[0], wall_bgr[1], wall_bgr[2]));
  cv::Mat depth(rows, cols, CV_8U, cv::Scalar(128));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = img.Index(c, r);
      if (img.Count(i) == 0) continue;
      const auto rgb = img.Rgb(i);
      colour.at<cv::Vec3b>(r, c) = cv::Vec3b(rgb[0], rgb[1], rgb[2]);
      depth.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(
          std::clamp(128.0 + std::round(img.Depth(i) / p.depth_step), 1.0, 255.0));
    }
  // Sampling gaps: a pixel without points that no ray passed or stopped in front of takes the
  // mean of its seen 8-neighbours, repeatedly up to gap_fill away. Where the wall is sampled
  // more sparsely than the pixel (far from every scan position), a leaf or casing keeps its
  // own colour and depth there instead of the wall's, and the edges follow the door, not the
  // boundary of the sparse area.
  const int fill_px = static_cast<int>(std::lround(p.gap_fill / px));
  cv::Mat have(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (img.Count(img.Index(c, r)) > 0) have.at<std::uint8_t>(r, c) = 1;
  for (int it = 0; it < fill_px; ++it) {
    cv::Mat next = have.clone();
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = img.Index(c, r);
        if (have.at<std::uint8_t>(r, c) || img.Passed(i) > 0 || img.Blocked(i) > 0) continue;
        double sc[3] = {0, 0, 0}, sd = 0;
        int n = 0;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if (rr < 0 || rr >= rows || cc < 0 || cc >= cols || !have.at<std::uint8_t>(rr, cc))
              continue;
            const cv::Vec3b& q = colour.at<cv::Vec3b>(rr, cc);
            for (int k = 0; k < 3; ++k) sc[k] += q[k];
            sd += depth.at<std::uint8_t>(rr, cc);
            ++n;
          }
        if (n == 0) continue;
        colour.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<std::uint8_t>(std::lround(sc[0] / n)),
                                               static_cast<std::uint8_t>(std::lround(sc[1] / n)),
                                               static_cast<std::uint8_t>(std::lround(sc[2] / n)));
        depth.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(std::lround(sd / n));
        next.at<std::uint8_t>(r, c) = 1;
      }
    have = next;
  }
  cv::Mat ev_door = ClassMask(
      area, cols, rows, {OrthoClass::kOffColour, OrthoClass::kRecessed, OrthoClass::kThrough});
  const cv::Mat ev_hole = ev_door.clone();
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (area.through_no_return[img.Index(c, r)]) ev_door.at<std::uint8_t>(r, c) = 0;
  const cv::Mat ev_window =
      ClassMask(area, cols, rows, {OrthoClass::kRecessed, OrthoClass::kThrough});
  const cv::Mat known = ClassMask(
      area, cols, rows,
      {OrthoClass::kWall, OrthoClass::kOffColour, OrthoClass::kRecessed, OrthoClass::kThrough});
  const cv::Mat hidden =
      ClassMask(area, cols, rows, {OrthoClass::kOccluded, OrthoClass::kProtruding});
  const cv::Mat through = ClassMask(area, cols, rows, {OrthoClass::kThrough});
  const cv::Mat wall = ClassMask(area, cols, rows, {OrthoClass::kWall});
  const cv::Mat flush = ClassMask(area, cols, rows, {OrthoClass::kWall, OrthoClass::kOffColour});
  cv::Mat e_c, e_d, e_e, edges;
  cv::medianBlur(colour, colour, p.median_kernel);
  cv::medianBlur(depth, depth, p.median_kernel);
  cv::Canny(colour, e_c, p.canny_low, p.canny_high);
  cv::Canny(depth, e_d, p.canny_low, p.canny_high);
  cv::Mat ev255 = (ev_door | ev_window) * 255;  // outlines of any hole
  cv::medianBlur(ev255, ev255, p.median_kernel);
  cv::Canny(ev255, e_e, p.canny_low, p.canny_high);
  cv::bitwise_or(e_c, e_d, edges);
  cv::bitwise_or(edges, e_e, edges);
  cv::Mat edge01 = edges / 255;
  const int sb = std::max(1, static_cast<int>(std::lround(p.side_band / px)));
  cv::Mat edge_v, edge_h, hid_v, hid_h;
  cv::dilate(edge01, edge_v, cv::Mat::ones(1, 2 * sb + 1, CV_8U));
  cv::dilate(edge01, edge_h, cv::Mat::ones(2 * sb + 1, 1, CV_8U));
  // Hidden rows of a side: no edge and occluded or protruding somewhere across the band.
  cv::Mat hid_dv, hid_dh;
  cv::dilate(hidden, hid_dv, cv::Mat::ones(1, 2 * sb + 1, CV_8U));
  cv::dilate(hidden, hid_dh, cv::Mat::ones(2 * sb + 1, 1, CV_8U));
  hid_v = hid_dv & (1 - edge_v);
  hid_h = hid_dh & (1 - edge_h);
  const Masks m{Integral(known), Integral(ev_door), Integral(ev_window), Integral(through),
                Integral(wall),  Integral(edge_v),  Integral(edge_h),    Integral(hid_v),
                Integral(hid_h), Integral(flush),   Integral(hidden),    Integral(ev_hole)};
  cv::Mat grad[2];
  for (int axis = 0; axis < 2; ++axis) {
    grad[axis] = cv::Mat::zeros(rows, cols, CV_32F);
    for (const cv::Mat* im : {&colour, &depth, &ev255}) {
      cv::Mat g;
      cv::Sobel(*im, g, CV_32F, axis == 0 ? 1 : 0, axis == 0 ? 0 : 1, 3, 1.0 / (4.0 * 255.0));
      g = cv::abs(g);
      if (g.channels() > 1) cv::reduce(g.reshape(1, rows * cols), g, 1, cv::REDUCE_MAX);
      grad[axis] += g.reshape(1, rows);
    }
  }
  return {edge01, m, grad[0], grad[1]};
}

std::pair<std::vector<Line>, std::vector<Line>> WallLines(const WallEdges& we, double px,
                                                          const OpeningParams& p) {
  const cv::Mat& edge01 = we.edge01;
  const int cols = edge01.cols, rows = edge01.rows;
  const int gap = static_cast<int>(std::lround(p.line_gap / px));
  const int min_len = std::max(2, static_cast<int>(std::lround(p.min_line / px)));
  auto e_at = [&](int r, int c) {
    return c >= 0 && c < cols && r >= 0 && r < rows && edge01.at<std::uint8_t>(r, c) != 0;
  };
  std::vector<Line> vert = FindLines(
      cols, rows, [&](int c, int r) { return e_at(r, c - 1) || e_at(r, c) || e_at(r, c + 1); }, gap,
      min_len, p.max_lines);
  std::vector<Line> horz = FindLines(
      rows, cols, [&](int r, int c) { return e_at(r - 1, c) || e_at(r, c) || e_at(r + 1, c); }, gap,
      min_len, p.max_lines);
  LocateEdges(vert, we.grad_c, true);
  LocateEdges(horz, we.grad_r, false);
  return {std::move(vert), std::move(horz)};
}

}  // namespace detail
}  // namespace mopad::modelling
