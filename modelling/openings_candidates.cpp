// Step 3 of SM4 on one wall (modelling/openings.h): rectangles from the wall's lines, scored
// and validated (Score), the kept holes (not their casings), the openings they make, and one
// opening per hole.
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "modelling/openings.h"
#include "modelling/openings_internal.h"

namespace mopad::modelling::detail {
namespace {

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

// Scores one rectangle (see the file comment, step 3).
void Score(Candidate& k, const Masks& m, const OpeningParams& p, double px, int floor_row) {
  const int sb = std::max(1, static_cast<int>(std::lround(p.side_band / px)));
  const int ring = std::max(1, static_cast<int>(std::lround(p.ring / px)));
  const int c0 = k.cl + 1, c1 = k.cr, r0 = k.rt + 1, r1 = k.rb;
  const double area = double(c1 - c0) * (r1 - r0);
  if (area <= 0) return;
  k.known = m.known.Sum(c0, c1, r0, r1) / area;
  const Integral& ev =
      k.type == OpeningType::kDoor ? (k.needs_leaf ? m.ev_hole : m.ev_door) : m.ev_window;
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

}  // namespace

std::vector<Candidate> RectangleCandidates(const std::vector<Line>& vert,
                                           const std::vector<Line>& horz, const Masks& m,
                                           const OpeningParams& p, double px, int floor_row,
                                           int ceiling_row) {
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
        // Door: bottom at the floor, its head under a lintel (the wall's top edge, a line along
        // every wall, is no door's head).
        const double dh = (floor_row - rt) * px;
        if (width >= p.door_min_width && width <= p.door_max_width && dh >= p.door_min_height &&
            dh <= p.door_max_height && (rt - ceiling_row) * px >= p.door_head_clearance) {
          Candidate k;
          k.type = OpeningType::kDoor, k.cl = cl, k.cr = cr, k.rt = rt, k.rb = floor_row;
          if (interior_lines(cl, cr, rt, floor_row) <= p.max_interior_lines) {
            Score(k, m, p, px, floor_row);
            if (!k.valid) {
              // A doorway whose far side returned nothing (a door to the outside of a storey
              // standing in nothing, or under the sky): a door only if its leaf says so.
              Candidate q;
              q.type = k.type, q.cl = cl, q.cr = cr, q.rt = rt, q.rb = floor_row;
              q.needs_leaf = true;
              Score(q, m, p, px, floor_row);
              if (q.valid) k = q;
            }
          }
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

std::vector<Candidate> KeepHoles(const std::vector<Candidate>& cands, const Masks& m,
                                 const OpeningParams& p, double px) {
  std::vector<std::size_t> order(cands.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  // Best first; a door its leaf must confirm (needs_leaf) after every hole the images show
  // alone, so that it never displaces one and is then dropped for want of a leaf.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (cands[x].needs_leaf != cands[y].needs_leaf) return cands[y].needs_leaf;
    return cands[x].score > cands[y].score;
  });
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
    SetCorners(o, f);
    o.confidence = std::clamp(k.score, 0.0, 1.0);
    o.known_share = k.known, o.evidence_share = k.evidence, o.through_share = k.through;
    o.side_support = k.support;
    if (o.type == OpeningType::kDoor) {
      const DetectedOpening rect = o;
      FitDoor(o, vert, img, points, p, static_cast<std::uint64_t>(k.cl) * 100003u + k.rt);
      if (k.needs_leaf && !LeafOpenedOut(o, p)) continue;
      // The rectangle its lines gave is an object's outline (a shelf against the wall, its
      // side taken for a leaf that widened it): not a door, however wide the fit made it.
      if (o.u0 < rect.u0 || o.u1 > rect.u1) {
        DetectedOpening lines = o;
        lines.u0 = rect.u0, lines.u1 = rect.u1;
        if (StandsInFrontOfTheWall(lines, f, points.in, p)) continue;
      }
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

std::vector<DetectedOpening> OneOpeningPerHoleWithLines(std::vector<DetectedOpening> in,
                                                        const std::vector<Line>& vert,
                                                        const Masks& masks, const Orthoimage& img,
                                                        const WallPoints& points,
                                                        const OpeningParams& p) {
  const auto area = [](const DetectedOpening& o) { return o.Width() * o.Height(); };
  // The strip between two windows side by side, over their common rows: most of what is seen of
  // it is window evidence.
  const auto mullion_between = [&](const DetectedOpening& a, const DetectedOpening& b) {
    const DetectedOpening& l = a.u0 <= b.u0 ? a : b;
    const DetectedOpening& r = a.u0 <= b.u0 ? b : a;
    const auto tl = img.PixelOf(l.u1, std::min(a.v1, b.v1));
    const auto br = img.PixelOf(r.u0, std::max(a.v0, b.v0));
    const int c0 = tl[0], c1 = std::max(br[0], c0 + 1), r0 = tl[1], r1 = br[1] + 1;
    const double strip = double(c1 - c0) * std::max(0, r1 - r0);
    const double known = masks.known.Sum(c0, c1, r0, r1);
    return strip > 0.0 && known >= 0.2 * strip &&
           masks.ev_window.Sum(c0, c1, r0, r1) >= 0.5 * known;
  };
  bool merged = true;
  for (int round = 0; merged && round < 16; ++round) {
    merged = false;
    for (std::size_t i = 0; i < in.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < in.size() && !merged; ++j) {
        const DetectedOpening &a = in[i], &b = in[j];
        const bool doors = a.type == OpeningType::kDoor && b.type == OpeningType::kDoor;
        const bool windows = a.type == OpeningType::kWindow && b.type == OpeningType::kWindow;
        if (!doors && !windows) continue;
        const double gap = std::max(a.u0, b.u0) - std::min(a.u1, b.u1);
        const double u0 = std::min(a.u0, b.u0), u1 = std::max(a.u1, b.u1);
        if (doors && (gap >= p.door_merge_gap || u1 - u0 > p.door_max_width)) continue;
        // Two windows whose rows agree over half or more of the shorter one's, and that share
        // columns or have window evidence (recessed or seen through) over most of what is seen
        // of the strip between them: the casements of one window either side of its mullion (a
        // pier between two windows is on the wall's surface).
        const double rows = std::min(a.v1, b.v1) - std::max(a.v0, b.v0);
        if (windows && (rows < 0.5 * std::min(a.Height(), b.Height()) ||
                        u1 - u0 > p.window_max_width || (gap >= 0.0 && !mullion_between(a, b))))
          continue;
        DetectedOpening m = a.confidence >= b.confidence ? a : b;
        const double wa = area(a), wb = area(b), wsum = std::max(1e-12, wa + wb);
        m.u0 = u0, m.u1 = u1, m.v0 = std::min(a.v0, b.v0), m.v1 = std::max(a.v1, b.v1);
        m.confidence = std::max(a.confidence, b.confidence);
        m.known_share = (wa * a.known_share + wb * b.known_share) / wsum;
        m.evidence_share = (wa * a.evidence_share + wb * b.evidence_share) / wsum;
        m.through_share = (wa * a.through_share + wb * b.through_share) / wsum;
        m.side_support = std::max(a.side_support, b.side_support);
        if (windows) {
          SetCorners(m, img.Frame());
        } else {
          InsetCasingSides(m, vert, masks, img, p);
          const auto col = img.PixelOf(u0, m.v1);
          FitDoor(m, vert, img, points, p,
                  static_cast<std::uint64_t>(std::max(0, col[0])) * 100003u +
                      static_cast<std::uint64_t>(std::max(0, col[1])) + 7u);
        }
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

}  // namespace mopad::modelling::detail
