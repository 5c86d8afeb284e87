#include "modelling/orthoimage.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/statistics.h"
#include "io/image_codec.h"

namespace mopad::modelling {

void OrthoimageParams::Validate() const {
  ValidateParams(*this, "orthoimage.");
  if (finest_pixel > coarsest_pixel)
    throw InputError("", "parameter 'orthoimage.finest_pixel' exceeds coarsest_pixel",
                     std::to_string(finest_pixel), "<= " + std::to_string(coarsest_pixel));
}

PatchFrame PatchFrame::Of(const Vec3& normal, const std::vector<Vec3>& polygon) {
  if (polygon.size() < 3)
    throw InputError("", "orthoimage patch polygon has fewer than 3 vertices",
                     std::to_string(polygon.size()), ">= 3");
  if (!normal.allFinite() || normal.norm() < 1e-9)
    throw InputError("", "orthoimage patch normal is zero or not finite");
  PatchFrame f;
  f.n = normal.normalized();
  if (std::abs(f.n.z()) < 0.9) {
    f.v = (Vec3::UnitZ() - f.n * f.n.z()).normalized();
    f.u = f.v.cross(f.n).normalized();
  } else {
    f.u = (Vec3::UnitX() - f.n * f.n.x()).normalized();
    f.v = f.n.cross(f.u).normalized();
  }
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (const auto& p : polygon) {
    if (!p.allFinite()) throw InputError("", "orthoimage patch polygon is not finite");
    u0 = std::min(u0, f.u.dot(p)), u1 = std::max(u1, f.u.dot(p));
    v0 = std::min(v0, f.v.dot(p)), v1 = std::max(v1, f.v.dot(p));
  }
  // Origin on the plane (through the polygon's first vertex) at (u0, v0).
  const double d0 = f.n.dot(polygon.front());
  f.origin = u0 * f.u + v0 * f.v + d0 * f.n;
  f.width = u1 - u0;
  f.height = v1 - v0;
  return f;
}

Orthoimage::Orthoimage(const PatchFrame& frame, double pixel, int cols, int rows)
    : frame_(frame), pixel_(pixel), cols_(cols), rows_(rows) {
  const std::size_t n = static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows);
  count_.assign(n, 0), passed_.assign(n, 0), blocked_.assign(n, 0);
  passed_no_return_.assign(n, 0);
  rgb_.assign(n, {0, 0, 0});
  rgb_sum_.assign(n, {0.0, 0.0, 0.0});
  depth_.assign(n, std::numeric_limits<float>::quiet_NaN());
  depth_sum_.assign(n, 0.0);
  front_.assign(n, std::numeric_limits<float>::quiet_NaN());
}

namespace {

// A pixel index k = floor(...) of an axis of n pixels as an int, limited to [-1, n]: one past
// either edge stands for every point beyond it (a grazing ray meets the plane kilometres off
// the image), so the cast never overflows; NaN gives -1.
int AxisIndex(double k, int n) {
  if (!(k >= 0.0)) return -1;
  return k < n ? static_cast<int>(k) : n;
}

}  // namespace

std::array<int, 2> Orthoimage::PixelOf(double pu, double pv) const {
  const int c = AxisIndex(std::floor((pu + margin_) / pixel_), cols_);
  const int r = rows_ - 1 - AxisIndex(std::floor((pv + margin_) / pixel_), rows_);
  return {c, r};
}

std::array<float, 3> Orthoimage::Hsv(std::size_t i) const {
  const float r = rgb_[i][0] / 255.0f, g = rgb_[i][1] / 255.0f, b = rgb_[i][2] / 255.0f;
  const float mx = std::max({r, g, b}), mn = std::min({r, g, b}), d = mx - mn;
  float h = 0.0f;
  if (d > 0.0f) {
    if (mx == r)
      h = 60.0f * std::fmod((g - b) / d, 6.0f);
    else if (mx == g)
      h = 60.0f * ((b - r) / d + 2.0f);
    else
      h = 60.0f * ((r - g) / d + 4.0f);
    if (h < 0.0f) h += 360.0f;
  }
  return {h, mx > 0.0f ? d / mx : 0.0f, mx};
}

void Orthoimage::AddPoint(double pu, double pv, double depth,
                          const std::array<std::uint8_t, 3>& rgb) {
  const auto [c, r] = PixelOf(pu, pv);
  if (!Inside(c, r)) return;
  AccumulatePoint(Index(c, r), depth, rgb);
  SetMean(Index(c, r));
}

void Orthoimage::AccumulatePoint(std::size_t i, double depth,
                                 const std::array<std::uint8_t, 3>& rgb) {
  const std::uint32_t k = ++count_[i];
  for (int ch = 0; ch < 3; ++ch) rgb_sum_[i][ch] += rgb[ch];
  depth_sum_[i] += depth;
  front_[i] = k == 1 ? static_cast<float>(depth) : std::max(front_[i], static_cast<float>(depth));
}

void Orthoimage::SetMean(std::size_t i) {
  const std::uint32_t k = count_[i];
  if (k == 0) return;
  for (int ch = 0; ch < 3; ++ch)
    rgb_[i][ch] = static_cast<std::uint8_t>(std::lround(rgb_sum_[i][ch] / k));
  depth_[i] = static_cast<float>(depth_sum_[i] / k);
}

void Orthoimage::FinishMeans() {
  for (std::size_t i = 0; i < count_.size(); ++i) SetMean(i);
}

void CheckOrthoPoints(const OrthoPoints& in) {
  if (in.points == nullptr || in.colours == nullptr)
    throw InputError("", "orthoimage input has no points or no colours");
  if (in.colours->size() != in.points->size())
    throw InputError("", "orthoimage colours and points differ in count",
                     std::to_string(in.colours->size()), std::to_string(in.points->size()));
  if ((in.scan_index == nullptr) != in.scan_origins.empty())
    throw InputError("", "orthoimage input needs both scan_index and scan_origins, or neither");
  if (in.no_return_dirs.size() != in.no_return_scan.size())
    throw InputError("", "orthoimage no_return_dirs and no_return_scan differ in count",
                     std::to_string(in.no_return_dirs.size()),
                     std::to_string(in.no_return_scan.size()));
  for (const auto k : in.no_return_scan)
    if (k >= in.scan_origins.size())
      throw InputError("", "orthoimage no_return_scan out of range", std::to_string(k),
                       "< " + std::to_string(in.scan_origins.size()));
  if (in.scan_index != nullptr) {
    if (in.scan_index->size() != in.points->size())
      throw InputError("", "orthoimage scan_index and points differ in count",
                       std::to_string(in.scan_index->size()), std::to_string(in.points->size()));
    for (std::size_t i = 0; i < in.scan_index->size(); ++i)
      if ((*in.scan_index)[i] >= in.scan_origins.size())
        throw InputError("", "orthoimage scan_index out of range",
                         std::to_string((*in.scan_index)[i]),
                         "< " + std::to_string(in.scan_origins.size()));
  }
  if (!in.scan_steps.empty() && in.scan_steps.size() != in.scan_origins.size())
    throw InputError("", "orthoimage scan_steps and scan_origins differ in count",
                     std::to_string(in.scan_steps.size()), std::to_string(in.scan_origins.size()));
  for (const double step : in.scan_steps)
    if (!(step >= 0.0 && step < 1.0))
      throw InputError("", "orthoimage scan step out of range", std::to_string(step), "[0, 1) rad");
}

namespace {

// ChoosePixelSize on checked input. The density cells are counted in a dense grid over the
// patch (points outside it are skipped), or, for a patch too large for one, from sorted cell
// keys: the median count is the same either way.
double PixelSizeOf(const OrthoPoints& in, const PatchFrame& frame, const OrthoimageParams& params) {
  const double cell = params.density_cell;
  if (!(frame.width >= 0.0) || !(frame.height >= 0.0)) return params.coarsest_pixel;
  const double nu_d = std::floor(frame.width / cell) + 1,
               nv_d = std::floor(frame.height / cell) + 1;
  const bool dense = nu_d * nv_d <= 4e6;
  const std::size_t nu = dense ? static_cast<std::size_t>(nu_d) : 0;
  std::vector<std::uint32_t> grid(dense ? nu * static_cast<std::size_t>(nv_d) : 0, 0);
  std::vector<std::uint64_t> keys;
  for (const auto& pf : *in.points) {
    const Vec3 p = pf.cast<double>();
    if (std::abs(frame.Depth(p)) > params.band) continue;
    const Vec2 uv = frame.ToUv(p);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > frame.width || uv.y() > frame.height) continue;
    const auto cu = static_cast<std::uint64_t>(std::floor(uv.x() / cell));
    const auto cv = static_cast<std::uint64_t>(std::floor(uv.y() / cell));
    if (dense)
      ++grid[cv * nu + cu];
    else
      keys.push_back(cu << 32 | cv);
  }
  std::vector<std::uint32_t> counts;
  for (const std::uint32_t c : grid)
    if (c > 0) counts.push_back(c);
  std::sort(keys.begin(), keys.end());
  for (std::size_t a = 0; a < keys.size();) {
    std::size_t b = a;
    while (b < keys.size() && keys[b] == keys[a]) ++b;
    counts.push_back(static_cast<std::uint32_t>(b - a));
    a = b;
  }
  if (counts.empty()) return params.coarsest_pixel;
  const double density = UpperMedian(counts) / (cell * cell);  // points per m^2
  double px = std::sqrt(params.points_per_pixel / density);
  px = std::clamp(px, params.finest_pixel, params.coarsest_pixel);
  return std::max(params.finest_pixel, std::round(px * 1000.0) / 1000.0);
}

}  // namespace

double ChoosePixelSize(const OrthoPoints& in, const PatchFrame& frame,
                       const OrthoimageParams& params) {
  params.Validate();
  CheckOrthoPoints(in);
  return PixelSizeOf(in, frame, params);
}

namespace {

// What a sample says about the pixel it falls in (BuildOrthoimage).
enum class SampleKind : std::uint8_t { kPoint, kPassed, kBlocked, kPassedNoReturn };

// One sample of the plane: a point within the band, or where a ray crossed the plane. `index`
// is the point's (or the no-return ray's), `scan` its scan, `range` the scanner's distance to
// where it meets the plane (m) and `cos_incidence` the cosine of its angle to the normal.
struct PlaneSample {
  SampleKind kind = SampleKind::kPoint;
  std::size_t index = 0, scan = 0;
  Vec2 uv = Vec2::Zero();
  double depth = 0.0;  ///< m, signed, points only
  double range = 0.0, cos_incidence = 1.0;
};

// Calls f(PlaneSample) for every sample of `frame` in the order of the points, then of the
// rays without a return (BuildOrthoimage's rules for each).
template <class F>
void ForEachSample(const OrthoPoints& in, const PatchFrame& frame, const OrthoimageParams& params,
                   F&& f) {
  std::vector<double> origin_depth;
  for (const auto& o : in.scan_origins) origin_depth.push_back(frame.Depth(o));
  PlaneSample s;
  for (std::size_t i = 0; i < in.points->size(); ++i) {
    const Vec3 p = (*in.points)[i].cast<double>();
    const double dp = frame.Depth(p);
    s.index = i;
    const bool indexed = in.scan_index != nullptr;
    s.scan = indexed ? (*in.scan_index)[i] : 0;
    if (std::abs(dp) <= params.band) {
      s.kind = SampleKind::kPoint, s.uv = frame.ToUv(p), s.depth = dp;
      if (indexed) {
        const Vec3 ray = p - in.scan_origins[s.scan];
        s.range = ray.norm();
        s.cos_incidence = s.range > 0.0 ? std::abs(frame.n.dot(ray)) / s.range : 1.0;
      }
      f(s);
      continue;
    }
    if (!indexed) continue;
    const double dc = origin_depth[s.scan];
    if (dc <= 0.0) continue;  // the scanner is behind the plane: no evidence about it
    if (dp >= dc) continue;   // heading away from the plane
    // Below the band the ray crossed the plane on its way: seen through there; above it the
    // ray stopped in front of the plane while heading for it: occluded there.
    const Vec3& c = in.scan_origins[s.scan];
    const Vec3 x = c + dc / (dc - dp) * (p - c);
    s.kind = dp < -params.band ? SampleKind::kPassed : SampleKind::kBlocked;
    s.uv = frame.ToUv(x), s.range = (x - c).norm();
    s.cos_incidence = s.range > 0.0 ? dc / s.range : 1.0;
    f(s);
  }
  const NoReturnRule rule(params);
  for (std::size_t i = 0; i < in.no_return_dirs.size(); ++i) {
    s.scan = in.no_return_scan[i], s.index = i;
    const Vec3& c = in.scan_origins[s.scan];
    Vec3 x;
    if (!rule.Crossing(c, origin_depth[s.scan], in.no_return_dirs[i].cast<double>().normalized(),
                       frame, &x))
      continue;
    s.kind = SampleKind::kPassedNoReturn, s.uv = frame.ToUv(x), s.range = (x - c).norm();
    s.cos_incidence = s.range > 0.0 ? origin_depth[s.scan] / s.range : 1.0;
    f(s);
  }
}

// Guards the footprint's division at a grazing angle (84 deg); footprint_max bounds it anyway.
constexpr double kMinFootprintCos = 0.1;

// Half the side (m) of the square of plane one sample stands for: half the spacing of its
// scan's neighbouring beams where they meet the plane, range * step / cos(incidence) (the surfel
// of point-based fusion). 0 without the scan's step, and where that spacing exceeds
// footprint_max: so sparse a sample says too little about what lies around it.
double FootprintHalfSide(const PlaneSample& s, const OrthoPoints& in,
                         const OrthoimageParams& params) {
  if (in.scan_steps.empty() || params.footprint_max <= 0.0) return 0.0;
  const double spacing =
      s.range * in.scan_steps[s.scan] / std::max(s.cos_incidence, kMinFootprintCos);
  return spacing <= params.footprint_max ? 0.5 * spacing : 0.0;
}

}  // namespace

Orthoimage BuildOrthoimage(const OrthoPoints& in, const PatchFrame& frame,
                           const OrthoimageParams& params, double pixel) {
  params.Validate();
  CheckOrthoPoints(in);
  if (!(frame.width > 0.0) || !(frame.height > 0.0))
    throw InputError("", "orthoimage patch has no extent",
                     std::to_string(frame.width) + " x " + std::to_string(frame.height), "> 0");
  if (pixel <= 0.0) pixel = PixelSizeOf(in, frame, params);
  const double m = params.margin;
  const double cols_d = std::ceil((frame.width + 2 * m) / pixel - 1e-9);
  const double rows_d = std::ceil((frame.height + 2 * m) / pixel - 1e-9);
  if (cols_d * rows_d > params.max_pixels)
    throw InputError("", "orthoimage too large",
                     std::to_string(cols_d) + " x " + std::to_string(rows_d),
                     "<= max_pixels " + std::to_string(params.max_pixels));
  Orthoimage img(frame, pixel, static_cast<int>(cols_d), static_cast<int>(rows_d));
  img.SetMargin(m);
  auto deposit = [&](const PlaneSample& s, std::size_t i) {
    switch (s.kind) {
      case SampleKind::kPoint:
        img.AccumulatePoint(i, s.depth, (*in.colours)[s.index]);
        break;
      case SampleKind::kPassed:
        ++img.passed_[i];
        break;
      case SampleKind::kBlocked:
        ++img.blocked_[i];
        break;
      case SampleKind::kPassedNoReturn:
        ++img.passed_[i], ++img.passed_no_return_[i];
        break;
    }
  };
  ForEachSample(in, frame, params, [&](const PlaneSample& s) {
    const auto [c, r] = img.PixelOf(s.uv.x(), s.uv.y());
    if (img.Inside(c, r)) deposit(s, img.Index(c, r));
  });
  // Sampling gaps: where the beams meet the plane farther apart than a pixel (far from the
  // scanner, at an oblique angle), the pixels between two samples hold none. Each such pixel
  // takes the sample nearest its centre among those whose footprint (the square of plane
  // between its beam and the neighbouring beams) covers it, so a window seen every third pixel
  // is a window, not unseen; a pixel no footprint reaches stays unseen.
  if (!in.scan_steps.empty() && params.footprint_max > 0.0) {
    const std::size_t n = img.count_.size();
    std::vector<float> best(n, std::numeric_limits<float>::infinity());
    struct Nearest {
      SampleKind kind = SampleKind::kPoint;
      std::uint32_t index = 0;
      float depth = 0.0f;
    };
    std::vector<Nearest> nearest(n);
    auto empty = [&](std::size_t i) {
      return img.count_[i] == 0 && img.passed_[i] == 0 && img.blocked_[i] == 0;
    };
    ForEachSample(in, frame, params, [&](const PlaneSample& s) {
      const double half = FootprintHalfSide(s, in, params);
      if (half < 0.5 * pixel) return;
      const auto [c0, r0] = img.PixelOf(s.uv.x() - half, s.uv.y() + half);
      const auto [c1, r1] = img.PixelOf(s.uv.x() + half, s.uv.y() - half);
      for (int r = std::max(r0, 0); r <= std::min(r1, img.Rows() - 1); ++r)
        for (int c = std::max(c0, 0); c <= std::min(c1, img.Cols() - 1); ++c) {
          const std::size_t i = img.Index(c, r);
          if (!empty(i)) continue;
          const Vec2 d = img.CentreUv(c, r) - s.uv;
          if (std::abs(d.x()) > half || std::abs(d.y()) > half) continue;
          const auto d2 = static_cast<float>(d.squaredNorm());
          if (d2 >= best[i]) continue;
          best[i] = d2;
          nearest[i] = {s.kind, static_cast<std::uint32_t>(s.index), static_cast<float>(s.depth)};
        }
    });
    PlaneSample s;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(best[i])) continue;
      s.kind = nearest[i].kind, s.index = nearest[i].index, s.depth = nearest[i].depth;
      deposit(s, i);
    }
  }
  img.FinishMeans();
  return img;
}

NoReturnRule::NoReturnRule(const OrthoimageParams& params)
    : min_cos_(std::cos(DegToRad(params.no_return_max_incidence_deg))),
      min_range_(params.no_return_min_range) {}

bool NoReturnRule::Crossing(const Vec3& origin, double origin_depth, const Vec3& dir,
                            const PatchFrame& frame, Vec3* crossing) const {
  const double nd = frame.n.dot(dir);
  if (origin_depth <= 0.0 || nd >= -1e-9) return false;  // behind the plane, or heading away
  if (-nd < min_cos_) return false;  // grazing (a unit ray meets the plane at |nd| = cos)
  const double t = origin_depth / -nd;
  if (t < min_range_) return false;
  *crossing = origin + t * dir;
  return true;
}

void AddNoReturnRays(const interfaces::TlsScan& scan, const Pose3& X_MS, std::uint16_t scan_index,
                     OrthoPoints& out, const OrthoimageParams& params) {
  if (scan.points.size() != static_cast<std::size_t>(scan.rows) * scan.columns)
    throw InputError("", "scan grid and point count disagree", std::to_string(scan.points.size()),
                     std::to_string(scan.rows) + " x " + std::to_string(scan.columns));
  params.Validate();
  // The grid's regions without a return (8-connected; azimuth wraps round on a full turn), each
  // with the returns that border it. A region bordered mostly by returns nearer than
  // no_return_min_range is a surface inside the scanner's minimum range (an opened leaf or a
  // desk beside the scanner, seen over a wide angle), not a view into space: its rays are left
  // out. Flood fill in grid order with an explicit stack (deterministic).
  const int rows = static_cast<int>(scan.rows), cols = static_cast<int>(scan.columns);
  const bool wraps = scan.azimuth_step > 0.0 &&
                     std::abs(cols * scan.azimuth_step - 2.0 * kPi) < 1.5 * scan.azimuth_step;
  std::vector<std::uint8_t> keep(scan.points.size(), 1);
  std::vector<std::int32_t> region(scan.points.size(), -1);
  std::vector<std::size_t> stack, cells;
  std::int32_t next = 0;
  for (std::size_t start = 0; start < scan.points.size(); ++start) {
    if (scan.points[start].valid() || region[start] >= 0) continue;
    stack.assign(1, start);
    cells.clear();
    region[start] = next;
    std::size_t border = 0, near = 0;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      cells.push_back(i);
      const int r = static_cast<int>(i / cols), c = static_cast<int>(i % cols);
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr;
          int cc = c + dc;
          if (rr < 0 || rr >= rows || (dr == 0 && dc == 0)) continue;
          if (cc < 0 || cc >= cols) {
            if (!wraps) continue;
            cc = (cc + cols) % cols;
          }
          const std::size_t j = static_cast<std::size_t>(rr) * cols + cc;
          if (scan.points[j].valid()) {
            ++border;
            near += scan.points[j].range < params.no_return_min_range;
          } else if (region[j] < 0) {
            region[j] = next;
            stack.push_back(j);
          }
        }
    }
    ++next;
    if (border > 0 && near > params.no_return_near_border_share * border)
      for (std::size_t i : cells) keep[i] = 0;
  }
  const Eigen::Matrix3d R = X_MS.linear();
  for (std::uint32_t r = 0; r < scan.rows; ++r) {
    const double el = scan.elevation_max - r * scan.elevation_step;
    for (std::uint32_t c = 0; c < scan.columns; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * scan.columns + c;
      if (scan.points[i].valid() || !keep[i]) continue;
      const double az = scan.azimuth_min + c * scan.azimuth_step;
      const Vec3 d_S(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      out.no_return_dirs.push_back((R * d_S).cast<float>());
      out.no_return_scan.push_back(scan_index);
    }
  }
}

std::size_t DropNoReturnRaysThroughSeenSurfaces(OrthoPoints& in, const OrthoimageParams& params) {
  params.Validate();
  const double voxel = params.no_return_blocker_cell;
  if (in.no_return_dirs.size() != in.no_return_scan.size())
    throw InputError("", "no-return rays and their scans disagree",
                     std::to_string(in.no_return_dirs.size()),
                     std::to_string(in.no_return_scan.size()));
  for (const std::uint16_t s : in.no_return_scan)
    if (s >= in.scan_origins.size())
      throw InputError("", "no-return ray of an unknown scan", std::to_string(s),
                       "< " + std::to_string(in.scan_origins.size()));
  const double reach = params.no_return_min_range - 2.0 * voxel;
  if (in.points == nullptr || in.points->empty() || in.no_return_dirs.empty() || reach <= voxel)
    return 0;
  // Occupancy of the points' bounding box, one byte per cell.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  for (const auto& p : *in.points) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  const Eigen::Vector3i dims = ((hi - lo) / voxel).array().floor().cast<int>() + 1;
  const std::size_t cells = static_cast<std::size_t>(dims.x()) * dims.y() * dims.z();
  if (cells > 400'000'000u)
    throw InputError("", "points span too many blocker cells", std::to_string(cells),
                     "<= 400000000");
  std::vector<std::uint8_t> occ(cells, 0);
  auto cell = [&](const Eigen::Vector3d& x, std::size_t* idx) {
    const Eigen::Vector3d q = (x - lo) / voxel;
    if ((q.array() < 0.0).any()) return false;
    const Eigen::Vector3i c = q.array().floor().cast<int>();
    if ((c.array() >= dims.array()).any()) return false;
    *idx = (static_cast<std::size_t>(c.z()) * dims.y() + c.y()) * dims.x() + c.x();
    return true;
  };
  for (const auto& p : *in.points) {
    std::size_t i = 0;
    if (cell(p.cast<double>(), &i)) occ[i] = 1;
  }
  std::vector<std::uint8_t> keep(in.no_return_dirs.size(), 1);
  tbb::parallel_for(std::size_t{0}, keep.size(), [&](std::size_t r) {
    const Vec3& o = in.scan_origins[in.no_return_scan[r]];
    const Vec3 d = in.no_return_dirs[r].cast<double>().normalized();
    for (double t = voxel; t <= reach; t += 0.5 * voxel) {
      std::size_t i = 0;
      if (cell(o + t * d, &i) && occ[i]) {
        keep[r] = 0;
        return;
      }
    }
  });
  std::size_t n = 0, dropped = 0;
  for (std::size_t r = 0; r < keep.size(); ++r) {
    if (!keep[r]) {
      ++dropped;
      continue;
    }
    in.no_return_dirs[n] = in.no_return_dirs[r];
    in.no_return_scan[n] = in.no_return_scan[r];
    ++n;
  }
  in.no_return_dirs.resize(n);
  in.no_return_scan.resize(n);
  return dropped;
}

void WriteOrthoimagePngs(const Orthoimage& img, const std::string& stem) {
  cv::Mat colour(img.Rows(), img.Cols(), CV_8UC3, cv::Scalar(0, 0, 0));
  cv::Mat depth(img.Rows(), img.Cols(), CV_16UC1, cv::Scalar(0));
  for (int r = 0; r < img.Rows(); ++r)
    for (int c = 0; c < img.Cols(); ++c) {
      const std::size_t i = img.Index(c, r);
      if (img.Count(i) > 0) {
        const auto rgb = img.Rgb(i);
        colour.at<cv::Vec3b>(r, c) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);  // OpenCV is BGR
        const double q = 32768.0 + img.Depth(i) / 1e-4;
        depth.at<std::uint16_t>(r, c) =
            static_cast<std::uint16_t>(std::clamp(std::lround(q), 1L, 65535L));
      } else if (img.Passed(i) > 0) {
        colour.at<cv::Vec3b>(r, c) = cv::Vec3b(160, 120, 90);
      } else if (img.Blocked(i) > 0) {
        colour.at<cv::Vec3b>(r, c) = cv::Vec3b(20, 20, 110);
      }
    }
  for (const auto& [path, mat] :
       {std::pair<std::string, const cv::Mat*>{stem + "_colour.png", &colour},
        {stem + "_depth.png", &depth}}) {
    std::string png;
    try {
      png = io::EncodePng({mat->data, mat->cols, mat->rows, mat->channels(),
                           mat->depth() == CV_16U ? 16 : 8, mat->step});
    } catch (const std::exception& e) {
      throw InputError(path, "cannot write the image", e.what());
    }
    WriteWholeFile(path, png);
  }
}

}  // namespace mopad::modelling
