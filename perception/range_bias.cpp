#include "perception/range_bias.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/error.h"
#include "common/format.h"
#include "common/frames.h"

namespace mopad::perception {
namespace {

constexpr double kBin = 0.01;                      // m, z histogram bin
constexpr double kMaxHeight = 20.0;                // m, |z| beyond this is no floor or ceiling
constexpr double kStrong = 0.25;                   // a peak counts at this share of the highest one
constexpr double kNeighbourAngle = DegToRad(0.4);  // rad, rows compared for flatness
constexpr double kMaxSlope = DegToRad(15.0);       // rad, steepest "horizontal" surface

struct PlanePoint {
  double z, uz, x, y;
  int plane;  // 0 floor, 1 ceiling
};

// Centre of the outermost strong peak of the |z| histogram on one side of the scanner (the
// lowest below it, the highest above it): desk tops and lamps lie inside the room's shell.
bool OutermostPeak(const std::vector<int>& hist, bool below, double& z_peak) {
  const int n = static_cast<int>(hist.size());
  const int hmax = *std::max_element(hist.begin(), hist.end());
  if (hmax == 0) return false;
  // Bin k holds |z| in [k kBin, (k+1) kBin); the outermost peak has the largest k.
  for (int k = n - 1; k >= 0; --k) {
    const int c = hist[k];
    if (c < kStrong * hmax) continue;
    if (k + 1 < n && hist[k + 1] > c) continue;
    if (k > 0 && hist[k - 1] > c) continue;
    const double mag = (k + 0.5) * kBin;
    z_peak = below ? -mag : mag;
    return true;
  }
  return false;
}

// The points of the floor and ceiling bands (`has` a plane, its height `peak`), with the
// regressors of the fit.
// A point counts when its neighbours a few rows up and down (0.4 deg or more apart) lie on a
// horizontal surface with it: the bottoms and tops of walls inside the band would otherwise
// lean the fit (they sit on one side of the plane only, at grazing rays).
std::vector<PlanePoint> FlatPlanePoints(const interfaces::TlsScan& scan,
                                        const RangeBiasParams& params,
                                        const std::array<bool, 2>& has,
                                        const std::array<double, 2>& peak) {
  const int k_rows =
      scan.elevation_step > 0.0
          ? std::max(1, static_cast<int>(std::ceil(kNeighbourAngle / scan.elevation_step - 1e-9)))
          : 1;
  const double max_slope = std::tan(kMaxSlope);
  auto flat_towards = [&](const interfaces::TlsPoint& p, std::int64_t row, std::uint32_t col) {
    if (row < 0 || row >= static_cast<std::int64_t>(scan.rows)) return false;
    const auto& q = scan.at(static_cast<std::uint32_t>(row), col);
    if (!q.valid()) return false;
    const double dz = double(q.z) - p.z, dxy = std::hypot(double(q.x) - p.x, double(q.y) - p.y);
    return std::abs(dz) <= max_slope * dxy;
  };
  std::vector<PlanePoint> pts;
  for (const auto& p : scan.points) {
    if (!p.valid()) continue;
    const double z = p.z;
    if (std::abs(z) < params.min_height) continue;
    const int plane = z > 0 ? 1 : 0;
    if (!has[plane] || std::abs(z - peak[plane]) > params.band) continue;
    if (!flat_towards(p, std::int64_t(p.row) - k_rows, p.column) ||
        !flat_towards(p, std::int64_t(p.row) + k_rows, p.column))
      continue;
    // The slopes' regressors come from the ray's direction and the plane's height, not from
    // the point: its x and y carry the same range noise as its z, which would bias b.
    const double r = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + z * z);
    const double reach = peak[plane] / z;  // R / r: the plane's range over the measured one
    pts.push_back({z, z / r, reach * p.x, reach * p.y, plane});
  }
  return pts;
}

}  // namespace

RangeBiasEstimate EstimateRangeBias(const interfaces::TlsScan& scan,
                                    const RangeBiasParams& params) {
  ValidateParams(params, "range_bias.");
  RangeBiasEstimate e;
  if (scan.points.size() != static_cast<std::size_t>(scan.rows) * scan.columns) {
    e.message = "range bias not estimated: the scan's grid is inconsistent";
    return e;
  }
  const int nbins = static_cast<int>(kMaxHeight / kBin);
  std::array<std::vector<int>, 2> hist{std::vector<int>(nbins, 0), std::vector<int>(nbins, 0)};
  for (const auto& p : scan.points) {
    if (!p.valid()) continue;
    const double z = p.z;
    if (std::abs(z) < params.min_height || std::abs(z) >= kMaxHeight) continue;
    ++hist[z > 0 ? 1 : 0][static_cast<int>(std::abs(z) / kBin)];
  }
  std::array<double, 2> peak{0.0, 0.0};
  std::array<bool, 2> has{OutermostPeak(hist[0], true, peak[0]),
                          OutermostPeak(hist[1], false, peak[1])};
  const std::vector<PlanePoint> pts = FlatPlanePoints(scan, params, has, peak);
  // Unknowns: the present planes' heights, then b, s_x, s_y.
  std::array<int, 2> col{-1, -1};
  int nc = 0;
  for (int k = 0; k < 2; ++k) {
    std::size_t count = 0;
    for (const auto& q : pts) count += q.plane == k;
    if (count >= static_cast<std::size_t>(params.min_points) / 4) col[k] = nc++;
  }
  const int ib = nc, nu = nc + 3;
  std::vector<std::uint8_t> in(pts.size(), 1);
  Eigen::VectorXd sol = Eigen::VectorXd::Zero(nu);
  Eigen::MatrixXd ata;
  double rms = 0.0;
  std::size_t n_in = 0;
  for (int pass = 0; pass < 3 && nc > 0; ++pass) {
    ata = Eigen::MatrixXd::Zero(nu, nu);
    Eigen::VectorXd atb = Eigen::VectorXd::Zero(nu);
    Eigen::VectorXd row(nu);
    n_in = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const PlanePoint& q = pts[i];
      if (!in[i] || col[q.plane] < 0) continue;
      row.setZero();
      row(col[q.plane]) = 1.0;
      row(ib) = q.uz;
      row(ib + 1) = q.x;
      row(ib + 2) = q.y;
      ata.noalias() += row * row.transpose();
      atb.noalias() += row * q.z;
      ++n_in;
    }
    if (n_in < static_cast<std::size_t>(params.min_points)) break;
    sol = ata.ldlt().solve(atb);
    double ss = 0.0;
    std::vector<double> res(pts.size(), 0.0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const PlanePoint& q = pts[i];
      if (col[q.plane] < 0) continue;
      res[i] = q.z - (sol(col[q.plane]) + sol(ib) * q.uz + sol(ib + 1) * q.x + sol(ib + 2) * q.y);
      if (in[i]) ss += res[i] * res[i];
    }
    rms = std::sqrt(ss / static_cast<double>(n_in));
    // Clutter lying on the floor or hanging under the ceiling leaves the band's plane.
    const double keep = std::max(3.0 * rms, 0.002);
    for (std::size_t i = 0; i < pts.size(); ++i) in[i] = std::abs(res[i]) <= keep;
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!in[i] || col[pts[i].plane] < 0) continue;
    (pts[i].plane == 0 ? e.floor_points : e.ceiling_points) += 1;
  }
  if (nc == 0 || n_in < static_cast<std::size_t>(params.min_points)) {
    e.message = FormatNumbers(
        "range bias not estimated: %.0f floor and %.0f ceiling points (%.0f "
        "needed)",
        double(e.floor_points), double(e.ceiling_points), double(params.min_points));
    return e;
  }
  const Eigen::MatrixXd cov = ata.ldlt().solve(Eigen::MatrixXd::Identity(nu, nu)) * rms * rms;
  e.bias = sol(ib);
  e.sigma = std::sqrt(std::max(0.0, cov(ib, ib)));
  e.rms = rms;
  e.ok =
      std::isfinite(e.bias) && e.sigma <= params.max_sigma && std::abs(e.bias) <= params.max_bias;
  e.message = FormatNumbers("range bias %.2f mm +- %.2f mm", 1e3 * e.bias, 1e3 * e.sigma) +
              FormatNumbers(" from %.0f floor and %.0f ceiling points (rms %.2f mm)",
                            double(e.floor_points), double(e.ceiling_points), 1e3 * rms) +
              (e.ok                         ? ""
               : e.sigma > params.max_sigma ? ": too uncertain, not applied"
                                            : ": implausible, not applied");
  return e;
}

void RemoveRangeBias(interfaces::TlsScan& scan, double bias) {
  for (auto& p : scan.points) {
    if (!p.valid()) continue;
    const double r = p.range - bias;
    if (!(r > 0.0)) continue;
    const double s = r / static_cast<double>(p.range);
    p.x = static_cast<float>(p.x * s);
    p.y = static_cast<float>(p.y * s);
    p.z = static_cast<float>(p.z * s);
    p.range = static_cast<float>(r);
  }
}

}  // namespace mopad::perception
