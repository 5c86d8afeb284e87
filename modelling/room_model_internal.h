#pragma once
// Internal to the room model (RoomModel's implementation files, modelling/room_*.cpp): the plan
// boundary used for the signed-distance lookups of the labels and the column search, and the
// tags packed with each point's azimuth column.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "modelling/room_model.h"

namespace mopad::modelling {

// ---------------------------------------------------------------------------------------------
// Plan boundary: the perimeter and column outlines as segments whose outward normal points out
// of the room's free space, with vertex pseudo-normals so the sign of the distance is right at
// corners; a coarse raster lists the segments near each cell so a point costs a few segments.
struct RoomModel::Boundary {
  struct Seg {
    Vec2 a = Vec2::Zero(), b = Vec2::Zero();    // ends
    Vec2 t = Vec2::UnitX(), n = Vec2::UnitY();  // unit direction, unit outward normal
    double len = 0.0;
    Vec2 na = Vec2::UnitY(), nb = Vec2::UnitY();  // pseudo-normals at a and b
    int face = -1;                                // RoI face index
    bool column = false;
  };
  std::vector<Seg> segs;
  Vec2 origin = Vec2::Zero();
  double cell = 0.1;
  int w = 0, h = 0;
  // zone: 0 = inside beyond `near`, 1 = near (check segs), 2 = outside beyond `near`
  std::vector<std::uint8_t> zone;
  std::vector<std::uint32_t> near_begin;  // w*h+1 offsets into near_ids
  std::vector<std::uint16_t> near_ids;

  void AddLoop(const std::vector<Vec2>& loop, bool column, int first_face) {
    const std::size_t n = loop.size(), base = segs.size();
    for (std::size_t i = 0; i < n; ++i) {
      Seg s;
      s.a = loop[i];
      s.b = loop[(i + 1) % n];
      s.len = (s.b - s.a).norm();
      s.t = s.len > 1e-12 ? Vec2((s.b - s.a) / s.len) : Vec2::UnitX();
      // Perimeter is CCW: outward = right of the direction. Columns are CCW too, but the room's
      // outside is their inside: left of the direction.
      s.n = column ? Vec2(-s.t.y(), s.t.x()) : Vec2(s.t.y(), -s.t.x());
      s.face = first_face + static_cast<int>(i);
      s.column = column;
      segs.push_back(s);
    }
    for (std::size_t i = 0; i < n; ++i) {
      Seg& s = segs[base + i];
      const Seg& prev = segs[base + (i + n - 1) % n];
      const Seg& next = segs[base + (i + 1) % n];
      s.na = (prev.n + s.n).normalized();
      s.nb = (s.n + next.n).normalized();
    }
  }

  // Signed distance (positive outside the room's free space) using segments `ids` (or all).
  double Signed(const Vec2& p, const std::uint16_t* ids, std::size_t count, int* seg_out) const {
    double best = std::numeric_limits<double>::infinity(), sign = 1.0;
    int best_seg = -1;
    const std::size_t m = ids ? count : segs.size();
    for (std::size_t k = 0; k < m; ++k) {
      const int si = ids ? ids[k] : static_cast<int>(k);
      const Seg& s = segs[si];
      const Vec2 ap = p - s.a;
      const double u = ap.dot(s.t);
      double d2;
      Vec2 nrm;
      Vec2 rel;
      if (u <= 0.0) {
        rel = ap;
        nrm = s.na;
      } else if (u >= s.len) {
        rel = p - s.b;
        nrm = s.nb;
      } else {
        rel = ap;
        nrm = s.n;
      }
      d2 = (u > 0.0 && u < s.len) ? std::pow(ap.dot(s.n), 2) : rel.squaredNorm();
      if (d2 < best) {
        best = d2;
        sign = rel.dot(nrm) >= 0.0 ? 1.0 : -1.0;
        best_seg = si;
      }
    }
    if (seg_out) *seg_out = best_seg;
    return sign * std::sqrt(best);
  }

  void BuildRaster(const Vec2& lo, const Vec2& hi, double cell_size, double near) {
    cell = cell_size;
    origin = lo;
    w = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
    h = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
    zone.assign(static_cast<std::size_t>(w) * h, 2);
    near_begin.assign(static_cast<std::size_t>(w) * h + 1, 0);
    near_ids.clear();
    const double hd = 0.5 * std::sqrt(2.0) * cell;
    std::vector<std::vector<std::uint16_t>> lists(static_cast<std::size_t>(w) * h);
    tbb::parallel_for(0, h, [&](int j) {
      for (int i = 0; i < w; ++i) {
        const Vec2 c = origin + cell * Vec2(i + 0.5, j + 0.5);
        const double sd = Signed(c, nullptr, 0, nullptr);
        const std::size_t idx = static_cast<std::size_t>(j) * w + i;
        if (sd < -(near + hd)) {
          zone[idx] = 0;
        } else if (sd > near + hd) {
          zone[idx] = 2;
        } else {
          zone[idx] = 1;
          const double reach = std::abs(sd) + 2.0 * hd + 1e-9;
          for (std::size_t k = 0; k < segs.size(); ++k) {
            if (SegDistance(segs[k], c) <= reach) {
              lists[idx].push_back(static_cast<std::uint16_t>(k));
            }
          }
        }
      }
    });
    for (std::size_t idx = 0; idx < lists.size(); ++idx) {
      near_begin[idx + 1] = near_begin[idx] + static_cast<std::uint32_t>(lists[idx].size());
      near_ids.insert(near_ids.end(), lists[idx].begin(), lists[idx].end());
    }
  }

  static double SegDistance(const Seg& s, const Vec2& p) {
    const double u = std::clamp((p - s.a).dot(s.t), 0.0, s.len);
    return (p - (s.a + u * s.t)).norm();
  }

  // Signed distance of p; `zone_out` 0/2 when p is deep inside/outside (distance then only a
  // bound: returns -inf / +inf).
  double Lookup(const Vec2& p, int* seg_out) const {
    const int i = static_cast<int>(std::floor((p.x() - origin.x()) / cell));
    const int j = static_cast<int>(std::floor((p.y() - origin.y()) / cell));
    if (seg_out) *seg_out = -1;
    if (i < 0 || j < 0 || i >= w || j >= h) return std::numeric_limits<double>::infinity();
    const std::size_t idx = static_cast<std::size_t>(j) * w + i;
    if (zone[idx] == 0) return -std::numeric_limits<double>::infinity();
    if (zone[idx] == 2) return std::numeric_limits<double>::infinity();
    const std::uint32_t b = near_begin[idx], e = near_begin[idx + 1];
    if (b == e) return Signed(p, nullptr, 0, seg_out);
    return Signed(p, near_ids.data() + b, e - b, seg_out);
  }
};

namespace detail {

// RoomModel::column_index_ packs each point's azimuth column with two flags.
constexpr std::uint32_t kRayCastBit = 0x80000000u;  // on the ray-casting stride
constexpr std::uint32_t kGapBit =
    0x40000000u;  // a gap (outline.gap_rows) without return precedes it
constexpr std::uint32_t kColumnMask = 0x3FFFFFFFu;

inline Vec2 Plan(const Eigen::Vector3f& p) { return Vec2(p.x(), p.y()); }

}  // namespace detail
}  // namespace mopad::modelling
