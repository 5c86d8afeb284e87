// SM5's colour path (step 3, modelling/components.h): regions of the SE off the wall's colour
// matched with the classes' colour models and read by the recogniser; and the colour check of
// the depth path's detections.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "modelling/component_features.h"
#include "modelling/components.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {}  // namespace

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
      // pattern alone, and as a detector it takes chance matches at shelf edges and radiator
      // fins.
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

}  // namespace mopad::modelling::detail
