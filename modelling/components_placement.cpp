// SM5's placement on the samples (step 7, modelling/components.h, modelling/sample_fit.h): an
// instance's box moved to where its class's model best explains the SE's own points.
#include <algorithm>

#include "modelling/component_features.h"
#include "modelling/components.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {}  // namespace

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

}  // namespace mopad::modelling::detail
