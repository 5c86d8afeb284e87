#include "modelling/sample_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/statistics.h"

namespace mopad::modelling {
namespace {

// Bilinear value of `m` (CV_32F or CV_32FC3) at (x, y) in pixel-centre coordinates, clamped
// to its border (the padding is the wall).
template <class T>
T At(const cv::Mat& m, double x, double y) {
  x = std::clamp(x, 0.0, m.cols - 1.0);
  y = std::clamp(y, 0.0, m.rows - 1.0);
  const int x0 = std::min(m.cols - 2, static_cast<int>(x)),
            y0 = std::min(m.rows - 2, static_cast<int>(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  return (1 - fy) * ((1 - fx) * m.at<T>(y0, x0) + fx * m.at<T>(y0, x0 + 1)) +
         fy * ((1 - fx) * m.at<T>(y0 + 1, x0) + fx * m.at<T>(y0 + 1, x0 + 1));
}

cv::Mat Blurred(const cv::Mat& m, double sigma_px) {
  cv::Mat out;
  cv::GaussianBlur(m, out, cv::Size(0, 0), std::max(0.3, sigma_px), 0, cv::BORDER_REPLICATE);
  return out;
}

// The wall around a component: the samples of `near` beyond `ring0` (image pixels) off its
// footprint (half sizes hw, hh about col, row) and within surface_band of the SE plane (`wall`,
// ascending), their depth offset `b` (m, their median; 0 with fewer than 5) and depth noise
// `sigma_d` (m).
struct WallAround {
  std::vector<int> wall;
  double b = 0.0, sigma_d = 0.0;
};

WallAround WallOf(const SeSamples& samples, const std::vector<int>& near, double col, double row,
                  double hw, double hh, double ring0, double surface_band) {
  std::vector<float> wall_depth;
  std::vector<int> wall;
  for (int i : near)
    if ((std::abs(samples.Col(i) - col) > hw + ring0 ||
         std::abs(samples.Row(i) - row) > hh + ring0) &&
        std::abs(samples.Depth(i)) < surface_band) {
      wall.push_back(i);
      wall_depth.push_back(samples.Depth(i));
    }
  const double b = wall.size() >= 5 ? UpperMedian(wall_depth) : 0.0;
  double sigma_d = surface_band / 3.0;  // too little wall to measure: the band as 3 sigma
  if (wall.size() >= 20) {
    std::vector<float> dev;
    for (float z : wall_depth) dev.push_back(std::abs(z - static_cast<float>(b)));
    sigma_d = std::max(1e-3, 1.4826 * UpperMedian(dev));
  }
  return {wall, b, sigma_d};
}

// The used samples' colours in CIE Lab (`lab`, one row) and the colour noise of the wall among
// them (Lab units): the Lab distances of the wall samples to their median colour are the norm
// of a 3D Gaussian, whose median is 1.538 sigma.
double UsedColours(const SeSamples& samples, const std::vector<int>& use,
                   const std::vector<int>& wall, cv::Mat& lab) {
  cv::Mat rgb(1, static_cast<int>(use.size()), CV_32FC3);
  for (std::size_t k = 0; k < use.size(); ++k) {
    const cv::Vec3b c = samples.Rgb(use[k]);
    rgb.at<cv::Vec3f>(0, static_cast<int>(k)) = cv::Vec3f(c[0], c[1], c[2]) / 255.0f;
  }
  cv::cvtColor(rgb, lab, cv::COLOR_RGB2Lab);
  std::array<std::vector<float>, 3> ch;
  std::vector<int> wall_k;
  for (std::size_t k = 0; k < use.size(); ++k)
    if (std::binary_search(wall.begin(), wall.end(), use[k])) {
      wall_k.push_back(static_cast<int>(k));
      for (int c = 0; c < 3; ++c) ch[c].push_back(lab.at<cv::Vec3f>(0, static_cast<int>(k))[c]);
    }
  // Too little wall to measure: the colour path's noise, half colour_delta_e.
  double sigma_c = 4.0;
  if (wall_k.size() >= 20) {
    const cv::Vec3f centre(UpperMedian(ch[0]), UpperMedian(ch[1]), UpperMedian(ch[2]));
    std::vector<float> dist;
    for (int k : wall_k)
      dist.push_back(static_cast<float>(cv::norm(lab.at<cv::Vec3f>(0, k) - centre)));
    sigma_c = std::max(1.0, UpperMedian(dist) / 1.538);
  }
  return sigma_c;
}

// The model's images (`depth0` where it has a depth model, `lab0`, in CIE Lab, where it has a
// colour one) padded with the wall by the reach of the widest blur (4 sigma: OpenCV's kernel),
// so that blurring blends the model's edge with the wall; a lookup beyond the padding takes its
// border, the wall (At clamps).
void PaddedModel(const SampleModel& model, double edge, double radius, cv::Mat& depth0,
                 cv::Mat& lab0) {
  const int pad = static_cast<int>(std::ceil(4.0 * std::max(edge, radius / 4.0) / model.pixel)) + 2;
  if (!model.depth.empty())
    cv::copyMakeBorder(model.depth, depth0, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
  if (!model.colour_rgb.empty()) {
    cv::Mat padded, f;
    const cv::Vec3b w = model.wall_rgb;
    cv::copyMakeBorder(model.colour_rgb, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT,
                       cv::Scalar(w[0], w[1], w[2]));
    padded.convertTo(f, CV_32FC3, 1.0 / 255.0);
    cv::cvtColor(f, lab0, cv::COLOR_RGB2Lab);
  }
}

}  // namespace

SeSamples::SeSamples(const Orthoimage& image, const std::vector<Eigen::Vector3f>& uvd,
                     const std::vector<std::array<std::uint8_t, 3>>& rgb) {
  if (uvd.size() != rgb.size())
    throw InputError("", "SE samples and colours differ in number", std::to_string(rgb.size()),
                     std::to_string(uvd.size()));
  const double px = image.Pixel(), margin = image.Margin();
  cells_c_ = image.Cols() / kCell + 1;
  cells_r_ = image.Rows() / kCell + 1;
  std::vector<int> bucket;
  for (std::size_t k = 0; k < uvd.size(); ++k) {
    const float c = static_cast<float>((uvd[k].x() + margin) / px);
    const float r = static_cast<float>(image.Rows() - (uvd[k].y() + margin) / px);
    if (!(c >= 0 && r >= 0 && c < image.Cols() && r < image.Rows())) continue;
    col_.push_back(c);
    row_.push_back(r);
    depth_.push_back(uvd[k].z());
    rgb_.emplace_back(rgb[k][0], rgb[k][1], rgb[k][2]);
    bucket.push_back(static_cast<int>(r) / kCell * cells_c_ + static_cast<int>(c) / kCell);
  }
  start_.assign(static_cast<std::size_t>(cells_c_) * cells_r_ + 1, 0);
  for (int b : bucket) ++start_[static_cast<std::size_t>(b) + 1];
  for (std::size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
  order_.assign(bucket.size(), 0);
  std::vector<int> next(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < bucket.size(); ++i)
    order_[static_cast<std::size_t>(next[static_cast<std::size_t>(bucket[i])]++)] =
        static_cast<int>(i);
}

std::vector<int> SeSamples::In(double c0, double r0, double c1, double r1) const {
  std::vector<int> out;
  if (col_.empty() || !(c1 > c0 && r1 > r0)) return out;
  const int a0 = std::clamp(static_cast<int>(std::floor(c0 / kCell)), 0, cells_c_ - 1);
  const int a1 = std::clamp(static_cast<int>(std::floor(c1 / kCell)), 0, cells_c_ - 1);
  const int b0 = std::clamp(static_cast<int>(std::floor(r0 / kCell)), 0, cells_r_ - 1);
  const int b1 = std::clamp(static_cast<int>(std::floor(r1 / kCell)), 0, cells_r_ - 1);
  for (int b = b0; b <= b1; ++b)
    for (int a = a0; a <= a1; ++a) {
      const std::size_t cell = static_cast<std::size_t>(b) * cells_c_ + a;
      for (int j = start_[cell]; j < start_[cell + 1]; ++j) {
        const int i = order_[static_cast<std::size_t>(j)];
        if (Col(i) >= c0 && Col(i) < c1 && Row(i) >= r0 && Row(i) < r1) out.push_back(i);
      }
    }
  std::sort(out.begin(), out.end());
  return out;
}

SampleFit FitOnSamples(const SeSamples& samples, const SampleModel& model, double col, double row,
                       double image_pixel, double spacing, const ComponentParams& params) {
  constexpr int kMinSamples = 10;  // least samples in the window to fit at all
  const double radius = params.place_radius;
  SampleFit fit;
  const bool use_depth = !model.depth.empty(), use_colour = !model.colour_rgb.empty();
  if (samples.Empty() || (!use_depth && !use_colour)) return fit;
  const double edge = std::max(0.25e-3, params.place_edge_share * spacing);  // m
  const double hw = 0.5 * model.width / image_pixel, hh = 0.5 * model.height / image_pixel;
  const double ring0 = (radius + 2.0 * edge) / image_pixel;         // the wall ring begins
  const double reach = (radius + 4.0 * edge + 0.01) / image_pixel;  // and ends
  const std::vector<int> near =
      samples.In(col - hw - reach, row - hh - reach, col + hw + reach, row + hh + reach);
  if (static_cast<int>(near.size()) < kMinSamples) return fit;

  const WallAround around = WallOf(samples, near, col, row, hw, hh, ring0, params.surface_band);
  const std::vector<int>& wall = around.wall;
  const double b = around.b, sigma_d = around.sigma_d;
  // Samples that can be the model or the wall beside it (not behind the wall, not in front of
  // the object).
  std::vector<int> use;
  for (int i : near) {
    const double z = samples.Depth(i) - b;
    if (z > -3.0 * sigma_d && z < model.protrusion + 3.0 * sigma_d) use.push_back(i);
  }
  if (static_cast<int>(use.size()) < kMinSamples) return fit;
  cv::Mat lab;  // the used samples' colours, CIE Lab (one row)
  const double sigma_c = use_colour ? UsedColours(samples, use, wall, lab) : 0.0;
  const double inv_d2 = 1.0 / std::pow(params.place_cauchy_k * sigma_d, 2);
  const double inv_c2 = sigma_c > 0.0 ? 1.0 / std::pow(params.place_cauchy_k * sigma_c, 2) : 0.0;

  cv::Mat depth0, lab0;
  PaddedModel(model, edge, radius, depth0, lab0);
  const cv::Size size = use_depth ? depth0.size() : lab0.size();
  const double f = image_pixel / model.pixel;  // model pixels per image pixel
  const double x0 = 0.5 * size.width - 0.5, y0 = 0.5 * size.height - 0.5;

  double best_c = 0.0, best_r = 0.0;  // current best shift, image pixels
  double step = radius / 4.0;         // m
  constexpr int kHalf = 4;            // each level: (2 kHalf + 1)^2 shifts around the best
  std::vector<double> cost(static_cast<std::size_t>((2 * kHalf + 1) * (2 * kHalf + 1)));
  while (true) {
    const double blur = std::max(edge, step) / model.pixel;
    const cv::Mat dm = use_depth ? Blurred(depth0, blur) : cv::Mat();
    const cv::Mat cm = use_colour ? Blurred(lab0, blur) : cv::Mat();
    const double s = step / image_pixel;
    // A sample farther from the model's footprint, at every shift of this level, than the
    // blur reaches (OpenCV's kernel: 4 sigma) meets the wall at all of them: the same cost,
    // which cannot move the best shift, so it is left out.
    const double out = kHalf * s + 4.0 * blur * model.pixel / image_pixel + 1.0;
    std::vector<std::size_t> level;
    for (std::size_t k = 0; k < use.size(); ++k) {
      const int i = use[k];
      if (std::abs(samples.Col(i) - col - best_c) <= hw + out &&
          std::abs(samples.Row(i) - row - best_r) <= hh + out)
        level.push_back(k);
    }
    auto eval = [&](double dc, double dr) {
      double e = 0.0;
      for (const std::size_t k : level) {
        const int i = use[k];
        const double x = (samples.Col(i) - col - dc) * f + x0;
        const double y = (samples.Row(i) - row - dr) * f + y0;
        if (use_depth) {
          const double r = samples.Depth(i) - b - At<float>(dm, x, y);
          e += std::log1p(r * r * inv_d2);
        }
        if (use_colour) {
          const cv::Vec3f r = lab.at<cv::Vec3f>(0, static_cast<int>(k)) - At<cv::Vec3f>(cm, x, y);
          e += std::log1p(static_cast<double>(r.dot(r)) * inv_c2);
        }
      }
      return e;
    };
    double best = std::numeric_limits<double>::infinity();
    int bi = 0, bj = 0;
    for (int j = -kHalf; j <= kHalf; ++j)
      for (int i = -kHalf; i <= kHalf; ++i) {
        const double dc = best_c + i * s, dr = best_r + j * s;
        double e = std::numeric_limits<double>::infinity();
        if (std::hypot(dc, dr) * image_pixel <= radius + 1e-9) e = eval(dc, dr);
        cost[static_cast<std::size_t>((j + kHalf) * (2 * kHalf + 1) + i + kHalf)] = e;
        if (e < best) best = e, bi = i, bj = j;
      }
    const bool last = step < 1e-3;
    double di = bi, dj = bj;
    if (last) {  // a parabola through the best and its two neighbours, per axis
      auto at = [&](int i, int j) {
        return cost[static_cast<std::size_t>((j + kHalf) * (2 * kHalf + 1) + i + kHalf)];
      };
      auto vertex = [](double l, double c, double r) {
        const double den = l - 2.0 * c + r;
        return std::isfinite(den) && den > 1e-12 ? std::clamp(0.5 * (l - r) / den, -0.5, 0.5) : 0.0;
      };
      if (bi > -kHalf && bi < kHalf) di += vertex(at(bi - 1, bj), best, at(bi + 1, bj));
      if (bj > -kHalf && bj < kHalf) dj += vertex(at(bi, bj - 1), best, at(bi, bj + 1));
    }
    best_c += di * s;
    best_r += dj * s;
    if (last) break;
    step /= 4.0;
  }
  // A best shift at the edge of the search is no minimum the data show (a model that does not
  // describe them slides as far as it may): the component keeps its place.
  if (std::hypot(best_c, best_r) * image_pixel > radius - radius / 8.0) return fit;
  fit.fitted = true;
  fit.dcol = best_c;
  fit.drow = best_r;
  fit.samples = static_cast<int>(use.size());
  return fit;
}

}  // namespace mopad::modelling
