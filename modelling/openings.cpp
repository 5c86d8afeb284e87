#include "modelling/openings.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "common/error.h"
#include "common/rng.h"

namespace mopad::modelling {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;
}  // namespace

void OpeningParams::Validate() const {
  ValidateParams(*this, "openings.");
  orthoimage.Validate();
  auto order = [](const char* lo_name, double lo, const char* hi_name, double hi) {
    if (lo > hi)
      throw InputError(
          "", std::string("parameter 'openings.") + lo_name + "' exceeds '" + hi_name + "'",
          std::to_string(lo), "<= " + std::to_string(hi));
  };
  order("door_min_width", door_min_width, "door_max_width", door_max_width);
  order("door_min_height", door_min_height, "door_max_height", door_max_height);
  order("window_min_width", window_min_width, "window_max_width", window_max_width);
  order("window_min_height", window_min_height, "window_max_height", window_max_height);
  order("canny_low", canny_low, "canny_high", canny_high);
  order("casing_min", casing_min, "casing_max", casing_max);
  order("leaf_v_low", leaf_v_low, "leaf_v_high", leaf_v_high);
  if (median_kernel % 2 == 0)
    throw InputError("", "parameter 'openings.median_kernel' must be odd",
                     std::to_string(median_kernel), "1, 3, 5, ...");
}

const char* ToString(OpeningType t) { return t == OpeningType::kDoor ? "door" : "window"; }

const char* ToString(DoorState s) {
  switch (s) {
    case DoorState::kClosed:
      return "closed";
    case DoorState::kSemiOpen:
      return "semi_open";
    case DoorState::kOpen:
      return "open";
  }
  return "closed";
}

DoorState DoorStateFromAngleDeg(double lambda_deg, double closed_below_deg,
                                double open_tolerance_deg) {
  if (lambda_deg >= 90.0 - open_tolerance_deg) return DoorState::kOpen;
  if (lambda_deg >= closed_below_deg) return DoorState::kSemiOpen;
  return DoorState::kClosed;
}

// ---- Step 1: wall area ----

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

namespace {

// ---- Step 2: straight lines ----

struct Line {
  double pos = 0;    // column (vertical line) or row (horizontal line), pixel index
  int a = 0, b = 0;  // extent along the other axis, inclusive
  // Where the step lies across the line, in continuous pixel coordinates (ColU/RowV take it):
  // pos + 0.5 is the edge pixel's centre (LocateEdges).
  double edge = 0;
  int Length() const { return b - a + 1; }
};

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

// The pixel (column, row) of the line at (u, v) of a rectangle's side (the inverse of ColU and
// RowV of a Line::edge; PixelOf would take the next pixel for a step on a pixel boundary).
std::array<int, 2> LinePixel(const Orthoimage& img, double u, double v) {
  const double px = img.Pixel();
  return {static_cast<int>(std::lround((u + img.Margin()) / px - 0.5)),
          static_cast<int>(std::lround(img.Rows() - (v + img.Margin()) / px - 0.5))};
}

// The step of the longest line at index i (a rectangle's side), or the pixel's centre.
double EdgeAt(const std::vector<Line>& lines, int i) {
  const Line* best = nullptr;
  for (const Line& l : lines)
    if (std::lround(l.pos) == i && (best == nullptr || l.Length() > best->Length())) best = &l;
  return best != nullptr ? best->edge : i + 0.5;
}

// Sum of a 0/1 mask over [c0, c1) x [r0, r1) from its integral image (clipped).
struct Integral {
  cv::Mat s;  // CV_32S, (rows+1) x (cols+1)
  int cols = 0, rows = 0;
  explicit Integral(const cv::Mat& mask) : cols(mask.cols), rows(mask.rows) {
    cv::integral(mask, s, CV_32S);
  }
  double Sum(int c0, int c1, int r0, int r1) const {
    c0 = std::clamp(c0, 0, cols), c1 = std::clamp(c1, 0, cols);
    r0 = std::clamp(r0, 0, rows), r1 = std::clamp(r1, 0, rows);
    if (c1 <= c0 || r1 <= r0) return 0.0;
    return s.at<int>(r1, c1) - s.at<int>(r0, c1) - s.at<int>(r1, c0) + s.at<int>(r0, c0);
  }
};

struct Candidate {
  OpeningType type = OpeningType::kDoor;
  int cl = 0, cr = 0, rt = 0, rb = 0;  // side lines: columns cl < cr, rows rt < rb (rb: bottom)
  double score = 0, known = 0, evidence = 0, through = 0, support = 0;
  bool valid = false;
};

struct Masks {
  Integral known, ev_door, ev_window, through, wall, edge_v, edge_h, hidden_v, hidden_h, flush,
      hidden;
};

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

// Scores one rectangle (see the file comment, step 3).
void Score(Candidate& k, const Masks& m, const OpeningParams& p, double px, int floor_row) {
  const int sb = std::max(1, static_cast<int>(std::lround(p.side_band / px)));
  const int ring = std::max(1, static_cast<int>(std::lround(p.ring / px)));
  const int c0 = k.cl + 1, c1 = k.cr, r0 = k.rt + 1, r1 = k.rb;
  const double area = double(c1 - c0) * (r1 - r0);
  if (area <= 0) return;
  k.known = m.known.Sum(c0, c1, r0, r1) / area;
  const Integral& ev = k.type == OpeningType::kDoor ? m.ev_door : m.ev_window;
  const double known_px = m.known.Sum(c0, c1, r0, r1);
  k.evidence = known_px > 0 ? ev.Sum(c0, c1, r0, r1) / known_px : 0.0;
  k.through = m.through.Sum(c0, c1, r0, r1) / area;
  // Frame support: edge share of each side's visible length; a side hidden over 75% of its
  // length (by a cabinet, or by the door's own opened leaf) is unknown, and one may be.
  int unknown = 0;
  double s_sum = 0.0, s_min = 1.0;
  auto side = [&](double len, double e, double hidden) {
    if (len - hidden <= 0.25 * len) {
      ++unknown;
      return;
    }
    const double s = std::min(1.0, e / (len - hidden));
    s_sum += s, s_min = std::min(s_min, s);
  };
  side(r1 - r0, m.edge_v.Sum(k.cl, k.cl + 1, r0, r1), m.hidden_v.Sum(k.cl, k.cl + 1, r0, r1));
  side(r1 - r0, m.edge_v.Sum(k.cr, k.cr + 1, r0, r1), m.hidden_v.Sum(k.cr, k.cr + 1, r0, r1));
  side(c1 - c0, m.edge_h.Sum(c0, c1, k.rt, k.rt + 1), m.hidden_h.Sum(c0, c1, k.rt, k.rt + 1));
  int sides = 3;
  if (k.type == OpeningType::kWindow) {
    side(c1 - c0, m.edge_h.Sum(c0, c1, k.rb, k.rb + 1), m.hidden_h.Sum(c0, c1, k.rb, k.rb + 1));
    ++sides;
  }
  k.support = s_sum / sides;
  const double ev_area = ev.Sum(c0, c1, r0, r1) * px * px;
  k.valid = unknown <= 1 && k.known >= p.min_known_share && k.evidence >= p.min_evidence_share &&
            ev_area >= p.min_evidence_area && s_min >= p.min_side_support;
  if (k.valid && k.type == OpeningType::kWindow) {
    // Location: a sill has wall under it.
    const int b0 = k.rb + sb + 1, b1 = std::min(b0 + ring, floor_row);
    const double band = double(c1 - c0) * std::max(0, b1 - b0);
    const double wall = m.wall.Sum(c0, c1, b0, b1);
    if (band <= 0 || wall / band < p.min_sill_wall_share) k.valid = false;
  }
  if (!k.valid) return;
  // Outside ring (left, right, top): seen-through or recessed pixels there mean the rectangle
  // is inside a larger hole (an off-colour casing around a hole is no such sign).
  const int o = sb + 1;
  const double ring_area = 2.0 * ring * (r1 - r0) + double(c1 - c0 + 2 * (o + ring)) * ring;
  const Integral& deep = m.ev_window;
  const double ring_ev = deep.Sum(k.cl - o - ring, k.cl - o + 1, r0, r1) +
                         deep.Sum(k.cr + o, k.cr + o + ring, r0, r1) +
                         deep.Sum(k.cl - o - ring, k.cr + o + ring, k.rt - o - ring, k.rt - o + 1);
  const double outer = std::clamp(ring_ev / std::max(1.0, ring_area), 0.0, 1.0);
  k.score = k.support * k.evidence * (1.0 - 0.5 * outer) * std::min(1.0, 0.5 + k.known);
}

double Overlap(const Candidate& a, const Candidate& b) {
  const int w = std::min(a.cr, b.cr) - std::max(a.cl, b.cl);
  const int h = std::min(a.rb, b.rb) - std::max(a.rt, b.rt);
  if (w <= 0 || h <= 0) return 0.0;
  const double aa = double(a.cr - a.cl) * (a.rb - a.rt), ab = double(b.cr - b.cl) * (b.rb - b.rt);
  return double(w) * h / std::min(aa, ab);
}

}  // namespace

// ---- Step 4: the door leaf ----

namespace {

// The leaf's plan line (step 4): seeded RANSAC over lines through a jamb, then least squares on
// the inliers of all points, twice. Sets the line (a, dir) and its inliers; false if none.
bool FitLeafLine(const std::vector<Vec2>& pts, double u0, double u1, const OpeningParams& p,
                 std::uint64_t index, Vec2& a, Vec2& dir, std::vector<Vec2>& inl) {
  std::vector<Vec2> sample;
  const std::size_t stride = std::max<std::size_t>(1, pts.size() / p.leaf_max_points);
  for (std::size_t i = 0; i < pts.size(); i += stride) sample.push_back(pts[i]);
  // A leaf's line passes a jamb: the segment u = u_j, depth in [-max_wall_thickness,
  // leaf_hinge_front] (hinged on this face or on the far one).
  auto near_jamb = [&](const Vec2& a, const Vec2& dir) {
    for (double uj : {u0, u1}) {
      if (std::abs(dir.x()) > 1e-6) {
        const double t = (uj - a.x()) / dir.x();
        const double d = a.y() + t * dir.y();
        if (d >= -p.max_wall_thickness && d <= p.leaf_hinge_front) return true;
      }
      const Vec2 nrm(-dir.y(), dir.x());
      for (double dj : {-p.max_wall_thickness, p.leaf_hinge_front})
        if (std::abs(nrm.dot(Vec2(uj, dj) - a)) < p.leaf_jamb_reach) return true;
    }
    return false;
  };
  // Hypotheses scored by the truncated quadratic (MSAC, Torr & Zisserman 2000), not by the
  // inlier count: both faces of a thick leaf may be seen, and a line crossing diagonally from
  // one face to the other collects as many points within the band as a face does, but
  // farther from the line.
  CounterRng rng(p.seed, "sm4_leaf", index);
  double best = 0.0;
  const double inv_band2 = 1.0 / (p.leaf_inlier * p.leaf_inlier);
  Vec2 best_a = Vec2::Zero(), best_dir = Vec2::UnitX();
  const std::size_t n = sample.size();
  for (int it = 0; it < p.leaf_iterations; ++it) {
    const std::size_t i = static_cast<std::size_t>(rng.Uniform() * n) % n;
    const std::size_t j = static_cast<std::size_t>(rng.Uniform() * n) % n;
    const Vec2 dv = sample[j] - sample[i];
    if (dv.norm() < 0.05) continue;
    const Vec2 dir = dv.normalized();
    if (!near_jamb(sample[i], dir)) continue;
    const Vec2 nrm(-dir.y(), dir.x());
    double c = 0.0;
    for (const auto& q : sample) {
      const double r = nrm.dot(q - sample[i]);
      c += std::max(0.0, 1.0 - r * r * inv_band2);
    }
    if (c > best) best = c, best_a = sample[i], best_dir = dir;
  }
  if (best <= 0.0) return false;
  // Least squares on the inliers of all points, twice.
  a = best_a, dir = best_dir;
  for (int round = 0; round < 2; ++round) {
    const Vec2 nrm(-dir.y(), dir.x());
    inl.clear();
    for (const auto& q : pts)
      if (std::abs(nrm.dot(q - a)) <= p.leaf_inlier) inl.push_back(q);
    if (inl.size() < 3) return false;
    Vec2 mean = Vec2::Zero();
    for (const auto& q : inl) mean += q;
    mean /= static_cast<double>(inl.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& q : inl) cov += (q - mean) * (q - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    a = mean;
    dir = es.eigenvectors().col(1).normalized();
  }
  // The least squares may carry a hypothesis through a jamb onto a stronger surface nearby (a
  // side wall beside the door, perpendicular like a leaf at 90 deg): a leaf hinges at a jamb,
  // so the fitted line must still pass one.
  return near_jamb(a, dir);
}

// One leaf fit (step 4) on plan points (u, depth) of a door [u0, u1] of width w; `far_face`
// is the depth of the wall's far face where its reveals gave it (< 0), else NaN.
// With `fixed` (a point and a unit direction), the line is taken as given: no RANSAC, no
// least squares; the run, hinge and lambda follow from `pts` along it.
LeafFit FitLeafPoints(const std::vector<Vec2>& pts, double u0, double u1, double w, double far_face,
                      const OpeningParams& p, std::uint64_t index,
                      const std::pair<Vec2, Vec2>* fixed = nullptr) {
  LeafFit out;
  if (static_cast<int>(pts.size()) < p.leaf_min_points) return out;
  Vec2 a, dir;
  std::vector<Vec2> inl;
  if (fixed != nullptr) {
    a = fixed->first, dir = fixed->second;
    const Vec2 nrm(-dir.y(), dir.x());
    for (const auto& q : pts)
      if (std::abs(nrm.dot(q - a)) <= p.leaf_inlier) inl.push_back(q);
    if (inl.size() < 3) return out;
  } else if (!FitLeafLine(pts, u0, u1, p, index, a, dir, inl)) {
    return out;
  }
  out.line_point = a, out.line_dir = dir;
  // The leaf is the most populated run of inliers along the line without a gap over 10 cm
  // (other surfaces on the same line, e.g. a reveal or far furniture, are not the leaf).
  std::vector<double> ts;
  for (const auto& q : inl) ts.push_back(dir.dot(q - a));
  std::sort(ts.begin(), ts.end());
  std::size_t run_begin = 0, best_begin = 0, best_end = 0;
  for (std::size_t i = 1; i <= ts.size(); ++i) {
    if (i == ts.size() || ts[i] - ts[i - 1] > p.leaf_run_gap) {
      if (i - run_begin > best_end - best_begin) best_begin = run_begin, best_end = i;
      run_begin = i;
    }
  }
  const double t0 = ts[best_begin], t1 = ts[best_end - 1];
  out.inliers = static_cast<int>(best_end - best_begin);
  out.extent = t1 - t0;
  // Hinge end: the end nearer a jamb's hinge line. A hinge stands at a jamb on one of the
  // wall's faces: at depth 0 or at the far face where the reveals gave it, else anywhere on
  // the jamb segment [-max_wall_thickness, leaf_hinge_front].
  const Vec2 e0 = a + t0 * dir, e1 = a + t1 * dir;
  auto jamb_dist = [&](const Vec2& e, double* uj_out) {
    double best_d = 1e300;
    for (double uj : {u0, u1}) {
      double dist;
      if (std::isnan(far_face)) {
        const double dd = std::clamp(e.y(), -p.max_wall_thickness, p.leaf_hinge_front);
        dist = (e - Vec2(uj, dd)).norm();
      } else {
        dist = std::min((e - Vec2(uj, 0.0)).norm(), (e - Vec2(uj, far_face)).norm());
      }
      if (dist < best_d) best_d = dist, *uj_out = uj;
    }
    return best_d;
  };
  double uj0 = u0, uj1 = u0;
  const double d0 = jamb_dist(e0, &uj0), d1 = jamb_dist(e1, &uj1);
  // A run that starts at a jamb is a leaf even when the rest of it is hidden (seen through
  // the hole at a slant); a run that does not must span more of the width.
  const double min_extent =
      (std::min(d0, d1) <= p.leaf_jamb_reach ? p.leaf_min_extent_hinged : p.leaf_min_extent) * w;
  if (out.inliers < p.leaf_min_points || out.extent < min_extent) {
    out.inliers = 0;
    return out;
  }
  Vec2 hinge = d0 <= d1 ? e0 : e1, free_end = d0 <= d1 ? e1 : e0;
  double uj = d0 <= d1 ? uj0 : uj1;
  out.hinge_u = hinge.x();
  // The line itself passes its hinge: where it passes one jamb's hinge and not the other's
  // (the leaf is not along the wall), that jamb holds the hinge, the hinge is the line's point
  // nearest it, and the leaf runs from there towards its seen points. The seen run's ends say
  // less: only the part near the free end may be seen (through the hole at a slant, or past
  // an occluder), and its far end may then lie nearer the other jamb.
  const Vec2 nrm(-dir.y(), dir.x());
  auto line_hinge = [&](double uj_c, Vec2* h) {
    // Distance from the line to the jamb's hinge points (depth 0 and the far face where the
    // reveals gave it, else the jamb segment), and the line's point nearest them.
    std::vector<Vec2> cand;
    if (std::isnan(far_face)) {
      if (std::abs(dir.x()) > 1e-9) {
        const double d_cross = a.y() + (uj_c - a.x()) / dir.x() * dir.y();
        if (d_cross >= -p.max_wall_thickness && d_cross <= p.leaf_hinge_front) {
          *h = Vec2(uj_c, d_cross);
          return 0.0;
        }
      }
      cand = {Vec2(uj_c, -p.max_wall_thickness), Vec2(uj_c, p.leaf_hinge_front)};
    } else {
      cand = {Vec2(uj_c, 0.0), Vec2(uj_c, far_face)};
    }
    double best_d = 1e300;
    for (const Vec2& c : cand) {
      const double d = std::abs(nrm.dot(c - a));
      if (d < best_d) best_d = d, *h = a + dir.dot(c - a) * dir;
    }
    return best_d;
  };
  Vec2 h0, h1;
  const double l0 = line_hinge(u0, &h0), l1 = line_hinge(u1, &h1);
  if (std::min(l0, l1) <= p.leaf_jamb_reach && std::max(l0, l1) > p.leaf_jamb_reach) {
    uj = l0 <= l1 ? u0 : u1;
    hinge = l0 <= l1 ? h0 : h1;
    free_end = 0.5 * (e0 + e1);
    out.hinge_u = hinge.x();
  }
  // lambda: the angle between the wall's direction from the hinge jamb into the opening and
  // the leaf's direction from its hinge to its free end, in [0, 180] deg (over 90 deg when it
  // has swung past the hinge jamb). From the line's direction, not from the ends' positions:
  // only part of the leaf may be seen.
  const bool left = std::abs(uj - u0) <= std::abs(uj - u1);
  Vec2 leaf_dir = dir;
  if (leaf_dir.dot(free_end - hinge) < 0.0) leaf_dir = -leaf_dir;
  const double along_wall = left ? leaf_dir.x() : -leaf_dir.x();
  out.lambda_deg = std::atan2(std::abs(leaf_dir.y()), along_wall) * kRadToDeg;
  return out;
}

// Removes the reveals of the jambs u0 and u1 from plan points (u, depth): behind the wall's
// face (depth < -flush_depth) the reveal is the plan line u = u_r, u_r the densest 5 mm bin of
// the points within reveal_search of the jamb (on its half of the opening) and less than 5 cm
// behind the surface layer (only the wall's slab is there: a leaf hinges outside its casing,
// and walls are at least 10 cm thick), followed from the face into the wall while its
// points continue (gaps < leaf_run_gap). A leaf at 90 deg beside it is a leaf's thickness away.
// Returns each reveal's u_r where one is found, else NaN, and the wall's far face: the depth
// the deeper reveal reaches (NaN when none is found).
struct Reveals {
  std::array<double, 2> u{std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::quiet_NaN()};
  double far_face = std::numeric_limits<double>::quiet_NaN();
};
Reveals RemoveReveals(std::vector<Vec2>& pts, double u0, double u1, const OpeningParams& p) {
  Reveals jambs;
  constexpr double kBin = 0.005, kSlabProbe = 0.05;
  std::vector<std::uint8_t> drop(pts.size(), 0);
  const double mid = 0.5 * (u0 + u1);
  for (double uj : {u0, u1}) {
    // The search window: reveal_search either side of the jamb, not past the middle.
    const double lo = uj < mid ? uj - p.reveal_search : std::max(mid, uj - p.reveal_search);
    const double hi = uj < mid ? std::min(mid, uj + p.reveal_search) : uj + p.reveal_search;
    const int nb = static_cast<int>(std::ceil((hi - lo) / kBin)) + 1;
    std::vector<int> hist(nb, 0);
    for (const Vec2& q : pts)
      if (q.y() < -p.flush_depth && q.y() >= -p.flush_depth - kSlabProbe && q.x() >= lo &&
          q.x() <= hi)
        ++hist[static_cast<int>((q.x() - lo) / kBin)];
    int best = -1;
    for (int b = 0; b < nb; ++b)
      if (hist[b] > 0 && (best < 0 || hist[b] > hist[best])) best = b;
    if (best < 0 || hist[best] < 10) continue;
    const double u_bin = lo + (best + 0.5) * kBin;
    double sum = 0.0;
    int n = 0;
    for (const Vec2& q : pts)
      if (q.y() < -p.flush_depth && q.y() >= -p.flush_depth - kSlabProbe &&
          std::abs(q.x() - u_bin) <= p.reveal_band)
        sum += q.x(), ++n;
    const double u_r = sum / std::max(1, n);
    jambs.u[uj < mid ? 0 : 1] = u_r;
    // Follow the line from the face into the wall.
    std::vector<std::pair<double, std::size_t>> line;  // (-depth, index)
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (pts[i].y() < -p.flush_depth && std::abs(pts[i].x() - u_r) <= p.reveal_band)
        line.push_back({-pts[i].y(), i});
    std::sort(line.begin(), line.end());
    double last = p.flush_depth;
    for (const auto& [dd, i] : line) {
      if (dd - last > p.leaf_run_gap) break;
      drop[i] = 1, last = dd;
    }
    if (!(jambs.far_face <= -last)) jambs.far_face = -last;
  }
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!drop[i]) pts[k++] = pts[i];
  pts.resize(k);
  return jambs;
}

// The lintel's underside from the slab's points near a door's top (u, v, depth; u inside the
// rectangle): of those in the hole's middle 80 % and in front of the wall's far face (where the
// reveals gave it), the densest 5 mm bin in v within lintel_search of v1; its v is the mean of
// the points within reveal_band of the bin's centre. NaN when the bin holds fewer than
// lintel_min_points or less than lintel_peak_ratio times the window's mean bin (a leaf or a
// far-side surface spreads over the heights; a lintel's face is one height).
double LintelV(const std::vector<Vec3>& pts, double u0, double u1, double v1, double far_face,
               const OpeningParams& p) {
  constexpr double kBin = 0.005;
  const double m = 0.1 * (u1 - u0);
  const double lo = v1 - p.lintel_search;
  const int nb = std::max(1, static_cast<int>(std::ceil(2.0 * p.lintel_search / kBin)));
  std::vector<int> hist(static_cast<std::size_t>(nb), 0);
  std::vector<Vec2> kept;  // (v, u)
  int total = 0;
  for (const Vec3& q : pts) {
    if (q.x() < u0 + m || q.x() > u1 - m) continue;
    if (!std::isnan(far_face) && q.z() < far_face + 0.01) continue;
    const int b = std::clamp(static_cast<int>((q.y() - lo) / kBin), 0, nb - 1);
    ++hist[static_cast<std::size_t>(b)], ++total;
    kept.push_back({q.y(), q.x()});
  }
  int best = 0;
  for (int b = 1; b < nb; ++b)
    if (hist[static_cast<std::size_t>(b)] > hist[static_cast<std::size_t>(best)]) best = b;
  const int peak = hist[static_cast<std::size_t>(best)];
  if (peak < p.lintel_min_points || peak < p.lintel_peak_ratio * total / nb)
    return std::numeric_limits<double>::quiet_NaN();
  const double centre = lo + (best + 0.5) * kBin;
  double sum = 0.0;
  int n = 0;
  for (const Vec2& q : kept)
    if (std::abs(q.x() - centre) <= p.reveal_band) sum += q.x(), ++n;
  return sum / n;
}

// The room's points as one wall's door steps read them: OrthoPoints and, optionally, each
// point's u along the wall (float) for a quick range test, so that a door's leaf and front are
// sought among the points beside it instead of all the room's. Without u every point is read.
struct WallPoints {
  const OrthoPoints& in;
  std::vector<float> u;
};

WallPoints AlongWall(const OrthoPoints& in, const PatchFrame& f) {
  WallPoints w{in, {}};
  if (in.points == nullptr) return w;
  w.u.reserve(in.points->size());
  for (const auto& pf : *in.points)
    w.u.push_back(static_cast<float>(f.ToUv(pf.cast<double>()).x()));
  return w;
}

// Calls visit(q) for each point q (map frame) whose u may lie in [lo, hi], in point order: all
// points when w has no u, else those whose float u is within [lo, hi] widened by its rounding.
// The caller applies its exact test to q, so the points it keeps, and their order, are those of
// a pass over all points.
template <class F>
void ForPointsInU(const WallPoints& w, double lo, double hi, F&& visit) {
  const auto& pts = *w.in.points;
  if (w.u.empty()) {
    for (const auto& pf : pts) visit(pf.cast<double>());
    return;
  }
  const double tol = 1e-3 + 1e-6 * std::max(std::abs(lo), std::abs(hi));
  const float a = static_cast<float>(lo - tol), b = static_cast<float>(hi + tol);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (w.u[i] >= a && w.u[i] <= b) visit(pts[i].cast<double>());
}

LeafFit FitLeafNear(const WallPoints& wp, const PatchFrame& frame, double u0, double u1, double v0,
                    double v1, const OpeningParams& p, std::uint64_t index) {
  LeafFit out;
  double w = u1 - u0;
  const double h = v1 - v0;
  if (wp.in.points == nullptr || !(w > 0) || !(h > 0)) return out;
  std::vector<Vec2> pts;     // (u, depth)
  std::vector<Vec3> lintel;  // (u, v, depth): behind the surface layer near the top
  // The lintel's u range (u0, u1) lies inside the leaf's.
  ForPointsInU(wp, u0 - p.leaf_u_margin * w, u1 + p.leaf_u_margin * w, [&](const Vec3& q) {
    const Vec2 uv = frame.ToUv(q);
    if (std::abs(uv.y() - v1) <= p.lintel_search && uv.x() > u0 && uv.x() < u1) {
      const double d = frame.Depth(q);
      if (d < -p.flush_depth && d >= -p.max_wall_thickness) lintel.push_back({uv.x(), uv.y(), d});
    }
    if (uv.y() < v0 + p.leaf_v_low * h || uv.y() > v0 + p.leaf_v_high * h) return;
    if (uv.x() < u0 - p.leaf_u_margin * w || uv.x() > u1 + p.leaf_u_margin * w) return;
    const double d = frame.Depth(q);
    if (d < -(w + p.max_wall_thickness) || d > w + p.leaf_hinge_front) return;
    // The wall and its casing beside the opening are not the leaf.
    if (std::abs(d) <= p.flush_depth && (uv.x() < u0 + 0.02 || uv.x() > u1 - 0.02)) return;
    pts.push_back({uv.x(), d});
  });
  // The leaf hinges at a jamb: the reveals where seen (an opened leaf may hide a jamb's edge
  // in the images), else the rectangle's sides.
  const Reveals rv = RemoveReveals(pts, u0, u1, p);
  const std::array<double, 2> reveals = rv.u;
  out.reveal_u = reveals;
  const double j0 = std::isnan(reveals[0]) ? u0 : reveals[0];
  const double j1 = std::isnan(reveals[1]) ? u1 : reveals[1];
  if (j1 - j0 > 0.5 * w) u0 = j0, u1 = j1, w = u1 - u0;
  const double lintel_v = LintelV(lintel, u0, u1, v1, rv.far_face, p);
  out.lintel_v = lintel_v;
  // The leaf first from the points off the wall's surface layer: a casing beside a door whose
  // rectangle came out too wide, or the floor-level reveal, would tilt a line through the leaf;
  // only a leaf flush with the wall (closed, on this side) needs the layer.
  std::vector<Vec2> deep;
  for (const Vec2& q : pts)
    if (std::abs(q.y()) > p.flush_depth) deep.push_back(q);
  LeafFit first = FitLeafPoints(deep, u0, u1, w, rv.far_face, p, index);
  first.reveal_u = reveals;
  first.lintel_v = lintel_v;
  if (first.inliers == 0) {
    // The surface layer serves a leaf lying in it (closed); a steeper line through it mixes
    // the casing and the reveal's face end with what little is seen of an opened leaf.
    LeafFit flush = FitLeafPoints(pts, u0, u1, w, rv.far_face, p, index);
    if (flush.inliers > 0 && !(flush.lambda_deg < p.closed_below_deg)) flush = LeafFit{};
    flush.reveal_u = reveals;
    flush.lintel_v = lintel_v;
    return flush;
  }
  // Its run, hinge and width from all the points along that line (the part near the hinge is
  // on the surface layer).
  // Only on the leaf's side of the wall: the reveal behind a leaf opened into the room (or in
  // front of one opened away) lies on the same line.
  const double side = first.line_point.y() >= 0.0 ? 1.0 : -1.0;
  std::vector<Vec2> same_side;
  for (const Vec2& q : pts)
    if (side * q.y() >= -p.flush_depth) same_side.push_back(q);
  const std::pair<Vec2, Vec2> line{first.line_point, first.line_dir};
  LeafFit along = FitLeafPoints(same_side, u0, u1, w, rv.far_face, p, index, &line);
  along.reveal_u = reveals;
  along.lintel_v = lintel_v;
  return along.inliers > 0 ? along : first;
}

}  // namespace

LeafFit FitDoorLeaf(const OrthoPoints& in, const PatchFrame& frame, double u0, double u1, double v0,
                    double v1, const OpeningParams& p, std::uint64_t index) {
  return FitLeafNear(WallPoints{in, {}}, frame, u0, u1, v0, v1, p, index);
}

// ---- Steps 1-4 for one wall ----

namespace {

// Step 2-3 inputs for one wall: J_C, J_D and the evidence mask as edge images (Canny after a
// median), and the integral images of the masks the rectangle tests sum over.
// Pixels without points take the wall's colour and depth: a hole's outline is a line of the
// evidence mask, and the scan-line gaps of sparse data or the speckle of glass returns must
// not make lines in J_C and J_D (a 5x5 median removes what speckle is left).
struct WallEdges {
  cv::Mat edge01;  // 1 where any of the three images has an edge
  Masks m;
  // |d/dcol| and |d/drow| of the three images (3x3 Sobel, each scaled to 1 for a full-range
  // step, summed; CV_32F): where across a line its step lies (LocateEdges).
  cv::Mat grad_c, grad_r;
};

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
                Integral(hid_h), Integral(flush),   Integral(hidden)};
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

// Step 3: rectangles from pairs of vertical lines and one (door, down to the floor) or two
// (window, with a sill) horizontal lines, within the typical sizes, scored (Score).
std::vector<Candidate> RectangleCandidates(const std::vector<Line>& vert,
                                           const std::vector<Line>& horz, const Masks& m,
                                           const OpeningParams& p, double px, int floor_row) {
  std::vector<Candidate> cands;
  const int ring_px = std::max(1, static_cast<int>(std::lround(p.ring / px)));
  // Horizontal lines across at least half the width strictly inside (consistency, step 3).
  auto interior_lines = [&](int cl, int cr, int rt, int rb) {
    int n = 0;
    for (const Line& l : horz)
      if (l.pos > rt + ring_px && l.pos < rb - ring_px &&
          std::min(l.b, cr) - std::max(l.a, cl) >= 0.5 * (cr - cl))
        ++n;
    return n;
  };
  // Length of [cl, cr] covered by the horizontal lines within 2 pixels of row `pos`.
  auto row_cover = [&](double pos, int cl, int cr) {
    int n = 0;
    for (const Line& l : horz)
      if (std::abs(l.pos - pos) <= 2.0) n += std::max(0, std::min(l.b, cr) - std::max(l.a, cl));
    return std::min(n, cr - cl);
  };
  for (std::size_t a = 0; a < vert.size(); ++a)
    for (std::size_t b = a + 1; b < vert.size(); ++b) {
      const int cl = static_cast<int>(std::lround(vert[a].pos)),
                cr = static_cast<int>(std::lround(vert[b].pos));
      const double width = (cr - cl) * px;
      if (width < std::min(p.door_min_width, p.window_min_width)) continue;
      if (width > std::max(p.door_max_width, p.window_max_width)) continue;
      for (std::size_t ti = 0; ti < horz.size(); ++ti) {
        const Line& t = horz[ti];
        const int rt = static_cast<int>(std::lround(t.pos));
        if (ti > 0 && std::lround(horz[ti - 1].pos) == rt) continue;  // one row once
        // The top line spans at least half the width between the sides (its pieces together:
        // an opened leaf may hide its middle).
        if (row_cover(t.pos, cl, cr) < 0.5 * (cr - cl)) continue;
        // Door: bottom at the floor.
        const double dh = (floor_row - rt) * px;
        if (width >= p.door_min_width && width <= p.door_max_width && dh >= p.door_min_height &&
            dh <= p.door_max_height) {
          Candidate k;
          k.type = OpeningType::kDoor, k.cl = cl, k.cr = cr, k.rt = rt, k.rb = floor_row;
          if (interior_lines(cl, cr, rt, floor_row) <= p.max_interior_lines)
            Score(k, m, p, px, floor_row);
          if (k.valid) cands.push_back(k);
        }
        if (width < p.window_min_width || width > p.window_max_width) continue;
        for (std::size_t bi = 0; bi < horz.size(); ++bi) {
          const Line& bl = horz[bi];
          const int rb = static_cast<int>(std::lround(bl.pos));
          if (bi > 0 && std::lround(horz[bi - 1].pos) == rb) continue;
          const double wh = (rb - rt) * px, sill = (floor_row - rb) * px;
          if (wh < p.window_min_height || wh > p.window_max_height || sill < p.min_sill) continue;
          if (row_cover(bl.pos, cl, cr) < 0.5 * (cr - cl)) continue;
          Candidate k;
          k.type = OpeningType::kWindow, k.cl = cl, k.cr = cr, k.rt = rt, k.rb = rb;
          if (interior_lines(cl, cr, rt, rb) <= p.max_interior_lines) Score(k, m, p, px, floor_row);
          if (k.valid) cands.push_back(k);
        }
      }
    }
  return cands;
}

// Best first (ties: position), non-maximum suppression by overlap; then the hole, not the
// casing, for each kept rectangle.
std::vector<Candidate> KeepHoles(const std::vector<Candidate>& cands, const Masks& m,
                                 const OpeningParams& p, double px) {
  std::vector<std::size_t> order(cands.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return cands[x].score > cands[y].score; });
  std::vector<Candidate> kept;
  for (std::size_t oi : order) {
    const Candidate& k = cands[oi];
    bool clash = false;
    for (const Candidate& q : kept)
      if (Overlap(k, q) > p.max_overlap) clash = true;
    if (!clash) kept.push_back(k);
  }
  // The hole, not the casing: the valid rectangle inside a kept one whose every side is either
  // the same line, or inset by a casing's width over a strip on the wall's surface (a casing),
  // or inset over a strip mostly hidden (an occlusion boundary is no frame); most insets first,
  // then the largest (the casing's inner edge, not a line further in).
  const int in_min = static_cast<int>(std::lround(p.casing_min / px));
  const int in_max = static_cast<int>(std::lround(p.casing_max / px));
  auto strip_ok = [&](int inset, int c0, int c1, int r0, int r1, int* moved) {
    if (inset < 0) return false;
    if (inset <= 1) return true;
    const double a = double(std::max(0, c1 - c0)) * std::max(0, r1 - r0);
    if (a <= 0) return false;
    ++*moved;
    const double hidden = m.hidden.Sum(c0, c1, r0, r1), seen = a - hidden;
    if (inset >= in_min && inset <= in_max && seen >= 0.2 * a &&
        m.flush.Sum(c0, c1, r0, r1) >= p.min_casing_share * seen)
      return true;
    return hidden >= p.min_casing_share * a;
  };
  for (Candidate& k : kept) {
    const Candidate* best = nullptr;
    int best_moved = 0;
    for (const Candidate& q : cands) {
      if (q.type != k.type) continue;
      int moved = 0;
      const bool ok = strip_ok(q.cl - k.cl, k.cl + 1, q.cl, q.rt, q.rb, &moved) &&
                      strip_ok(k.cr - q.cr, q.cr + 1, k.cr, q.rt, q.rb, &moved) &&
                      strip_ok(q.rt - k.rt, k.cl, k.cr, k.rt + 1, q.rt, &moved) &&
                      (k.type == OpeningType::kDoor ||
                       strip_ok(k.rb - q.rb, k.cl, k.cr, q.rb + 1, k.rb, &moved));
      if (!ok || moved == 0) continue;
      const auto area = [](const Candidate& c) { return double(c.cr - c.cl) * (c.rb - c.rt); };
      if (best == nullptr || moved > best_moved || (moved == best_moved && area(q) > area(*best)))
        best = &q, best_moved = moved;
    }
    if (best != nullptr) {
      const double conf = k.score;
      k = *best;
      k.score = std::max(conf, best->score);
    }
  }
  std::sort(kept.begin(), kept.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.cl, x.rt) < std::tie(y.cl, y.rt);
  });
  return kept;
}

// Step 4 for one door rectangle o (u0, u1, v0, v1 set; known_share and through_share of its
// interior set): its leaf (angle, state, clear width), its sides moved to its reveals where
// they were seen, widened to the leaf where it is wider. `index` keys the leaf's RANSAC stream.
LeafFit FitDoor(DetectedOpening& o, const std::vector<Line>& vert, const Orthoimage& img,
                const WallPoints& points, const OpeningParams& p, std::uint64_t index) {
  const PatchFrame& f = img.Frame();
  const LeafFit leaf = FitLeafNear(points, f, o.u0, o.u1, o.v0, o.v1, p, index);
  o.leaf_points = leaf.inliers;
  o.leaf_line_point = leaf.line_point, o.leaf_line_dir = leaf.line_dir;
  // The hole's sides are its reveals where they were seen (an opened leaf or a casing of
  // the wall's colour may have moved a side's line in the images).
  if (!std::isnan(leaf.reveal_u[0])) o.u0 = leaf.reveal_u[0];
  if (!std::isnan(leaf.reveal_u[1])) o.u1 = leaf.reveal_u[1];
  if (!std::isnan(leaf.lintel_v)) o.v1 = leaf.lintel_v;
  // The leaf is as wide as the hole: a rectangle narrower than the leaf (its latch jamb
  // hidden behind the opened leaf, the leaf's free edge taken for it) widens to the leaf's
  // width from the hinge jamb, to the nearest vertical line within 5 cm if there is one.
  if (leaf.inliers > 0 && leaf.extent > o.Width() + p.leaf_widen_margin) {
    const bool hinge_high = leaf.hinge_u > 0.5 * (o.u0 + o.u1);
    auto snap = [&](double u) {
      double best_d = 0.05, out_u = u;
      for (const Line& l : vert) {
        const double lu = img.ColU(l.edge);
        if (std::abs(lu - u) < best_d) best_d = std::abs(lu - u), out_u = lu;
      }
      return out_u;
    };
    const double hinge = snap(leaf.hinge_u);
    const double latch = snap(hinge_high ? leaf.hinge_u - leaf.extent : leaf.hinge_u + leaf.extent);
    o.u0 = std::min(o.u0, std::min(hinge, latch));
    o.u1 = std::max(o.u1, std::max(hinge, latch));
  }
  o.corners = {f.ToMap(o.u0, o.v0), f.ToMap(o.u1, o.v0), f.ToMap(o.u1, o.v1), f.ToMap(o.u0, o.v1)};
  o.opening_angle_deg = std::numeric_limits<double>::quiet_NaN();
  if (leaf.inliers > 0) {
    o.opening_angle_deg = leaf.lambda_deg;
    o.state = DoorStateFromAngleDeg(leaf.lambda_deg, p.closed_below_deg, p.open_tolerance_deg);
  } else {
    // No leaf seen: open if the robot saw through most of what it saw of it, else closed
    // (its leaf is the wall's colour and flush, or hidden).
    const double through_of_known = o.known_share > 0.0 ? o.through_share / o.known_share : 0.0;
    o.state = through_of_known >= p.open_through_share ? DoorState::kOpen : DoorState::kClosed;
  }
  if (o.state == DoorState::kClosed) {
    o.clear_width_m = 0.0;
  } else {
    const double lam = std::isnan(o.opening_angle_deg) ? 90.0 : o.opening_angle_deg;
    const double l = lam / kRadToDeg;
    const double intrusion =
        std::max(0.0, o.Width() * std::cos(l)) + p.leaf_thickness * std::sin(l);
    o.clear_width_m = std::max(0.0, o.Width() - intrusion);
  }
  return leaf;
}

// A door side beside hidden pixels (occluded, or protruding: an opened leaf in front) is an
// occlusion boundary, not a jamb: the doorway may go on behind the occluder. Each such side of
// k moves out to the nearest vertical line beyond it where the wall resumes (its outside strip
// on the wall's surface, min_casing_share of it), the strip crossed being hole-like (hidden or
// evidence over min_evidence_share of it, over the door's height) and the door no wider than
// door_max_width. Returns which sides moved (bit 0: left, bit 1: right).
int ExtendOccludedSides(Candidate& k, const std::vector<Line>& vert, const Masks& m,
                        const OpeningParams& p, double px) {
  const int ring = std::max(1, static_cast<int>(std::lround(p.ring / px)));
  const int max_w = static_cast<int>(std::lround(p.door_max_width / px));
  const int r0 = k.rt + 1, r1 = k.rb;
  if (r1 <= r0) return 0;
  const auto share = [&](const Integral& in, int c0, int c1) {
    const double a = double(std::max(0, c1 - c0)) * (r1 - r0);
    return a > 0 ? in.Sum(c0, c1, r0, r1) / a : 0.0;
  };
  int moved = 0;
  for (int dir : {-1, +1}) {
    const int side = dir < 0 ? k.cl : k.cr;
    const int out0 = dir < 0 ? side - ring : side + 1, out1 = dir < 0 ? side : side + 1 + ring;
    if (share(m.hidden, out0, out1) < 0.5) continue;
    int best = -1;
    for (const Line& l : vert) {
      const int c = static_cast<int>(std::lround(l.pos));
      if (dir < 0 ? c >= side - 1 : c <= side + 1) continue;
      if ((dir < 0 ? k.cr - c : c - k.cl) > max_w) continue;
      if (std::min(l.b, r1) - std::max(l.a, r0) < 0.5 * (r1 - r0)) continue;  // a jamb's line
      const int x0 = dir < 0 ? c + 1 : side + 1, x1 = dir < 0 ? side : c;
      if (share(m.hidden, x0, x1) + share(m.ev_door, x0, x1) < p.min_evidence_share) continue;
      const int o0 = dir < 0 ? c - ring : c + 1, o1 = dir < 0 ? c : c + 1 + ring;
      if (share(m.flush, o0, o1) < p.min_casing_share) continue;
      if (best < 0 || std::abs(c - side) < std::abs(best - side)) best = c;
    }
    if (best < 0) continue;
    (dir < 0 ? k.cl : k.cr) = best;
    moved |= dir < 0 ? 1 : 2;
  }
  return moved;
}

// Step 4 and the file's fields: each kept rectangle as an opening in the wall's frame, doors
// with their leaf (FitDoor).
std::vector<DetectedOpening> ToOpenings(const std::vector<Candidate>& kept,
                                        const std::vector<Line>& vert,
                                        const std::vector<Line>& horz, const Masks& m,
                                        const Orthoimage& img, const std::string& host,
                                        const WallPoints& points, const OpeningParams& p,
                                        double floor_v) {
  std::vector<DetectedOpening> out;
  const PatchFrame& f = img.Frame();
  for (const Candidate& k : kept) {
    DetectedOpening o;
    o.type = k.type;
    o.host = host;
    o.u0 = img.ColU(EdgeAt(vert, k.cl)), o.u1 = img.ColU(EdgeAt(vert, k.cr));
    o.v1 = img.RowV(EdgeAt(horz, k.rt));
    o.v0 = k.type == OpeningType::kDoor ? floor_v : img.RowV(EdgeAt(horz, k.rb));
    o.corners = {f.ToMap(o.u0, o.v0), f.ToMap(o.u1, o.v0), f.ToMap(o.u1, o.v1),
                 f.ToMap(o.u0, o.v1)};
    o.confidence = std::clamp(k.score, 0.0, 1.0);
    o.known_share = k.known, o.evidence_share = k.evidence, o.through_share = k.through;
    o.side_support = k.support;
    if (o.type == OpeningType::kDoor) {
      const DetectedOpening rect = o;
      FitDoor(o, vert, img, points, p, static_cast<std::uint64_t>(k.cl) * 100003u + k.rt);
      // A side that is an occlusion boundary: the doorway with that side moved out to where the
      // wall resumes, taken when the occluder is the door's own leaf (a leaf hinged at the
      // moved side is found).
      Candidate e = k;
      const int moved = ExtendOccludedSides(e, vert, m, p, img.Pixel());
      if (moved != 0) {
        DetectedOpening x = rect;
        x.u0 = img.ColU(EdgeAt(vert, e.cl)), x.u1 = img.ColU(EdgeAt(vert, e.cr));
        const LeafFit leaf =
            FitDoor(x, vert, img, points, p, static_cast<std::uint64_t>(e.cl) * 100003u + e.rt);
        const bool hinged_at_moved =
            leaf.inliers > 0 &&
            (((moved & 1) && std::abs(leaf.hinge_u - x.u0) <= p.leaf_jamb_reach) ||
             ((moved & 2) && std::abs(leaf.hinge_u - x.u1) <= p.leaf_jamb_reach));
        if (hinged_at_moved) o = x;
      }
    }
    out.push_back(o);
  }
  return out;
}

// The hole, not the casing (KeepHoles' rule, for a door rectangle in u, v): each side moves in
// to the nearest vertical line casing_min..casing_max inside it when the strip between is a
// casing (on the wall's surface over min_casing_share of its seen part, seen over a fifth).
void InsetCasingSides(DetectedOpening& o, const std::vector<Line>& vert, const Masks& m,
                      const Orthoimage& img, const OpeningParams& p) {
  const double px = img.Pixel();
  const int in_min = static_cast<int>(std::lround(p.casing_min / px));
  const int in_max = static_cast<int>(std::lround(p.casing_max / px));
  const auto lo = LinePixel(img, o.u0, o.v1), hi = LinePixel(img, o.u1, o.v0);
  const int cl = lo[0], cr = hi[0], r0 = lo[1] + 1, r1 = hi[1];
  if (r1 <= r0 || cr <= cl) return;
  const auto casing = [&](int c0, int c1) {
    const double a = double(std::max(0, c1 - c0)) * (r1 - r0);
    if (a <= 0) return false;
    const double seen = a - m.hidden.Sum(c0, c1, r0, r1);
    return seen >= 0.2 * a && m.flush.Sum(c0, c1, r0, r1) >= p.min_casing_share * seen;
  };
  int new_cl = cl, new_cr = cr;
  for (const Line& l : vert) {
    const int c = static_cast<int>(std::lround(l.pos));
    if (c - cl >= in_min && c - cl <= in_max && (new_cl == cl || c < new_cl) && casing(cl + 1, c))
      new_cl = c;
    if (cr - c >= in_min && cr - c <= in_max && (new_cr == cr || c > new_cr) && casing(c + 1, cr))
      new_cr = c;
  }
  if (new_cr - new_cl < 2) return;
  if (new_cl != cl) o.u0 = img.ColU(EdgeAt(vert, new_cl));
  if (new_cr != cr) o.u1 = img.ColU(EdgeAt(vert, new_cr));
}

// One hole, one opening. The leaf and reveal steps move the sides of the rectangles KeepHoles
// kept apart, and an opened leaf splits a doorway into a part seen through and a part behind
// the leaf, each with a frame of edges: two door rectangles on one wall that overlap or lie
// closer than door_merge_gap (distinct doors are kept apart by their casings and a strip of
// wall) and together are no wider than a door are parts of one hole; the door step runs again
// on their union (its reveals give the sides). Any other pair overlapping by more than
// max_overlap of the smaller keeps the more confident (ties: the first). Order by u0.
std::vector<DetectedOpening> OneOpeningPerHoleWithLines(std::vector<DetectedOpening> in,
                                                        const std::vector<Line>& vert,
                                                        const Masks& masks, const Orthoimage& img,
                                                        const WallPoints& points,
                                                        const OpeningParams& p) {
  const auto area = [](const DetectedOpening& o) { return o.Width() * o.Height(); };
  bool merged = true;
  for (int round = 0; merged && round < 16; ++round) {
    merged = false;
    for (std::size_t i = 0; i < in.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < in.size() && !merged; ++j) {
        const DetectedOpening &a = in[i], &b = in[j];
        if (a.type != OpeningType::kDoor || b.type != OpeningType::kDoor) continue;
        const double gap = std::max(a.u0, b.u0) - std::min(a.u1, b.u1);
        const double u0 = std::min(a.u0, b.u0), u1 = std::max(a.u1, b.u1);
        if (gap >= p.door_merge_gap || u1 - u0 > p.door_max_width) continue;
        DetectedOpening m = a.confidence >= b.confidence ? a : b;
        const double wa = area(a), wb = area(b), wsum = std::max(1e-12, wa + wb);
        m.u0 = u0, m.u1 = u1, m.v0 = std::min(a.v0, b.v0), m.v1 = std::max(a.v1, b.v1);
        m.confidence = std::max(a.confidence, b.confidence);
        m.known_share = (wa * a.known_share + wb * b.known_share) / wsum;
        m.evidence_share = (wa * a.evidence_share + wb * b.evidence_share) / wsum;
        m.through_share = (wa * a.through_share + wb * b.through_share) / wsum;
        m.side_support = std::max(a.side_support, b.side_support);
        InsetCasingSides(m, vert, masks, img, p);
        const auto col = img.PixelOf(u0, m.v1);
        FitDoor(m, vert, img, points, p,
                static_cast<std::uint64_t>(std::max(0, col[0])) * 100003u +
                    static_cast<std::uint64_t>(std::max(0, col[1])) + 7u);
        in[i] = m;
        in.erase(in.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
  }
  const auto overlap = [&](const DetectedOpening& a, const DetectedOpening& b) {
    const double w = std::min(a.u1, b.u1) - std::max(a.u0, b.u0);
    const double h = std::min(a.v1, b.v1) - std::max(a.v0, b.v0);
    if (w <= 0.0 || h <= 0.0) return 0.0;
    return w * h / std::max(1e-12, std::min(area(a), area(b)));
  };
  std::vector<std::size_t> order(in.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return in[x].confidence > in[y].confidence;
  });
  std::vector<bool> keep(in.size(), false);
  for (std::size_t i : order) {
    bool clash = false;
    for (std::size_t j = 0; j < in.size() && !clash; ++j)
      clash = keep[j] && overlap(in[i], in[j]) > p.max_overlap;
    keep[i] = !clash;
  }
  std::vector<DetectedOpening> out;
  for (std::size_t i = 0; i < in.size(); ++i)
    if (keep[i]) out.push_back(in[i]);
  std::stable_sort(out.begin(), out.end(),
                   [](const DetectedOpening& x, const DetectedOpening& y) { return x.u0 < y.u0; });
  return out;
}

}  // namespace

namespace {

// Step 2's straight lines of one wall: along columns (vertical) and rows (horizontal), on the
// edge map with a 1-pixel slack, each with its step (LocateEdges).
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

}  // namespace

namespace {

// A door among `openings` overlaps the hint along the wall.
bool Shown(const HoleHint& h, const std::vector<DetectedOpening>& openings) {
  for (const DetectedOpening& o : openings)
    if (o.type == OpeningType::kDoor && std::min(o.u1, h.u1) > std::max(o.u0, h.u0)) return true;
  return false;
}

// Step 4 on the hint's rectangle (from the floor to its top) of `img`'s wall; leaf_points 0
// unless a leaf opened out of the wall's plane was found (lambda >= closed_below_deg): a
// closed leaf's fit takes any flat wall's surface layer, which is no evidence of a door here.
DetectedOpening DoorOnHint(const HoleHint& h, const std::vector<Line>& vert, const Orthoimage& img,
                           const std::string& host, const WallPoints& points,
                           const OpeningParams& p, double floor_v) {
  DetectedOpening o;
  o.type = OpeningType::kDoor;
  o.host = host;
  o.hole_from = h.room;
  if (!(h.u1 > h.u0) || !(h.v1 > floor_v)) return o;
  const PatchFrame& f = img.Frame();
  o.u0 = h.u0, o.u1 = h.u1, o.v0 = floor_v, o.v1 = h.v1;
  o.corners = {f.ToMap(o.u0, o.v0), f.ToMap(o.u1, o.v0), f.ToMap(o.u1, o.v1), f.ToMap(o.u0, o.v1)};
  o.confidence = h.confidence;
  const double px = img.Pixel();
  FitDoor(o, vert, img, points, p,
          static_cast<std::uint64_t>(std::max(0L, std::lround(h.u0 / px))) * 100003u +
              static_cast<std::uint64_t>(std::max(0L, std::lround(h.v1 / px))) + 11u);
  if (!(o.opening_angle_deg >= p.closed_below_deg)) o.leaf_points = 0;
  return o;
}

}  // namespace

std::vector<HoleHint> HoleHints(const PatchFrame& frame, const std::string& room,
                                const std::vector<Sm4Model>& others, const OpeningParams& p) {
  std::vector<HoleHint> hints;
  for (const Sm4Model& other : others) {
    if (other.room == room) continue;
    for (const DetectedOpening& o : other.openings) {
      if (o.type != OpeningType::kDoor) continue;
      HoleHint h{other.room, 1e300, -1e300, -1e300, o.confidence};
      bool near = true;
      for (const Vec3& c : o.corners) {
        const double d = frame.Depth(c);
        near = near && d <= p.flush_depth && d >= -p.max_wall_thickness;
        const Vec2 uv = frame.ToUv(c);
        h.u0 = std::min(h.u0, uv.x()), h.u1 = std::max(h.u1, uv.x());
        h.v1 = std::max(h.v1, uv.y());
      }
      if (near && h.u0 >= -p.flush_depth && h.u1 <= frame.width + p.flush_depth) hints.push_back(h);
    }
  }
  return hints;
}

int AddDoorsFromNeighbours(const StructuralModel& sm3, Sm4Model& sm4, const OrthoPoints& points,
                           const std::vector<Sm4Model>& others, const OpeningParams& params) {
  params.Validate();
  int added = 0;
  for (const StructuralPatch& wall : sm3.patches) {
    if (wall.patch_class != PatchClass::kWall) continue;
    const PatchFrame frame = PatchFrame::Of(wall);
    // Step 4 needs the wall's frame only (no image lines: a widened side is not snapped).
    const Orthoimage frame_only(frame, params.orthoimage.finest_pixel, 1, 1);
    std::vector<DetectedOpening> on_wall;
    for (const DetectedOpening& o : sm4.openings)
      if (o.host == wall.id) {
        DetectedOpening q = o;
        const Vec2 a = frame.ToUv(o.corners[0]), b = frame.ToUv(o.corners[2]);
        q.u0 = std::min(a.x(), b.x()), q.u1 = std::max(a.x(), b.x());
        on_wall.push_back(q);
      }
    for (const HoleHint& h : HoleHints(frame, sm3.room, others, params)) {
      if (Shown(h, on_wall)) continue;
      DetectedOpening o =
          DoorOnHint(h, {}, frame_only, wall.id, WallPoints{points, {}}, params, 0.0);
      if (o.leaf_points == 0) continue;
      o.id = "opening_" + std::to_string(sm4.openings.size() + 1);
      on_wall.push_back(o);
      sm4.openings.push_back(std::move(o));
      ++added;
    }
  }
  return added;
}

namespace {

bool StandsInFront(const DetectedOpening& o, const PatchFrame& f, const WallPoints& in,
                   const OpeningParams& p) {
  // 2 cm plan bins along u from casing_max + 0.1 m before u0 to as far after u1; a bin is
  // occupied when points of the upper half of the leaf's v band stand in front of the wall
  // there (a door seen behind a low cabinet shows its frame and leaf above it).
  if (in.in.points == nullptr || o.type != OpeningType::kDoor || !(o.u1 > o.u0)) return false;
  constexpr double kBin = 0.02;
  const double lo = o.u0 - p.casing_max - 0.1, hi = o.u1 + p.casing_max + 0.1, h = o.Height();
  const int nb = static_cast<int>(std::ceil((hi - lo) / kBin));
  std::vector<int> bins(static_cast<std::size_t>(nb), 0);
  const Vec2 nrm(-o.leaf_line_dir.y(), o.leaf_line_dir.x());
  ForPointsInU(in, lo, hi, [&](const Vec3& q) {
    const double d = f.Depth(q);
    if (d <= p.flush_depth || d > p.front_depth) return;
    const Vec2 uv = f.ToUv(q);
    if (uv.x() < lo || uv.x() >= hi) return;
    if (uv.y() < o.v0 + 0.5 * (p.leaf_v_low + p.leaf_v_high) * h ||
        uv.y() > o.v0 + p.leaf_v_high * h)
      return;
    // The leaf's own points (either face) are not in front of the doorway: it swung there.
    if (o.leaf_points > 0 &&
        std::abs(nrm.dot(Vec2(uv.x(), d) - o.leaf_line_point)) <= p.leaf_thickness + p.leaf_inlier)
      return;
    ++bins[std::min(nb - 1, static_cast<int>((uv.x() - lo) / kBin))];
  });
  const int b0 = static_cast<int>((o.u0 - lo) / kBin);
  const int b1 = std::min(nb, static_cast<int>((o.u1 - lo) / kBin));
  int occupied = 0;
  for (int b = b0; b < b1; ++b) occupied += bins[b] > 0;
  if (b1 <= b0 || occupied < p.front_min_share * (b1 - b0)) return false;
  // The occupied run (one-bin gaps bridged) holding most of the door's occupied bins: an
  // object in front of a door frame seen beside it ends away from the door's sides.
  double a = 0.0, b = 0.0;
  int best_in = 0;
  for (int k = 0; k < nb;) {
    if (bins[k] == 0) {
      ++k;
      continue;
    }
    int e = k, in_door = 0;
    while (e < nb && (bins[e] > 0 || (e + 1 < nb && bins[e + 1] > 0))) {
      in_door += e >= b0 && e < b1 && bins[e] > 0;
      ++e;
    }
    if (in_door > best_in) best_in = in_door, a = lo + k * kBin, b = lo + e * kBin;
    k = e;
  }
  return std::abs(a - o.u0) <= p.casing_max && std::abs(b - o.u1) <= p.casing_max;
}

}  // namespace

bool StandsInFrontOfTheWall(const DetectedOpening& o, const PatchFrame& f, const OrthoPoints& in,
                            const OpeningParams& p) {
  return StandsInFront(o, f, WallPoints{in, {}}, p);
}

std::vector<DetectedOpening> DetectWallOpenings(const Orthoimage& img, const std::string& host,
                                                const OrthoPoints& room_points,
                                                const OpeningParams& p, double floor_v,
                                                const std::vector<HoleHint>& hints) {
  p.Validate();
  const int cols = img.Cols(), rows = img.Rows();
  if (cols < 3 || rows < 3) return {};
  const double px = img.Pixel();
  const WallPoints points = AlongWall(room_points, img.Frame());
  const WallArea area = SegmentWallArea(img, p);
  const WallEdges we = BuildWallEdges(img, area, p);
  const auto [vert, horz] = WallLines(we, px, p);
  // Rectangles, the kept holes, the openings.
  const int floor_row =
      std::clamp(static_cast<int>(std::lround(rows - (floor_v + img.Margin()) / px)), 0, rows);
  const std::vector<Candidate> cands = RectangleCandidates(vert, horz, we.m, p, px, floor_row);
  std::vector<Candidate> kept = KeepHoles(cands, we.m, p, px);
  std::vector<DetectedOpening> out =
      OneOpeningPerHoleWithLines(ToOpenings(kept, vert, horz, we.m, img, host, points, p, floor_v),
                                 vert, we.m, img, points, p);
  for (const HoleHint& h : hints)
    if (!Shown(h, out)) {
      DetectedOpening o = DoorOnHint(h, vert, img, host, points, p, floor_v);
      if (o.leaf_points > 0) out.push_back(std::move(o));
    }
  std::stable_sort(out.begin(), out.end(),
                   [](const DetectedOpening& a, const DetectedOpening& b) { return a.u0 < b.u0; });
  // A door whose front is occupied by one object ending at its sides is that object's outline.
  out.erase(std::remove_if(
                out.begin(), out.end(),
                [&](const DetectedOpening& o) { return StandsInFront(o, img.Frame(), points, p); }),
            out.end());
  return out;
}

std::vector<DetectedOpening> OneOpeningPerHole(std::vector<DetectedOpening> openings,
                                               const Orthoimage& image, const OrthoPoints& points,
                                               const OpeningParams& params) {
  params.Validate();
  if (image.Cols() < 3 || image.Rows() < 3) return openings;
  const WallEdges we = BuildWallEdges(image, SegmentWallArea(image, params), params);
  const auto lines = WallLines(we, image.Pixel(), params);
  return OneOpeningPerHoleWithLines(std::move(openings), lines.first, we.m, image,
                                    AlongWall(points, image.Frame()), params);
}

Sm4Model DetectOpenings(const StructuralModel& sm3, const OrthoPoints& points,
                        const OpeningParams& params,
                        std::vector<std::pair<std::string, Orthoimage>>* images,
                        const std::vector<Sm4Model>& neighbours) {
  params.Validate();
  Sm4Model out;
  out.room = sm3.room;
  std::vector<const StructuralPatch*> walls;
  for (const StructuralPatch& patch : sm3.patches)
    if (patch.patch_class == PatchClass::kWall) walls.push_back(&patch);
  // One task per wall (each wall's steps read only its own image and the shared points; its
  // leaf streams are keyed by its own rectangles), gathered in wall order: the same bytes on
  // any number of threads.
  std::vector<std::vector<DetectedOpening>> found(walls.size());
  std::vector<std::unique_ptr<Orthoimage>> wall_images(walls.size());
  tbb::parallel_for(std::size_t{0}, walls.size(), [&](std::size_t i) {
    const PatchFrame frame = PatchFrame::Of(*walls[i]);
    auto img = std::make_unique<Orthoimage>(BuildOrthoimage(points, frame, params.orthoimage));
    found[i] = DetectWallOpenings(*img, walls[i]->id, points, params, 0.0,
                                  HoleHints(frame, sm3.room, neighbours, params));
    if (images != nullptr) wall_images[i] = std::move(img);
  });
  for (std::size_t i = 0; i < walls.size(); ++i) {
    for (auto& o : found[i]) out.openings.push_back(std::move(o));
    if (images != nullptr) images->emplace_back(walls[i]->id, std::move(*wall_images[i]));
  }
  for (std::size_t i = 0; i < out.openings.size(); ++i)
    out.openings[i].id = "opening_" + std::to_string(i + 1);
  return out;
}

int MarkOpeningVoxels(const std::vector<DetectedOpening>& openings, VoxelSpace& voxels,
                      double band) {
  if (voxels.empty()) return 0;
  const double size = voxels.Size();
  if (band <= 0.0) band = size;
  const double inset = 0.375 * size;
  int marked = 0;
  for (const DetectedOpening& o : openings) {
    const Vec3 c0 = o.corners[0];
    const Vec3 du = o.corners[1] - c0, dv = o.corners[3] - c0;
    const double w = du.norm(), h = dv.norm();
    if (w <= 2 * inset || h <= 2 * inset) continue;
    const Vec3 eu = du / w, ev = dv / h, n = eu.cross(ev).normalized();
    // Bounding box of the rectangle thickened by the band, in voxel indices.
    Vec3 lo = c0, hi = c0;
    for (const Vec3& c : o.corners)
      for (const Vec3& q : {Vec3(c + band * n), Vec3(c - band * n)})
        lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    const Eigen::Vector3i a = voxels.VoxelOf(lo), b = voxels.VoxelOf(hi);
    for (int k = std::max(0, a.z()); k <= std::min(voxels.Nz() - 1, b.z()); ++k)
      for (int j = std::max(0, a.y()); j <= std::min(voxels.Ny() - 1, b.y()); ++j)
        for (int i = std::max(0, a.x()); i <= std::min(voxels.Nx() - 1, b.x()); ++i) {
          const std::size_t idx = voxels.Index(i, j, k);
          std::uint8_t& f = voxels.MutableFlags(idx);
          if (!(f & VoxelSpace::kStructural) || (f & VoxelSpace::kOpeningFace)) continue;
          const Vec3 r = voxels.Centre(i, j, k) - c0;
          if (std::abs(n.dot(r)) > band) continue;
          const double pu = eu.dot(r), pv = ev.dot(r);
          if (pu < inset || pu > w - inset || pv < inset || pv > h - inset) continue;
          f |= VoxelSpace::kOpeningFace;
          ++marked;
        }
  }
  return marked;
}

std::vector<std::uint8_t> ClosedDoorPointMask(const std::vector<Eigen::Vector3f>& points,
                                              const std::vector<StructuralPatch>& patches,
                                              const std::vector<DetectedOpening>& openings,
                                              double margin, double band) {
  std::vector<std::uint8_t> mask(points.size(), 0);
  for (const DetectedOpening& o : openings) {
    if (o.type != OpeningType::kDoor || o.state != DoorState::kClosed) continue;
    const auto it = std::find_if(patches.begin(), patches.end(),
                                 [&](const StructuralPatch& s) { return s.id == o.host; });
    if (it == patches.end()) continue;
    const PatchFrame f = PatchFrame::Of(*it);
    // The rectangle from the map-frame corners, so a refitted host still finds its door.
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const Vec3& c : o.corners) {
      const Vec2 uv = f.ToUv(c);
      u0 = std::min(u0, uv.x()), u1 = std::max(u1, uv.x());
      v0 = std::min(v0, uv.y()), v1 = std::max(v1, uv.y());
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 q = points[i].cast<double>();
      if (std::abs(f.Depth(q)) > band) continue;
      const Vec2 uv = f.ToUv(q);
      if (uv.x() >= u0 - margin && uv.x() <= u1 + margin && uv.y() >= v0 - margin &&
          uv.y() <= v1 + margin)
        mask[i] = 1;
    }
  }
  return mask;
}

}  // namespace mopad::modelling
