#include "scenes/as_built.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

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

namespace {

// Every vertex of the scene, found by position: the seams where two parts meet without sharing
// vertices (a wall's top edge and a ceiling's, two walls at a corner, a hole and its lining).
class VertexIndex {
 public:
  explicit VertexIndex(const Scene& scene) {
    for (const MeshPart& part : scene.parts)
      for (const Eigen::Vector3f& p : part.positions) {
        auto& cell = cells_[Key(p)];
        if (std::find(cell.begin(), cell.end(), p) == cell.end()) cell.push_back(p);
      }
  }
  /// A vertex strictly inside segment a-b (within kOnEdge of it), or nullopt.
  std::optional<Eigen::Vector3f> OnSegment(const Eigen::Vector3f& a,
                                           const Eigen::Vector3f& b) const {
    const Eigen::Vector3f d = b - a;
    const float len2 = d.squaredNorm();
    if (len2 <= 0.0f) return std::nullopt;
    const Eigen::Vector3f lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    const Eigen::Vector3i c0 = Cell(lo), c1 = Cell(hi);
    std::optional<Eigen::Vector3f> best;
    float best_t = 2.0f;
    const float margin = kOnEdge / std::sqrt(len2);
    for (int x = c0.x() - 1; x <= c1.x() + 1; ++x)
      for (int y = c0.y() - 1; y <= c1.y() + 1; ++y)
        for (int z = c0.z() - 1; z <= c1.z() + 1; ++z) {
          const auto it = cells_.find({x, y, z});
          if (it == cells_.end()) continue;
          for (const Eigen::Vector3f& p : it->second) {
            const float t = (p - a).dot(d) / len2;
            if (t <= margin || t >= 1.0f - margin) continue;
            if ((a + t * d - p).squaredNorm() > kOnEdge * kOnEdge) continue;
            // The first along the edge, so that splitting is the same from either end.
            if (t < best_t) best_t = t, best = p;
          }
        }
    return best;
  }

 private:
  static constexpr float kCell = 0.5f;     // m
  static constexpr float kOnEdge = 1e-5f;  // m, a vertex this close to an edge lies on it
  static Eigen::Vector3i Cell(const Eigen::Vector3f& p) {
    return {static_cast<int>(std::floor(p.x() / kCell)),
            static_cast<int>(std::floor(p.y() / kCell)),
            static_cast<int>(std::floor(p.z() / kCell))};
  }
  static std::tuple<int, int, int> Key(const Eigen::Vector3f& p) {
    const Eigen::Vector3i c = Cell(p);
    return {c.x(), c.y(), c.z()};
  }
  std::map<std::tuple<int, int, int>, std::vector<Eigen::Vector3f>> cells_;
};

// Whether p comes before q in a fixed order of positions (the end an edge is split from).
bool PositionBefore(const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
  return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
}

}  // namespace

void ApplyAsBuilt(const AsBuiltParams& params, Scene* scene) {
  if (!params.Enabled()) return;
  const AsBuiltField field(params);
  const VertexIndex seams(*scene);
  for (MeshPart& part : scene->parts) {
    const bool has_uv = part.uvs.size() == part.positions.size() && !part.uvs.empty();
    std::vector<Eigen::Vector3f> pos = part.positions;
    std::vector<Eigen::Vector2f> uvs = part.uvs;
    std::vector<Eigen::Vector3i> tris;
    tris.reserve(part.triangles.size());
    // Conforming refinement, within a part and across parts. First every edge is split where
    // a vertex of any part lies on it (a seam where two parts meet without shared vertices),
    // then a triangle bisects its longest edge until no edge is longer than the spacing, each
    // edge split at a point that depends on its end positions alone: ceil(n/2) of n =
    // ceil(length / spacing) equal pieces from the end that comes first in PositionBefore.
    // Two triangles, of one part or two, that meet along an edge thus split it at the same
    // points whatever their sizes, and the moved surfaces have no cracks along it (a split on
    // one side only would open by the field's departure from linear over the edge).
    const float spacing = static_cast<float>(params.mesh_spacing);
    // Split points already made, by edge (its end indices, lower first): at seam vertices (-1:
    // the edge has none) and at bisection points.
    std::map<std::pair<int, int>, int> seam_at, bisect_at;
    auto add_vertex = [&](int lo, int hi, const Eigen::Vector3f& p) {
      const Eigen::Vector3f a = pos[lo], b = pos[hi];
      pos.push_back(p);
      if (has_uv) {
        const float t = (p - a).dot(b - a) / (b - a).squaredNorm();
        const Eigen::Vector2f ua = uvs[lo], ub = uvs[hi];
        uvs.push_back(ua + (ub - ua) * t);
      }
      return static_cast<int>(pos.size()) - 1;
    };
    // Edge p-q's seam vertex (-1: none) and its bisection point.
    auto seam = [&](int p, int q) {
      const auto key = std::make_pair(std::min(p, q), std::max(p, q));
      const auto it = seam_at.find(key);
      if (it != seam_at.end()) return it->second;
      const auto on = seams.OnSegment(pos[p], pos[q]);
      const int id = on ? add_vertex(p, q, *on) : -1;
      seam_at.emplace(key, id);
      return id;
    };
    auto bisect = [&](int p, int q) {
      const auto key = std::make_pair(std::min(p, q), std::max(p, q));
      const auto it = bisect_at.find(key);
      if (it != bisect_at.end()) return it->second;
      const int lo = PositionBefore(pos[p], pos[q]) ? p : q, hi = lo == p ? q : p;
      const Eigen::Vector3f a = pos[lo], b = pos[hi];
      const int n = std::max(2, static_cast<int>(std::ceil((b - a).norm() / spacing)));
      const float f = static_cast<float>(n - n / 2) / static_cast<float>(n);
      const int id = add_vertex(lo, hi, a + (b - a) * f);
      bisect_at.emplace(key, id);
      return id;
    };
    std::vector<Eigen::Vector3i> todo;
    for (const Eigen::Vector3i& t : part.triangles) {
      todo.push_back(t);
      while (!todo.empty()) {
        const Eigen::Vector3i tri = todo.back();
        todo.pop_back();
        // A seam vertex on any edge first; else the longest edge if longer than the spacing.
        int k = -1, m = -1;
        for (int e = 0; e < 3 && m < 0; ++e) {
          m = seam(tri[e], tri[(e + 1) % 3]);
          if (m >= 0) k = e;
        }
        if (m < 0) {
          float longest = -1.0f;
          for (int e = 0; e < 3; ++e) {
            const float l2 = (pos[tri[(e + 1) % 3]] - pos[tri[e]]).squaredNorm();
            if (l2 > longest) longest = l2, k = e;
          }
          if (longest > spacing * spacing) m = bisect(tri[k], tri[(k + 1) % 3]);
        }
        if (m < 0) {
          tris.push_back(tri);
          continue;
        }
        const int v0 = tri[k], v1 = tri[(k + 1) % 3], v2 = tri[(k + 2) % 3];
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
