// SM5's depth path (step 2, modelling/components.h): protrusions of the SE's high-pass depth
// matched with the classes' depth models; detections cut short by a hidden part extended, and
// placed by the known pixels.
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "modelling/component_features.h"
#include "modelling/components.h"
#include "modelling/components_internal.h"

namespace mopad::modelling::detail {
namespace {

// Two classes of one outline family, the second a longer version of the first (a four-gang
// socket of a single one): the same depth (within 25 %) and one side (within 10 %), the other
// side at least 1.3 times as long.
bool Extends(const interfaces::ObjectModel& longer, const interfaces::ObjectModel& m) {
  auto same = [](double a, double b, double tol) { return std::abs(a - b) <= tol * b; };
  return longer.mounting == m.mounting && same(longer.depth, m.depth, 0.25) &&
         ((same(longer.height, m.height, 0.1) && longer.width >= 1.3 * m.width) ||
          (same(longer.width, m.width, 0.1) && longer.height >= 1.3 * m.height));
}

// A depth detection cut short by a hidden part (furniture before the wall): where the measured
// protrusion goes on past the detection's box (beyond the filling's blur) and a longer class
// of its family, placed over the box, matches the KNOWN pixels (MaskedMatch, at least
// masked_known_min of its template known) at least as well as the detection's own class does
// there, the detection becomes the longer class (the best such). The unknown part neither
// refutes nor supports the longer class; the protrusion past the box refutes the shorter one.
// A single socket in its own shadow has no protrusion past its box and stays as it is. The
// evidence (score) stays at most the detection's own: a match that ignores the unknown part
// must not outrank, across classes, one that had to explain it.
void ExtendTruncated(const SeImages& se, const cv::Mat& hp_padded, const cv::Mat& known_padded,
                     int pad, double pixel, const interfaces::ObjectModelCatalogue& cat,
                     const ComponentParams& p, const std::function<const cv::Mat&(int)>& templ,
                     PathDetection& d) {
  const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(d.class_index)];
  std::vector<int> longer;
  for (int k = 0; k < static_cast<int>(cat.models.size()); ++k)
    if (Extends(cat.models[static_cast<std::size_t>(k)], m)) longer.push_back(k);
  const cv::Rect own = BoxRect(se, d);
  if (longer.empty() || own.area() <= 0) return;
  const cv::Point mid(own.x + own.width / 2, own.y + own.height / 2);
  const Peak self = MaskedMatch(hp_padded, known_padded, pad, templ(d.class_index),
                                cv::Rect(mid.x, mid.y, 1, 1), p.masked_known_min);
  // Past the box: outside it grown by the filling's blur there (an edge's spread) + 1 pixel.
  const int blur = static_cast<int>(std::ceil(se.blur.at<float>(mid.y, mid.x))) + 1;
  const cv::Rect near(own.x - blur, own.y - blur, own.width + 2 * blur, own.height + 2 * blur);
  const int margin = static_cast<int>(std::ceil(p.search_margin / pixel));
  PathDetection best = d;
  double best_ncc = self.score;
  for (const int k : longer) {
    const interfaces::ObjectModel& l = cat.models[static_cast<std::size_t>(k)];
    // Centres of the longer box that keep the detection's box inside it (and the margin).
    const int ex = static_cast<int>(std::ceil(0.5 * (l.width - m.width) / pixel)) + margin;
    const int ey = static_cast<int>(std::ceil(0.5 * (l.height - m.height) / pixel)) + margin;
    const Peak pk =
        MaskedMatch(hp_padded, known_padded, pad, templ(k),
                    cv::Rect(mid.x - ex, mid.y - ey, 2 * ex + 1, 2 * ey + 1), p.masked_known_min);
    if (pk.score < std::max(p.depth_ncc_min, best_ncc)) continue;
    const PathDetection e = BoxAt(k, l, pixel, pk);
    if (OverlapOfSmaller(d, e) <= p.max_class_overlap) continue;  // not the same object
    const cv::Rect box = BoxRect(se, e);
    const int past = ProtrudingSamplesIn(se, box, p) - ProtrudingSamplesIn(se, box & near, p);
    if (past < p.extend_samples) continue;
    best = e, best_ncc = pk.score;
  }
  if (best.class_index == d.class_index) return;
  const interfaces::ObjectModel& l = cat.models[static_cast<std::size_t>(best.class_index)];
  best.ncc = best_ncc;
  const double top = BoxProtrusion(se, best);
  const double agree =
      std::isfinite(top) && top > 0.0 ? std::min(top, l.depth) / std::max(top, l.depth) : 0.5;
  best.score = std::min(d.score, best_ncc * agree);
  best.samples = ProtrudingSamples(se, best, p);
  d = best;
}

// A depth detection's place: the peak of its class's NCC over the known pixels only
// (MaskedMatch, at least masked_known_min of the template known) within search_margin of where
// the plain NCC put it. The plain NCC reads what no scan saw (a shadow, a part hidden by
// furniture) as wall and pulls the template away from it; the known pixels alone do not. The
// score stays the plain NCC's: the place changes, not the evidence. Only for classes whose
// depth model is a front face (FrontFaceModel): the known pixels of a deeper object's sides
// mislead as much as the unknown ones (they move an extinguisher's place by centimetres).
void PlaceByKnownPixels(const cv::Mat& hp_padded, const cv::Mat& known_padded, int pad,
                        double pixel, const ComponentParams& p, const cv::Mat& templ,
                        PathDetection& d) {
  const double col = 0.5 * (d.col0 + d.col1), row = 0.5 * (d.row0 + d.row1);
  const int r = static_cast<int>(std::ceil(p.search_margin / pixel));
  const int c0 = static_cast<int>(std::floor(col)), r0 = static_cast<int>(std::floor(row));
  const Peak pk = MaskedMatch(hp_padded, known_padded, pad, templ,
                              cv::Rect(c0 - r, r0 - r, 2 * r + 1, 2 * r + 1), p.masked_known_min);
  if (pk.score < -1.0) return;
  const double dc = pk.col - col, dr = pk.row - row;
  d.col0 += dc, d.col1 += dc, d.row0 += dr, d.row1 += dr;
}

// An unknown area whose rim is protruding pixels alone (no wall pixel on it, not at the image
// border, not in a removed opening) lies inside an object: samples too sparse there for the filling
// (the gaps between a radiator's fins, seen from close by at a slant, hold a point in several
// centimetres while its fins' sides hold many), wider than gap_close. It takes the mean protrusion
// of its rim and counts as known. Read as wall it perforated the object, and the NCC fell below its
// floor.
void FillEnclosedHoles(const std::vector<cv::Rect>& openings, double protrusion_min, cv::Mat& hp,
                       cv::Mat& known) {
  cv::Mat labels;
  const int n = cv::connectedComponents(~known, labels, 8, CV_32S);
  if (n <= 1) return;
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  std::vector<int> count(static_cast<std::size_t>(n), 0);
  std::vector<char> open(static_cast<std::size_t>(n), 0);
  for (const cv::Rect& o : openings) {
    const cv::Rect in = o & cv::Rect(0, 0, hp.cols, hp.rows);
    for (int r = in.y; r < in.y + in.height; ++r)
      for (int c = in.x; c < in.x + in.width; ++c)
        open[static_cast<std::size_t>(labels.at<int>(r, c))] = 1;
  }
  const int rows = hp.rows, cols = hp.cols;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l > 0) {
        if (r == 0 || c == 0 || r == rows - 1 || c == cols - 1)
          open[static_cast<std::size_t>(l)] = 1;
        continue;
      }
      // A known pixel: the unknown areas beside it have it on their rim.
      const float h = hp.at<float>(r, c);
      const bool proud = h > protrusion_min;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
          const int k = labels.at<int>(rr, cc);
          if (k <= 0) continue;
          if (!proud) open[static_cast<std::size_t>(k)] = 1;
          sum[static_cast<std::size_t>(k)] += h;
          ++count[static_cast<std::size_t>(k)];
        }
    }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l <= 0 || open[static_cast<std::size_t>(l)] || count[static_cast<std::size_t>(l)] == 0)
        continue;
      hp.at<float>(r, c) =
          static_cast<float>(sum[static_cast<std::size_t>(l)] / count[static_cast<std::size_t>(l)]);
      known.at<uchar>(r, c) = 255;
    }
}

}  // namespace

std::vector<PathDetection> DepthPath(const SeImages& se, double pixel, bool ceiling,
                                     const interfaces::ObjectModelCatalogue& cat,
                                     const ComponentParams& p) {
  // An unknown pixel in a gap narrower than gap_close between protruding ones takes their
  // protrusion (a grey closing of the high-pass depth, on unknown pixels only): the wall
  // behind a radiator's fins or in an extinguisher's own shadow is hidden by the object, not a
  // hole in it, and read as wall it broke the object into fragments no class fitted and pulled
  // the NCC down. A shadow wider than gap_close stays unknown.
  cv::Mat hp = se.highpass.clone(), known;
  const int gap = 2 * static_cast<int>(std::lround(0.5 * p.gap_close / pixel)) + 1;
  if (gap >= 3) {
    cv::Mat closed;
    cv::morphologyEx(se.highpass, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(gap, gap)));
    closed.copyTo(hp, ~se.valid);
    known = se.valid | (hp > p.protrusion_min);
  } else {
    known = se.valid.clone();
  }
  FillEnclosedHoles(se.openings, p.protrusion_min, hp, known);
  cv::Mat mask = (hp > p.protrusion_min) & known;
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  CutCasings(se, p, pixel, 0, mask);
  const std::vector<cv::Rect> regions = Regions(mask, 0);
  const int pad = static_cast<int>(std::ceil((1.2 + p.template_pad * 2 + p.search_margin) / pixel));
  cv::Mat padded;
  cv::copyMakeBorder(hp, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
  std::map<int, cv::Mat> templates;
  auto templ = [&](int k) -> const cv::Mat& {
    auto it = templates.find(k);
    if (it == templates.end())
      it = templates
               .emplace(k, MaybeFlip(ModelDepthOnWall(cat.models[static_cast<std::size_t>(k)],
                                                      p.template_pad, pixel),
                                     ceiling))
               .first;
    return it->second;
  };
  std::vector<PathDetection> out;
  const int margin = static_cast<int>(std::ceil(p.search_margin / pixel));
  for (const cv::Rect& r : regions) {
    if (r.area() * pixel * pixel < p.min_region_area || TouchesOpening(se, r)) continue;
    // The filling blurs a protrusion's edges: a step of depth H crosses protrusion_min
    // sigma x Phi^-1(1 - protrusion_min / H) outside the object, about one sigma for a 4 cm
    // socket. Where the wall is sparsely sampled (sigma up to fill_sigma_max) an 8 cm high
    // four-gang socket made a 15 cm high region that no class of its size fitted.
    const double spread = se.blur.at<float>(r.y + r.height / 2, r.x + r.width / 2) * pixel;
    for (int k = 0; k < static_cast<int>(cat.models.size()); ++k) {
      const interfaces::ObjectModel& m = cat.models[static_cast<std::size_t>(k)];
      if (!MountsOn(m, ceiling) || m.depth < 1.5 * p.protrusion_min) continue;
      if (!SizeFits(r, pixel, m, p, 1.0 - p.size_tolerance, spread)) continue;
      const Peak pk = MatchAround(padded, pad, templ(k), r, margin);
      if (pk.score < p.depth_ncc_min) continue;
      PathDetection d = BoxAt(k, m, pixel, pk);
      d.ncc = pk.score;
      // NCC ignores the amplitude: a 12 mm switch and a 40 mm socket correlate alike. The
      // score weighs the NCC by how well the measured protrusion matches the class's depth.
      const double top = BoxProtrusion(se, d);
      const double agree =
          std::isfinite(top) && top > 0.0 ? std::min(top, m.depth) / std::max(top, m.depth) : 0.5;
      d.score = pk.score * agree;
      d.samples = ProtrudingSamples(se, d, p);
      out.push_back(d);
    }
  }
  if (p.masked_known_min > 0.0 && !out.empty()) {
    cv::Mat known_padded;
    cv::copyMakeBorder(known, known_padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
    for (PathDetection& d : out)
      ExtendTruncated(se, padded, known_padded, pad, pixel, cat, p, templ, d);
    for (PathDetection& d : out)
      if (FrontFaceModel(cat.models[static_cast<std::size_t>(d.class_index)]))
        PlaceByKnownPixels(padded, known_padded, pad, pixel, p, templ(d.class_index), d);
  }
  Dedupe(out);
  return out;
}

}  // namespace mopad::modelling::detail
