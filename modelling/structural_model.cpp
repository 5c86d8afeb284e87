#include "modelling/structural_model.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "common/error.h"
#include "common/frames.h"
#include "common/polygon.h"
#include "common/rng.h"
#include "modelling/room_model.h"

namespace mopad::modelling {
namespace {

// Least-squares plane through `pts` (PCA: the normal is the smallest eigenvector).
Plane PcaPlane(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Plane pl;
  pl.n = es.eigenvectors().col(0).normalized();
  pl.d = -pl.n.dot(c);
  return pl;
}

// A fit's tilt from `nominal` (a wall's plumb or a floor's level normal) read from inliers that
// span less than prm.min_tilt_extent along the slope is not observed: the plane is set to
// `nominal` through their centroid. The span is taken between the 2nd and 98th percentiles.
void KeepTiltOnlyWhereObserved(PlaneFit& f, const std::vector<Eigen::Vector3d>& points,
                               Eigen::Vector3d nominal, const Sm3Params& prm) {
  if (!f.fitted || prm.min_tilt_extent <= 0.0) return;
  if (nominal.dot(f.plane.n) < 0.0) nominal = -nominal;
  const Eigen::Vector3d slope = f.plane.n - f.plane.n.dot(nominal) * nominal;
  if (slope.norm() < 1e-12) return;
  const Eigen::Vector3d s = slope.normalized();
  std::vector<double> along;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) {
    if (std::abs(f.plane.Distance(p)) >= 3 * prm.mlesac_sigma) continue;
    along.push_back(s.dot(p));
    c += p;
  }
  if (along.size() < 3) return;
  const auto at = [&](double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(along.size() - 1));
    std::nth_element(along.begin(), along.begin() + k, along.end());
    return along[static_cast<std::size_t>(k)];
  };
  if (at(0.98) - at(0.02) >= prm.min_tilt_extent) return;
  c /= static_cast<double>(along.size());
  f.plane.n = nominal;
  f.plane.d = -nominal.dot(c);
}

// Newell normal of a polygon (not normalised).
Eigen::Vector3d Newell(const std::vector<Eigen::Vector3d>& poly) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    n += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                         (a.x() - b.x()) * (a.y() + b.y()));
  }
  return n;
}

// The point on three planes; nullopt-like flag when they are (nearly) dependent.
bool ThreePlanes(const Plane& a, const Plane& b, const Plane& c, Eigen::Vector3d* out) {
  Eigen::Matrix3d m;
  m.row(0) = a.n.transpose();
  m.row(1) = b.n.transpose();
  m.row(2) = c.n.transpose();
  if (std::abs(m.determinant()) < 1e-6) return false;
  *out = m.fullPivLu().solve(Eigen::Vector3d(-a.d, -b.d, -c.d));
  return true;
}

Plane VerticalPlaneThrough(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                           const Eigen::Vector2d& into) {
  Plane p;
  p.n = Eigen::Vector3d(into.x(), into.y(), 0.0).normalized();
  p.d = -p.n.dot(Eigen::Vector3d(a.x(), a.y(), 0.0));
  (void)b;
  return p;
}

// One closed ring of vertical faces (room walls, or a column's faces): per edge a plane fitted
// to the points near it, consecutive planes intersected with the floor and ceiling planes.
// `into_left`: the room lies to the left of each edge (a CCW perimeter) or to its right (a CCW
// column footprint).
struct Ring {
  std::vector<Plane> planes;
  std::vector<PlaneFit> fits;
  std::vector<Eigen::Vector3d> bottom, top;  // corner i = between face i-1 and face i
};

std::vector<Eigen::Vector2d> MergeCollinear(std::vector<Eigen::Vector2d> loop, double angle_deg) {
  const double cos_max = std::cos(angle_deg * M_PI / 180.0);
  bool changed = true;
  while (changed && loop.size() > 3) {
    changed = false;
    for (std::size_t i = 0; i < loop.size() && loop.size() > 3; ++i) {
      const auto& p = loop[(i + loop.size() - 1) % loop.size()];
      const auto& q = loop[i];
      const auto& r = loop[(i + 1) % loop.size()];
      const Eigen::Vector2d u = q - p, v = r - q;
      if (u.norm() < 1e-9 || v.norm() < 1e-9 || u.normalized().dot(v.normalized()) > cos_max) {
        loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        break;
      }
    }
  }
  return loop;
}

// Collapses edges shorter than `min_len` into one corner (the intersection of the neighbouring
// edges' lines, or the short edge's midpoint when they are nearly parallel or meet far away): a
// column footprint traced from points can carry a 1 mm chamfer, whose face would be a sliver
// with a meaningless plane and a degenerate polygon.
std::vector<Eigen::Vector2d> DropShortEdges(std::vector<Eigen::Vector2d> loop, double min_len) {
  while (loop.size() > 3) {
    const std::size_t n = loop.size();
    std::size_t best = n;
    double shortest = min_len;
    for (std::size_t i = 0; i < n; ++i) {
      const double l = (loop[(i + 1) % n] - loop[i]).norm();
      if (l < shortest) shortest = l, best = i;
    }
    if (best == n) break;
    const Eigen::Vector2d p0 = loop[(best + n - 1) % n], p1 = loop[best];
    const Eigen::Vector2d q0 = loop[(best + 1) % n], q1 = loop[(best + 2) % n];
    const Eigen::Vector2d mid = 0.5 * (p1 + q0);
    Eigen::Vector2d corner = mid;
    const Eigen::Vector2d u = p1 - p0, v = q1 - q0;
    const double den = u.x() * v.y() - u.y() * v.x();
    if (std::abs(den) > 1e-9 * u.norm() * v.norm()) {
      const Eigen::Vector2d w = q0 - p0;
      const Eigen::Vector2d x = p0 + ((w.x() * v.y() - w.y() * v.x()) / den) * u;
      if ((x - mid).norm() <= 2.0 * min_len) corner = x;
    }
    loop[best] = corner;
    loop.erase(loop.begin() + static_cast<std::ptrdiff_t>((best + 1) % n));
  }
  return loop;
}

// One face per loop edge, fitted to the points near it; corners where neighbouring faces meet
// the floor and ceiling planes. A face whose fitted corners leave it shorter than `min_edge`
// along its loop edge (or reversed: neighbours fitted across it) is no face: its two loop
// vertices become one and the ring is fitted again.
Ring FitRing(const std::vector<Eigen::Vector2d>& loop, bool into_left,
             const std::vector<Eigen::Vector3d>& points, const Plane& floor, const Plane& ceiling,
             double floor_z, double ceiling_z, const Sm3Params& prm, const std::string& stream,
             double min_edge);
Ring FitRing(const std::vector<Eigen::Vector2d>& loop, bool into_left,
             const std::vector<Eigen::Vector3d>& points, const Plane& floor, const Plane& ceiling,
             double floor_z, double ceiling_z, const Sm3Params& prm, const std::string& stream,
             double min_edge) {
  Ring ring;
  const std::size_t n = loop.size();
  // The ring again without loop vertex `drop`, `keep` put in place of vertex `at`.
  auto refit = [&](std::size_t drop, std::size_t at, const Eigen::Vector2d& keep) {
    std::vector<Eigen::Vector2d> fewer = loop;
    fewer[at] = keep;
    fewer.erase(fewer.begin() + static_cast<std::ptrdiff_t>(drop));
    return FitRing(fewer, into_left, points, floor, ceiling, floor_z, ceiling_z, prm, stream,
                   min_edge);
  };
  // Points per edge.
  std::vector<std::vector<Eigen::Vector3d>> near(n);
  const double z_lo = floor_z + 0.15, z_hi = ceiling_z - 0.15;
  std::vector<Eigen::Vector2d> t(n), in(n);
  std::vector<double> len(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d d = loop[(i + 1) % n] - loop[i];
    len[i] = d.norm();
    t[i] = d / std::max(len[i], 1e-12);
    in[i] = into_left ? Eigen::Vector2d(-t[i].y(), t[i].x()) : Eigen::Vector2d(t[i].y(), -t[i].x());
  }
  for (const auto& p : points) {
    if (p.z() < z_lo || p.z() > z_hi) continue;
    const Eigen::Vector2d q = p.head<2>();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d r = q - loop[i];
      const double s = r.dot(t[i]);
      const double margin = std::min(prm.corner_margin, 0.2 * len[i]);  // narrow column faces
      if (s < margin || s > len[i] - margin) continue;
      if (std::abs(r.dot(in[i])) > prm.plane_band) continue;
      near[i].push_back(p);
    }
  }
  // One task per face, each with its own MLESAC stream: the same fits on any number of threads.
  std::vector<PlaneFit> fits(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (static_cast<int>(near[i].size()) >= prm.min_points)
      fits[i] = FitPlaneMlesac(near[i], prm, stream + "/" + std::to_string(i));
  });
  for (std::size_t i = 0; i < n; ++i) {
    PlaneFit f = fits[i];
    const Eigen::Vector3d in3(in[i].x(), in[i].y(), 0.0);
    if (f.fitted && std::abs(f.plane.n.z()) < 0.9)
      KeepTiltOnlyWhereObserved(
          f, near[i], Eigen::Vector3d(f.plane.n.x(), f.plane.n.y(), 0.0).normalized(), prm);
    if (!f.fitted || std::abs(f.plane.n.dot(in3)) < 0.9) {  // no data or not this wall
      f.plane = VerticalPlaneThrough(loop[i], loop[(i + 1) % n], in[i]);
      f.fitted = false;
    }
    if (f.plane.n.dot(in3) < 0) f.plane.n = -f.plane.n, f.plane.d = -f.plane.d;
    ring.planes.push_back(f.plane);
    ring.fits.push_back(f);
  }
  // Consecutive faces that turn out parallel and coincident are one face: drop the vertex
  // between them and fit again (a perimeter may break a straight wall at a door reveal).
  if (n > 3) {
    const double cos_max = std::cos(prm.merge_angle_deg * M_PI / 180.0);
    for (std::size_t i = 0; i < n; ++i) {
      const Plane& a = ring.planes[(i + n - 1) % n];
      const Plane& b = ring.planes[i];
      const Eigen::Vector3d mid(loop[i].x(), loop[i].y(), 0.5 * (floor_z + ceiling_z));
      if (a.n.dot(b.n) > cos_max && std::abs(a.Distance(mid) - b.Distance(mid)) < prm.plane_band) {
        return refit(i, i, loop[i]);
      }
      // Consecutive faces on one surface facing opposite ways are a spike or a thin wedge (the
      // trace ran out along that surface and back): no floor between them, and no corner for
      // the ring. The vertex between them goes.
      if (a.n.dot(b.n) < -cos_max && std::abs(a.Distance(mid) + b.Distance(mid)) < prm.plane_band)
        return refit(i, i, loop[i]);
    }
    // A face its own points do not fit (too few, or they belong to another face), between two
    // fitted faces that turn (not parallel) and meet within its length of its middle, is no
    // face: the perimeter cut across a corner no scan saw well (the inner corner of an L-shaped
    // hall, seen only past its edge). Its two loop vertices become the neighbours' corner and
    // the ring is fitted again.
    const double cos_parallel = std::cos(DegToRad(prm.corner_min_angle_deg));
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t h = (i + n - 1) % n, j = (i + 1) % n;
      if (ring.fits[i].fitted || !ring.fits[h].fitted || !ring.fits[j].fitted) continue;
      const Eigen::Vector2d a = ring.planes[h].n.head<2>(), b = ring.planes[j].n.head<2>();
      if (std::abs(a.normalized().dot(b.normalized())) > cos_parallel) continue;
      Eigen::Vector3d corner;
      if (!ThreePlanes(ring.planes[h], ring.planes[j], floor, &corner)) continue;
      if ((corner.head<2>() - 0.5 * (loop[i] + loop[j])).norm() > len[i]) continue;
      return refit(j, i, corner.head<2>());
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Plane& prev = ring.planes[(i + n - 1) % n];
    const Plane& cur = ring.planes[i];
    Eigen::Vector3d b, u;
    if (!ThreePlanes(prev, cur, floor, &b)) b = Eigen::Vector3d(loop[i].x(), loop[i].y(), floor_z);
    if (!ThreePlanes(prev, cur, ceiling, &u))
      u = Eigen::Vector3d(loop[i].x(), loop[i].y(), ceiling_z);
    ring.bottom.push_back(b);
    ring.top.push_back(u);
  }
  if (n > 3) {
    const double least = std::max(min_edge, 1e-3);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      const double along = std::min((ring.bottom[j] - ring.bottom[i]).head<2>().dot(t[i]),
                                    (ring.top[j] - ring.top[i]).head<2>().dot(t[i]));
      if (along < least) return refit(j, i, 0.5 * (loop[i] + loop[j]));
    }
  }
  return ring;
}

PlaneFit FitHorizontal(const std::vector<Eigen::Vector3d>& points, double z, bool up,
                       const Sm3Params& prm, const std::string& stream) {
  std::vector<Eigen::Vector3d> band;
  for (const auto& p : points)
    if (std::abs(p.z() - z) < prm.plane_band) band.push_back(p);
  PlaneFit f;
  if (static_cast<int>(band.size()) >= prm.min_points) f = FitPlaneMlesac(band, prm, stream);
  if (f.fitted && std::abs(f.plane.n.z()) >= 0.9)
    KeepTiltOnlyWhereObserved(f, band, Eigen::Vector3d::UnitZ(), prm);
  if (!f.fitted || std::abs(f.plane.n.z()) < 0.9) {
    f.plane.n = Eigen::Vector3d::UnitZ();
    f.plane.d = -z;
    f.fitted = false;
  } else if (std::acos(std::min(1.0, std::abs(f.plane.n.z()))) <
             DegToRad(prm.level_tolerance_deg)) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : band) c += p;
    c /= static_cast<double>(band.size());
    const double zc = -(f.plane.n.x() * c.x() + f.plane.n.y() * c.y() + f.plane.d) / f.plane.n.z();
    f.plane.n = Eigen::Vector3d::UnitZ();
    f.plane.d = -zc;
  }
  if ((f.plane.n.z() > 0) != up) f.plane.n = -f.plane.n, f.plane.d = -f.plane.d;
  return f;
}

// Kasa's algebraic circle fit (linear least squares on x^2 + y^2 + D x + E y + F = 0), computed
// about the mean for conditioning. Returns false for fewer than 3 points or a degenerate set.
bool KasaCircle(const std::vector<Eigen::Vector2d>& p, Eigen::Vector2d* centre, double* radius) {
  if (p.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& q : p) mean += q;
  mean /= static_cast<double>(p.size());
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const auto& q : p) {
    const Eigen::Vector2d d = q - mean;
    const Eigen::Vector3d a(d.x(), d.y(), 1.0);
    ata += a * a.transpose();
    atb -= a * d.squaredNorm();
  }
  if (std::abs(ata.determinant()) < 1e-18) return false;
  const Eigen::Vector3d x = ata.ldlt().solve(atb);
  const Eigen::Vector2d c(-0.5 * x(0), -0.5 * x(1));
  const double r2 = c.squaredNorm() - x(2);
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  *centre = mean + c;
  *radius = std::sqrt(r2);
  return true;
}

// Geometric circle fit: Gauss-Newton on |p - c| - r from the given start.
void RefineCircle(const std::vector<Eigen::Vector2d>& p, Eigen::Vector2d* centre, double* radius) {
  for (int it = 0; it < 20; ++it) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (const auto& q : p) {
      const Eigen::Vector2d d = q - *centre;
      const double n = d.norm();
      if (n < 1e-12) continue;
      const Eigen::Vector3d j(-d.x() / n, -d.y() / n, -1.0);
      const double r = n - *radius;
      jtj += j * j.transpose();
      jtr += j * r;
    }
    if (std::abs(jtj.determinant()) < 1e-18) return;
    const Eigen::Vector3d step = -jtj.ldlt().solve(jtr);
    *centre += step.head<2>();
    *radius += step(2);
    if (step.norm() < 1e-9) return;
  }
}

}  // namespace

CircleFit FitColumnCircle(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<Eigen::Vector2d>& footprint, double floor_z,
                          double ceiling_z, const Sm3Params& prm) {
  CircleFit out;
  const auto loop = MergeCollinear(footprint, prm.merge_angle_deg);
  const std::size_t n = loop.size();
  if (static_cast<int>(n) < prm.round_min_vertices) return out;
  const double max_turn = prm.round_max_turn_deg * M_PI / 180.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d u = loop[i] - loop[(i + n - 1) % n], v = loop[(i + 1) % n] - loop[i];
    const double turn = std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
    if (turn > max_turn) return out;
  }
  Eigen::Vector2d c;
  double r = 0.0;
  if (!KasaCircle(loop, &c, &r)) return out;
  const double z_lo = floor_z + 0.15, z_hi = ceiling_z - 0.15;
  std::vector<Eigen::Vector2d> near;
  for (double band : {prm.plane_band, 0.5 * prm.plane_band}) {
    near.clear();
    for (const auto& p : points) {
      if (p.z() < z_lo || p.z() > z_hi) continue;
      const Eigen::Vector2d q = p.head<2>();
      if (std::abs((q - c).norm() - r) < band) near.push_back(q);
    }
    if (static_cast<int>(near.size()) < std::max(3, prm.min_points)) return out;
    Eigen::Vector2d c1;
    double r1 = 0.0;
    if (!KasaCircle(near, &c1, &r1)) return out;
    RefineCircle(near, &c1, &r1);
    if (!(r1 > 0.0) || !c1.allFinite()) return out;
    c = c1, r = r1;
  }
  double ss = 0.0;
  for (const auto& q : near) ss += std::pow((q - c).norm() - r, 2);
  out.centre = c;
  out.radius = r;
  out.support = static_cast<int>(near.size());
  out.rms = std::sqrt(ss / static_cast<double>(near.size()));
  out.round = out.rms <= prm.round_max_rms_ratio * r;
  return out;
}

const char* ToString(PatchClass c) {
  switch (c) {
    case PatchClass::kWall:
      return "wall";
    case PatchClass::kFloor:
      return "floor";
    case PatchClass::kCeiling:
      return "ceiling";
    case PatchClass::kColumn:
      return "column";
  }
  return "?";
}

PlaneFit FitPlaneMlesac(const std::vector<Eigen::Vector3d>& all, const Sm3Params& prm,
                        const std::string& stream) {
  PlaneFit out;
  if (all.size() < 3) return out;
  // Even subsample (deterministic) beyond max_fit_points.
  std::vector<Eigen::Vector3d> pts;
  const std::size_t stride =
      std::max<std::size_t>(1, all.size() / static_cast<std::size_t>(prm.max_fit_points));
  for (std::size_t i = 0; i < all.size(); i += stride) pts.push_back(all[i]);
  Eigen::AlignedBox3d box;
  for (const auto& p : pts) box.extend(p);
  const double v = std::max(box.diagonal().norm(), 10.0 * prm.mlesac_sigma);  // outlier range
  const double s2 = prm.mlesac_sigma * prm.mlesac_sigma;
  const double norm_in = 1.0 / std::sqrt(2.0 * M_PI * s2);
  CounterRng rng(prm.seed, "sm3/mlesac/" + stream);
  double best_cost = std::numeric_limits<double>::infinity();
  Plane best;
  // Per point of a hypothesis: exp(-r^2 / (2 sigma^2)), the unnormalised inlier density.
  std::vector<double> g(pts.size());
  for (int it = 0; it < prm.mlesac_iterations; ++it) {
    const auto& a = pts[rng.Below(pts.size())];
    const auto& b = pts[rng.Below(pts.size())];
    const auto& c = pts[rng.Below(pts.size())];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    const double d = -n.dot(a);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const double r = n.dot(pts[k]) + d;
      g[k] = std::exp(-(r * r) / (2 * s2));
    }
    // Mixing weight by EM (Torr & Zisserman), then the negative log-likelihood.
    double gamma = 0.5;
    for (int em = 0; em < 3; ++em) {
      double sum = 0.0;
      for (double x : g) {
        const double pi = gamma * norm_in * x;
        const double po = (1 - gamma) / v;
        sum += pi / (pi + po);
      }
      gamma = sum / static_cast<double>(g.size());
    }
    double cost = 0.0;
    for (double x : g) cost -= std::log(gamma * norm_in * x + (1 - gamma) / v);
    if (cost < best_cost) best_cost = cost, best = Plane{n, d};
  }
  if (!std::isfinite(best_cost)) return out;
  // Least-squares refinement on the 3-sigma inliers (twice: the set shrinks as the plane improves).
  Plane pl = best;
  std::vector<Eigen::Vector3d> in;
  for (int pass = 0; pass < 3; ++pass) {
    in.clear();
    for (const auto& p : all)
      if (std::abs(pl.Distance(p)) < 3 * prm.mlesac_sigma) in.push_back(p);
    if (in.size() < 3) return out;
    const Plane refined = PcaPlane(in);
    pl = refined.n.dot(pl.n) < 0 ? Plane{-refined.n, -refined.d} : refined;
  }
  double ss = 0.0;
  for (const auto& p : in) ss += pl.Distance(p) * pl.Distance(p);
  out.plane = pl;
  out.support = static_cast<int>(in.size());
  out.rms = std::sqrt(ss / static_cast<double>(in.size()));
  out.fitted = true;
  return out;
}

std::pair<double, double> FloorCeilingFromHistogram(const std::vector<Eigen::Vector3d>& points,
                                                    double bin) {
  if (points.empty()) throw InputError("sm3: error: no points for the Z-histogram");
  double zmin = 1e18, zmax = -1e18;
  for (const auto& p : points) zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z());
  const int nb = static_cast<int>(std::ceil((zmax - zmin) / bin)) + 1;
  std::vector<double> h(static_cast<std::size_t>(nb), 0.0);
  for (const auto& p : points) h[static_cast<std::size_t>((p.z() - zmin) / bin)] += 1.0;
  // The two strongest local maxima at least 1 m apart: floor the lower, ceiling the upper.
  std::vector<int> order(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) order[static_cast<std::size_t>(i)] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return h[a] > h[b]; });
  const int first = order[0];
  int second = -1;
  for (int i : order)
    if (std::abs(i - first) * bin >= 1.0 && h[i] > 0) {
      second = i;
      break;
    }
  if (second < 0)
    throw InputError("sm3: error: the Z-histogram has one maximum; got points spanning " +
                     std::to_string(zmax - zmin) + " m, expected a floor and a ceiling");
  // Refine each peak as the mean z of the points within one bin of it.
  auto refine = [&](int peak) {
    const double zc = zmin + (peak + 0.5) * bin;
    double s = 0.0, n = 0.0;
    for (const auto& p : points)
      if (std::abs(p.z() - zc) <= 1.5 * bin) s += p.z(), n += 1.0;
    return s / n;
  };
  const double a = refine(first), b = refine(second);
  return {std::min(a, b), std::max(a, b)};
}

namespace {

// The sloped ceilings of a room (Sm3Input::slopes), each refit to the room's points on it, and
// the top of the walls' ring: the level ceiling, or without one the roof's highest point along
// the loop (the walls are ended under the slopes afterwards).
struct Slopes {
  std::vector<CeilingPlane> planes;  // the slopes, then the level ceiling when there is one
  std::vector<PlaneFit> fits;        // of the slopes
  std::size_t sloped = 0;            // how many of `planes` are slopes
  Plane top_plane;
  double top_z = 0.0;
};

Slopes FitSlopes(const Sm3Input& input, const std::vector<Eigen::Vector3d>& pts,
                 const std::vector<Eigen::Vector2d>& loop, const Plane& ceiling, double ceiling_z,
                 const Sm3Params& prm) {
  Slopes out;
  out.top_plane = ceiling;
  out.top_z = ceiling_z;
  if (input.slopes.empty()) return out;
  for (std::size_t k = 0; k < input.slopes.size(); ++k) {
    const CeilingPlane& s = input.slopes[k];
    std::vector<Eigen::Vector3d> band;
    for (const auto& p : pts)
      if (std::abs(s.n.dot(p) - s.c) < prm.plane_band) band.push_back(p);
    PlaneFit f;
    if (static_cast<int>(band.size()) >= prm.min_points)
      f = FitPlaneMlesac(band, prm, input.room + "/ceiling_" + std::to_string(k + 1));
    if (f.fitted && f.plane.n.z() > 0.0) f.plane.n = -f.plane.n, f.plane.d = -f.plane.d;
    CeilingPlane plane = s;
    if (f.fitted && f.plane.n.dot(s.n) > std::cos(DegToRad(5.0))) {
      plane.n = f.plane.n;
      plane.c = -f.plane.d;
    } else {
      f.plane.n = s.n;
      f.plane.d = -s.c;
      f.fitted = false;
    }
    out.planes.push_back(plane);
    out.fits.push_back(f);
  }
  out.sloped = out.planes.size();
  if (input.level_ceiling) {
    CeilingPlane level;
    level.n = ceiling.n;
    level.c = -ceiling.d;
    out.planes.push_back(level);
    return out;
  }
  // Every 5 cm along the loop, the lowest slope there: the walls' highest point.
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Eigen::Vector2d a = loop[i], b = loop[(i + 1) % loop.size()];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.05)));
    for (int j = 0; j <= n; ++j) {
      const Eigen::Vector2d q = a + (b - a) * (static_cast<double>(j) / n);
      double z = std::numeric_limits<double>::infinity();
      for (const auto& p : out.planes) z = std::min(z, p.ZAt(q));
      top = std::max(top, z);
    }
  }
  if (!std::isfinite(top)) return out;
  out.top_z = top;
  out.top_plane.n = -Eigen::Vector3d::UnitZ();
  out.top_plane.d = top;
  return out;
}

// The ceiling patches of a room with sloped ceilings: `ceiling` (the level one, where it is the
// lowest) and `ceiling_<k>` per slope, each cut to where it is the lowest in the walls' plan;
// the walls ended under them. Returns the index of the first ceiling patch.
int AddSlopedCeilings(const Slopes& slopes, const Ring& walls, const std::vector<int>& wall_ids,
                      const PlaneFit& level, int floor_id, StructuralModel& m) {
  std::vector<Eigen::Vector2d> plan;
  for (const auto& v : walls.bottom) plan.push_back(v.head<2>());
  if (SignedArea(plan) < 0.0) std::reverse(plan.begin(), plan.end());
  const std::vector<std::vector<Eigen::Vector2d>> regions =
      LowestCeilingRegions(plan, slopes.planes, nullptr, 0.05);
  int first = -1;
  std::vector<int> ids;
  for (std::size_t i = 0; i < slopes.planes.size(); ++i) {
    if (regions[i].empty()) continue;
    const bool is_level = i >= slopes.sloped;
    StructuralPatch c;
    c.id = is_level ? "ceiling" : "ceiling_" + std::to_string(i + 1);
    c.patch_class = PatchClass::kCeiling;
    const PlaneFit& f = is_level ? level : slopes.fits[i];
    c.plane.n = slopes.planes[i].n;
    c.plane.d = -slopes.planes[i].c;
    for (const auto& q : regions[i]) c.polygon.emplace_back(q.x(), q.y(), slopes.planes[i].ZAt(q));
    if (Newell(c.polygon).dot(c.plane.n) < 0) std::reverse(c.polygon.begin(), c.polygon.end());
    c.support = f.support, c.rms = f.rms, c.fitted = f.fitted;
    m.patches.push_back(std::move(c));
    ids.push_back(static_cast<int>(m.patches.size()) - 1);
    if (first < 0) first = ids.back();
  }
  // Each wall ended under the ceilings over it: (u, v) on the face's quad, v up its side.
  const std::size_t n = walls.bottom.size();
  for (std::size_t i = 0; i < n && i < wall_ids.size(); ++i) {
    const Eigen::Vector3d b0 = walls.bottom[i], b1 = walls.bottom[(i + 1) % n];
    const Eigen::Vector3d t0 = walls.top[i], t1 = walls.top[(i + 1) % n];
    const double length = (b1 - b0).head<2>().norm(), height = t0.z() - b0.z();
    if (length <= 1e-6 || height <= 1e-6) continue;
    const Eigen::Vector2d dir = (b1 - b0).head<2>() / length;
    StructuralPatch& w = m.patches[wall_ids[i]];
    const Eigen::Vector2d inward = w.plane.n.head<2>().normalized();
    const std::vector<Eigen::Vector2d> outline = WallUnderCeilings(
        b0.head<2>(), dir, inward, length, b0.z(), height, slopes.planes, regions);
    if (outline.empty()) continue;
    std::vector<Eigen::Vector3d> poly;
    for (const auto& uv : outline) {
      const double s = uv.x() / length, r = uv.y() / height;
      const Eigen::Vector3d foot = b0 + s * (b1 - b0), head = t0 + s * (t1 - t0);
      poly.push_back(foot + r * (head - foot));
    }
    if (Newell(poly).dot(w.plane.n) < 0) std::reverse(poly.begin(), poly.end());
    w.polygon = std::move(poly);
  }
  for (int w : wall_ids) {
    m.adjacency.emplace_back(w, floor_id);
    for (int c : ids) m.adjacency.emplace_back(w, c);
  }
  return first;
}

// The ceiling patch `ceiling` over the walls' corners, or with sloped ceilings their patches
// (AddSlopedCeilings); each wall adjacent to the floor and the ceilings. Returns the index of
// the first ceiling patch, -1 when none.
int AddCeilings(const Slopes& slopes, const Ring& walls, const std::vector<int>& wall_ids,
                const PlaneFit& level, int floor_id, StructuralModel& m) {
  if (!slopes.planes.empty()) return AddSlopedCeilings(slopes, walls, wall_ids, level, floor_id, m);
  StructuralPatch c;
  c.id = "ceiling";
  c.patch_class = PatchClass::kCeiling;
  c.plane = level.plane;
  c.polygon = walls.top;
  if (Newell(c.polygon).dot(c.plane.n) < 0) std::reverse(c.polygon.begin(), c.polygon.end());
  c.support = level.support, c.rms = level.rms, c.fitted = level.fitted;
  m.patches.push_back(std::move(c));
  const int id = static_cast<int>(m.patches.size()) - 1;
  for (int w : wall_ids) m.adjacency.emplace_back(w, floor_id), m.adjacency.emplace_back(w, id);
  return id;
}

}  // namespace

StructuralModel BuildStructuralModel(const Sm3Input& input, const Sm3Params& prm) {
  ValidateParams(prm, "sm3.");
  if (!input.points || input.points->empty())
    throw InputError("sm3: error: room '" + input.room + "' has no points");
  if (input.perimeter.size() < 3)
    throw InputError("sm3: error: room '" + input.room + "' perimeter has " +
                     std::to_string(input.perimeter.size()) + " vertices, expected >= 3");
  const auto& pts = *input.points;
  StructuralModel m;
  m.room = input.room;
  std::tie(m.floor_z, m.ceiling_z) = FloorCeilingFromHistogram(pts, prm.histogram_bin);
  if (std::isfinite(input.floor_z) && std::abs(m.floor_z - input.floor_z) > prm.heights_tolerance)
    m.floor_z = input.floor_z;
  if (std::isfinite(input.ceiling_z) &&
      std::abs(m.ceiling_z - input.ceiling_z) > prm.heights_tolerance)
    m.ceiling_z = input.ceiling_z;
  PlaneFit floor, ceiling;
  tbb::parallel_invoke(
      [&] { floor = FitHorizontal(pts, m.floor_z, /*up=*/true, prm, input.room + "/floor"); },
      [&] {
        ceiling = FitHorizontal(pts, m.ceiling_z, /*up=*/false, prm, input.room + "/ceiling");
      });

  const std::vector<Eigen::Vector2d> loop = MergeCollinear(input.perimeter, prm.merge_angle_deg);
  const Slopes slopes = FitSlopes(input, pts, loop, ceiling.plane, m.ceiling_z, prm);
  const Ring walls = FitRing(loop, /*into_left=*/true, pts, floor.plane, slopes.top_plane,
                             m.floor_z, slopes.top_z, prm, input.room + "/walls", 0.0);
  auto add = [&](StructuralPatch p) {
    if (Newell(p.polygon).dot(p.plane.n) < 0) std::reverse(p.polygon.begin(), p.polygon.end());
    m.patches.push_back(std::move(p));
    return static_cast<int>(m.patches.size()) - 1;
  };
  auto add_ring = [&](const Ring& ring, PatchClass cls, const std::string& prefix) {
    const std::size_t n = ring.planes.size();
    std::vector<int> ids;
    for (std::size_t i = 0; i < n; ++i) {
      StructuralPatch p;
      p.id = prefix + std::to_string(i + 1);
      p.patch_class = cls;
      p.plane = ring.planes[i];
      p.polygon = {ring.bottom[i], ring.bottom[(i + 1) % n], ring.top[(i + 1) % n], ring.top[i]};
      p.support = ring.fits[i].support;
      p.rms = ring.fits[i].rms;
      p.fitted = ring.fits[i].fitted;
      ids.push_back(add(std::move(p)));
    }
    for (std::size_t i = 0; i < n; ++i) m.adjacency.emplace_back(ids[i], ids[(i + 1) % n]);
    return ids;
  };
  const std::vector<int> wall_ids = add_ring(walls, PatchClass::kWall, "wall_");

  StructuralPatch f;
  f.id = "floor";
  f.patch_class = PatchClass::kFloor;
  f.plane = floor.plane;
  f.polygon = walls.bottom;
  f.support = floor.support, f.rms = floor.rms, f.fitted = floor.fitted;
  const int floor_id = add(std::move(f));
  const int ceiling_id = AddCeilings(slopes, walls, wall_ids, ceiling, floor_id, m);

  for (std::size_t k = 0; k < input.columns.size(); ++k) {
    const auto footprint =
        DropShortEdges(MergeCollinear(input.columns[k], prm.merge_angle_deg), prm.min_column_edge);
    if (footprint.size() < 3) continue;
    const CircleFit circle = FitColumnCircle(pts, input.columns[k], m.floor_z, m.ceiling_z, prm);
    Ring ring;
    if (circle.round) {
      // Regular prism of the circle's area (vertex radius R: (s/2) R^2 sin(2 pi / s) = pi r^2).
      const int s = prm.round_segments;
      const double R = circle.radius * std::sqrt(2.0 * M_PI / (s * std::sin(2.0 * M_PI / s)));
      std::vector<Eigen::Vector2d> vtx;
      for (int i = 0; i < s; ++i) {
        const double a = 2.0 * M_PI * i / s;
        vtx.push_back(circle.centre + R * Eigen::Vector2d(std::cos(a), std::sin(a)));
      }
      for (int i = 0; i < s; ++i) {
        const Eigen::Vector2d out2 = (vtx[i] + vtx[(i + 1) % s]) * 0.5 - circle.centre;
        PlaneFit f;
        f.plane = VerticalPlaneThrough(vtx[i], vtx[(i + 1) % s], out2.normalized());
        f.support = circle.support;
        f.rms = circle.rms;
        f.fitted = true;
        ring.planes.push_back(f.plane);
        ring.fits.push_back(f);
      }
      auto on = [](const Plane& p, const Eigen::Vector2d& q, double z) {
        return std::abs(p.n.z()) > 1e-9
                   ? Eigen::Vector3d(q.x(), q.y(),
                                     -(p.n.x() * q.x() + p.n.y() * q.y() + p.d) / p.n.z())
                   : Eigen::Vector3d(q.x(), q.y(), z);
      };
      for (int i = 0; i < s; ++i) {
        ring.bottom.push_back(on(floor.plane, vtx[i], m.floor_z));
        ring.top.push_back(on(ceiling.plane, vtx[i], m.ceiling_z));
      }
    } else {
      ring = FitRing(footprint, /*into_left=*/false, pts, floor.plane, ceiling.plane, m.floor_z,
                     m.ceiling_z, prm, input.room + "/column_" + std::to_string(k + 1),
                     prm.min_column_edge);
    }
    const auto ids =
        add_ring(ring, PatchClass::kColumn, "column_" + std::to_string(k + 1) + "_face_");
    for (int id : ids) {
      m.adjacency.emplace_back(id, floor_id);
      if (ceiling_id >= 0) m.adjacency.emplace_back(id, ceiling_id);
    }
  }
  return m;
}

StructuralModel BuildRoomSm3(const RoomModel& model, const Sm3Params& params,
                             const std::string& room, const std::vector<std::uint8_t>* exclude) {
  const auto& labels = model.Labels();
  const auto& pts = model.Points();
  if (exclude != nullptr && exclude->size() != pts.size())
    throw InputError("sm3", "exclusion mask does not match the room's points",
                     std::to_string(exclude->size()), std::to_string(pts.size()));
  auto used = [&](std::size_t i) {
    return labels[i] == PointLabel::kInlier && (exclude == nullptr || (*exclude)[i] == 0);
  };
  std::size_t inliers = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) inliers += used(i);
  const std::size_t stride = std::max<std::size_t>(1, inliers / 1000000);
  std::vector<Eigen::Vector3d> in;
  in.reserve(inliers / stride + 1);
  std::size_t n = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (used(i) && n++ % stride == 0) in.push_back(pts[i].cast<double>());
  Sm3Input input;
  input.room = room;
  input.points = &in;
  input.perimeter = model.Perimeter();
  input.columns = model.Columns();
  input.floor_z = model.FloorZ();
  input.ceiling_z = model.CeilingZ();
  input.slopes = model.GetRoi().slopes;
  input.level_ceiling = model.GetRoi().level_ceiling;
  return BuildStructuralModel(input, params);
}

}  // namespace mopad::modelling
