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

/// A piece of an SE imaged on its own: `frame` is the SE's frame moved to (u0, v0) and cut to
/// the tile's extent; detections count for this tile when their centre lies in its core
/// [core_u0, core_u1) x [core_v0, core_v1) (SE frame; the last tile of a row or column closed).
struct SeTile {
  PatchFrame frame;
  double u0 = 0.0, v0 = 0.0;
  double core_u0 = 0.0, core_u1 = 0.0, core_v0 = 0.0, core_v1 = 0.0;
  bool whole = true;  ///< the SE in one image (no shift, no core test)
};

/// An SE whose image fits max_pixels is one tile; a larger one (a hall's ceiling) is cut into
/// equal cores, each grown by `overlap` on every side (clamped to the SE) so that a component
/// straddling a core's edge lies whole in the tile whose core holds its centre.
std::vector<SeTile> SeTiles(const PatchFrame& f, double pixel, int max_pixels, double overlap) {
  if ((f.width / pixel) * (f.height / pixel) <= max_pixels) {
    SeTile t;
    t.frame = f;
    t.core_u1 = f.width;
    t.core_v1 = f.height;
    return {t};
  }
  const double side = std::sqrt(static_cast<double>(max_pixels)) * pixel - 2.0 * overlap;
  if (!(side > overlap))
    throw InputError("", "components.max_image_pixels too small for a tile of the SE",
                     std::to_string(max_pixels),
                     "room for the largest catalogue model twice over at the SE pixel");
  const int nu = static_cast<int>(std::ceil(f.width / side)),
            nv = static_cast<int>(std::ceil(f.height / side));
  std::vector<SeTile> out;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      SeTile t;
      t.whole = false;
      t.core_u0 = f.width * i / nu;
      t.core_u1 = f.width * (i + 1) / nu;
      t.core_v0 = f.height * j / nv;
      t.core_v1 = f.height * (j + 1) / nv;
      t.u0 = std::max(0.0, t.core_u0 - overlap);
      t.v0 = std::max(0.0, t.core_v0 - overlap);
      t.frame = f;
      t.frame.origin = f.ToMap(t.u0, t.v0);
      t.frame.width = std::min(f.width, t.core_u1 + overlap) - t.u0;
      t.frame.height = std::min(f.height, t.core_v1 + overlap) - t.v0;
      out.push_back(t);
    }
  return out;
}

bool InCore(const SeTile& t, const PatchFrame& se, double u, double v) {
  const bool in_u = u >= t.core_u0 && (u < t.core_u1 || t.core_u1 >= se.width);
  const bool in_v = v >= t.core_v0 && (v < t.core_v1 || t.core_v1 >= se.height);
  return in_u && in_v;
}

/// The SE's openings moved into a tile's frame.
std::vector<DetectedOpening> ShiftOpenings(const std::vector<DetectedOpening>& openings,
                                           const SeTile& t) {
  std::vector<DetectedOpening> out = openings;
  for (DetectedOpening& o : out) {
    o.u0 -= t.u0;
    o.u1 -= t.u0;
    o.v0 -= t.v0;
    o.v1 -= t.v0;
  }
  return out;
}

/// The largest extent of any catalogue model, m: the overlap two tiles need.
double LargestModel(const ComponentRecogniser& recogniser) {
  double m = 0.0;
  for (const auto& model : recogniser.Catalogue().models)
    m = std::max({m, model.width, model.height});
  return m;
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
  // Every SE but the floor, in tiles of at most max_image_pixels: one task per tile (each reads
  // only its own image, the shared points and the trained recogniser), gathered in SE and tile
  // order: the same bytes on any number of threads.
  struct Task {
    std::size_t se;
    SeTile tile;
  };
  std::vector<Task> tasks;
  // A component whose centre lies in a core reaches at most half its extent past it; the other
  // half of the overlap is the context its detection reads around it.
  const double overlap = LargestModel(recogniser);
  for (std::size_t j = 0; j < sm3.patches.size(); ++j) {
    if (sm3.patches[j].patch_class == PatchClass::kFloor) continue;
    for (const SeTile& t : SeTiles(PatchFrame::Of(sm3.patches[j]), params.pixel,
                                   params.max_image_pixels, overlap))
      tasks.push_back({j, t});
  }
  std::vector<std::vector<DetectedComponent>> found(tasks.size());
  tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t i) {
    const std::size_t se = tasks[i].se;
    const SeTile& tile = tasks[i].tile;
    std::vector<Eigen::Vector3f> own_points;
    std::vector<std::array<std::uint8_t, 3>> own_colours;
    for (const std::size_t k : SePointIndices(sm3, se, *points.points, params)) {
      const Vec3 x = (*points.points)[k].cast<double>();
      if (!tile.whole && !OverExtent(tile.frame, x, 0.0)) continue;
      own_points.push_back((*points.points)[k]);
      own_colours.push_back((*points.colours)[k]);
    }
    OrthoPoints own;
    own.points = &own_points;
    own.colours = &own_colours;
    const Orthoimage image = BuildOrthoimage(own, tile.frame, op, params.pixel);
    const bool ceiling = sm3.patches[se].patch_class == PatchClass::kCeiling;
    const std::string& host = sm3.patches[se].id;
    found[i] = DetectSeComponents(image, host, ceiling,
                                  tile.whole ? sm4.openings : ShiftOpenings(sm4.openings, tile),
                                  recogniser, params, &own);
    if (tile.whole) return;
    const PatchFrame se_frame = PatchFrame::Of(sm3.patches[se]);
    std::vector<DetectedComponent> kept;
    for (DetectedComponent& d : found[i]) {
      d.u += tile.u0;
      d.v += tile.v0;
      if (InCore(tile, se_frame, d.u, d.v)) kept.push_back(std::move(d));
    }
    found[i] = std::move(kept);
  });
  for (std::size_t i = 0; i < tasks.size();) {
    // One SE's tiles together, in (u, v) order as DetectSeComponents orders one image's.
    std::size_t e = i;
    std::vector<DetectedComponent> se;
    for (; e < tasks.size() && tasks[e].se == tasks[i].se; ++e)
      for (DetectedComponent& d : found[e]) se.push_back(std::move(d));
    if (e - i > 1)
      std::stable_sort(se.begin(), se.end(), [](const auto& a, const auto& b) {
        return a.u != b.u ? a.u < b.u : a.v < b.v;
      });
    for (DetectedComponent& d : se) out.components.push_back(std::move(d));
    i = e;
  }
  for (std::size_t i = 0; i < out.components.size(); ++i)
    out.components[i].id = "bsc_" + std::to_string(i + 1);
  return out;
}

}  // namespace mopad::modelling
