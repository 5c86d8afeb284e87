#pragma once
// Internal to SM4 (modelling/openings.h; openings*.cpp): the lines, masks and rectangles the
// steps of one wall pass between each other, the room's points as a wall's door steps read
// them, and the steps that more than one of those files call.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

#include "modelling/openings.h"

namespace mopad::modelling::detail {

struct Line {
  double pos = 0;    // column (vertical line) or row (horizontal line), pixel index
  int a = 0, b = 0;  // extent along the other axis, inclusive
  // Where the step lies across the line, in continuous pixel coordinates (ColU/RowV take it):
  // pos + 0.5 is the edge pixel's centre (LocateEdges).
  double edge = 0;
  int Length() const { return b - a + 1; }
};

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
  /// A door whose evidence counts the seen-through pixels that returned nothing (Masks::ev_hole):
  /// kept only where a leaf hinged at it, opened out of the wall's plane, is found (ToOpenings).
  bool needs_leaf = false;
};

struct Masks {
  Integral known, ev_door, ev_window, through, wall, edge_v, edge_h, hidden_v, hidden_h, flush,
      hidden;
  /// ev_door with the seen-through pixels whose rays returned nothing (a door open onto nothing
  /// a scanner sees: no ground or building beyond it, or the sky)
  Integral ev_hole;
};

// The opening's corners in the map frame from its rectangle (u0..u1, v0..v1 on wall frame f):
// lower left, lower right, upper right, upper left.
inline void SetCorners(DetectedOpening& o, const PatchFrame& f) {
  o.corners = {f.ToMap(o.u0, o.v0), f.ToMap(o.u1, o.v0), f.ToMap(o.u1, o.v1), f.ToMap(o.u0, o.v1)};
}

// The room's points as one wall's door steps read them: OrthoPoints and, optionally, each
// point's u along the wall (float) for a quick range test, so that a door's leaf and front are
// sought among the points beside it instead of all the room's. Without u every point is read.
struct WallPoints {
  const OrthoPoints& in;
  std::vector<float> u;
};

WallPoints AlongWall(const OrthoPoints& in, const PatchFrame& f);

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

WallEdges BuildWallEdges(const Orthoimage& img, const WallArea& area, const OpeningParams& p);

// Step 2's straight lines of one wall: along columns (vertical) and rows (horizontal), on the
// edge map with a 1-pixel slack, each with its step (LocateEdges).
std::pair<std::vector<Line>, std::vector<Line>> WallLines(const WallEdges& we, double px,
                                                          const OpeningParams& p);

// Step 3: rectangles from pairs of vertical lines and one (door, down to the floor) or two
// (window, with a sill) horizontal lines, within the typical sizes, scored (Score).
// `floor_row` and `ceiling_row` are the image rows of the wall's bottom and top edges.
std::vector<Candidate> RectangleCandidates(const std::vector<Line>& vert,
                                           const std::vector<Line>& horz, const Masks& m,
                                           const OpeningParams& p, double px, int floor_row,
                                           int ceiling_row);

// Best first (ties: position), non-maximum suppression by overlap; then the hole, not the
// casing, for each kept rectangle.
std::vector<Candidate> KeepHoles(const std::vector<Candidate>& cands, const Masks& m,
                                 const OpeningParams& p, double px);

// Step 4 and the file's fields: each kept rectangle as an opening in the wall's frame, doors
// with their leaf (FitDoor).
std::vector<DetectedOpening> ToOpenings(const std::vector<Candidate>& kept,
                                        const std::vector<Line>& vert,
                                        const std::vector<Line>& horz, const Masks& m,
                                        const Orthoimage& img, const std::string& host,
                                        const WallPoints& points, const OpeningParams& p,
                                        double floor_v);

// One hole, one opening. The leaf and reveal steps move the sides of the rectangles KeepHoles
// kept apart, and an opened leaf splits a doorway into a part seen through and a part behind
// the leaf, each with a frame of edges: two door rectangles on one wall that overlap or lie
// closer than door_merge_gap (distinct doors are kept apart by their casings and a strip of
// wall) and together are no wider than a door are parts of one hole; the door step runs again
// on their union (its reveals give the sides). Two window rectangles that share columns over
// at least half the rows of the shorter one, together no wider than a window, are the casements
// either side of one window's mullion: their union. Any other pair overlapping by more than
// max_overlap of the smaller keeps the more confident (ties: the first). Order by u0.
std::vector<DetectedOpening> OneOpeningPerHoleWithLines(std::vector<DetectedOpening> in,
                                                        const std::vector<Line>& vert,
                                                        const Masks& masks, const Orthoimage& img,
                                                        const WallPoints& points,
                                                        const OpeningParams& p);

// Step 4 for one door rectangle o (u0, u1, v0, v1 set; known_share and through_share of its
// interior set): its leaf (angle, state, clear width), its sides moved to its reveals where
// they were seen, widened to the leaf where it is wider. `index` keys the leaf's RANSAC stream.
LeafFit FitDoor(DetectedOpening& o, const std::vector<Line>& vert, const Orthoimage& img,
                const WallPoints& points, const OpeningParams& p, std::uint64_t index);

// After FitDoor: a leaf opened out of the wall's plane was found (lambda >= closed_below_deg).
// A closed leaf's fit takes any flat wall's surface layer, which is no evidence of a door.
inline bool LeafOpenedOut(const DetectedOpening& o, const OpeningParams& p) {
  return o.leaf_points > 0 && o.opening_angle_deg >= p.closed_below_deg;
}

}  // namespace mopad::modelling::detail
