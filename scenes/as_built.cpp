#include "scenes/as_built.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "common/frames.h"
#include "common/polygon.h"
#include "common/rng.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr int kFlatTerms = 12;
constexpr int kLeanTerms = 6;
constexpr double kSampleSpacing = 0.1;  // m, grid on which surfaces are measured and fitted

Vector3d UnitVector(CounterRng& rng) {
  const double z = rng.Uniform(-1.0, 1.0), a = rng.Uniform(0.0, 2.0 * kPi);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(a), r * std::sin(a), z};
}

// Points of a planar polygon on a grid of `spacing` in its plane (the polygon's vertices when
// it is smaller than one cell), with the polygon's frame.
std::vector<Vector3d> SurfaceSamples(const std::vector<Vector3d>& poly, double spacing) {
  std::vector<Vector3d> out;
  if (poly.size() < 3) return poly;
  Vector3d n = NewellVector(poly);
  if (n.norm() < 1e-12) return poly;
  n.normalize();
  Vector3d u = (poly[1] - poly[0]);
  u = (u - u.dot(n) * n).normalized();
  const Vector3d w = n.cross(u);
  std::vector<Vector2d> p2;
  Vector2d lo = Vector2d::Constant(1e300), hi = Vector2d::Constant(-1e300);
  for (const auto& p : poly) {
    p2.emplace_back((p - poly[0]).dot(u), (p - poly[0]).dot(w));
    lo = lo.cwiseMin(p2.back());
    hi = hi.cwiseMax(p2.back());
  }
  const int nu = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / spacing)));
  const int nw = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / spacing)));
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nw; ++j) {
      const Vector2d q(lo.x() + (i + 0.5) * (hi.x() - lo.x()) / nu,
                       lo.y() + (j + 0.5) * (hi.y() - lo.y()) / nw);
      if (PointInPolygon(q, p2)) out.push_back(poly[0] + q.x() * u + q.y() * w);
    }
  if (out.size() < 3) return poly;
  return out;
}

// Least-squares plane through points: (unit normal oriented like `towards`, centroid).
std::pair<Vector3d, Vector3d> FitPlane(const std::vector<Vector3d>& pts, const Vector3d& towards) {
  Vector3d c = Vector3d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Vector3d n = es.eigenvectors().col(0);
  if (n.dot(towards) < 0.0) n = -n;
  return {n, c};
}

double AngleDeg(const Vector3d& a, const Vector3d& b) {
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

}  // namespace

AsBuiltField::AsBuiltField(const AsBuiltParams& params) {
  CounterRng rng(params.seed, "scenes/as_built");
  // Every draw is taken whatever the sigmas, so one factor's value does not move another's.
  const double a_sigma = 1e-3 * params.flatness_mm * std::sqrt(2.0 / kFlatTerms);
  for (int k = 0; k < kFlatTerms; ++k) {
    Term t;
    const double lambda = params.wavelength * rng.Uniform(1.0, 3.0);
    t.omega = UnitVector(rng) * (2.0 * kPi / lambda);
    t.phase = rng.Uniform(0.0, 2.0 * kPi);
    t.amplitude = Vector3d(rng.Normal(), rng.Normal(), rng.Normal()) * a_sigma;
    flat_.push_back(t);
  }
  const double g_sigma = std::tan(DegToRad(params.lean_sigma_deg)) * std::sqrt(2.0 / kLeanTerms);
  for (int j = 0; j < kLeanTerms; ++j) {
    Term t;
    const double lambda = params.wavelength * rng.Uniform(2.0, 6.0);
    const double a = rng.Uniform(0.0, 2.0 * kPi);
    t.omega = Vector3d(std::cos(a), std::sin(a), 0.0) * (2.0 * kPi / lambda);
    t.phase = rng.Uniform(0.0, 2.0 * kPi);
    t.amplitude = Vector3d(rng.Normal(), rng.Normal(), 0.0) * g_sigma;
    lean_.push_back(t);
  }
}

Vector3d AsBuiltField::Displacement(const Vector3d& p) const {
  Vector3d d = Vector3d::Zero();
  for (const Term& t : flat_) d += t.amplitude * std::sin(t.omega.dot(p) + t.phase);
  Vector3d slope = Vector3d::Zero();
  for (const Term& t : lean_) slope += t.amplitude * std::sin(t.omega.dot(p) + t.phase);
  return d + p.z() * slope;
}

void ApplyAsBuilt(const AsBuiltParams& params, Scene* scene) {
  if (!params.Enabled()) return;
  const AsBuiltField field(params);
  for (MeshPart& part : scene->parts) {
    const bool has_uv = part.uvs.size() == part.positions.size() && !part.uvs.empty();
    std::vector<Eigen::Vector3f> pos = part.positions;
    std::vector<Eigen::Vector2f> uvs = part.uvs;
    std::vector<Eigen::Vector3i> tris;
    tris.reserve(part.triangles.size());
    // Conforming refinement: a triangle bisects its longest edge until no edge is longer than
    // the spacing, and where an edge is split depends on that edge alone (its end vertices):
    // ceil(n/2) of n = ceil(length / spacing) equal pieces from its lower-index end. Two
    // triangles that share an edge split it at the same points, whatever their sizes, so the
    // moved surface has no cracks along it (a split shared by only one side would open by the
    // field's departure from linear over the edge).
    const float spacing2 = static_cast<float>(params.mesh_spacing * params.mesh_spacing);
    std::map<std::pair<int, int>, int> split_at;
    auto length2 = [&](int p, int q) {
      return (pos[std::max(p, q)] - pos[std::min(p, q)]).squaredNorm();
    };
    auto split = [&](int p, int q) {
      const int lo = std::min(p, q), hi = std::max(p, q);
      const auto it = split_at.find({lo, hi});
      if (it != split_at.end()) return it->second;
      const Eigen::Vector3f a = pos[lo], b = pos[hi];
      const int n = std::max(
          2, static_cast<int>(std::ceil((b - a).norm() / static_cast<float>(params.mesh_spacing))));
      const float f = static_cast<float>(n - n / 2) / static_cast<float>(n);
      pos.push_back(a + (b - a) * f);
      if (has_uv) {
        const Eigen::Vector2f ua = uvs[lo], ub = uvs[hi];
        uvs.push_back(ua + (ub - ua) * f);
      }
      const int id = static_cast<int>(pos.size()) - 1;
      split_at.emplace(std::make_pair(lo, hi), id);
      return id;
    };
    std::vector<Eigen::Vector3i> todo;
    for (const Eigen::Vector3i& t : part.triangles) {
      todo.push_back(t);
      while (!todo.empty()) {
        const Eigen::Vector3i tri = todo.back();
        todo.pop_back();
        int k = 0;  // the longest edge is (tri[k], tri[k + 1])
        float longest = -1.0f;
        for (int e = 0; e < 3; ++e) {
          const float l2 = length2(tri[e], tri[(e + 1) % 3]);
          if (l2 > longest) longest = l2, k = e;
        }
        if (longest <= spacing2) {
          tris.push_back(tri);
          continue;
        }
        const int v0 = tri[k], v1 = tri[(k + 1) % 3], v2 = tri[(k + 2) % 3];
        const int m = split(v0, v1);
        todo.emplace_back(m, v1, v2);
        todo.emplace_back(v0, m, v2);
      }
    }
    for (Eigen::Vector3f& p : pos) p = field.Moved(p.cast<double>()).cast<float>();
    part.positions = std::move(pos);
    if (has_uv) part.uvs = std::move(uvs);
    part.triangles = std::move(tris);
  }
}

SurfaceDeviation MeasureDeviation(const StructuralElement& e, const AsBuiltField& field) {
  SurfaceDeviation d;
  std::vector<Vector3d> moved;
  double sum2 = 0.0;
  std::size_t count = 0;
  for (const auto& poly : e.polygons)
    for (const Vector3d& p : SurfaceSamples(poly, kSampleSpacing)) {
      const double dn = 1e3 * field.Displacement(p).dot(e.normal);
      sum2 += dn * dn;
      d.max_mm = std::max(d.max_mm, std::abs(dn));
      ++count;
      moved.push_back(field.Moved(p));
    }
  if (count == 0) return d;
  d.rms_mm = std::sqrt(sum2 / static_cast<double>(count));
  if (e.polygons.size() == 1) d.tilt_deg = AngleDeg(e.normal, FitPlane(moved, e.normal).first);
  return d;
}

GroundTruth AsBuiltTruth(const GroundTruth& design, const AsBuiltParams& params) {
  if (!params.Enabled()) return design;
  const AsBuiltField field(params);
  GroundTruth t = design;
  for (StructuralElement& e : t.elements) {
    for (auto& poly : e.polygons) {
      std::vector<Vector3d> moved;
      for (const Vector3d& p : SurfaceSamples(poly, kSampleSpacing))
        moved.push_back(field.Moved(p));
      const auto [n, c] = FitPlane(moved, NewellVector(poly));
      for (Vector3d& p : poly) {
        p = field.Moved(p);
        p -= (p - c).dot(n) * n;
      }
      if (e.polygons.size() == 1) e.normal = e.normal.dot(n) < 0.0 ? Vector3d(-n) : n;
    }
    if (e.element_class == ElementClass::kWall && e.polygons.size() == 1 &&
        e.polygons[0].size() == 4) {
      // The design polygon runs (0,0), (0,h), (L,h), (L,0) in the wall's (u, v).
      const auto& q = e.polygons[0];
      e.origin = q[0];
      e.u_axis = (q[3] - q[0]).normalized();
      e.length = (q[3] - q[0]).norm();
      e.height = (q[1] - q[0]).norm();
    }
  }
  for (Opening& o : t.openings) {
    for (Vector3d& p : o.corners) p = field.Moved(p);
    o.hinge_point = field.Moved(o.hinge_point);
  }
  for (ServiceComponent& s : t.service_components) s.centre = field.Moved(s.centre);
  for (FurnitureItem& f : t.furniture) f.centre = field.Moved(f.centre);
  for (FurnitureItem& f : t.details) f.centre = field.Moved(f.centre);
  return t;
}

}  // namespace mopad::scenes
