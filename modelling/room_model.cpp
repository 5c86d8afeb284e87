#include "modelling/room_model.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace mopad::modelling {

const char* ToString(PointLabel label) {
  switch (label) {
    case PointLabel::kNone:
      return "none";
    case PointLabel::kInlier:
      return "inlier";
    case PointLabel::kOutlier:
      return "outlier";
    case PointLabel::kClutter:
      return "clutter";
  }
  return "?";
}

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

namespace {

constexpr double kRefitGuard = 0.1;  // m, edge ends left out of a refit (corners)
constexpr double kChamferMax = 0.3;  // m, unfitted corner-cutting edges collapsed below this
constexpr double kWallEndMax = 0.6;  // m, a wall's end face is at most this wide (thick walls)
// m, a jump in the ceiling's reach between neighbouring azimuths that the outline steps
// radially around (TraceOutline): above the reach's noise along a wall.
constexpr double kShadowStep = 0.05;
// m, the outline's reach in a direction the scan saw nothing in (TraceOutline): about the
// robot's own half-width around the scanner, the only space known to be free there.
constexpr double kBlindOutlineRadius = 0.25;
constexpr double kRefitHighBand = 2.2;  // m above the floor: above door heads (2.0-2.1 m)
// column_index_ packs the azimuth column with two flags.
constexpr std::uint32_t kRayCastBit = 0x80000000u;  // on the ray-casting stride
constexpr std::uint32_t kGapBit = 0x40000000u;      // > kGapRows rows without return precede it
constexpr std::uint32_t kColumnMask = 0x3FFFFFFFu;
// Missing rows that make a gap. A wall closer than the scanner's minimum range returns nothing
// (the lintel over a door beside the scanner), so the next return may lie beyond the wall; a
// single dropout (dark, specular) is not a gap.
constexpr std::int64_t kGapRows = 2;
// m, 3D range under which a return may be followed by surfaces too close to return (scanners'
// minimum ranges are 0.5-1.5 m).
constexpr double kNearRange = 2.0;
// m: a return this close to the scan's shortest one lies at the scanner's minimum range.
constexpr double kMinRangeSlack = 0.1;

std::int64_t VoxelKey(const Eigen::Vector3f& p, double size) {
  const auto q = [size](float v) {
    return static_cast<std::int64_t>(std::floor(static_cast<double>(v) / size)) + (1 << 20);
  };
  return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
}

Vec2 Plan(const Eigen::Vector3f& p) { return Vec2(p.x(), p.y()); }

// Intersection of lines p + s*t and q + r*u; false if nearly parallel.
bool IntersectLines(const Vec2& p, const Vec2& t, const Vec2& q, const Vec2& u, Vec2* out) {
  const double den = t.x() * u.y() - t.y() * u.x();
  if (std::abs(den) < std::sin(DegToRad(5.0))) return false;
  const Vec2 d = q - p;
  const double s = (d.x() * u.y() - d.y() * u.x()) / den;
  *out = p + s * t;
  return true;
}

// Drops vertices whose neighbours make them (nearly) collinear or that close edges shorter
// than `min_len`; with `max_offset` > 0 first the jogs shallower than it (the refit moves
// edges onto their walls, and a short edge fitted across a doorway, where there is no wall,
// can land a few cm off the line and split one wall into pieces in SM3).
void Clean(std::vector<Vec2>& poly, double min_len, double max_offset = 0.0) {
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
      const bool collinear = std::abs(cross) < std::sin(DegToRad(3.0)) * ab.norm() * bc.norm();
      if (collinear || bc.norm() < min_len) {
        poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        break;
      }
    }
  }
}

// Views through openings (RoomModelParams::seal_depth): a run of vertices after a wall edge
// (at least kSealMinWall long) that passes behind the wall's line by more than kSealMinDepth
// (or jog_tolerance, if smaller) and at most seal_depth, never further into the room than
// seal_inward, spans at most seal_width along the line and comes back onto it ahead of the edge,
// where a parallel wall edge goes on, is replaced by the straight wall. A detour that stays in the
// room (a pilaster, a cabinet) is kept: it never passes behind.
constexpr double kSealMinWall = 0.3;    // m, the wall edges either side of the detour
constexpr double kSealOnLine = 0.03;    // m, the detour's end this close to the wall line
constexpr double kSealMinDepth = 0.05;  // m, behind the line: beyond the wall's own noise
constexpr std::size_t kSealMaxVertices = 12;

void SealOpenings(std::vector<Vec2>& poly, const RoomModelParams& P) {
  if (P.seal_depth <= 0.0) return;
  // Shallower detours are the jog rule's (Clean with jog_tolerance): the two rules meet, so a
  // vertex 4-5 cm behind a wall line falls between them (one split a wall in SM3).
  const double min_depth =
      P.jog_tolerance > 0.0 ? std::min(kSealMinDepth, P.jog_tolerance) : kSealMinDepth;
  bool changed = true;
  while (changed && poly.size() > 4) {
    changed = false;
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n && !changed; ++i) {
      const Vec2& a = poly[(i + n - 1) % n];
      const Vec2& b = poly[i];
      const double la = (b - a).norm();
      if (la < kSealMinWall) continue;
      const Vec2 t = (b - a) / la, out(t.y(), -t.x());  // CCW: `out` leaves the room
      double behind = 0.0, u_min = 0.0;
      for (std::size_t s = 1; s < std::min(n - 2, kSealMaxVertices + 1); ++s) {
        const Vec2& v = poly[(i + s) % n];
        const double u = (v - b).dot(t), d = (v - b).dot(out);
        u_min = std::min(u_min, u);  // a reveal seen obliquely reaches back under the wall
        if (u - u_min > P.seal_width + kSealOnLine || d > P.seal_depth || d < -P.seal_inward) break;
        if (s >= 2 && std::abs(d) <= kSealOnLine && u > 0.0 && behind > min_depth) {
          const Vec2& w = poly[(i + s + 1) % n];
          const double lw = (w - v).norm();
          if (lw >= kSealMinWall && (w - v).dot(t) >= lw * std::cos(DegToRad(5.0))) {
            const std::size_t first = i + 1, last = i + s;  // erase [first, last)
            if (last <= n) {
              poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(first),
                         poly.begin() + static_cast<std::ptrdiff_t>(last));
            } else {
              poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(first), poly.end());
              poly.erase(poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(last - n));
            }
            Clean(poly, P.min_edge_length);  // the wall's pieces either side become one edge
            changed = true;
            break;
          }
        }
        behind = std::max(behind, d);
      }
    }
  }
}

}  // namespace

void TidyPerimeter(std::vector<Vec2>& poly, const RoomModelParams& params) {
  Clean(poly, params.min_edge_length, params.jog_tolerance);
  SealOpenings(poly, params);
  Clean(poly, params.min_edge_length, params.jog_tolerance);
}

RoomModel::RoomModel(RoomModelParams params) : params_(params) { params_.Validate(); }

LabelCounts RoomModel::CountLabels() const {
  LabelCounts c;
  for (PointLabel l : labels_) {
    switch (l) {
      case PointLabel::kNone:
        ++c.none;
        break;
      case PointLabel::kInlier:
        ++c.inlier;
        break;
      case PointLabel::kOutlier:
        ++c.outlier;
        break;
      case PointLabel::kClutter:
        ++c.clutter;
        break;
    }
  }
  return c;
}

void RoomModel::AddScan(const interfaces::TlsScan& scan, const Pose3& X_MS) {
  const std::string where = "scan " + std::to_string(scan.scan_id);
  if (static_cast<std::size_t>(scan.rows) * scan.columns != scan.points.size()) {
    throw InputError(where, "scan grid and point count disagree",
                     std::to_string(scan.points.size()),
                     std::to_string(scan.rows) + " x " + std::to_string(scan.columns));
  }
  if (!X_MS.matrix().allFinite()) throw InputError(where, "scanner pose is not finite");
  if (scans_.size() >= 65535) throw InputError(where, "too many scans in one room", "", "< 65535");

  ScanRecord rec;
  rec.begin = points_.size();
  rec.origin = X_MS.translation();
  const Eigen::Matrix3f R = X_MS.linear().cast<float>();
  const Eigen::Vector3f T = X_MS.translation().cast<float>();
  const auto scan_no = static_cast<std::uint16_t>(scans_.size());
  // Column by column, top row first: the perimeter trace walks each column in this order.
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    std::int64_t prev_row = -1;
    for (std::uint32_t r = 0; r < scan.rows; ++r) {
      const interfaces::TlsPoint& p = scan.at(r, c);
      if (!p.valid()) continue;
      const Eigen::Vector3f q = R * Eigen::Vector3f(p.x, p.y, p.z) + T;
      if (!q.allFinite()) continue;
      points_.push_back(q);
      colours_.push_back({p.r, p.g, p.b});
      intensity_.push_back(p.intensity);
      scan_index_.push_back(scan_no);
      std::uint32_t tag = c;
      if (r % params_.ray_stride == 0 && c % params_.ray_stride == 0) tag |= kRayCastBit;
      if (static_cast<std::int64_t>(r) - prev_row > kGapRows) tag |= kGapBit;
      column_index_.push_back(tag);
      prev_row = r;
    }
  }
  rec.end = points_.size();
  if (rec.end == rec.begin) throw InputError(where, "scan has no valid return");
  rec.columns = scan.columns;
  rec.azimuth_min = scan.azimuth_min;
  rec.azimuth_step = scan.azimuth_step;
  rec.R_MS = X_MS.linear();
  rec.min_range = std::numeric_limits<double>::infinity();
  for (const auto& p : scan.points)
    if (p.valid()) rec.min_range = std::min(rec.min_range, static_cast<double>(p.range));
  labels_.resize(points_.size(), PointLabel::kNone);
  scans_.push_back(rec);
  scan_poses_.push_back(X_MS);

  UpdateWorkingCloud(rec.begin, rec.end);
  if (!structure_frozen_) {
    const double old_ceiling = roi_.ceiling_z;
    EstimateHeights();
    const bool retrace = scans_.size() == 1 || std::abs(roi_.ceiling_z - old_ceiling) > 0.01;
    for (std::size_t s = retrace ? 0 : scans_.size() - 1; s < scans_.size(); ++s) {
      TraceOutline(scans_[s]);
    }
    BuildPerimeter();
    DetectColumns();
    BuildRoi();
  }
  LabelAll();
  UpdateFaces();
  UpdateVoxels(true);
  UpdateCoverage();
}

void RoomModel::UpdateWorkingCloud(std::size_t begin, std::size_t end) {
  const double v = params_.working_voxel;
  for (std::size_t i = begin; i < end; ++i) {
    const std::int64_t key = VoxelKey(points_[i], v);
    auto [it, inserted] = work_slot_.try_emplace(key, static_cast<std::uint32_t>(work_sum_.size()));
    if (inserted) {
      work_sum_.push_back(Vec3::Zero());
      work_count_.push_back(0);
    }
    work_sum_[it->second] += points_[i].cast<double>();
    ++work_count_[it->second];
  }
  work_points_.resize(work_sum_.size());
  for (std::size_t k = 0; k < work_sum_.size(); ++k) {
    work_points_[k] = (work_sum_[k] / work_count_[k]).cast<float>();
  }
}

void RoomModel::EstimateHeights() {
  // Z-histogram of the working cloud (area-like weights: one count per working voxel). Floor:
  // the lowest strong peak below the scanners; ceiling: the highest strong peak above them.
  double zs = 0.0;
  for (const auto& s : scans_) zs += s.origin.z();
  zs /= static_cast<double>(scans_.size());
  const double bin = params_.histogram_bin;
  const double lo = zs - 10.0, hi = zs + 10.0;
  const int n = static_cast<int>((hi - lo) / bin);
  std::vector<double> hist(n, 0.0);
  for (const auto& p : work_points_) {
    const int b = static_cast<int>(std::floor((p.z() - lo) / bin));
    if (b >= 0 && b < n) hist[b] += 1.0;
  }
  std::vector<double> sm(n, 0.0);
  for (int b = 1; b + 1 < n; ++b) sm[b] = 0.25 * hist[b - 1] + 0.5 * hist[b] + 0.25 * hist[b + 1];
  const int mid = static_cast<int>((zs - lo) / bin);
  const int guard = static_cast<int>(0.3 / bin);
  auto pick = [&](int b0, int b1, bool lowest) {
    double m = 0.0;
    for (int b = b0; b < b1; ++b) m = std::max(m, sm[b]);
    if (m <= 0.0) return -1;
    // Strong local maxima (>= 30 % of the highest); the extreme one wins.
    int best = -1;
    for (int b = std::max(b0, 1); b < std::min(b1, n - 1); ++b) {
      if (sm[b] >= 0.3 * m && sm[b] >= sm[b - 1] && sm[b] >= sm[b + 1]) {
        if (best < 0 || !lowest) best = b;
        if (lowest) break;
      }
    }
    return best;
  };
  const int bf = pick(0, std::max(1, mid - guard), true);
  const int bc = pick(std::min(n - 1, mid + guard), n, false);
  auto refine = [&](int b) {
    const double c = lo + (b + 0.5) * bin;
    double sum = 0.0, cnt = 0.0;
    for (const auto& p : work_points_) {
      if (std::abs(p.z() - c) <= 1.5 * bin) {
        sum += p.z();
        cnt += 1.0;
      }
    }
    return cnt > 0 ? sum / cnt : c;
  };
  roi_.floor_z = bf >= 0 ? refine(bf) : zs - 1.4;
  roi_.ceiling_z = bc >= 0 ? refine(bc) : zs + 1.4;
}

void RoomModel::TraceOutline(ScanRecord& rec) const {
  // Per azimuth column, walk down from the top row: ceiling points (and small things hanging
  // just below it) continue the walk; the first point well below the ceiling that is not closer
  // than the ceiling seen so far (a wall, a lintel, a column) ends it. The farthest accepted
  // point is the outline vertex of that azimuth. The blind cone above the scanner lies inside.
  const double ceil = roi_.ceiling_z;
  const double tol = params_.ceiling_tolerance;
  const double hang = 0.25;  // m, hanging depth tolerated below the ceiling
  const Vec2 o = rec.origin.head<2>();
  rec.outline.clear();
  // Per column: no return at all (empty), or the vertex of its walk (has).
  struct Column {
    bool empty = true, has = false;
    Vec2 vertex = Vec2::Zero();
  };
  std::vector<Column> cols(rec.columns);
  std::size_t i = rec.begin;
  while (i < rec.end) {
    const std::uint32_t col = column_index_[i] & kColumnMask;
    std::size_t j = i;
    while (j < rec.end && (column_index_[j] & kColumnMask) == col) ++j;
    double best_rho = -1.0, last_rho = 0.0;
    Vec2 vertex = Vec2::Zero();
    bool any = false, on_ceiling = false, last_near = false;
    for (std::size_t k = i; k < j; ++k) {
      const Eigen::Vector3f& p = points_[k];
      const Vec2 q = Plan(p);
      const double rho = (q - o).norm();
      const double dz = ceil - p.z();
      const bool ceiling_like = std::abs(dz) <= tol || (dz > 0 && dz <= hang);
      // Rows without return before this point: what they looked at is unknown. After a wall
      // top (or before anything was seen) it is typically the rest of a wall too close to
      // return (a lintel over a door beside the scanner), and the next return is the next
      // room's ceiling: the walk ends. On the ceiling a gap is a dropout, unless the last
      // ceiling return was itself near the minimum range (a low ceiling beside a door wall).
      // A gap before a column's first return, when that return is ceiling at the scan's
      // shortest range, is the ceiling inside the scanner's minimum range (a low ceiling right
      // above the scanner), not a wall too close to return.
      const double range = (p.cast<double>() - rec.origin).norm();
      const bool near = range < kNearRange;
      const bool ceiling_above =
          !any && std::abs(dz) <= tol && range <= rec.min_range + kMinRangeSlack;
      if ((column_index_[k] & kGapBit) && ceiling_like && !ceiling_above &&
          (!any || !on_ceiling || last_near))
        break;
      if (ceiling_like) {
        last_near = near;
        if (rho > best_rho) {
          best_rho = rho;
          vertex = q;
        }
        on_ceiling = std::abs(dz) <= tol;
        if (on_ceiling) last_rho = std::max(last_rho, rho);
        any = true;
        continue;
      }
      if (dz > 0 && rho < last_rho - 0.05) continue;  // an occluder in front of the ceiling
      if (!any && p.z() > rec.origin.z()) {           // a wall right beside the scanner
        vertex = q;
        best_rho = rho;
      }
      break;
    }
    if (col < cols.size()) {
      cols[col].empty = false;
      if (best_rho > 0.0) cols[col] = {false, true, vertex};
    }
    i = j;
  }
  // Columns without a vertex are bridged by the edge between their neighbours' vertices. A
  // column without any return saw something inside the minimum range (a wall's end right
  // beside the scanner): where the bridge passes beyond that range, it would claim space the
  // column says is blocked nearer, so those columns keep to the scanner's surroundings instead.
  // (A wall along the scanner closer than the minimum range is bridged by its own far parts.)
  std::vector<std::uint32_t> with;
  for (std::uint32_t c = 0; c < rec.columns; ++c)
    if (cols[c].has) with.push_back(c);
  const double reach = rec.min_range + kMinRangeSlack;
  auto direction = [&](std::uint32_t c) {
    const double a = rec.azimuth_min + rec.azimuth_step * static_cast<double>(c);
    return Vec2((rec.R_MS * Vec3(std::cos(a), std::sin(a), 0.0)).head<2>().normalized());
  };
  for (std::size_t k = 0; k < with.size(); ++k) {
    const std::uint32_t a = with[k], b = with[(k + 1) % with.size()];
    rec.outline.push_back(cols[a].vertex);
    const std::uint32_t n_between = (b + rec.columns - a - 1) % rec.columns;
    if (with.size() < 2 || n_between == 0) continue;
    const Vec2 A = cols[a].vertex, AB = cols[b].vertex - A;
    bool beyond = false;
    for (std::uint32_t m = 1; m <= n_between && !beyond; ++m) {
      const std::uint32_t c = (a + m) % rec.columns;
      if (!cols[c].empty) continue;
      // Where the column's ray meets the bridge A-B (none: taken as beyond).
      const Vec2 d = direction(c), w = A - o;
      const double den = d.x() * AB.y() - d.y() * AB.x();
      const double t = std::abs(den) > 1e-12 ? (w.x() * AB.y() - w.y() * AB.x()) / den : -1.0;
      const double u = std::abs(den) > 1e-12 ? (w.x() * d.y() - w.y() * d.x()) / den : -1.0;
      beyond = !(t > 0.0 && u >= -1e-9 && u <= 1.0 + 1e-9 && t <= reach);
    }
    if (!beyond) continue;
    for (std::uint32_t m = 1; m <= n_between; ++m) {
      const std::uint32_t c = (a + m) % rec.columns;
      if (cols[c].empty) rec.outline.push_back(o + kBlindOutlineRadius * direction(c));
    }
  }
  // Where the ceiling's reach jumps between neighbouring azimuths (the end of a wall, a door
  // jamb, a re-entrant corner seen past its edge), the straight edge between the two vertices
  // would claim the unseen shadow behind the nearer one: the outline steps radially instead,
  // at the nearer reach on the farther azimuth. Along a smooth wall the step costs a sliver
  // of one azimuth step's width.
  const std::size_t m = rec.outline.size();
  if (m < 3) return;
  std::vector<Vec2> stepped;
  stepped.reserve(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    const Vec2& a = rec.outline[k];
    const Vec2& b = rec.outline[(k + 1) % m];
    stepped.push_back(a);
    const double ra = (a - o).norm(), rb = (b - o).norm();
    if (std::abs(ra - rb) <= kShadowStep) continue;
    stepped.push_back(ra < rb ? o + (b - o) * (ra / rb) : o + (a - o) * (rb / ra));
  }
  rec.outline.swap(stepped);
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
  Clean(poly, params_.min_edge_length);
  RefitPerimeter(poly);
  TidyPerimeter(poly, params_);
  if (SignedArea(poly) < 0) std::reverse(poly.begin(), poly.end());
  roi_.perimeter = poly;
}

namespace {

// One perimeter edge a -> b moved onto its wall (RoomModel::RefitPerimeter): `band` are the
// plan points between the floor and ceiling bands, `high` flags those above door heads.
PerimeterLine FitWallEdge(const Vec2& a, const Vec2& b, const std::vector<Vec2>& band,
                          const std::vector<std::uint8_t>& high, const RoomModelParams& P) {
  const double bandw = P.refit_band, tol = P.wall_tolerance;
  const double len = (b - a).norm();
  const Vec2 t = (b - a) / std::max(len, 1e-12), nrm(t.y(), -t.x());
  PerimeterLine fit{a, t, false, t};
  const double guard = len > 3 * kRefitGuard ? kRefitGuard : 0.0;
  const int nb = static_cast<int>(std::ceil(2 * bandw / 0.005)) + 1;
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
    const int bin = static_cast<int>((s + bandw) / 0.005);
    ++hist[bin];
    if (high[k]) ++hist_high[bin], ++n_high;
  }
  if (static_cast<int>(near.size()) < P.refit_min_points) return fit;
  // The wall is the outermost strong peak: a closed door leaf or a cabinet flush against the
  // wall can be nearly as dense as the wall itself but lies in front of it, and where it
  // covers most of the wall below its head it outnumbers the wall (office_5rooms, the hall's
  // 2 m west end wall behind closed door D13: 4633 against 1918 points). Above door heads
  // (kRefitHighBand) only the wall remains: its peak there is the anchor when it has enough
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
    if (peak && sm[k] >= 0.5 * hmax) hb = k;
  }
  const double s0 = (hb + 0.5) * 0.005 - bandw;
  // Points within tol of the offset line; support must span part of the edge.
  Vec2 mean = Vec2::Zero();
  std::vector<Vec2> sel, sel_high;
  std::vector<std::uint8_t> bins(static_cast<std::size_t>(len / 0.1) + 1, 0);
  std::vector<std::uint8_t> bins_high(bins.size(), 0);
  for (std::size_t k = 0; k < near.size(); ++k) {
    const Vec2& p = near[k];
    const double s = (p - a).dot(nrm);
    if (std::abs(s - s0) <= tol) {
      sel.push_back(p);
      mean += p;
      const std::size_t b =
          std::min(bins.size() - 1, static_cast<std::size_t>((p - a).dot(t) / 0.1));
      bins[b] = 1;
      if (near_high[k]) sel_high.push_back(p), bins_high[b] = 1;
    }
  }
  const int covered = std::accumulate(bins.begin(), bins.end(), 0);
  if (static_cast<int>(sel.size()) < P.refit_min_points ||
      covered < std::max<int>(2, static_cast<int>(0.2 * bins.size()))) {
    return fit;
  }
  // The line itself from the points above door heads where they cover most of the edge:
  // below, window reveals and furniture flush against the wall tilt it (R1's 14 m south
  // wall, two windows and desks along it: 1.55 cm over its length, 1.8 % of its points then
  // past the tolerance).
  const int covered_high = std::accumulate(bins_high.begin(), bins_high.end(), 0);
  if (static_cast<int>(sel_high.size()) >= P.refit_min_points &&
      covered_high >= static_cast<int>(0.5 * covered)) {
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
    return dir.dot(t) < std::cos(DegToRad(10.0)) ? t : dir;  // else keep the direction, only shift
  };
  Vec2 dir = pca_dir(sel, mean);
  // Tighten about the wall peak: clutter flush against part of a wall (a closed door leaf or
  // casing 2 cm proud over half of a 2 m end wall, a whiteboard row) lies inside the band and
  // pulls a least-squares line towards it, up to onto it where it has more points than the
  // wall (a long wall tilts; an end wall behind a closed door moves onto the door, its wall
  // points then outliers; docs/room-scanning.md has the cases). Refit from the line at
  // the outermost strong peak s0 on the points within 0.6 and then 0.4 of the band about the
  // current line, while at least a fifth of the band's points remain.
  {
    Vec2 lp = a + s0 * nrm + 0.5 * len * t, ld = t;
    bool refit = false;
    for (double f : {0.6, 0.4}) {
      std::vector<Vec2> tight;
      Vec2 m2 = Vec2::Zero();
      const Vec2 nn(ld.y(), -ld.x());
      for (const auto& p : sel)
        if (std::abs((p - lp).dot(nn)) <= f * tol) tight.push_back(p), m2 += p;
      if (static_cast<int>(tight.size()) <
          std::max(P.refit_min_points, static_cast<int>(0.2 * sel.size())))
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

void RoomModel::RefitPerimeter(std::vector<Vec2>& poly) const {
  // Each edge is moved onto its wall: the densest offset of the wall points near it (walls are
  // the farthest dense surface; clutter in front only thins the histogram), then a total
  // least-squares line through the points close to that offset. Corners are re-intersected.
  const std::size_t n = poly.size();
  if (n < 3) return;
  const double z0 = roi_.floor_z + 0.2, z1 = roi_.ceiling_z - 0.1;
  // Above door heads only the wall itself reaches (a lintel, the wall over a cabinet): the
  // wall's offset is looked for there first.
  const double z_high = roi_.floor_z + kRefitHighBand;
  std::vector<Vec2> band;
  std::vector<std::uint8_t> high;
  band.reserve(work_points_.size() / 2);
  for (const auto& p : work_points_) {
    if (p.z() > z0 && p.z() < z1) {
      band.push_back(Plan(p));
      high.push_back(p.z() > z_high ? 1 : 0);
    }
  }
  std::vector<PerimeterLine> fits(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    fits[i] = FitWallEdge(poly[i], poly[(i + 1) % n], band, high, params_);
  });
  poly = JoinPerimeterLines(poly, fits, params_);
}

std::vector<Vec2> JoinPerimeterLines(const std::vector<Vec2>& poly,
                                     const std::vector<PerimeterLine>& lines,
                                     const RoomModelParams& params) {
  const std::size_t n = poly.size();
  if (n < 3 || lines.size() != n) return poly;
  std::vector<Vec2> line_p(n), line_t(n);
  std::vector<bool> fitted(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    line_p[i] = lines[i].p;
    line_t[i] = lines[i].t;
    fitted[i] = lines[i].fitted;
  }
  // A short fitted edge between two antiparallel fitted walls is the end face of a wall that
  // stands into the room: walls are prisms, so it is square to them. Its traced direction is
  // poor (each end moved by up to perimeter_epsilon: tens of degrees on a 0.2 m edge) and tilts
  // its fit. The trace may also have cut one of its corners (a second short edge): of the two
  // the squarer is the end face, the other is left unfitted and collapses below.
  auto length = [&](std::size_t k) { return (poly[(k + 1) % n] - poly[k]).norm(); };
  for (std::size_t i = 0; i < n && n >= 6; ++i) {
    if (!fitted[i] || length(i) >= kWallEndMax) continue;
    std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n, other = n;
    if (length(pi) < kChamferMax)
      other = pi, pi = (pi + n - 1) % n;
    else if (length(ni) < kChamferMax)
      other = ni, ni = (ni + 1) % n;
    if (!fitted[pi] || !fitted[ni] || pi == ni) continue;
    if (line_t[pi].dot(line_t[ni]) > -std::cos(DegToRad(5.0))) continue;
    const Vec2 side = (line_t[pi] - line_t[ni]).normalized();
    if (other < n && other != i && fitted[other] &&
        std::abs(line_t[other].dot(side)) < std::abs(line_t[i].dot(side)))
      continue;  // the other is the end face
    if (other < n && length(i) + length(other) >= kWallEndMax) continue;
    const Vec2 square(-side.y(), side.x());
    const Vec2 traced = poly[(i + 1) % n] - poly[i];
    line_t[i] = square.dot(traced) >= 0.0 ? square : Vec2(-square);
    if (other < n) fitted[other] = false;
  }
  // A short fitted edge whose points run within 10 deg of a fitted neighbour's line and lie on
  // it (their mean within twice the wall tolerance: the band one wall's points fill) carries
  // that wall's own points: the tracer cut the corner at the wall's end (along the wall, up to
  // a wall end's width) and the refit moved the cut onto the wall's face. It is no face of its
  // own (SM3 would get a wall a few degrees off beside the real one): it collapses below with
  // the unfitted cuts, its neighbours extended to their corner. Only at a corner: the other
  // neighbour is a fitted wall at least 45 deg off.
  std::vector<bool> on_neighbour(n, false);
  for (std::size_t i = 0; i < n && n >= 5; ++i) {
    if (!fitted[i] || length(i) >= kWallEndMax) continue;
    const std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n;
    if (!fitted[pi] || !fitted[ni] ||
        std::abs(line_t[pi].dot(line_t[ni])) > std::cos(DegToRad(45.0)))
      continue;
    for (const std::size_t k : {pi, ni}) {
      const Vec2 nk(-line_t[k].y(), line_t[k].x());
      if (std::abs(lines[i].support.dot(line_t[k])) > std::cos(DegToRad(10.0)) &&
          std::abs((line_p[i] - line_p[k]).dot(nk)) <= 2.0 * params.wall_tolerance) {
        fitted[i] = false;
        on_neighbour[i] = true;
        break;
      }
    }
  }
  // A short edge left unfitted between two fitted walls is the tracer cutting their corner
  // (a re-entrant corner seen obliquely: office_5rooms R1's L corner got a 13 cm chamfer, a
  // false 'wall' in SM3): the two walls meet in one corner instead.
  std::vector<bool> collapse(n, false);
  std::vector<Vec2> corner(n, Vec2::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t pi = (i + n - 1) % n, ni = (i + 1) % n;
    if (fitted[i] || !fitted[pi] || !fitted[ni] || (pi > 0 && collapse[pi]) || n < 5) continue;
    const double reach = on_neighbour[i] ? kWallEndMax : kChamferMax;
    if ((poly[ni] - poly[i]).norm() >= reach) continue;
    Vec2 x;
    if (IntersectLines(line_p[pi], line_t[pi], line_p[ni], line_t[ni], &x) &&
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
    if (IntersectLines(line_p[pi], line_t[pi], line_p[i], line_t[i], &x) &&
        (x - poly[i]).norm() < 0.5) {
      out.push_back(x);
    } else {
      // Nearly parallel neighbours (a jog) or a far intersection: the old corner projected on
      // both lines.
      const Vec2 a = line_p[pi] + (poly[i] - line_p[pi]).dot(line_t[pi]) * line_t[pi];
      const Vec2 b = line_p[i] + (poly[i] - line_p[i]).dot(line_t[i]) * line_t[i];
      out.push_back(a);
      if ((a - b).norm() > 0.02) out.push_back(b);
    }
  }
  return out;
}

void RoomModel::DetectColumns() {
  // Vertical structures inside the perimeter that reach from near the floor to just below the
  // ceiling: plan cells (5 cm) with points in the top slice, grouped; a group small enough and
  // seen over most of the height is a column; its footprint is the convex hull of its points.
  roi_.columns.clear();
  if (roi_.perimeter.size() < 3) return;
  Boundary outer;
  outer.AddLoop(roi_.perimeter, false, 0);
  const double c = 0.05;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi_.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const int w = static_cast<int>(std::ceil((hi.x() - lo.x()) / c)) + 1;
  const int h = static_cast<int>(std::ceil((hi.y() - lo.y()) / c)) + 1;
  constexpr int kSlices = 8;
  const double z0 = roi_.floor_z + 0.1, z1 = roi_.ceiling_z - 0.05;
  const double sh = (z1 - z0) / kSlices;
  if (sh <= 0) return;
  std::vector<std::uint16_t> mask(static_cast<std::size_t>(w) * h, 0);
  // Cells near the perimeter are wall; skip them (columns touching walls are pilasters, part of
  // the perimeter).
  cv::Mat inside = cv::Mat::zeros(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const Vec2 p = lo + c * Vec2(i + 0.5, j + 0.5);
      if (outer.Signed(p, nullptr, 0, nullptr) < -0.15) inside.at<std::uint8_t>(j, i) = 1;
    }
  }
  for (const auto& p : work_points_) {
    if (p.z() < z0 || p.z() >= z1) continue;
    const int i = static_cast<int>((p.x() - lo.x()) / c),
              j = static_cast<int>((p.y() - lo.y()) / c);
    if (i < 0 || j < 0 || i >= w || j >= h || !inside.at<std::uint8_t>(j, i)) continue;
    const int s = std::min(kSlices - 1, static_cast<int>((p.z() - z0) / sh));
    mask[static_cast<std::size_t>(j) * w + i] |= static_cast<std::uint16_t>(1u << s);
  }
  cv::Mat top = cv::Mat::zeros(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      if (mask[static_cast<std::size_t>(j) * w + i] & (1u << (kSlices - 1)))
        top.at<std::uint8_t>(j, i) = 255;
    }
  }
  cv::dilate(top, top, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::Mat labels, stats, centroids;
  const int ncomp = cv::connectedComponentsWithStats(top, labels, stats, centroids, 8, CV_32S);
  const int max_cells = static_cast<int>(params_.column_max_size / c) + 2;
  for (int k = 1; k < ncomp; ++k) {
    const int bw = stats.at<int>(k, cv::CC_STAT_WIDTH), bh = stats.at<int>(k, cv::CC_STAT_HEIGHT);
    if (bw > max_cells || bh > max_cells) continue;
    const int bx = stats.at<int>(k, cv::CC_STAT_LEFT), by = stats.at<int>(k, cv::CC_STAT_TOP);
    std::uint16_t all = 0;
    for (int j = by; j < by + bh; ++j) {
      for (int i = bx; i < bx + bw; ++i) {
        if (labels.at<int>(j, i) == k) all |= mask[static_cast<std::size_t>(j) * w + i];
      }
    }
    if (__builtin_popcount(all) < params_.column_min_height_share * kSlices) continue;
    std::vector<cv::Point2f> pts;
    for (const auto& p : work_points_) {
      if (p.z() < z0 || p.z() >= z1) continue;
      const int i = static_cast<int>((p.x() - lo.x()) / c),
                j = static_cast<int>((p.y() - lo.y()) / c);
      if (i < 0 || j < 0 || i >= w || j >= h || labels.at<int>(j, i) != k) continue;
      pts.emplace_back(p.x(), p.y());
    }
    if (pts.size() < 20) continue;
    std::vector<cv::Point2f> hull, simple;
    cv::convexHull(pts, hull);
    cv::approxPolyDP(hull, simple, 0.01, true);
    std::vector<Vec2> fp;
    for (const auto& p : simple) fp.emplace_back(p.x, p.y);
    if (fp.size() < 3 || std::abs(SignedArea(fp)) < 0.01) continue;
    if (SignedArea(fp) < 0) std::reverse(fp.begin(), fp.end());
    roi_.columns.push_back(fp);
  }
}

namespace {

// A horizontal RoI face (floor or ceiling) at height z over the plan bounding box [lo, hi]:
// cells inside the RoI's plan are unsensed, the others off.
RoiFace HorizontalFace(const Roi& roi, FaceKind kind, double z, const Vec2& lo, const Vec2& hi,
                       double plan_area, double cell) {
  RoiFace f;
  f.kind = kind;
  f.normal = kind == FaceKind::kFloor ? Vec3(0, 0, -1) : Vec3(0, 0, 1);
  f.area = plan_area;
  f.origin = Vec3(lo.x(), lo.y(), z);
  f.u_axis = Vec3::UnitX();
  f.v_axis = Vec3::UnitY();
  f.cell = cell;
  f.nu = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
  f.nv = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
  f.cells.assign(static_cast<std::size_t>(f.nu) * f.nv, FaceCell::kOff);
  f.cell_area.assign(f.cells.size(), 0.0f);
  for (int iv = 0; iv < f.nv; ++iv) {
    for (int iu = 0; iu < f.nu; ++iu) {
      const Vec2 c = lo + cell * Vec2(iu + 0.5, iv + 0.5);
      if (roi.ContainsPlan(c)) {
        f.cells[static_cast<std::size_t>(iv) * f.nu + iu] = FaceCell::kUnsensed;
        f.cell_area[static_cast<std::size_t>(iv) * f.nu + iu] = static_cast<float>(cell * cell);
      }
    }
  }
  return f;
}

// A vertical RoI face (wall or column face) from plan point a to b, floor zf to zf + H, with
// outward normal n_out; its cells unsensed, the last row and column cut to the face.
RoiFace VerticalFace(FaceKind kind, int element, const Vec2& a, const Vec2& b, const Vec2& n_out,
                     std::vector<int> loop, double zf, double H, double cell) {
  RoiFace f;
  f.kind = kind;
  f.element = element;
  f.loop = std::move(loop);
  f.normal = Vec3(n_out.x(), n_out.y(), 0.0);
  const double len = (b - a).norm();
  f.area = len * H;
  const Vec2 t = (b - a) / std::max(len, 1e-12);
  f.origin = Vec3(a.x(), a.y(), zf);
  f.u_axis = Vec3(t.x(), t.y(), 0.0);
  f.v_axis = Vec3::UnitZ();
  f.cell = cell;
  f.nu = std::max(1, static_cast<int>(std::ceil(len / cell)));
  f.nv = std::max(1, static_cast<int>(std::ceil(H / cell)));
  f.cells.assign(static_cast<std::size_t>(f.nu) * f.nv, FaceCell::kUnsensed);
  f.cell_area.resize(f.cells.size());
  for (int iv = 0; iv < f.nv; ++iv) {
    const double hv = std::min(cell, H - iv * cell);
    for (int iu = 0; iu < f.nu; ++iu) {
      const double hu = std::min(cell, len - iu * cell);
      f.cell_area[static_cast<std::size_t>(iv) * f.nu + iu] = static_cast<float>(hu * hv);
    }
  }
  return f;
}

// Edges of one prism ring: the floor and ceiling edges of each side face and the vertical
// corners between consecutive side faces (faces face_first .. face_first + m - 1).
void AddRingEdges(Roi& roi, const std::vector<int>& b, const std::vector<int>& t, int face_first) {
  const int m = static_cast<int>(b.size());
  for (int i = 0; i < m; ++i) {
    roi.edges.push_back({b[i], b[(i + 1) % m], 0, face_first + i});
    roi.edges.push_back({t[i], t[(i + 1) % m], 1, face_first + i});
    roi.edges.push_back({b[i], t[i], face_first + (i + m - 1) % m, face_first + i});
  }
}

}  // namespace

void RoomModel::BuildRoi() {
  Roi& roi = roi_;
  roi.vertices.clear();
  roi.edges.clear();
  roi.faces.clear();
  roi.face_adjacency.clear();
  if (roi.perimeter.size() < 3) return;
  const double zf = roi.floor_z, zc = roi.ceiling_z, H = zc - zf, cell = params_.face_cell;
  // Faces: 0 floor, 1 ceiling, walls, column faces.
  auto add_loop_vertices = [&](const std::vector<Vec2>& loop, std::vector<int>& bottom,
                               std::vector<int>& top) {
    for (const auto& v : loop) {
      bottom.push_back(static_cast<int>(roi.vertices.size()));
      roi.vertices.emplace_back(v.x(), v.y(), zf);
      top.push_back(static_cast<int>(roi.vertices.size()));
      roi.vertices.emplace_back(v.x(), v.y(), zc);
    }
  };
  std::vector<int> pb, pt;
  add_loop_vertices(roi.perimeter, pb, pt);
  std::vector<std::vector<int>> cb(roi.columns.size()), ct(roi.columns.size());
  for (std::size_t k = 0; k < roi.columns.size(); ++k)
    add_loop_vertices(roi.columns[k], cb[k], ct[k]);

  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  double plan_area = std::abs(SignedArea(roi.perimeter));
  for (const auto& c : roi.columns) plan_area -= std::abs(SignedArea(c));
  RoiFace floor = HorizontalFace(roi, FaceKind::kFloor, zf, lo, hi, plan_area, cell);
  floor.loop.assign(pb.rbegin(), pb.rend());
  for (std::size_t k = 0; k < roi.columns.size(); ++k) floor.holes.push_back(cb[k]);
  RoiFace ceiling = HorizontalFace(roi, FaceKind::kCeiling, zc, lo, hi, plan_area, cell);
  ceiling.loop = pt;
  for (std::size_t k = 0; k < roi.columns.size(); ++k)
    ceiling.holes.emplace_back(ct[k].rbegin(), ct[k].rend());
  roi.faces.push_back(std::move(floor));
  roi.faces.push_back(std::move(ceiling));

  const int n = static_cast<int>(roi.perimeter.size());
  const int wall0 = 2;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = roi.perimeter[i], b = roi.perimeter[(i + 1) % n];
    const Vec2 t = (b - a).normalized();
    roi.faces.push_back(VerticalFace(FaceKind::kWall, i, a, b, Vec2(t.y(), -t.x()),
                                     {pb[i], pb[(i + 1) % n], pt[(i + 1) % n], pt[i]}, zf, H,
                                     cell));
  }
  std::vector<int> col0(roi.columns.size());
  for (std::size_t k = 0; k < roi.columns.size(); ++k) {
    col0[k] = static_cast<int>(roi.faces.size());
    const auto& c = roi.columns[k];
    const int m = static_cast<int>(c.size());
    for (int i = 0; i < m; ++i) {
      const Vec2 a = c[i], b = c[(i + 1) % m];
      const Vec2 t = (b - a).normalized();
      roi.faces.push_back(
          VerticalFace(FaceKind::kColumn, static_cast<int>(k), a, b, Vec2(-t.y(), t.x()),
                       {cb[k][(i + 1) % m], cb[k][i], ct[k][i], ct[k][(i + 1) % m]}, zf, H, cell));
    }
  }
  // Edges: floor and ceiling rings, vertical corners; then each face's neighbours.
  AddRingEdges(roi, pb, pt, wall0);
  for (std::size_t k = 0; k < roi.columns.size(); ++k) AddRingEdges(roi, cb[k], ct[k], col0[k]);
  roi.face_adjacency.assign(roi.faces.size(), {});
  for (const auto& e : roi.edges) {
    roi.face_adjacency[e.face0].push_back(e.face1);
    roi.face_adjacency[e.face1].push_back(e.face0);
  }
  for (auto& adj : roi.face_adjacency) {
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
  }
}

namespace {

struct Classified {
  PointLabel label = PointLabel::kNone;
  int face = -1;
};

}  // namespace

// The per-point rule (see the header and docs/room-scanning.md).
static Classified ClassifyWith(const RoomModelParams& P, const Roi& roi,
                               const RoomModel::Boundary* bnd, const Vec3& p) {
  Classified out;
  if (roi.empty()) return out;
  const double zf = roi.floor_z, zc = roi.ceiling_z;
  int seg = -1;
  const double sd = bnd->Lookup(p.head<2>(), &seg);
  const double dzf = std::abs(p.z() - zf), dzc = std::abs(p.z() - zc);
  if (p.z() < zf - P.plane_tolerance || p.z() > zc + P.plane_tolerance) {
    out.label = PointLabel::kOutlier;
    return out;
  }
  if (sd > P.wall_tolerance) {
    const bool column = seg >= 0 && bnd->segs[seg].column;
    const bool in_reveal =
        sd <= P.reveal_depth && p.z() > zf + P.plane_tolerance && p.z() < zc - P.plane_tolerance;
    out.label = (column || in_reveal) ? PointLabel::kClutter : PointLabel::kOutlier;
    return out;
  }
  if (sd >= -P.wall_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = seg >= 0 ? bnd->segs[seg].face : -1;
    const double asd = std::abs(sd);
    if (dzf <= P.plane_tolerance && dzf < asd) out.face = 0;
    if (dzc <= P.plane_tolerance && dzc < asd) out.face = 1;
    return out;
  }
  if (dzf <= P.plane_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = 0;
  } else if (dzc <= P.plane_tolerance) {
    out.label = PointLabel::kInlier;
    out.face = 1;
  } else {
    out.label = PointLabel::kClutter;
  }
  return out;
}

PointLabel RoomModel::Classify(const Vec3& p_M) const {
  if (roi_.empty() || !boundary_) return PointLabel::kNone;
  return ClassifyWith(params_, roi_, boundary_.get(), p_M).label;
}

void RoomModel::LabelAll() {
  boundary_.reset();
  if (roi_.empty()) return;
  auto b = std::make_shared<Boundary>();
  b->AddLoop(roi_.perimeter, false, 2);
  int face = 2 + static_cast<int>(roi_.perimeter.size());
  for (const auto& c : roi_.columns) {
    b->AddLoop(c, true, face);
    face += static_cast<int>(c.size());
  }
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : roi_.perimeter) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double m = params_.reveal_depth + 0.5;
  b->BuildRaster(lo - Vec2(m, m), hi + Vec2(m, m), 0.1,
                 std::max(params_.reveal_depth, params_.wall_tolerance) + 0.05);
  boundary_ = b;
  const Boundary* bp = b.get();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        labels_[i] =
                            ClassifyWith(params_, roi_, bp, points_[i].cast<double>()).label;
                      }
                    });
  work_labels_.resize(work_points_.size());
  work_face_.resize(work_points_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work_points_.size(), 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        const Classified c =
                            ClassifyWith(params_, roi_, bp, work_points_[i].cast<double>());
                        work_labels_[i] = c.label;
                        work_face_[i] = c.face;
                      }
                    });
}

void RoomModel::UpdateFaces() {
  if (roi_.empty()) return;
  for (auto& f : roi_.faces) {
    for (auto& c : f.cells) {
      if (c != FaceCell::kOff) c = FaceCell::kUnsensed;
    }
  }
  // Sensed: structural working points in their face's cell.
  for (std::size_t i = 0; i < work_points_.size(); ++i) {
    if (work_labels_[i] != PointLabel::kInlier || work_face_[i] < 0) continue;
    RoiFace& f = roi_.faces[work_face_[i]];
    const int c = f.CellIndexOf(work_points_[i].cast<double>());
    if (c >= 0 && f.cells[c] != FaceCell::kOff) f.cells[c] = FaceCell::kSensed;
  }
  // Openings: beams of outlier points cross the perimeter where there is no wall.
  const auto& P = roi_.perimeter;
  const int n = static_cast<int>(P.size());
  const double zf = roi_.floor_z, zc = roi_.ceiling_z;
  for (const auto& s : scans_) {
    const Vec3 o = s.origin;
    for (std::size_t i = s.begin; i < s.end; ++i) {
      if (labels_[i] != PointLabel::kOutlier) continue;
      const Vec3 p = points_[i].cast<double>();
      const Vec2 d = p.head<2>() - o.head<2>();
      double best_t = 2.0;
      int best_e = -1;
      for (int e = 0; e < n; ++e) {
        const Vec2 a = P[e], b = P[(e + 1) % n];
        const Vec2 ab = b - a;
        const double den = d.x() * ab.y() - d.y() * ab.x();
        if (std::abs(den) < 1e-12) continue;
        const Vec2 ao = a - o.head<2>();
        const double t = (ao.x() * ab.y() - ao.y() * ab.x()) / den;
        const double u = (ao.x() * d.y() - ao.y() * d.x()) / den;
        if (t > 0 && t < best_t && u >= 0 && u <= 1) {
          best_t = t;
          best_e = e;
        }
      }
      if (best_e < 0) continue;
      const Vec3 q = o + best_t * (p - o);
      if (q.z() <= zf || q.z() >= zc) continue;
      RoiFace& f = roi_.faces[2 + best_e];
      const int c = f.CellIndexOf(q);
      if (c >= 0 && f.cells[c] == FaceCell::kUnsensed) f.cells[c] = FaceCell::kOpening;
    }
  }
  for (auto& f : roi_.faces) {
    double on = 0.0, sensed = 0.0;
    for (std::size_t c = 0; c < f.cells.size(); ++c) {
      if (f.cells[c] == FaceCell::kOff) continue;
      on += f.cell_area[c];
      if (f.cells[c] == FaceCell::kSensed) sensed += f.cell_area[c];
    }
    f.sensed_share = on > 0 ? sensed / on : 0.0;
    f.structural = f.sensed_share >= params_.structural_share && sensed > 0;
  }
}

void RoomModel::UpdateVoxels(bool new_scan_only) {
  if (roi_.empty()) return;
  const double v = params_.voxel_size;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : roi_.perimeter) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo -= Vec2::Constant(params_.voxel_margin);
  hi += Vec2::Constant(params_.voxel_margin);
  // Layer 1 is centred on the floor.
  const double oz = roi_.floor_z - 1.5 * v;
  bool reuse = new_scan_only && !voxels_.empty() &&
               std::abs(voxels_.Origin().z() - oz) < 0.25 * v && voxels_.Origin().x() <= lo.x() &&
               voxels_.Origin().y() <= lo.y() &&
               voxels_.Origin().x() + v * voxels_.Nx() >= hi.x() &&
               voxels_.Origin().y() + v * voxels_.Ny() >= hi.y() &&
               voxels_.Origin().z() + v * voxels_.Nz() >= roi_.ceiling_z + v;
  if (!reuse) {
    const double extra = 1.0;  // m, growth room before the next re-cast
    const Vec3 origin(std::floor((lo.x() - extra) / v) * v, std::floor((lo.y() - extra) / v) * v,
                      oz);
    const int nx = static_cast<int>(std::ceil((hi.x() + extra - origin.x()) / v));
    const int ny = static_cast<int>(std::ceil((hi.y() + extra - origin.y()) / v));
    const int nz = static_cast<int>(std::ceil((roi_.ceiling_z + 1.5 * v - oz) / v));
    voxels_ = VoxelSpace(origin, v, nx, ny, nz);
  } else {
    for (std::size_t i = 0; i < voxels_.VoxelCount(); ++i) {
      voxels_.MutableFlags(i) &= VoxelSpace::kPassed;
    }
  }
  // Beams (every ray_stride-th row and column) mark the voxels they pass.
  const std::size_t s0 = reuse ? scans_.size() - 1 : 0;
  for (std::size_t s = s0; s < scans_.size(); ++s) {
    const ScanRecord& rec = scans_[s];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(rec.begin, rec.end, 1 << 12),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          if (!(column_index_[i] & kRayCastBit)) continue;
                          voxels_.MarkPassed(rec.origin, points_[i].cast<double>());
                        }
                      });
  }
  // Occupied: any working point.
  for (const auto& p : work_points_) {
    const Eigen::Vector3i q = voxels_.VoxelOf(p.cast<double>());
    if (voxels_.Contains(q.x(), q.y(), q.z())) {
      voxels_.MutableFlags(voxels_.Index(q.x(), q.y(), q.z())) |= VoxelSpace::kOccupied;
    }
  }
  // Structural: the single voxel layer containing a RoI face, as in the evaluator's truth DSM3
  // (which nudges a face on a voxel boundary to the room side). The face is taken
  // structure_tolerance into the room so that the robot's few-mm error does not flip a face
  // lying on a boundary to the layer behind it; a voxel whose centre lies more than half a
  // voxel behind a face is never structure. Inside: voxel centres inside the prism.
  const double eps = std::min(params_.structure_tolerance, 0.45 * v) + 1e-9 * v;
  const int kf = voxels_.VoxelOf(Vec3(0, 0, roi_.floor_z + eps)).z();
  const int kc = voxels_.VoxelOf(Vec3(0, 0, roi_.ceiling_z - eps)).z();
  for (int j = 0; j < voxels_.Ny(); ++j) {
    for (int i = 0; i < voxels_.Nx(); ++i) {
      const Vec3 c = voxels_.Centre(i, j, 0);
      if (!roi_.ContainsPlan(c.head<2>())) continue;
      for (int k = kf; k <= kc; ++k) {
        if (!voxels_.Contains(i, j, k)) continue;
        std::uint8_t& f = voxels_.MutableFlags(voxels_.Index(i, j, k));
        f |= VoxelSpace::kInside;
        if (k == kf || k == kc) f |= VoxelSpace::kStructural;
      }
    }
  }
  // `room_left`: the room lies to the left of each edge (CCW perimeter, CW column) or right.
  auto mark_loop = [&](const std::vector<Vec2>& loop, bool room_left) {
    const std::size_t m = loop.size();
    for (std::size_t e = 0; e < m; ++e) {
      const Vec2 a = loop[e], b = loop[(e + 1) % m];
      if ((b - a).norm() < 1e-12) continue;
      const Vec2 t = (b - a).normalized();
      const Vec2 in = room_left ? Vec2(-t.y(), t.x()) : Vec2(t.y(), -t.x());
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (v / 8))));
      for (int s = 0; s <= steps; ++s) {
        const Vec2 p = a + (b - a) * (static_cast<double>(s) / steps) + eps * in;
        const Eigen::Vector3i q = voxels_.VoxelOf(Vec3(p.x(), p.y(), roi_.floor_z));
        const Vec3 c = voxels_.Centre(q.x(), q.y(), 0);
        if ((c.head<2>() - a).dot(in) < -0.5 * v) continue;  // centre too far outside the face
        for (int k = kf; k <= kc; ++k) {
          if (voxels_.Contains(q.x(), q.y(), k)) {
            voxels_.MutableFlags(voxels_.Index(q.x(), q.y(), k)) |= VoxelSpace::kStructural;
          }
        }
      }
    }
  };
  auto ccw = [](const std::vector<Vec2>& loop) {
    double a = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vec2& p = loop[i];
      const Vec2& q = loop[(i + 1) % loop.size()];
      a += p.x() * q.y() - q.x() * p.y();
    }
    return a > 0.0;
  };
  mark_loop(roi_.perimeter, ccw(roi_.perimeter));
  for (const auto& c : roi_.columns) mark_loop(c, !ccw(c));
}

void RoomModel::UpdateCoverage() {
  CoverageFigures f;
  f.scans = ScanCount();
  double on = 0.0;
  for (const auto& face : roi_.faces) {
    for (std::size_t c = 0; c < face.cells.size(); ++c) {
      switch (face.cells[c]) {
        case FaceCell::kOff:
          break;
        case FaceCell::kUnsensed:
          on += face.cell_area[c];
          break;
        case FaceCell::kSensed:
          on += face.cell_area[c];
          f.sensed_area += face.cell_area[c];
          break;
        case FaceCell::kOpening:
          f.opening_area += face.cell_area[c];
          break;
      }
    }
  }
  f.total_area = on;
  f.ratio = on > 0 ? f.sensed_area / on : 0.0;
  const double prev = coverage_.empty() ? 0.0 : coverage_.back().sensed_area;
  f.increment = on > 0 ? (f.sensed_area - prev) / on : 0.0;
  f.observable_ratio = f.ratio;
  coverage_.push_back(f);
}

void CoverageFigures::SetHiddenArea(double area) {
  hidden_area = std::clamp(area, 0.0, std::max(0.0, total_area - sensed_area));
  const double observable = total_area - hidden_area;
  observable_ratio = observable > 0.0 ? sensed_area / observable : 0.0;
}

io::PointCloud RoomModel::Sm1Cloud() const {
  io::PointCloud cloud;
  cloud.points = points_;
  cloud.colors = colours_;
  io::ScalarField inten{"scalar_intensity", io::PlyType::kFloat32, {}};
  io::ScalarField label{"scalar_label", io::PlyType::kUInt8, {}};
  io::ScalarField scan{"scalar_scan", io::PlyType::kUInt16, {}};
  inten.values.assign(intensity_.begin(), intensity_.end());
  label.values.resize(labels_.size());
  for (std::size_t i = 0; i < labels_.size(); ++i)
    label.values[i] = static_cast<double>(labels_[i]);
  scan.values.assign(scan_index_.begin(), scan_index_.end());
  cloud.fields = {std::move(inten), std::move(label), std::move(scan)};
  char buf[256];
  cloud.comments.push_back("mopad_sm1 labels 0=none 1=inlier 2=outlier 3=clutter");
  std::snprintf(buf, sizeof(buf), "mopad_heights floor_z %.4f ceiling_z %.4f", roi_.floor_z,
                roi_.ceiling_z);
  cloud.comments.push_back(buf);
  for (std::size_t s = 0; s < scan_poses_.size(); ++s) {
    const Eigen::Quaterniond q(scan_poses_[s].linear());
    const Vec3 t = scan_poses_[s].translation();
    std::snprintf(buf, sizeof(buf), "mopad_scan_pose %zu %.6f %.6f %.6f %.9f %.9f %.9f %.9f", s,
                  t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
    cloud.comments.push_back(buf);
  }
  return cloud;
}

void RoomModel::WriteSm1(const std::string& path) const { io::WritePly(path, Sm1Cloud()); }

std::string RoomModel::FiguresJson() const {
  std::string s = "{";
  char buf[256];
  auto num = [&](const char* key, double v, bool comma = true) {
    std::snprintf(buf, sizeof(buf), "\"%s\": %.6g%s", key, v, comma ? ", " : "");
    s += buf;
  };
  num("scans", ScanCount());
  num("floor_z", roi_.floor_z);
  num("ceiling_z", roi_.ceiling_z);
  s += "\"perimeter\": [";
  for (std::size_t i = 0; i < roi_.perimeter.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%s[%.4f, %.4f]", i ? ", " : "", roi_.perimeter[i].x(),
                  roi_.perimeter[i].y());
    s += buf;
  }
  s += "], \"columns\": [";
  for (std::size_t k = 0; k < roi_.columns.size(); ++k) {
    s += k ? ", [" : "[";
    for (std::size_t i = 0; i < roi_.columns[k].size(); ++i) {
      std::snprintf(buf, sizeof(buf), "%s[%.4f, %.4f]", i ? ", " : "", roi_.columns[k][i].x(),
                    roi_.columns[k][i].y());
      s += buf;
    }
    s += "]";
  }
  s += "], \"faces\": [";
  for (std::size_t i = 0; i < roi_.faces.size(); ++i) {
    const RoiFace& f = roi_.faces[i];
    std::snprintf(buf, sizeof(buf),
                  "%s{\"kind\": \"%s\", \"element\": %d, \"area\": %.4f, \"structural\": %s, "
                  "\"sensed_share\": %.4f}",
                  i ? ", " : "", ToString(f.kind), f.element, f.area,
                  f.structural ? "true" : "false", f.sensed_share);
    s += buf;
  }
  s += "], \"voxels\": {";
  const auto counts = voxels_.LabelCounts();
  for (int l = 0; l < kVoxelLabelCount; ++l) {
    std::snprintf(buf, sizeof(buf), "%s\"%s\": %lld", l ? ", " : "",
                  ToString(static_cast<VoxelLabel>(l)), static_cast<long long>(counts[l]));
    s += buf;
  }
  std::snprintf(buf, sizeof(buf), ", \"size\": %.3f}, ", voxels_.Size());
  s += buf;
  const LabelCounts lc = CountLabels();
  std::snprintf(
      buf, sizeof(buf),
      "\"labels\": {\"none\": %lld, \"inlier\": %lld, \"outlier\": %lld, \"clutter\": %lld}, ",
      static_cast<long long>(lc.none), static_cast<long long>(lc.inlier),
      static_cast<long long>(lc.outlier), static_cast<long long>(lc.clutter));
  s += buf;
  s += "\"coverage\": [";
  for (std::size_t i = 0; i < coverage_.size(); ++i) {
    const CoverageFigures& c = coverage_[i];
    std::snprintf(
        buf, sizeof(buf),
        "%s{\"scans\": %d, \"sensed_area\": %.4f, \"total_area\": %.4f, \"opening_area\": %.4f, "
        "\"ratio\": %.5f, \"increment\": %.5f}",
        i ? ", " : "", c.scans, c.sensed_area, c.total_area, c.opening_area, c.ratio, c.increment);
    s += buf;
  }
  s += "]}";
  return s;
}

}  // namespace mopad::modelling
