#include "evaluation/observability.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>

#include "common/error.h"
#include "common/frames.h"
#include "common/polygon.h"
#include "scenes/geometry.h"

namespace mopad::evaluation {
namespace {

using Poly2 = std::vector<Eigen::Vector2d>;

// Clips a 3D convex polygon to sign * (z - c) <= 0.
std::vector<Eigen::Vector3d> ClipZ(const std::vector<Eigen::Vector3d>& in, double c, double sign) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t k = 0; k < in.size(); ++k) {
    const Eigen::Vector3d& a = in[k];
    const Eigen::Vector3d& b = in[(k + 1) % in.size()];
    const double da = sign * (a.z() - c), db = sign * (b.z() - c);
    if (da <= 0) out.push_back(a);
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// 1D squared Euclidean distance transform (Felzenszwalb & Huttenlocher 2012).
void Edt1d(const double* f, int n, double* d, int* v, double* z) {
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  const auto S = [&](int q, int p) {
    return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
  };
  for (int q = 1; q < n; ++q) {
    double s = S(q, v[k]);
    while (s <= z[k]) {
      --k;
      s = S(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    d[q] = (double(q) - v[k]) * (double(q) - v[k]) + f[v[k]];
  }
}

}  // namespace

ReachableArea ComputeReachable(const scenes::Scene& scene, const scenes::GroundTruth& truth,
                               const std::string& room, const ObservabilityParams& params) {
  ValidateParams(params, "observability.");
  if (params.body_z_max <= params.body_z_min) {
    throw InputError("", "observability.body_z_max must exceed body_z_min",
                     std::to_string(params.body_z_max), "> " + std::to_string(params.body_z_min));
  }
  const scenes::Room* r = truth.FindRoom(room);
  if (!r)
    throw InputError(scene.source, "unknown room", "'" + room + "'", "a room of the ground truth");
  const double res = params.raster_resolution;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Eigen::Vector2d& p : r->polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double margin = params.robot_radius + 2 * res;
  lo -= Eigen::Vector2d::Constant(margin);
  hi += Eigen::Vector2d::Constant(margin);
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / res));
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / res));
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  std::vector<std::uint8_t> occupied(n, 0);
  const double zlo = r->floor_z + params.body_z_min, zhi = r->floor_z + params.body_z_max;
  const double reach = res * std::sqrt(0.5) + 1e-9;  // conservative: centre within half a diagonal
  const auto centre = [&](int i, int j) {
    return Eigen::Vector2d(lo.x() + (i + 0.5) * res, lo.y() + (j + 0.5) * res);
  };

  // Rasterise the band's triangles.
  for (const scenes::MeshPart& part : scene.parts) {
    for (const Eigen::Vector3i& t : part.triangles) {
      std::vector<Eigen::Vector3d> poly = {part.positions[t[0]].cast<double>(),
                                           part.positions[t[1]].cast<double>(),
                                           part.positions[t[2]].cast<double>()};
      Eigen::Vector3d blo = poly[0].cwiseMin(poly[1]).cwiseMin(poly[2]);
      Eigen::Vector3d bhi = poly[0].cwiseMax(poly[1]).cwiseMax(poly[2]);
      if (bhi.z() < zlo || blo.z() > zhi || bhi.x() < lo.x() || blo.x() > hi.x() ||
          bhi.y() < lo.y() || blo.y() > hi.y()) {
        continue;
      }
      poly = ClipZ(ClipZ(poly, zlo, -1.0), zhi, 1.0);
      if (poly.empty()) continue;
      Poly2 p2;
      Eigen::Vector2d plo(1e300, 1e300), phi(-1e300, -1e300);
      for (const Eigen::Vector3d& q : poly) {
        p2.emplace_back(q.x(), q.y());
        plo = plo.cwiseMin(p2.back());
        phi = phi.cwiseMax(p2.back());
      }
      double area2 = 0;
      for (std::size_t k = 0; k < p2.size(); ++k) {
        const Eigen::Vector2d& a = p2[k];
        const Eigen::Vector2d& b = p2[(k + 1) % p2.size()];
        area2 += a.x() * b.y() - b.x() * a.y();
      }
      const double orient = area2 > 0 ? 1.0 : -1.0;
      const bool flat = std::abs(area2) < 1e-12;
      const int ia = std::max(0, static_cast<int>(std::floor((plo.x() - reach - lo.x()) / res)));
      const int ib =
          std::min(nx - 1, static_cast<int>(std::floor((phi.x() + reach - lo.x()) / res)));
      const int ja = std::max(0, static_cast<int>(std::floor((plo.y() - reach - lo.y()) / res)));
      const int jb =
          std::min(ny - 1, static_cast<int>(std::floor((phi.y() + reach - lo.y()) / res)));
      for (int j = ja; j <= jb; ++j) {
        for (int i = ia; i <= ib; ++i) {
          const std::size_t k = static_cast<std::size_t>(j) * nx + i;
          if (occupied[k]) continue;
          const Eigen::Vector2d c = centre(i, j);
          bool hit = false;
          if (!flat) {
            hit = true;
            for (std::size_t e = 0; e < p2.size() && hit; ++e) {
              const Eigen::Vector2d ed = p2[(e + 1) % p2.size()] - p2[e];
              const Eigen::Vector2d w = c - p2[e];
              if (orient * (ed.x() * w.y() - ed.y() * w.x()) < 0) hit = false;
            }
          }
          for (std::size_t e = 0; e < p2.size() && !hit; ++e) {
            if (SquaredDistanceToSegment(c, p2[e], p2[(e + 1) % p2.size()]) <= reach * reach)
              hit = true;
          }
          if (hit) occupied[k] = 1;
        }
      }
    }
  }

  // Squared distance (cells^2) from every cell centre to the nearest occupied centre.
  const double inf = 1e12;  // finite: keeps the parabola algebra exact enough
  std::vector<double> dist(n);
  for (std::size_t k = 0; k < n; ++k) dist[k] = occupied[k] ? 0.0 : inf;
  {
    const int m = std::max(nx, ny);
    std::vector<double> f(m), d(m), z(m + 1);
    std::vector<int> v(m);
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) f[j] = dist[static_cast<std::size_t>(j) * nx + i];
      Edt1d(f.data(), ny, d.data(), v.data(), z.data());
      for (int j = 0; j < ny; ++j) dist[static_cast<std::size_t>(j) * nx + i] = d[j];
    }
    for (int j = 0; j < ny; ++j) {
      double* row = &dist[static_cast<std::size_t>(j) * nx];
      std::copy(row, row + nx, f.begin());
      Edt1d(f.data(), nx, d.data(), v.data(), z.data());
      std::copy(d.begin(), d.begin() + nx, row);
    }
  }
  const double r2 = (params.robot_radius / res) * (params.robot_radius / res);
  std::vector<std::uint8_t> free(n, 0);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * nx + i;
      free[k] = dist[k] > r2 && scenes::PointInPolygon(centre(i, j), r->polygon);
    }

  // Largest 8-connected free region (first in scan order on ties).
  std::vector<std::int32_t> label(n, -1);
  std::int32_t best = -1;
  std::size_t best_size = 0;
  std::int32_t next = 0;
  std::vector<std::size_t> stack;
  for (std::size_t k0 = 0; k0 < n; ++k0) {
    if (!free[k0] || label[k0] >= 0) continue;
    std::size_t size = 0;
    label[k0] = next;
    stack.assign(1, k0);
    while (!stack.empty()) {
      const std::size_t k = stack.back();
      stack.pop_back();
      ++size;
      const int i = static_cast<int>(k % nx), j = static_cast<int>(k / nx);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int a = i + di, b = j + dj;
          if (a < 0 || b < 0 || a >= nx || b >= ny) continue;
          const std::size_t q = static_cast<std::size_t>(b) * nx + a;
          if (free[q] && label[q] < 0) {
            label[q] = next;
            stack.push_back(q);
          }
        }
    }
    if (size > best_size) {
      best_size = size;
      best = next;
    }
    ++next;
  }

  ReachableArea out;
  out.free_area = static_cast<double>(best_size) * res * res;
  if (best < 0) return out;
  const double step = params.grid_step;
  const long ja = static_cast<long>(std::ceil(lo.y() / step)),
             jb = static_cast<long>(std::floor(hi.y() / step));
  const long ia = static_cast<long>(std::ceil(lo.x() / step)),
             ib = static_cast<long>(std::floor(hi.x() / step));
  for (long j = ja; j <= jb; ++j)
    for (long i = ia; i <= ib; ++i) {
      const Eigen::Vector2d p(i * step, j * step);
      const int ci = static_cast<int>(std::floor((p.x() - lo.x()) / res));
      const int cj = static_cast<int>(std::floor((p.y() - lo.y()) / res));
      if (ci < 0 || cj < 0 || ci >= nx || cj >= ny) continue;
      if (label[static_cast<std::size_t>(cj) * nx + ci] == best) out.positions.push_back(p);
    }
  return out;
}

Observability ComputeObservability(const sim::EmbreeWorld& world,
                                   const StructuralSurfaces& surfaces,
                                   const ReachableArea& reachable,
                                   const ObservabilityParams& params) {
  ValidateParams(params, "observability.");
  Observability out;
  const std::size_t nc = surfaces.cells.size();
  out.observable.assign(nc, 0);
  out.total_area = surfaces.TotalArea();
  out.positions = reachable.positions.size();
  if (reachable.positions.empty() || nc == 0) return out;

  // Scene part -> surface element (or -1).
  const scenes::Scene& scene = world.scene();
  std::map<std::string, int> element_of;
  for (std::size_t e = 0; e < surfaces.elements.size(); ++e)
    element_of[surfaces.elements[e].id] = static_cast<int>(e);
  std::vector<int> part_element(scene.parts.size(), -1);
  for (std::size_t p = 0; p < scene.parts.size(); ++p) {
    if (!scenes::IsStructural(scene.parts[p].element_class)) continue;
    const auto it = element_of.find(scene.parts[p].element_id);
    if (it != element_of.end()) part_element[p] = it->second;
  }

  // Spread-out order of positions: start near the centroid, then farthest point first, so that
  // the first few positions see most cells and the early exit prunes the rest.
  const std::vector<Eigen::Vector2d>& pos = reachable.positions;
  const std::size_t np = pos.size();
  std::vector<std::size_t> order;
  order.reserve(np);
  {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : pos) mean += p;
    mean /= static_cast<double>(np);
    std::size_t first = 0;
    for (std::size_t k = 1; k < np; ++k)
      if ((pos[k] - mean).squaredNorm() < (pos[first] - mean).squaredNorm()) first = k;
    std::vector<double> d2(np, std::numeric_limits<double>::infinity());
    std::vector<std::uint8_t> used(np, 0);
    std::size_t cur = first;
    for (std::size_t it = 0; it < np; ++it) {
      order.push_back(cur);
      used[cur] = 1;
      std::size_t far = np;
      for (std::size_t k = 0; k < np; ++k) {
        if (used[k]) continue;
        d2[k] = std::min(d2[k], (pos[k] - pos[cur]).squaredNorm());
        if (far == np || d2[k] > d2[far]) far = k;
      }
      cur = far;
    }
  }

  const double sin_max = std::sin(DegToRad(params.elevation_max_deg));
  const double sin_min = std::sin(DegToRad(params.elevation_min_deg));
  const double z_scan = surfaces.floor_z + params.mast_height;
  std::vector<std::int32_t> unseen(nc);
  for (std::size_t k = 0; k < nc; ++k) unseen[k] = static_cast<std::int32_t>(k);
  constexpr std::size_t kChunk = 1024;
  std::size_t next = 0;
  int round = 0;
  while (next < np && !unseen.empty()) {
    const std::size_t batch =
        std::min<std::size_t>({np - next, std::size_t{1} << std::min(round, 4)});
    ++round;
    const std::size_t chunks = (unseen.size() + kChunk - 1) / kChunk;
    const std::size_t tasks = batch * chunks;
    std::vector<std::vector<std::int32_t>> seen(tasks);
    std::vector<std::uint64_t> rays(tasks, 0);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, tasks, 1),
        [&](const tbb::blocked_range<std::size_t>& rr) {
          std::vector<Eigen::Vector3f> origins, dirs;
          std::vector<sim::RayHit> hits;
          std::vector<std::int32_t> ids;
          std::vector<float> lens;
          for (std::size_t task = rr.begin(); task != rr.end(); ++task) {
            const std::size_t b = task / chunks, ch = task % chunks;
            const Eigen::Vector2d& p = pos[order[next + b]];
            const Eigen::Vector3d c(p.x(), p.y(), z_scan);
            origins.clear();
            dirs.clear();
            ids.clear();
            lens.clear();
            const std::size_t k1 = std::min(unseen.size(), (ch + 1) * kChunk);
            for (std::size_t k = ch * kChunk; k < k1; ++k) {
              const SurfaceCell& cell = surfaces.cells[unseen[k]];
              const Eigen::Vector3d d = cell.centre - c;
              if (cell.normal.dot(d) >= 0) continue;  // back side
              const double L = d.norm();
              if (L < params.range_min || L > params.range_max) continue;
              const double s = d.z() / L;
              if (s > sin_max || s < sin_min) continue;
              origins.push_back(c.cast<float>());
              dirs.push_back((d / L).cast<float>());
              ids.push_back(unseen[k]);
              lens.push_back(static_cast<float>(L));
            }
            hits.resize(ids.size());
            world.IntersectMany(origins, dirs, 0.0f, std::numeric_limits<float>::infinity(), hits);
            rays[task] = ids.size();
            for (std::size_t q = 0; q < ids.size(); ++q) {
              const sim::RayHit& h = hits[q];
              if (!h.hit() || part_element[h.part] != surfaces.cells[ids[q]].element) continue;
              if (h.t < lens[q] - params.hit_tolerance || h.t > lens[q] + params.hit_tolerance)
                continue;
              seen[task].push_back(ids[q]);
            }
          }
        });
    for (std::size_t t = 0; t < tasks; ++t) {
      out.rays += rays[t];
      for (std::int32_t id : seen[t]) out.observable[id] = 1;
    }
    std::vector<std::int32_t> rest;
    rest.reserve(unseen.size());
    for (std::int32_t id : unseen)
      if (!out.observable[id]) rest.push_back(id);
    unseen.swap(rest);
    next += batch;
  }
  for (std::size_t k = 0; k < nc; ++k)
    if (out.observable[k]) out.observable_area += surfaces.cells[k].area;
  return out;
}

}  // namespace mopad::evaluation
