// SM5 (modelling/components.h): its parameters and names, the steps on one SE in order
// (DetectSeComponents; the steps themselves in components_se_images.cpp,
// components_matching.cpp, components_depth_path.cpp, components_colour_path.cpp,
// components_consensus.cpp and components_placement.cpp), and the room's SM5.
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
#include "modelling/components_internal.h"
#include "modelling/sample_fit.h"

namespace mopad::modelling {

using detail::ApplyMarks;
using detail::Background;
using detail::ColourContradicts;
using detail::ColourPath;
using detail::DepthPath;
using detail::FillSe;
using detail::InstanceBox;
using detail::MarkSupport;
using detail::PlaceOnSamples;
using detail::SeImages;
using detail::SeLight;
using detail::SeSamplesOf;

namespace {

// x's projection onto the frame's plane lies within `margin` of its extent.
bool OverExtent(const PatchFrame& f, const Vec3& x, double margin) {
  const Vec2 uv = f.ToUv(x);
  return uv.x() >= -margin && uv.y() >= -margin && uv.x() <= f.width + margin &&
         uv.y() <= f.height + margin;
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
