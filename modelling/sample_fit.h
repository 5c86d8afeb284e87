#pragma once
// SM5's placement on the samples themselves (modelling/components.h, step 7). The paths find a
// component on the SE's orthoimage: 5 mm pixels filled between samples spaced 5-20 mm apart,
// which blurs an 8 cm socket's edges over a centimetre and leaves its centre a few millimetres
// off, most of all along a wall seen at a slant. The samples (the scan's points, never filled)
// hold that information exactly: each lies either on the object or on the wall beside it. So a
// found component is placed where its catalogue model best explains the samples near it: the
// model's height map (depth) and/or its colour face on the wall's colour (Lab), shifted over
// the SE plane, compared with every sample's depth and colour under a Cauchy loss whose scale is
// the noise measured on the wall around it (2.385 of its robust sigma: the constant of 95 %
// efficiency at Gaussian noise; Holland & Welsch 1977). An edge lies anywhere between the last
// sample on the object and the first beside it: the model is blurred by that uncertainty,
// spacing / sqrt(12), which also makes the cost smooth in the shift. A shadow holds no sample
// and so pulls nothing. The shift is searched coarse to fine over +-radius (the model blurred
// by at least each level's step), then refined by a parabola per axis.
//
// Internal to the modelling library (OpenCV types); components_placement.cpp is its user.
// Deterministic: samples in storage order, fixed search pattern.

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/frames.h"
#include "modelling/components.h"
#include "modelling/orthoimage.h"

namespace mopad::modelling {

/// The samples of one SE in its orthoimage's pixel coordinates (pixel c spans [c, c + 1), rows
/// downwards; see Orthoimage::ColU, RowV), with their depth off the SE plane (m) and colour,
/// bucketed for box queries. Samples outside the image are left out.
class SeSamples {
 public:
  SeSamples() = default;
  /// `uvd`: per point (u, v, depth) in the image's PatchFrame (m); `rgb`: one colour each
  /// (InputError when the sizes differ).
  SeSamples(const Orthoimage& image, const std::vector<Eigen::Vector3f>& uvd,
            const std::vector<std::array<std::uint8_t, 3>>& rgb);

  bool Empty() const { return col_.empty(); }
  /// Indices of the samples with col in [c0, c1) and row in [r0, r1), ascending.
  std::vector<int> In(double c0, double r0, double c1, double r1) const;
  float Col(int i) const { return col_[static_cast<std::size_t>(i)]; }
  float Row(int i) const { return row_[static_cast<std::size_t>(i)]; }
  float Depth(int i) const { return depth_[static_cast<std::size_t>(i)]; }  ///< m
  const cv::Vec3b& Rgb(int i) const { return rgb_[static_cast<std::size_t>(i)]; }

 private:
  static constexpr int kCell = 16;  // pixels per bucket side
  std::vector<float> col_, row_, depth_;
  std::vector<cv::Vec3b> rgb_;
  int cells_c_ = 0, cells_r_ = 0;
  std::vector<int> start_, order_;  // bucket b holds order_[start_[b] .. start_[b + 1])
};

/// What a sample is compared with: a model's faces in its own pixels (top row first, in the
/// orientation of the SE image), centred on the component. Either image may be empty.
struct SampleModel {
  cv::Mat depth;                     ///< CV_32F, m, protrusion (0 = the wall)
  cv::Mat colour_rgb;                ///< CV_8UC3, RGB, the model on the wall's colour
  cv::Vec3b wall_rgb;                ///< the wall's colour, beyond colour_rgb
  double pixel = 0.002;              ///< m per model pixel
  double width = 0.0, height = 0.0;  ///< m, the footprint
  double protrusion = 0.0;           ///< m, the model's depth
};

/// The fitted shift of a component (pixels of the SE image) and what it rests on.
struct SampleFit {
  bool fitted = false;  ///< false: too few samples (shift 0)
  double dcol = 0.0, drow = 0.0;
  int samples = 0;  ///< samples compared
};

/// Best shift of `model`, centred at (col, row) of an image of `image_pixel` metres, over the
/// samples near it; `spacing` is the local sample spacing there (m). Reads the place_* keys
/// and surface_band of `params` (modelling/components.h).
SampleFit FitOnSamples(const SeSamples& samples, const SampleModel& model, double col, double row,
                       double image_pixel, double spacing, const ComponentParams& params);

}  // namespace mopad::modelling
