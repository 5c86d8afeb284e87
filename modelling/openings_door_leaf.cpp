// Step 4 of SM4 (modelling/openings.h): a door's leaf fitted in plan on the room's points near
// the doorway (its angle, hence the door's state), the reveals and the lintel that give the
// hole's sides and top through the wall, and the door rectangle moved and widened by them.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "common/rng.h"
#include "modelling/openings.h"
#include "modelling/openings_internal.h"

namespace mopad::modelling {
namespace detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

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

WallPoints AlongWall(const OrthoPoints& in, const PatchFrame& f) {
  WallPoints w{in, {}};
  if (in.points == nullptr) return w;
  w.u.reserve(in.points->size());
  for (const auto& pf : *in.points)
    w.u.push_back(static_cast<float>(f.ToUv(pf.cast<double>()).x()));
  return w;
}

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
  SetCorners(o, f);
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

}  // namespace detail

using detail::FitLeafNear;
using detail::WallPoints;

LeafFit FitDoorLeaf(const OrthoPoints& in, const PatchFrame& frame, double u0, double u1, double v0,
                    double v1, const OpeningParams& p, std::uint64_t index) {
  return FitLeafNear(WallPoints{in, {}}, frame, u0, u1, v0, v1, p, index);
}

}  // namespace mopad::modelling
