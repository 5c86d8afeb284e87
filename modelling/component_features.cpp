#include "modelling/component_features.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "common/error.h"
#include "common/srgb.h"

namespace mopad::modelling {
namespace {

// 1D k-means with k = 3 (Lloyd, initialised at the 1/6, 1/2 and 5/6 quantiles, 12 rounds):
// centres and member counts, largest class first.
std::array<std::pair<float, int>, 3> ThreeClasses(std::vector<float> x) {
  std::array<std::pair<float, int>, 3> out{};
  if (x.empty()) return out;
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  std::array<float, 3> c{x[n / 6], x[n / 2], x[std::min(n - 1, 5 * n / 6)]};
  std::array<int, 3> cnt{};
  for (int round = 0; round < 12; ++round) {
    std::array<double, 3> sum{};
    cnt = {0, 0, 0};
    for (float v : x) {
      int best = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(v - c[k]) < std::abs(v - c[best])) best = k;
      sum[best] += v;
      ++cnt[best];
    }
    for (int k = 0; k < 3; ++k)
      if (cnt[k] > 0) c[k] = static_cast<float>(sum[k] / cnt[k]);
  }
  for (int k = 0; k < 3; ++k) out[k] = {c[k], cnt[k]};
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return out;
}

cv::Vec3b RandomWall(CounterRng& rng) {
  // Painted walls: light, low-saturation colours around a random tint.
  const double base = rng.Uniform(150.0, 250.0);
  cv::Vec3b w;
  for (int c = 0; c < 3; ++c) w[c] = cv::saturate_cast<uchar>(base + rng.Uniform(-25.0, 25.0));
  return w;
}

cv::Vec3b RandomColour(CounterRng& rng) {
  cv::Vec3b w;
  for (int c = 0; c < 3; ++c) w[c] = static_cast<uchar>(rng.Below(256));
  return w;
}

// Blur, colour gain/offset and noise of a scan (see ComponentTrainingParams).
void Degrade(cv::Mat& rgb, const ComponentTrainingParams& p, CounterRng& rng) {
  const double sigma = rng.Uniform(0.0, p.blur_max);
  if (sigma > 0.2) cv::GaussianBlur(rgb, rgb, cv::Size(0, 0), sigma);
  const double g = 1.0 + rng.Uniform(-p.colour_gain, p.colour_gain);
  std::array<double, 3> off{};
  for (double& o : off) o = rng.Uniform(-p.colour_offset, p.colour_offset);
  for (int r = 0; r < rgb.rows; ++r)
    for (int c = 0; c < rgb.cols; ++c) {
      cv::Vec3b& px = rgb.at<cv::Vec3b>(r, c);
      for (int k = 0; k < 3; ++k)
        px[k] = cv::saturate_cast<uchar>(g * px[k] + off[k] + p.noise * rng.Normal());
    }
}

// Resamples `canvas` (model pixel size `src_px`) to a pixel of `px` along x and `py` along y,
// shifted by (dx, dy) target pixels, then crops the box [x0, x0 + w) x [y0, y0 + h) metres.
cv::Mat Resample(const cv::Mat& canvas, double src_px, double px, double py, double dx, double dy,
                 double box_x0, double box_y0, double box_w, double box_h) {
  cv::Mat pre = canvas;
  const double f = std::min(px, py) / src_px;
  if (f > 1.5) cv::GaussianBlur(canvas, pre, cv::Size(0, 0), 0.4 * f);
  const int w = std::max(2, static_cast<int>(std::lround(box_w / px)));
  const int h = std::max(2, static_cast<int>(std::lround(box_h / py)));
  // Target pixel (i, j) centre maps to canvas metres box_x0 + (i + 0.5 + dx) px.
  cv::Mat A =
      (cv::Mat_<double>(2, 3) << px / src_px, 0.0, (box_x0 + (0.5 + dx) * px) / src_px - 0.5, 0.0,
       py / src_px, (box_y0 + (0.5 + dy) * py) / src_px - 0.5);
  cv::Mat out;
  cv::warpAffine(pre, out, A, cv::Size(w, h), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
  return out;
}

}  // namespace

ColourPattern ComputeColourPattern(const cv::Mat& rgb, double width_m, double height_m,
                                   bool lightness) {
  ColourPattern f{};
  if (rgb.empty() || rgb.type() != CV_8UC3)
    throw std::invalid_argument("ComputeColourPattern: expected a non-empty CV_8UC3 image");
  cv::Mat fl, hsv, lab;
  rgb.convertTo(fl, CV_32FC3, 1.0 / 255.0);
  cv::cvtColor(fl, hsv, cv::COLOR_RGB2HSV);
  cv::cvtColor(fl, lab, cv::COLOR_RGB2Lab);
  const std::size_t n = static_cast<std::size_t>(rgb.rows) * rgb.cols;
  std::array<std::vector<float>, kPatternChannels> ch;
  for (auto& c : ch) c.reserve(n);
  for (int r = 0; r < rgb.rows; ++r)
    for (int c = 0; c < rgb.cols; ++c) {
      ch[0].push_back(100.0f * hsv.at<cv::Vec3f>(r, c)[1]);  // S in [0, 100], as a and b
      ch[1].push_back(lab.at<cv::Vec3f>(r, c)[1]);
      ch[2].push_back(lab.at<cv::Vec3f>(r, c)[2]);
      if (kPatternChannels > 3) ch[3].push_back(lab.at<cv::Vec3f>(r, c)[0]);
    }
  for (int k = 0; k < (lightness ? kPatternChannels : 3); ++k) {
    const auto cl = ThreeClasses(ch[k]);
    f[4 * k + 0] = cl[0].first;
    f[4 * k + 1] = cl[1].second > 0 ? cl[1].first : cl[0].first;
    f[4 * k + 2] = static_cast<float>(cl[0].second) / static_cast<float>(n);
    f[4 * k + 3] = static_cast<float>(cl[1].second) / static_cast<float>(n);
  }
  f[4 * kPatternChannels] = static_cast<float>(width_m);
  f[4 * kPatternChannels + 1] = static_cast<float>(height_m);
  return f;
}

cv::Mat ModelColour(const interfaces::ObjectModel& m) {
  if (m.image_width <= 0 || m.image_height <= 0 ||
      m.colour_rgb.size() != static_cast<std::size_t>(m.image_width) * m.image_height * 3)
    throw InputError("", "object model '" + m.class_name + "' has no colour image",
                     std::to_string(m.colour_rgb.size()) + " bytes",
                     "image_width * image_height * 3");
  return cv::Mat(m.image_height, m.image_width, CV_8UC3,
                 const_cast<std::uint8_t*>(m.colour_rgb.data()))
      .clone();
}

cv::Mat ModelDepth(const interfaces::ObjectModel& m) {
  if (m.depth_m.size() != static_cast<std::size_t>(m.image_width) * m.image_height)
    throw InputError("", "object model '" + m.class_name + "' has no depth image",
                     std::to_string(m.depth_m.size()) + " values", "image_width * image_height");
  return cv::Mat(m.image_height, m.image_width, CV_32F, const_cast<float*>(m.depth_m.data()))
      .clone();
}

cv::Mat ModelMissMask(const interfaces::ObjectModel& m) {
  const cv::Mat c = ModelColour(m), d = ModelDepth(m);
  cv::Mat mask(c.size(), CV_8U, cv::Scalar(0));
  for (int r = 0; r < c.rows; ++r)
    for (int k = 0; k < c.cols; ++k) {
      const cv::Vec3b px = c.at<cv::Vec3b>(r, k);
      if (px[0] == 0 && px[1] == 0 && px[2] == 0 && d.at<float>(r, k) == 0.0f)
        mask.at<uchar>(r, k) = 255;
    }
  return mask;
}

cv::Mat Relit(const cv::Mat& rgb, double light) {
  if (light == 1.0) return rgb.clone();
  cv::Mat lut(1, 256, CV_8U);
  for (int v = 0; v < 256; ++v)
    lut.at<uchar>(v) =
        cv::saturate_cast<uchar>(255.0 * LinearToSrgb(light * SrgbToLinear(v / 255.0)));
  cv::Mat out;
  cv::LUT(rgb, lut, out);
  return out;
}

cv::Mat ModelColourOnWall(const interfaces::ObjectModel& m, const cv::Vec3b& wall_rgb, double pad,
                          double pixel, double light) {
  cv::Mat c = ModelColour(m);
  if (light != 1.0) c = Relit(c, light);
  c.setTo(wall_rgb, ModelMissMask(m));
  const int p = static_cast<int>(std::lround(pad / m.pixel_size));
  cv::Mat canvas;
  cv::copyMakeBorder(c, canvas, p, p, p, p, cv::BORDER_CONSTANT,
                     cv::Scalar(wall_rgb[0], wall_rgb[1], wall_rgb[2]));
  const double f = m.pixel_size / pixel;
  const int w = std::max(1, static_cast<int>(std::lround(canvas.cols * f)));
  const int h = std::max(1, static_cast<int>(std::lround(canvas.rows * f)));
  cv::Mat out;
  cv::resize(canvas, out, cv::Size(w, h), 0, 0, f < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

cv::Mat ModelDepthOnWall(const interfaces::ObjectModel& m, double pad, double pixel) {
  const int p = static_cast<int>(std::lround(pad / m.pixel_size));
  cv::Mat canvas;
  cv::copyMakeBorder(ModelDepth(m), canvas, p, p, p, p, cv::BORDER_CONSTANT, cv::Scalar(0));
  const double f = m.pixel_size / pixel;
  const int w = std::max(1, static_cast<int>(std::lround(canvas.cols * f)));
  const int h = std::max(1, static_cast<int>(std::lround(canvas.rows * f)));
  cv::Mat out;
  cv::resize(canvas, out, cv::Size(w, h), 0, 0, f < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

AugmentedBox AugmentModel(const interfaces::ObjectModel& m, const ComponentTrainingParams& p,
                          CounterRng& rng) {
  const cv::Vec3b wall = RandomWall(rng);
  cv::Mat c = ModelColour(m);
  c.setTo(wall, ModelMissMask(m));
  const double pad = 0.03;
  const int pp = static_cast<int>(std::lround(pad / m.pixel_size));
  cv::Mat canvas;
  cv::copyMakeBorder(c, canvas, pp, pp, pp, pp, cv::BORDER_CONSTANT,
                     cv::Scalar(wall[0], wall[1], wall[2]));
  const double pix = rng.Uniform(p.pixel_min, p.pixel_max);
  const double px = pix * (1.0 + rng.Uniform(0.0, p.stretch));
  const double py = pix * (1.0 + rng.Uniform(0.0, p.stretch));
  AugmentedBox b;
  b.width_m = m.width;
  b.height_m = m.height;
  const double dx = rng.Uniform(-0.7, 0.7), dy = rng.Uniform(-0.7, 0.7);
  b.rgb = Resample(canvas, m.pixel_size, px, py, dx, dy, pp * m.pixel_size, pp * m.pixel_size,
                   m.width, m.height);
  Degrade(b.rgb, p, rng);
  return b;
}

std::vector<int> LookAlikeGroups(const interfaces::ObjectModelCatalogue& cat) {
  const std::size_t n = cat.models.size();
  std::vector<cv::Mat> small(n);
  for (std::size_t i = 0; i < n; ++i) {
    cv::Mat c = ModelColour(cat.models[i]);
    c.setTo(cv::Vec3b(128, 128, 128), ModelMissMask(cat.models[i]));
    cv::resize(c, small[i], cv::Size(32, 32), 0, 0, cv::INTER_AREA);
  }
  std::vector<int> group(n, -1);
  int next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (group[i] >= 0) continue;
    group[i] = next++;
    for (std::size_t j = i + 1; j < n; ++j) {
      const auto& a = cat.models[i];
      const auto& b = cat.models[j];
      if (group[j] >= 0 || std::abs(a.width - b.width) > 0.1 * a.width ||
          std::abs(a.height - b.height) > 0.1 * a.height)
        continue;
      if (cv::norm(small[i], small[j], cv::NORM_L1) / (32.0 * 32.0 * 3.0) < 10.0)
        group[j] = group[i];
    }
  }
  return group;
}

AugmentedBox AugmentNegative(const interfaces::ObjectModel& m, int kind,
                             const ComponentTrainingParams& p, CounterRng& rng) {
  const double src = 0.002;
  const int w = std::max(4, static_cast<int>(std::lround(m.width / src)));
  const int h = std::max(4, static_cast<int>(std::lround(m.height / src)));
  const cv::Vec3b wall = RandomWall(rng);
  cv::Mat canvas(h, w, CV_8UC3, cv::Scalar(wall[0], wall[1], wall[2]));
  if (kind == 1) {  // a stain: one blob of any colour
    const cv::Vec3b s = RandomColour(rng);
    const int cx = static_cast<int>(rng.Below(w));
    const int cy = static_cast<int>(rng.Below(h));
    const int ax = 1 + static_cast<int>(rng.Below(w / 2 + 1));
    const int ay = 1 + static_cast<int>(rng.Below(h / 2 + 1));
    const double angle = rng.Uniform(0.0, 180.0);
    cv::ellipse(canvas, cv::Point(cx, cy), cv::Size(ax, ay), angle, 0, 360,
                cv::Scalar(s[0], s[1], s[2]), cv::FILLED);
  } else if (kind == 2) {  // a picture crop: random coloured rectangles over the whole box
    const cv::Vec3b bg = RandomColour(rng);
    canvas.setTo(cv::Scalar(bg[0], bg[1], bg[2]));
    const int shapes = 2 + static_cast<int>(rng.Below(8));
    for (int k = 0; k < shapes; ++k) {
      const cv::Vec3b s = RandomColour(rng);
      const int ax = static_cast<int>(rng.Below(w)), ay = static_cast<int>(rng.Below(h));
      const int bx = static_cast<int>(rng.Below(w)), by = static_cast<int>(rng.Below(h));
      cv::rectangle(canvas, cv::Point(ax, ay), cv::Point(bx, by), cv::Scalar(s[0], s[1], s[2]),
                    cv::FILLED);
    }
  }
  const double pix = rng.Uniform(p.pixel_min, p.pixel_max);
  AugmentedBox b;
  b.width_m = m.width;
  b.height_m = m.height;
  b.rgb = Resample(canvas, src, pix, pix, 0.0, 0.0, 0.0, 0.0, m.width, m.height);
  Degrade(b.rgb, p, rng);
  return b;
}

}  // namespace mopad::modelling
