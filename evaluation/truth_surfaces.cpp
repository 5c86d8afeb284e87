#include "evaluation/truth_surfaces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "common/error.h"
#include "scenes/as_built.h"

namespace mopad::evaluation {
namespace {

using Poly2 = std::vector<Eigen::Vector2d>;

// Sutherland-Hodgman clip of a convex polygon against the half-plane sign * (p[axis] - c) <= 0.
Poly2 ClipHalf(const Poly2& in, int axis, double c, double sign) {
  Poly2 out;
  if (in.empty()) return out;
  out.reserve(in.size() + 2);
  for (std::size_t k = 0; k < in.size(); ++k) {
    const Eigen::Vector2d& a = in[k];
    const Eigen::Vector2d& b = in[(k + 1) % in.size()];
    const double da = sign * (a[axis] - c), db = sign * (b[axis] - c);
    if (da <= 0) out.push_back(a);
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// Area and first moment (area * centroid) of a simple polygon (CCW or CW; absolute area).
void AreaMoment(const Poly2& p, double* area, Eigen::Vector2d* moment) {
  double a = 0;
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Eigen::Vector2d& q0 = p[k];
    const Eigen::Vector2d& q1 = p[(k + 1) % p.size()];
    const double cr = q0.x() * q1.y() - q1.x() * q0.y();
    a += cr;
    m += (q0 + q1) * cr;
  }
  a *= 0.5;
  m /= 6.0;
  if (a < 0) {
    a = -a;
    m = -m;
  }
  *area = a;
  *moment = m;
}

bool InsideConvex(const Poly2& p, const Eigen::Vector2d& x) {
  int sign = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Eigen::Vector2d e = p[(k + 1) % p.size()] - p[k];
    const Eigen::Vector2d w = x - p[k];
    const double cr = e.x() * w.y() - e.y() * w.x();
    if (std::abs(cr) < 1e-15) continue;
    const int s = cr > 0 ? 1 : -1;
    if (sign == 0)
      sign = s;
    else if (s != sign)
      return false;
  }
  return true;
}

struct PlaneBuild {
  SurfacePlane plane;
  std::vector<std::array<Eigen::Vector2d, 3>> triangles;  // plane coordinates
};

// The plane build of `element` that the plane n . p = d (n unit) lies on (normals within about
// 0.8 deg, offsets within 1 mm), added with its (u, v) axes when there is none yet.
PlaneBuild& PlaneOf(std::vector<PlaneBuild>& builds, int element, const Eigen::Vector3d& n,
                    double d) {
  for (PlaneBuild& q : builds) {
    if (q.plane.element == element && q.plane.normal.dot(n) > 1.0 - 1e-4 &&
        std::abs(q.plane.offset - d) < 1e-3) {
      return q;
    }
  }
  PlaneBuild q;
  q.plane.element = element;
  q.plane.normal = n;
  q.plane.offset = d;
  if (std::abs(n.z()) > 0.9) {
    q.plane.u_axis = Eigen::Vector3d::UnitX();
  } else {
    q.plane.u_axis = Eigen::Vector3d::UnitZ().cross(n).normalized();
  }
  q.plane.u_axis = (q.plane.u_axis - n * n.dot(q.plane.u_axis)).normalized();
  q.plane.v_axis = n.cross(q.plane.u_axis);
  builds.push_back(std::move(q));
  return builds.back();
}

// The front-facing triangles of the room's structural elements (element_of: element id ->
// index into `elements`), grouped by element and plane, in plane coordinates; adds each
// triangle's area to its element.
// The design position of as-built point p: the q with q + D(q) = p, by fixed-point iteration
// (D's slope is ~1e-2, so three steps leave nanometres). `field` null: p.
Eigen::Vector3d DesignPoint(const scenes::AsBuiltField* field, const Eigen::Vector3d& p) {
  if (!field) return p;
  Eigen::Vector3d q = p;
  for (int k = 0; k < 3; ++k) q = p - field->Displacement(q);
  return q;
}

std::vector<PlaneBuild> GroupByPlane(const scenes::Scene& scene,
                                     const std::map<std::string, int>& element_of,
                                     std::vector<SurfaceElement>& elements,
                                     const scenes::AsBuiltField* field) {
  std::vector<PlaneBuild> builds;
  for (const scenes::MeshPart& part : scene.parts) {
    const auto it = element_of.find(part.element_id);
    if (it == element_of.end() || !scenes::IsStructural(part.element_class)) continue;
    const int element = it->second;
    for (const Eigen::Vector3i& t : part.triangles) {
      const Eigen::Vector3d a = DesignPoint(field, part.positions[t[0]].cast<double>());
      const Eigen::Vector3d b = DesignPoint(field, part.positions[t[1]].cast<double>());
      const Eigen::Vector3d c = DesignPoint(field, part.positions[t[2]].cast<double>());
      const Eigen::Vector3d cr = (b - a).cross(c - a);
      const double area2 = cr.norm();
      if (area2 < 1e-12) continue;
      elements[element].area += 0.5 * area2;
      const Eigen::Vector3d n = cr / area2;
      PlaneBuild& pb = PlaneOf(builds, element, n, n.dot(a));
      const auto P = [&](const Eigen::Vector3d& x) {
        return Eigen::Vector2d(pb.plane.u_axis.dot(x), pb.plane.v_axis.dot(x));
      };
      pb.triangles.push_back({P(a), P(b), P(c)});
    }
  }
  return builds;
}

// What a plane's triangles cover of each square of its grid: area and first moment per square
// (row-major, ni x nj), and the pieces of the squares they cover only in part (square index,
// clipped polygon), by square.
struct Coverage {
  std::vector<double> area;
  std::vector<Eigen::Vector2d> moment;
  std::vector<std::pair<std::size_t, Poly2>> pieces;
};

// Sets the plane's grid window (i0, j0, ni, nj) to its triangles' bounding box and clips every
// triangle into the squares of side s.
Coverage CoverGrid(const std::vector<std::array<Eigen::Vector2d, 3>>& triangles, double s,
                   SurfacePlane& pl) {
  const double full = s * s;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& t : triangles)
    for (const auto& q : t) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  pl.i0 = static_cast<int>(std::floor(lo.x() / s));
  pl.j0 = static_cast<int>(std::floor(lo.y() / s));
  pl.ni = static_cast<int>(std::floor(hi.x() / s)) - pl.i0 + 1;
  pl.nj = static_cast<int>(std::floor(hi.y() / s)) - pl.j0 + 1;
  const std::size_t n = static_cast<std::size_t>(pl.ni) * pl.nj;
  Coverage cov;
  cov.area.assign(n, 0.0);
  cov.moment.assign(n, Eigen::Vector2d::Zero());
  for (const auto& t : triangles) {
    Eigen::Vector2d tlo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
    Eigen::Vector2d thi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    const int ia = std::max(0, static_cast<int>(std::floor(tlo.x() / s)) - pl.i0);
    const int ib = std::min(pl.ni - 1, static_cast<int>(std::floor(thi.x() / s)) - pl.i0);
    const int ja = std::max(0, static_cast<int>(std::floor(tlo.y() / s)) - pl.j0);
    const int jb = std::min(pl.nj - 1, static_cast<int>(std::floor(thi.y() / s)) - pl.j0);
    const Poly2 tri(t.begin(), t.end());
    for (int j = ja; j <= jb; ++j) {
      const double v0 = (pl.j0 + j) * s, v1 = v0 + s;
      Poly2 strip = ClipHalf(ClipHalf(tri, 1, v0, -1.0), 1, v1, 1.0);
      if (strip.size() < 3) continue;
      for (int i = ia; i <= ib; ++i) {
        const double u0 = (pl.i0 + i) * s, u1 = u0 + s;
        const Poly2 piece = ClipHalf(ClipHalf(strip, 0, u0, -1.0), 0, u1, 1.0);
        if (piece.size() < 3) continue;
        double a;
        Eigen::Vector2d m;
        AreaMoment(piece, &a, &m);
        if (a <= 1e-14) continue;
        const std::size_t k = static_cast<std::size_t>(j) * pl.ni + i;
        cov.area[k] += a;
        cov.moment[k] += m;
        if (a < full * (1 - 1e-9)) cov.pieces.emplace_back(k, piece);
      }
    }
  }
  std::stable_sort(cov.pieces.begin(), cov.pieces.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  return cov;
}

// The centre of a partly covered square: the area centroid `c` of what covers it when that lies
// on one of its pieces, else the centroid of its largest piece (an opening or room edge can
// leave the centroid of an L-shaped or split cover off the surface). `pieces` are the square's.
Eigen::Vector2d CentreOnSurface(const Eigen::Vector2d& c,
                                const std::vector<std::pair<std::size_t, Poly2>>& pieces,
                                std::size_t first, std::size_t k) {
  bool inside = false;
  double best_a = -1;
  Eigen::Vector2d best_c = c;
  for (std::size_t q = first; q < pieces.size() && pieces[q].first == k; ++q) {
    if (InsideConvex(pieces[q].second, c)) inside = true;
    double a;
    Eigen::Vector2d m;
    AreaMoment(pieces[q].second, &a, &m);
    if (a > best_a) {
      best_a = a;
      best_c = m / a;
    }
  }
  return inside ? c : best_c;
}

// Cuts one plane's triangles into cells of side s (appended to out.cells, indexed in the
// plane's grid) and appends the plane to out.planes.
void CutIntoCells(PlaneBuild& pb, double s, StructuralSurfaces& out) {
  SurfacePlane& pl = pb.plane;
  const double full = s * s;
  const Coverage cov = CoverGrid(pb.triangles, s, pl);
  const std::size_t n = cov.area.size();
  pl.index.assign(n, -1);
  const int plane_index = static_cast<int>(out.planes.size());
  std::size_t pi = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (pi < cov.pieces.size() && cov.pieces[pi].first < k) ++pi;
    if (cov.area[k] < full * 1e-4) continue;  // float slivers along hole edges
    Eigen::Vector2d c = cov.moment[k] / cov.area[k];
    if (cov.area[k] < full * (1 - 1e-9)) c = CentreOnSurface(c, cov.pieces, pi, k);
    SurfaceCell cell;
    cell.centre = pl.u_axis * c.x() + pl.v_axis * c.y() + pl.normal * pl.offset;
    cell.normal = pl.normal;
    cell.area = cov.area[k];
    cell.element = pl.element;
    cell.plane = plane_index;
    cell.element_class = out.elements[pl.element].element_class;
    pl.index[k] = static_cast<std::int32_t>(out.cells.size());
    out.cells.push_back(cell);
  }
  out.planes.push_back(std::move(pl));
}

}  // namespace

double StructuralSurfaces::TotalArea() const {
  double a = 0;
  for (const SurfaceCell& c : cells) a += c.area;
  return a;
}

std::int32_t StructuralSurfaces::FindCell(const Eigen::Vector3d& p, double tolerance) const {
  std::int32_t best = -1;
  double best_d = tolerance;
  for (const SurfacePlane& pl : planes) {
    const double d = std::abs(pl.normal.dot(p) - pl.offset);
    if (d > best_d || (best >= 0 && d == best_d)) continue;
    const long i = static_cast<long>(std::floor(pl.u_axis.dot(p) / cell_size)) - pl.i0;
    const long j = static_cast<long>(std::floor(pl.v_axis.dot(p) / cell_size)) - pl.j0;
    if (i < 0 || j < 0 || i >= pl.ni || j >= pl.nj) continue;
    const std::int32_t c = pl.index[static_cast<std::size_t>(j) * pl.ni + i];
    if (c < 0) continue;
    best = c;
    best_d = d;
  }
  return best;
}

StructuralSurfaces SampleStructuralSurfaces(const scenes::Scene& scene,
                                            const scenes::GroundTruth& truth,
                                            const std::string& room,
                                            const SurfaceSamplingParams& params) {
  ValidateParams(params, "surface_sampling.");
  const scenes::Room* r = truth.FindRoom(room);
  if (!r)
    throw InputError(scene.source, "unknown room", "'" + room + "'", "a room of the ground truth");
  StructuralSurfaces out;
  out.room = room;
  out.cell_size = params.cell_size;
  out.floor_z = r->floor_z;
  std::map<std::string, int> element_of;
  for (const scenes::StructuralElement& e : truth.elements) {
    if (!scenes::IsStructural(e.element_class)) continue;
    if (std::find(e.rooms.begin(), e.rooms.end(), room) == e.rooms.end()) continue;
    element_of[e.id] = static_cast<int>(out.elements.size());
    out.elements.push_back({e.id, e.element_class, 0.0});
  }
  std::optional<scenes::AsBuiltField> field;
  if (truth.as_built.Enabled()) field.emplace(truth.as_built);
  std::vector<PlaneBuild> builds =
      GroupByPlane(scene, element_of, out.elements, field ? &*field : nullptr);
  if (builds.empty()) {
    throw InputError(scene.source, "room has no structural geometry", "'" + room + "'",
                     "wall, floor, ceiling or column triangles of elements listing the room");
  }
  for (PlaneBuild& pb : builds) CutIntoCells(pb, params.cell_size, out);
  return out;
}

}  // namespace mopad::evaluation
