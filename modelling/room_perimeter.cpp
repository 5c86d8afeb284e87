// The room's perimeter (RoomModel::BuildPerimeter): the union of the scans' ceiling outlines
// (room_outline.cpp) rasterised and simplified, each edge refit onto its wall's points, the
// corners re-joined, then tidied (jogs, views through openings, short and collinear edges).
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "modelling/room_model.h"
#include "modelling/room_model_internal.h"

namespace mopad::modelling {

using detail::Plan;

namespace {

// Intersection of lines p + s*t and q + r*u; false if within parallel_deg of parallel.
bool IntersectLines(const Vec2& p, const Vec2& t, const Vec2& q, const Vec2& u, double parallel_deg,
                    Vec2* out) {
  const double den = t.x() * u.y() - t.y() * u.x();
  if (std::abs(den) < std::sin(DegToRad(parallel_deg))) return false;
  const Vec2 d = q - p;
  const double s = (d.x() * u.y() - d.y() * u.x()) / den;
  *out = p + s * t;
  return true;
}

// Drops vertices whose edges turn less than `collinear_deg` or that close edges shorter than
// `min_len`; with `max_offset` > 0 first the jogs shallower than it (the refit moves edges onto
// their walls, and a short edge fitted across a doorway, where there is no wall, can land a few
// cm off the line and split one wall into pieces in SM3).
void Clean(std::vector<Vec2>& poly, double collinear_deg, double min_len, double max_offset = 0.0) {
  if (max_offset > 0.0) RemoveShallowVertices(poly, max_offset);
  bool changed = true;
  while (changed && poly.size() > 3) {
    changed = false;
    for (std::size_t i = 0; i < poly.size() && poly.size() > 3; ++i) {
      const std::size_t n = poly.size();
      const Vec2& a = poly[(i + n - 1) % n];
      const Vec2& b = poly[i];
      const Vec2& c = poly[(i + 1) % n];
      const Vec2 ab = b - a, bc = c - b;
      const double cross = ab.x() * bc.y() - ab.y() * bc.x();
      const bool collinear =
          std::abs(cross) < std::sin(DegToRad(collinear_deg)) * ab.norm() * bc.norm();
      if (collinear || bc.norm() < min_len) {
        poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        break;
      }
    }
  }
}

// Views through openings (RoomModelParams::seal_depth): a run of at most seal.max_vertices
// vertices after a wall edge (at least seal.min_wall long) that passes behind the wall's line by
// more than seal.min_depth (or jog_tolerance, if smaller) and at most seal_depth, never further
// into the room than seal_inward, spans at most seal_width along the line and comes back onto it
// (within seal.on_line) ahead of the edge, where a parallel wall edge goes on, is replaced by the
// straight wall. A detour that stays in the room (a pilaster, a cabinet) is kept: it never
// passes behind. Deeper than seal_depth (up to seal.lintel_depth), the detour is cut across
// only where a lintel spans its mouth (WallSpans on the points above door heads).

// Whether the wall's face goes on across b -> v on a wall line: `points` (those above door heads
// for a lintel over a mouth, every wall-band point for a wall behind a shadow) within
// wall_tolerance of the line over at least seal.lintel_coverage of its 5 cm bins.
bool WallSpans(const Vec2& b, const Vec2& v, const std::vector<Vec2>& points,
               const RoomModelParams& P) {
  constexpr double kBin = 0.05;  // m, as the refit's support bins
  const double len = (v - b).norm();
  if (len < 1e-9 || points.empty()) return false;
  const Vec2 t = (v - b) / len, nrm(t.y(), -t.x());
  std::vector<std::uint8_t> bins(static_cast<std::size_t>(std::ceil(len / kBin)), 0);
  for (const Vec2& p : points) {
    const double u = (p - b).dot(t);
    if (u < 0.0 || u >= len || std::abs((p - b).dot(nrm)) > P.wall_tolerance) continue;
    bins[std::min(bins.size() - 1, static_cast<std::size_t>(u / kBin))] = 1;
  }
  const int covered = std::accumulate(bins.begin(), bins.end(), 0);
  return covered >= P.seal.lintel_coverage * static_cast<double>(bins.size());
}

void SealOpenings(std::vector<Vec2>& poly, const RoomModelParams& P,
                  const std::vector<Vec2>& above_heads) {
  if (P.seal_depth <= 0.0) return;
  // Shallower detours are the jog rule's (Clean with jog_tolerance): the two rules meet, so no
  // vertex a few cm behind a wall line falls between them (it would split the wall in SM3).
  const OpeningSealParams& S = P.seal;
  const double min_depth =
      P.jog_tolerance > 0.0 ? std::min(S.min_depth, P.jog_tolerance) : S.min_depth;
  const double max_depth =
      above_heads.empty() ? P.seal_depth : std::max(P.seal_depth, S.lintel_depth);
  bool changed = true;
  while (changed && poly.size() > 4) {
    changed = false;
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n && !changed; ++i) {
      const Vec2& a = poly[(i + n - 1) % n];
      const Vec2& b = poly[i];
      const double la = (b - a).norm();
      if (la < S.min_wall) continue;
      const Vec2 t = (b - a) / la, out(t.y(), -t.x());  // CCW: `out` leaves the room
      double behind = 0.0, u_min = 0.0;
      const std::size_t max_vertices = static_cast<std::size_t>(S.max_vertices);
      for (std::size_t s = 1; s < std::min(n - 2, max_vertices + 1); ++s) {
        const Vec2& v = poly[(i + s) % n];
        const double u = (v - b).dot(t), d = (v - b).dot(out);
        u_min = std::min(u_min, u);  // a reveal seen obliquely reaches back under the wall
        if (u - u_min > P.seal_width + S.on_line || d > max_depth || d < -P.seal_inward) break;
        if (s >= 2 && std::abs(d) <= S.on_line && u > 0.0 && behind > min_depth &&
            (behind <= P.seal_depth || WallSpans(b, v, above_heads, P))) {
          const Vec2& w = poly[(i + s + 1) % n];
          const double lw = (w - v).norm();
          if (lw >= S.min_wall && (w - v).dot(t) >= lw * std::cos(DegToRad(S.parallel_deg))) {
            const std::size_t first = i + 1, last = i + s;  // erase [first, last)
            if (last <= n) {
              poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(first),
                         poly.begin() + static_cast<std::ptrdiff_t>(last));
            } else {
              poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(first), poly.end());
              poly.erase(poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(last - n));
            }
            Clean(poly, P.collinear_deg, P.min_edge_length);  // the wall's pieces become one edge
            changed = true;
            break;
          }
        }
        behind = std::max(behind, d);
      }
    }
  }
}

struct HiddenCorner {
  Vec2 corner, end_a, start_b;  ///< the corner; a's end and b's start on their lines
};

// The corner of fitted walls a and b (lines[i] for poly[i] -> poly[i+1]) when they turn left (a
// convex corner, counter-clockwise) by at least corners.corner_min_deg and meet more than
// refit_band ahead of a's end and before b's start: both walls stop short of it.
bool CornerAhead(const std::vector<Vec2>& poly, const std::vector<PerimeterLine>& lines,
                 std::size_t a, std::size_t b, const RoomModelParams& params, HiddenCorner* c) {
  const std::size_t m = poly.size();
  const Vec2 ta = lines[a].t, tb = lines[b].t;
  if (ta.x() * tb.y() - ta.y() * tb.x() < std::sin(DegToRad(params.corners.corner_min_deg)))
    return false;
  if (!IntersectLines(lines[a].p, ta, lines[b].p, tb, params.corners.parallel_deg, &c->corner))
    return false;
  c->end_a = lines[a].p + (poly[(a + 1) % m] - lines[a].p).dot(ta) * ta;
  c->start_b = lines[b].p + (poly[b] - lines[b].p).dot(tb) * tb;
  return (c->corner - c->end_a).dot(ta) > params.refit_band &&
         (c->start_b - c->corner).dot(tb) > params.refit_band;
}

// Whether both ends of edge e stand more than the wall tolerance in front of the fitted walls
// a and b that meet at `corner`.
bool StandsInCorner(const std::vector<Vec2>& poly, const std::vector<PerimeterLine>& lines,
                    std::size_t e, std::size_t a, std::size_t b, const Vec2& corner, double tol) {
  const Vec2 in_a(-lines[a].t.y(), lines[a].t.x()), in_b(-lines[b].t.y(), lines[b].t.x());
  for (const Vec2& v : {poly[e], poly[(e + 1) % poly.size()]})
    if ((v - corner).dot(in_a) <= tol || (v - corner).dot(in_b) <= tol) return false;
  return true;
}

// Whether the run poly[a + 1] .. poly[b] between fitted walls a and b hides their corner
// (BridgeShadows' corner case); `corner` gets it. Of nested corners the outermost is the room's:
// a or b that is itself a face standing in the corner of the fitted walls before a (after b)
// is no wall of the room.
bool HidesCorner(const std::vector<Vec2>& poly, const std::vector<PerimeterLine>& lines,
                 std::size_t a, std::size_t b, const std::vector<Vec2>& band,
                 const RoomModelParams& params, Vec2* corner) {
  const std::size_t m = poly.size();
  const double tol = params.wall_tolerance;
  HiddenCorner c, outer;
  if (!CornerAhead(poly, lines, a, b, params, &c)) return false;
  const Vec2 x = c.corner;
  std::size_t a0 = (a + m - 1) % m, b1 = (b + 1) % m;
  while (a0 != b && !lines[a0].fitted) a0 = (a0 + m - 1) % m;
  while (b1 != a && !lines[b1].fitted) b1 = (b1 + 1) % m;
  if (a0 != b && CornerAhead(poly, lines, a0, b, params, &outer) &&
      StandsInCorner(poly, lines, a, a0, b, outer.corner, tol))
    return false;
  if (b1 != a && CornerAhead(poly, lines, a, b1, params, &outer) &&
      StandsInCorner(poly, lines, b, a, b1, outer.corner, tol))
    return false;
  const Vec2 ta = lines[a].t, tb = lines[b].t;
  const Vec2 in_a(-ta.y(), ta.x()), in_b(-tb.y(), tb.x());
  double deepest = 0.0, reach = 0.0;  // out of the corner (both ways), from either wall
  bool faced = false;
  for (std::size_t k = (a + 1) % m;; k = (k + 1) % m) {
    const double da = (poly[k] - x).dot(in_a), db = (poly[k] - x).dot(in_b);
    if (da < -tol || db < -tol) return false;  // it passes behind a wall: no shadow
    deepest = std::max(deepest, std::min(da, db));
    reach = std::max({reach, da, db});
    if (k == b) break;
    const Vec2 mid = 0.5 * (poly[k] + poly[(k + 1) % m]);
    faced = faced || (lines[k].fitted && (mid - x).dot(in_a) > tol && (mid - x).dot(in_b) > tol);
  }
  if (deepest <= 2 * tol) return false;
  const bool clutter = !faced && deepest > params.refit_band && reach <= params.shadow_depth;
  if (!clutter && !(WallSpans(c.end_a, x, band, params) && WallSpans(x, c.start_b, band, params)))
    return false;
  *corner = x;
  return true;
}

}  // namespace

void BridgeShadows(std::vector<Vec2>& poly, std::vector<PerimeterLine>& lines,
                   const std::vector<Vec2>& band, const RoomModelParams& params) {
  const double cos_par = std::cos(DegToRad(params.corners.parallel_deg));
  const double tol = params.wall_tolerance;
  bool changed = true;
  // Vertices a + 1 .. a + run go, and vertex a + run + 1 with them or, given `corner`, moved
  // there.
  auto splice = [&](std::size_t a, std::size_t run, const Vec2* corner) {
    const std::size_t m = poly.size();
    std::vector<Vec2> p2;
    std::vector<PerimeterLine> l2;
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t off = (k + m - a) % m;
      if (off >= 1 && off <= run) continue;
      if (off == run + 1 && corner == nullptr) continue;
      p2.push_back(off == run + 1 ? *corner : poly[k]);
      l2.push_back(lines[k]);
    }
    poly.swap(p2);
    lines.swap(l2);
    changed = true;
  };
  while (changed && poly.size() >= 5) {
    changed = false;
    const std::size_t m = poly.size();
    for (std::size_t a = 0; a < m && !changed; ++a) {
      if (!lines[a].fitted) continue;
      const Vec2 p = lines[a].p, t = lines[a].t, in(-t.y(), t.x());  // counter-clockwise
      // The next fitted edge b on a's line, no vertex before it more than seal_depth behind the
      // line; edges a + 1 .. b - 1 are the run.
      std::size_t b = (a + 1) % m, run = 0;
      bool found = false, faced = false;
      double depth = 0.0, behind = 0.0;  // how far the run stands into the room, behind the line
      Vec2 corner;
      bool at_corner = false;
      while (b != a) {
        if (run > 0 && lines[b].fitted && HidesCorner(poly, lines, a, b, band, params, &corner)) {
          at_corner = true;
          break;
        }
        const double d = (poly[b] - p).dot(in);  // how far vertex b stands into the room
        if (d < -params.seal_depth) break;
        behind = std::max(behind, -d);
        if (run > 0 && lines[b].fitted && t.dot(lines[b].t) >= cos_par &&
            std::abs((lines[b].p - p).dot(in)) <= 2 * tol) {
          found = true;
          break;
        }
        depth = std::max(depth, d);
        const Vec2 mid = 0.5 * (poly[b] + poly[(b + 1) % m]);
        faced = faced || (lines[b].fitted && (mid - p).dot(in) > tol);  // not a reveal's side
        b = (b + 1) % m, ++run;
      }
      if (at_corner && m - run >= 3) {  // vertices a + 1 .. b - 1 go, b moves to the corner
        splice(a, run, &corner);
        continue;
      }
      if (!found || depth <= 2 * tol || m - run - 1 < 3) continue;
      const Vec2 s0 = p + (poly[(a + 1) % m] - p).dot(t) * t, s1 = p + (poly[b] - p).dot(t) * t;
      if ((s1 - s0).dot(t) <= 0.0) continue;
      const bool clutter = !faced && depth > params.refit_band && depth <= params.shadow_depth;
      if (!clutter && (behind > tol || !WallSpans(s0, s1, band, params))) continue;
      splice(a, run, nullptr);  // vertices a + 1 .. b go: edge a runs on along its line
    }
  }
}

void TidyPerimeter(std::vector<Vec2>& poly, const RoomModelParams& params,
                   const std::vector<Vec2>& above_heads) {
  Clean(poly, params.collinear_deg, params.min_edge_length, params.jog_tolerance);
  SealOpenings(poly, params, above_heads);
  Clean(poly, params.collinear_deg, params.min_edge_length, params.jog_tolerance);
}

void RoomModel::BuildPerimeter() {
  const double r = params_.perimeter_raster;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& s : scans_) {
    for (const auto& v : s.outline) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  std::vector<Vec2> poly;
  if (lo.x() > hi.x()) {
    roi_.perimeter.clear();
    return;
  }
  lo -= Vec2(4 * r, 4 * r);
  hi += Vec2(4 * r, 4 * r);
  const int w = static_cast<int>(std::ceil((hi.x() - lo.x()) / r));
  const int h = static_cast<int>(std::ceil((hi.y() - lo.y()) / r));
  cv::Mat img = cv::Mat::zeros(h, w, CV_8U);
  constexpr int kShift = 4;
  for (const auto& s : scans_) {
    if (s.outline.size() < 3) continue;
    std::vector<cv::Point> pts;
    pts.reserve(s.outline.size());
    for (const auto& v : s.outline) {
      const Vec2 q = ((v - lo) / r - Vec2(0.5, 0.5)) * (1 << kShift);
      pts.emplace_back(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())));
    }
    const cv::Point* pp = pts.data();
    const int np = static_cast<int>(pts.size());
    cv::fillPoly(img, &pp, &np, 1, cv::Scalar(255), cv::LINE_8, kShift);
  }
  cv::morphologyEx(img, img, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(img, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  int best = -1;
  double best_area = 0.0;
  for (int k = 0; k < static_cast<int>(contours.size()); ++k) {
    const double a = cv::contourArea(contours[k]);
    if (a > best_area) {
      best_area = a;
      best = k;
    }
  }
  if (best < 0) {
    roi_.perimeter.clear();
    return;
  }
  std::vector<cv::Point> approx;
  cv::approxPolyDP(contours[best], approx, params_.perimeter_epsilon / r, true);
  for (const auto& p : approx) poly.push_back(lo + r * Vec2(p.x + 0.5, p.y + 0.5));
  if (SignedArea(poly) < 0) std::reverse(poly.begin(), poly.end());
  Clean(poly, params_.collinear_deg, params_.min_edge_length);
  std::vector<Vec2> band;
  std::vector<std::uint8_t> high;
  WallBand(band, high);
  RefitPerimeter(poly, band, high);
  std::vector<Vec2> above_heads;
  for (std::size_t k = 0; k < band.size(); ++k)
    if (high[k]) above_heads.push_back(band[k]);
  TidyPerimeter(poly, params_, above_heads);
  if (SignedArea(poly) < 0) std::reverse(poly.begin(), poly.end());
  roi_.perimeter = poly;
}

namespace {

// One perimeter edge a -> b moved onto its wall (RoomModel::RefitPerimeter): `band` are the
// plan points between the floor and ceiling bands, `high` flags those above door heads.
PerimeterLine FitWallEdge(const Vec2& a, const Vec2& b, const std::vector<Vec2>& band,
                          const std::vector<std::uint8_t>& high, const RoomModelParams& P) {
  const WallRefitParams& R = P.refit;
  const double bandw = P.refit_band, tol = P.wall_tolerance;
  const double len = (b - a).norm();
  const Vec2 t = (b - a) / std::max(len, 1e-12), nrm(t.y(), -t.x());
  PerimeterLine fit{a, t, false, t};
  const double guard = len > 3 * R.end_guard ? R.end_guard : 0.0;
  const int nb = static_cast<int>(std::ceil(2 * bandw / R.offset_bin)) + 1;
  std::vector<int> hist(nb, 0), hist_high(nb, 0);
  int n_high = 0;
  std::vector<Vec2> near;
  std::vector<std::uint8_t> near_high;
  for (std::size_t k = 0; k < band.size(); ++k) {
    const Vec2 ap = band[k] - a;
    const double u = ap.dot(t), s = ap.dot(nrm);
    if (u < guard || u > len - guard || std::abs(s) > bandw) continue;
    near.push_back(band[k]);
    near_high.push_back(high[k]);
    const int bin = static_cast<int>((s + bandw) / R.offset_bin);
    ++hist[bin];
    if (high[k]) ++hist_high[bin], ++n_high;
  }
  if (static_cast<int>(near.size()) < P.refit_min_points) return fit;
  // The wall is the outermost strong peak: a closed door leaf or a cabinet flush against the
  // wall can be nearly as dense as the wall itself but lies in front of it, and where it
  // covers most of the wall below its head it outnumbers the wall (a short end wall behind a
  // closed door can hold less than half the points of the leaf). Above door heads
  // (refit.high_band) only the wall remains: its peak there is the anchor when it has enough
  // points.
  if (n_high >= P.refit_min_points) hist.swap(hist_high);
  std::vector<double> sm(nb, 0.0);
  double hmax = 0.0;
  for (int k = 0; k < nb; ++k) {
    sm[k] = hist[k] + (k > 0 ? 0.5 * hist[k - 1] : 0) + (k + 1 < nb ? 0.5 * hist[k + 1] : 0);
    hmax = std::max(hmax, sm[k]);
  }
  int hb = 0;
  for (int k = 0; k < nb; ++k) {
    const bool peak = (k == 0 || sm[k] >= sm[k - 1]) && (k + 1 == nb || sm[k] >= sm[k + 1]);
    if (peak && sm[k] >= R.peak_share * hmax) hb = k;
  }
  const double s0 = (hb + 0.5) * R.offset_bin - bandw;
  // Points within tol of the offset line; support must span part of the edge.
  Vec2 mean = Vec2::Zero();
  std::vector<Vec2> sel, sel_high;
  std::vector<std::uint8_t> bins(static_cast<std::size_t>(len / R.support_bin) + 1, 0);
  std::vector<std::uint8_t> bins_high(bins.size(), 0);
  for (std::size_t k = 0; k < near.size(); ++k) {
    const Vec2& p = near[k];
    const double s = (p - a).dot(nrm);
    if (std::abs(s - s0) <= tol) {
      sel.push_back(p);
      mean += p;
      const std::size_t b =
          std::min(bins.size() - 1, static_cast<std::size_t>((p - a).dot(t) / R.support_bin));
      bins[b] = 1;
      if (near_high[k]) sel_high.push_back(p), bins_high[b] = 1;
    }
  }
  const int covered = std::accumulate(bins.begin(), bins.end(), 0);
  if (static_cast<int>(sel.size()) < P.refit_min_points ||
      covered < std::max<int>(2, static_cast<int>(R.min_coverage * bins.size()))) {
    return fit;
  }
  // The line itself from the points above door heads where they cover most of the edge:
  // below, window reveals and furniture flush against the wall tilt it (on a long wall with
  // windows and desks along it, by more than a centimetre over its length).
  const int covered_high = std::accumulate(bins_high.begin(), bins_high.end(), 0);
  if (static_cast<int>(sel_high.size()) >= P.refit_min_points &&
      covered_high >= static_cast<int>(R.high_coverage * covered)) {
    sel.swap(sel_high);
    mean = Vec2::Zero();
    for (const auto& p : sel) mean += p;
  }
  mean /= static_cast<double>(sel.size());
  Vec2 support = t;  // the principal direction of the points of the last fit
  auto pca_dir = [&](const std::vector<Vec2>& pts, const Vec2& c) {
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    Vec2 dir = es.eigenvectors().col(1);
    if (dir.dot(t) < 0) dir = -dir;
    support = dir;
    return dir.dot(t) < std::cos(DegToRad(R.max_turn_deg)) ? t : dir;  // else only shift
  };
  Vec2 dir = pca_dir(sel, mean);
  // Tighten about the wall peak: clutter flush against part of a wall (a closed door leaf or
  // casing 2 cm proud over half of a 2 m end wall, a whiteboard row) lies inside the band and
  // pulls a least-squares line towards it, up to onto it where it has more points than the
  // wall (a long wall tilts; an end wall behind a closed door moves onto the door, its wall
  // points then outliers; docs/room-scanning.md has the cases). Refit from the line at
  // the outermost strong peak s0 on the points within tighten_first and then tighten_second of
  // the band about the current line, while at least tighten_keep_share of its points remain.
  {
    Vec2 lp = a + s0 * nrm + 0.5 * len * t, ld = t;
    bool refit = false;
    for (double f : {R.tighten_first, R.tighten_second}) {
      std::vector<Vec2> tight;
      Vec2 m2 = Vec2::Zero();
      const Vec2 nn(ld.y(), -ld.x());
      for (const auto& p : sel)
        if (std::abs((p - lp).dot(nn)) <= f * tol) tight.push_back(p), m2 += p;
      if (static_cast<int>(tight.size()) <
          std::max(P.refit_min_points, static_cast<int>(R.tighten_keep_share * sel.size())))
        break;
      lp = m2 / static_cast<double>(tight.size());
      ld = pca_dir(tight, lp);
      refit = true;
    }
    if (refit) mean = lp, dir = ld;
  }
  return {mean, dir, true, support};
}

}  // namespace

void RoomModel::WallBand(std::vector<Vec2>& band, std::vector<std::uint8_t>& high) const {
  const WallRefitParams& R = params_.refit;
  const double z0 = roi_.floor_z + R.floor_clearance, z1 = roi_.ceiling_z - R.ceiling_clearance;
  // Above door heads only the wall itself reaches (a lintel, the wall over a cabinet).
  const double z_high = roi_.floor_z + R.high_band;
  band.clear();
  high.clear();
  band.reserve(work_points_.size() / 2);
  for (const auto& p : work_points_) {
    if (p.z() > z0 && p.z() < z1) {
      band.push_back(Plan(p));
      high.push_back(p.z() > z_high ? 1 : 0);
    }
  }
}

namespace {

// The end faces of walls standing into the room among the refit perimeter's edges (`lines[i]`
// for poly[i] -> poly[i+1]). A short fitted edge between two antiparallel fitted walls is the
// end face of a wall that stands into the room: walls are prisms, so it is square to them. Its
// traced direction is poor (each end moved by up to perimeter_epsilon: tens of degrees on a
// 0.2 m edge) and tilts its fit. The trace may also have cut one of its corners (a second short
// edge): of the two the squarer is the end face, the other is a corner cut.
struct WallEnds {
  std::vector<Vec2> square;      ///< an end face's direction square to its walls, else zero
  std::vector<bool> corner_cut;  ///< the second short edge beside an end face
};

WallEnds FindWallEnds(const std::vector<Vec2>& poly, const std::vector<PerimeterLine>& lines,
                      const RoomModelParams& params) {
  const std::size_t n = poly.size();
  const PerimeterCornerParams& C = params.corners;
  WallEnds out{std::vector<Vec2>(n, Vec2::Zero()), std::vector<bool>(n, false)};
  std::vector<bool> fitted(n, false);
  for (std::size_t i = 0; i < n; ++i) fitted[i] = lines[i].fitted;
  auto length = [&](std::size_t k) { return (poly[(k + 1) % n] - poly[k]).norm(); };
  for (std::size_t i = 0; i < n && n >= 6; ++i) {
    if (!fitted[i] || length(i) >= C.wall_end_max) continue;
    std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n, other = n;
    if (length(pi) < C.chamfer_max)
      other = pi, pi = (pi + n - 1) % n;
    else if (length(ni) < C.chamfer_max)
      other = ni, ni = (ni + 1) % n;
    if (!fitted[pi] || !fitted[ni] || pi == ni) continue;
    const Vec2 tp = out.square[pi] != Vec2::Zero() ? out.square[pi] : lines[pi].t;
    const Vec2 tn = out.square[ni] != Vec2::Zero() ? out.square[ni] : lines[ni].t;
    if (tp.dot(tn) > -std::cos(DegToRad(C.antiparallel_deg))) continue;
    const Vec2 side = (tp - tn).normalized();
    if (other < n && other != i && fitted[other]) {
      // Of two short edges the squarer is the end face.
      const Vec2 t_other = out.square[other] != Vec2::Zero() ? out.square[other] : lines[other].t;
      if (std::abs(t_other.dot(side)) < std::abs(lines[i].t.dot(side))) continue;
    }
    if (other < n && length(i) + length(other) >= C.wall_end_max) continue;
    const Vec2 square(-side.y(), side.x());
    const Vec2 traced = poly[(i + 1) % n] - poly[i];
    out.square[i] = square.dot(traced) >= 0.0 ? square : Vec2(-square);
    if (other < n) fitted[other] = false, out.corner_cut[other] = true;
  }
  return out;
}

}  // namespace

void RoomModel::RefitPerimeter(std::vector<Vec2>& poly, const std::vector<Vec2>& band,
                               const std::vector<std::uint8_t>& high) const {
  // Each edge is moved onto its wall: the densest offset of the wall points near it (walls are
  // the farthest dense surface; clutter in front only thins the histogram), then a total
  // least-squares line through the points close to that offset; above door heads first (the
  // wall alone reaches there). Corners are re-intersected.
  const std::size_t n = poly.size();
  if (n < 3) return;
  std::vector<PerimeterLine> fits(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    fits[i] = FitWallEdge(poly[i], poly[(i + 1) % n], band, high, params_);
  });
  // A wall's end face traced askew spreads its points over the offsets across the traced edge,
  // and its fit lands between them (FZK-Haus: 2.4 cm inside the end of the wall standing into
  // the hall): it is fitted again across the edge squared to its walls, through the traced
  // edge's middle.
  const WallEnds ends = FindWallEnds(poly, fits, params_);
  for (std::size_t i = 0; i < n; ++i) {
    if (ends.square[i] == Vec2::Zero()) continue;
    const Vec2 mid = 0.5 * (poly[i] + poly[(i + 1) % n]);
    const Vec2 half = 0.5 * (poly[(i + 1) % n] - poly[i]).norm() * ends.square[i];
    const PerimeterLine square = FitWallEdge(mid - half, mid + half, band, high, params_);
    if (square.fitted) fits[i] = square;
  }
  BridgeShadows(poly, fits, band, params_);
  poly = JoinPerimeterLines(poly, fits, params_);
}

std::vector<Vec2> JoinPerimeterLines(const std::vector<Vec2>& poly,
                                     const std::vector<PerimeterLine>& lines,
                                     const RoomModelParams& params) {
  const std::size_t n = poly.size();
  if (n < 3 || lines.size() != n) return poly;
  const PerimeterCornerParams& C = params.corners;
  const double wall_end_max = C.wall_end_max, chamfer_max = C.chamfer_max;
  std::vector<Vec2> line_p(n), line_t(n);
  std::vector<bool> fitted(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    line_p[i] = lines[i].p;
    line_t[i] = lines[i].t;
    fitted[i] = lines[i].fitted;
  }
  auto length = [&](std::size_t k) { return (poly[(k + 1) % n] - poly[k]).norm(); };
  const WallEnds ends = FindWallEnds(poly, lines, params);
  for (std::size_t i = 0; i < n; ++i) {
    if (ends.square[i] != Vec2::Zero()) line_t[i] = ends.square[i];
    if (ends.corner_cut[i]) fitted[i] = false;
  }
  // A short fitted edge whose points run within on_wall_deg of a fitted neighbour's line and lie
  // on it (their mean within twice the wall tolerance: the band one wall's points fill) carries
  // that wall's own points: the tracer cut the corner at the wall's end (along the wall, up to
  // a wall end's width) and the refit moved the cut onto the wall's face. It is no face of its
  // own (SM3 would get a wall a few degrees off beside the real one): it collapses below with
  // the unfitted cuts, its neighbours extended to their corner. Only at a corner: the other
  // neighbour is a fitted wall at least corner_min_deg off.
  std::vector<bool> on_neighbour(n, false);
  for (std::size_t i = 0; i < n && n >= 5; ++i) {
    if (!fitted[i] || length(i) >= wall_end_max) continue;
    const std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n;
    if (!fitted[pi] || !fitted[ni] ||
        std::abs(line_t[pi].dot(line_t[ni])) > std::cos(DegToRad(C.corner_min_deg)))
      continue;
    for (const std::size_t k : {pi, ni}) {
      const Vec2 nk(-line_t[k].y(), line_t[k].x());
      if (std::abs(lines[i].support.dot(line_t[k])) > std::cos(DegToRad(C.on_wall_deg)) &&
          std::abs((line_p[i] - line_p[k]).dot(nk)) <= 2.0 * params.wall_tolerance) {
        fitted[i] = false;
        on_neighbour[i] = true;
        break;
      }
    }
  }
  // A short edge left unfitted between two fitted walls is the tracer cutting their corner
  // (a re-entrant corner seen obliquely leaves a chamfer of a dozen centimetres, a false 'wall'
  // in SM3): the two walls meet in one corner instead.
  std::vector<bool> collapse(n, false);
  std::vector<Vec2> corner(n, Vec2::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n;
    if (fitted[i] || !fitted[pi] || !fitted[ni] || (pi > 0 && collapse[pi]) || n < 5) continue;
    const double reach = on_neighbour[i] ? wall_end_max : chamfer_max;
    if ((poly[ni] - poly[i]).norm() >= reach) continue;
    Vec2 x;
    if (IntersectLines(line_p[pi], line_t[pi], line_p[ni], line_t[ni], C.parallel_deg, &x) &&
        (x - poly[i]).norm() < reach && (x - poly[ni]).norm() < reach) {
      collapse[i] = true;
      corner[i] = x;
    }
  }
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t pi = (i + n - 1) % n;
    if (collapse[i]) {
      out.push_back(corner[i]);
      continue;
    }
    if (collapse[pi]) continue;  // the collapsed edge's end: its corner is out already
    if (!fitted[i] && !fitted[pi]) {
      out.push_back(poly[i]);
      continue;
    }
    Vec2 x;
    if (IntersectLines(line_p[pi], line_t[pi], line_p[i], line_t[i], C.parallel_deg, &x) &&
        (x - poly[i]).norm() < C.max_corner_shift) {
      out.push_back(x);
    } else {
      // Nearly parallel neighbours (a jog) or a far intersection: the old corner projected on
      // both lines.
      const Vec2 a = line_p[pi] + (poly[i] - line_p[pi]).dot(line_t[pi]) * line_t[pi];
      const Vec2 b = line_p[i] + (poly[i] - line_p[i]).dot(line_t[i]) * line_t[i];
      out.push_back(a);
      if ((a - b).norm() > C.split_corner) out.push_back(b);
    }
  }
  return out;
}

}  // namespace mopad::modelling
