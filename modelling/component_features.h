#pragma once
// Internals of SM5 (modelling/components.h) shared by components*.cpp, the recogniser's
// training and the tests: catalogue models as OpenCV images, the colour pattern fed to the
// perceptron, and the augmentation that degrades a model as a scan does. OpenCV types; not
// part of the robot's public API.

#include <array>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <string>
#include <vector>

#include "common/rng.h"
#include "interfaces/object_model_catalogue.h"
#include "modelling/components.h"

namespace mopad::modelling {

/// Features of a colour box: the paper's 12-value pattern (for S of HSV and a, b of Lab, each
/// reduced to three classes by 1D k-means: the values of the two largest classes and their
/// area shares), the same 4 values for L of Lab (zero unless `lightness`), then the box's width
/// and height in metres.
inline constexpr int kPatternChannels = 4;
inline constexpr int kPatternSize = 4 * kPatternChannels + 2;
using ColourPattern = std::array<float, kPatternSize>;
/// `rgb` CV_8UC3 (R, G, B order), at least 1 x 1.
ColourPattern ComputeColourPattern(const cv::Mat& rgb, double width_m, double height_m,
                                   bool lightness = true);

/// A model's colour image (CV_8UC3, RGB), depth image (CV_32F, m) and the mask of the pixels
/// its render missed (CV_8U, 255 = nothing there: black colour and zero depth).
cv::Mat ModelColour(const interfaces::ObjectModel& m);
cv::Mat ModelDepth(const interfaces::ObjectModel& m);
cv::Mat ModelMissMask(const interfaces::ObjectModel& m);

/// `rgb` (CV_8UC3) as lit by `light` times the light it was taken in: each channel's linear
/// value scaled, clipped at white.
cv::Mat Relit(const cv::Mat& rgb, double light);

/// A model's colour image on a wall of colour `wall_rgb` (missed pixels and a `pad` metres
/// margin), resampled to `pixel` metres (INTER_AREA): CV_8UC3 RGB. The model occupies the
/// centre; its box in the result starts at pad / pixel. `light` relights the model's own
/// pixels (Relit), not the wall's: the catalogue's colours are as photographed, the wall's as
/// the scan measured it.
cv::Mat ModelColourOnWall(const interfaces::ObjectModel& m, const cv::Vec3b& wall_rgb, double pad,
                          double pixel, double light = 1.0);
/// The model's depth image with a `pad` metres margin of 0, resampled to `pixel`: CV_32F.
cv::Mat ModelDepthOnWall(const interfaces::ObjectModel& m, double pad, double pixel);

/// One augmented sample of a model as a scan would image it (ComponentTrainingParams): the
/// box of the model's size at a random pixel size, RGB CV_8UC3, with its size in metres.
struct AugmentedBox {
  cv::Mat rgb;
  double width_m = 0.0, height_m = 0.0;
};
AugmentedBox AugmentModel(const interfaces::ObjectModel& m, const ComponentTrainingParams& p,
                          CounterRng& rng);
/// Look-alike groups of the catalogue's classes: two classes are alike when their sizes agree
/// within 10 % and their colour faces, resampled to 32 x 32, differ by less than 10 (0-255
/// units, mean absolute). Returns the group of each class (0, 1, ... in first-class order).
std::vector<int> LookAlikeGroups(const interfaces::ObjectModelCatalogue& catalogue);

/// A negative ("none") sample at the size of model `m`: kind 0 plain wall, 1 a stain, 2 a
/// picture crop.
AugmentedBox AugmentNegative(const interfaces::ObjectModel& m, int kind,
                             const ComponentTrainingParams& p, CounterRng& rng);

struct ComponentRecogniser::Impl {
  interfaces::ObjectModelCatalogue catalogue;
  cv::Ptr<cv::ml::ANN_MLP> mlp;
  std::array<float, kPatternSize> mean{}, scale{};  ///< feature standardisation
  ComponentTrainingParams training;
  /// Look-alike group of each class (classes whose colour faces agree, e.g. a flush and a
  /// surface-mounted socket): the network has one output per group and one for "none".
  std::vector<int> group;
  int groups = 0;

  cv::Mat Standardise(const ColourPattern& f) const;  ///< 1 x kPatternSize CV_32F
  /// Per class (its group's output) and "none", in [0, 1].
  std::vector<float> Score(const ColourPattern& f) const;
};

}  // namespace mopad::modelling
