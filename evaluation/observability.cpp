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

// The plan raster of a room's collision test: nx x ny square cells of side `res`, cell (i, j)
// covering [lo.x + i res, lo.x + (i+1) res) x [lo.y + j res, ...), row-major (j, then i).
struct PlanRaster {
  Eigen::Vector2d lo, hi;  // m, the room's plan box grown by the robot radius and 2 cells
  double res = 0.0;        // m
  int nx = 0, ny = 0;
  std::size_t Size() const { return static_cast<std::size_t>(nx) * ny; }
  std::size_t Index(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
  Eigen::Vector2d Centre(int i, int j) const {
    return Eigen::Vector2d(lo.x() + (i + 0.5) * res, lo.y() + (j + 0.5) * res);
  }
};

PlanRaster RasterOver(const Poly2& polygon, const ObservabilityParams& params) {
  PlanRaster r;
  r.res = params.raster_resolution;
  r.lo = Eigen::Vector2d(1e300, 1e300);
  r.hi = Eigen::Vector2d(-1e300, -1e300);
  for (const Eigen::Vector2d& p : polygon) {
    r.lo = r.lo.cwiseMin(p);
    r.hi = r.hi.cwiseMax(p);
  }
  const double margin = params.robot_radius + 2 * r.res;
  r.lo -= Eigen::Vector2d::Constant(margin);
  r.hi += Eigen::Vector2d::Constant(margin);
  r.nx = static_cast<int>(std::ceil((r.hi.x() - r.lo.x()) / r.res));
  r.ny = static_cast<int>(std::ceil((r.hi.y() - r.lo.y()) / r.res));
  return r;
}

// Whether the plan polygon `p2` (a triangle clipped to the body band, seen from above) covers
// the point `c` or passes within `reach` of it. `orient` is the sign of its winding; a `flat`
// polygon (a vertical face) only counts by distance.
bool Touches(const Poly2& p2, double orient, bool flat, const Eigen::Vector2d& c, double reach) {
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
    if (SquaredDistanceToSegment(c, p2[e], p2[(e + 1) % p2.size()]) <= reach * reach) hit = true;
  }
  return hit;
}

// Marks the raster cells whose centre the clipped triangle `poly` touches (Touches).
void MarkPolygon(const std::vector<Eigen::Vector3d>& poly, const PlanRaster& r, double reach,
                 std::vector<std::uint8_t>& occupied) {
  Poly2 p2;
  Eigen::Vector2d plo(1e300, 1e300), phi(-1e300, -1e300);
  for (const Eigen::Vector3d& q : poly) {
    p2.emplace_back(q.x(), q.y());
    plo = plo.cwiseMin(p2.back());
    phi = phi.cwiseMax(p2.back());
  }
  const double area2 = 2.0 * SignedArea(p2);
  const double orient = area2 > 0 ? 1.0 : -1.0;
  const bool flat = std::abs(area2) < 1e-12;
  const int ia = std::max(0, static_cast<int>(std::floor((plo.x() - reach - r.lo.x()) / r.res)));
  const int ib =
      std::min(r.nx - 1, static_cast<int>(std::floor((phi.x() + reach - r.lo.x()) / r.res)));
  const int ja = std::max(0, static_cast<int>(std::floor((plo.y() - reach - r.lo.y()) / r.res)));
  const int jb =
      std::min(r.ny - 1, static_cast<int>(std::floor((phi.y() + reach - r.lo.y()) / r.res)));
  for (int j = ja; j <= jb; ++j) {
    for (int i = ia; i <= ib; ++i) {
      const std::size_t k = r.Index(i, j);
      if (occupied[k]) continue;
      if (Touches(p2, orient, flat, r.Centre(i, j), reach)) occupied[k] = 1;
    }
  }
}

// The raster cells that scene geometry in the height band [zlo, zhi] occupies, conservatively:
// a cell is occupied when a triangle clipped to the band passes within half a cell diagonal of
// its centre.
std::vector<std::uint8_t> RasteriseBand(const scenes::Scene& scene, const PlanRaster& r, double zlo,
                                        double zhi) {
  std::vector<std::uint8_t> occupied(r.Size(), 0);
  const double reach = r.res * std::sqrt(0.5) + 1e-9;
  for (const scenes::MeshPart& part : scene.parts) {
    for (const Eigen::Vector3i& t : part.triangles) {
      std::vector<Eigen::Vector3d> poly = {part.positions[t[0]].cast<double>(),
                                           part.positions[t[1]].cast<double>(),
                                           part.positions[t[2]].cast<double>()};
      Eigen::Vector3d blo = poly[0].cwiseMin(poly[1]).cwiseMin(poly[2]);
      Eigen::Vector3d bhi = poly[0].cwiseMax(poly[1]).cwiseMax(poly[2]);
      if (bhi.z() < zlo || blo.z() > zhi || bhi.x() < r.lo.x() || blo.x() > r.hi.x() ||
          bhi.y() < r.lo.y() || blo.y() > r.hi.y()) {
        continue;
      }
      poly = ClipZ(ClipZ(poly, zlo, -1.0), zhi, 1.0);
      if (poly.empty()) continue;
      MarkPolygon(poly, r, reach, occupied);
    }
  }
  return occupied;
}

// Squared distance (cells^2) from every cell centre to the nearest occupied centre: the exact
// Euclidean distance transform, columns then rows.
std::vector<double> SquaredDistanceToOccupied(const std::vector<std::uint8_t>& occupied, int nx,
                                              int ny) {
  const double inf = 1e12;  // finite: keeps the parabola algebra exact enough
  std::vector<double> dist(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) dist[k] = occupied[k] ? 0.0 : inf;
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
  return dist;
}

// The 8-connected regions of the free cells: a label per cell (-1 not free), the largest
// region's label (-1 when none; the first in scan order on ties) and its size in cells.
struct FreeRegions {
  std::vector<std::int32_t> label;
  std::int32_t best = -1;
  std::size_t best_size = 0;
};

FreeRegions LabelFreeRegions(const std::vector<std::uint8_t>& free, int nx, int ny) {
  const std::size_t n = free.size();
  FreeRegions out;
  out.label.assign(n, -1);
  std::vector<std::int32_t>& label = out.label;
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
    if (size > out.best_size) {
      out.best_size = size;
      out.best = next;
    }
    ++next;
  }
  return out;
}

// The points of the `step` lattice (multiples of step in world x, y) whose raster cell is in
// the region labelled `region`, sorted by (y, x).
std::vector<Eigen::Vector2d> LatticeIn(const PlanRaster& r, const std::vector<std::int32_t>& label,
                                       std::int32_t region, double step) {
  std::vector<Eigen::Vector2d> out;
  const long ja = static_cast<long>(std::ceil(r.lo.y() / step)),
             jb = static_cast<long>(std::floor(r.hi.y() / step));
  const long ia = static_cast<long>(std::ceil(r.lo.x() / step)),
             ib = static_cast<long>(std::floor(r.hi.x() / step));
  for (long j = ja; j <= jb; ++j)
    for (long i = ia; i <= ib; ++i) {
      const Eigen::Vector2d p(i * step, j * step);
      const int ci = static_cast<int>(std::floor((p.x() - r.lo.x()) / r.res));
      const int cj = static_cast<int>(std::floor((p.y() - r.lo.y()) / r.res));
      if (ci < 0 || cj < 0 || ci >= r.nx || cj >= r.ny) continue;
      if (label[r.Index(ci, cj)] == region) out.push_back(p);
    }
  return out;
}

// Scene part -> index of its element in surfaces.elements, -1 for a part of no surface element.
std::vector<int> PartElements(const scenes::Scene& scene, const StructuralSurfaces& surfaces) {
  std::map<std::string, int> element_of;
  for (std::size_t e = 0; e < surfaces.elements.size(); ++e)
    element_of[surfaces.elements[e].id] = static_cast<int>(e);
  std::vector<int> part_element(scene.parts.size(), -1);
  for (std::size_t p = 0; p < scene.parts.size(); ++p) {
    if (!scenes::IsStructural(scene.parts[p].element_class)) continue;
    const auto it = element_of.find(scene.parts[p].element_id);
    if (it != element_of.end()) part_element[p] = it->second;
  }
  return part_element;
}

// A spread-out order of positions: the one nearest the centroid first, then each time the one
// farthest from those taken (farthest-point sampling), so that the first few positions see most
// cells and the early exit prunes the rest.
std::vector<std::size_t> SpreadOrder(const std::vector<Eigen::Vector2d>& pos) {
  const std::size_t np = pos.size();
  std::vector<std::size_t> order;
  order.reserve(np);
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
  return order;
}

// One scanner centre against a chunk of the cells not yet seen: what it sees (the visibility
// rule of the file comment) and how many rays it casts. Keeps its ray buffers from chunk to
// chunk; one per thread.
class ChunkCaster {
 public:
  ChunkCaster(const sim::EmbreeWorld& world, const StructuralSurfaces& surfaces,
              const std::vector<int>& part_element, const ObservabilityParams& params)
      : world_(world),
        surfaces_(surfaces),
        part_element_(part_element),
        params_(params),
        sin_max_(std::sin(DegToRad(params.elevation_max_deg))),
        sin_min_(std::sin(DegToRad(params.elevation_min_deg))) {}

  std::uint64_t Cast(const Eigen::Vector3d& c, const std::int32_t* cells, std::size_t count,
                     std::vector<std::int32_t>& seen) {
    origins_.clear();
    dirs_.clear();
    ids_.clear();
    lens_.clear();
    for (std::size_t k = 0; k < count; ++k) {
      const SurfaceCell& cell = surfaces_.cells[cells[k]];
      const Eigen::Vector3d d = cell.centre - c;
      if (cell.normal.dot(d) >= 0) continue;  // back side
      const double L = d.norm();
      if (L < params_.range_min || L > params_.range_max) continue;
      const double s = d.z() / L;
      if (s > sin_max_ || s < sin_min_) continue;
      origins_.push_back(c.cast<float>());
      dirs_.push_back((d / L).cast<float>());
      ids_.push_back(cells[k]);
      lens_.push_back(static_cast<float>(L));
    }
    hits_.resize(ids_.size());
    world_.IntersectMany(origins_, dirs_, 0.0f, std::numeric_limits<float>::infinity(), hits_);
    for (std::size_t q = 0; q < ids_.size(); ++q) {
      const sim::RayHit& h = hits_[q];
      if (!h.hit() || part_element_[h.part] != surfaces_.cells[ids_[q]].element) continue;
      if (h.t < lens_[q] - params_.hit_tolerance || h.t > lens_[q] + params_.hit_tolerance)
        continue;
      seen.push_back(ids_[q]);
    }
    return ids_.size();
  }

 private:
  const sim::EmbreeWorld& world_;
  const StructuralSurfaces& surfaces_;
  const std::vector<int>& part_element_;
  const ObservabilityParams& params_;
  const double sin_max_, sin_min_;
  std::vector<Eigen::Vector3f> origins_, dirs_;
  std::vector<sim::RayHit> hits_;
  std::vector<std::int32_t> ids_;
  std::vector<float> lens_;
};

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
  const PlanRaster raster = RasterOver(r->polygon, params);
  const std::vector<std::uint8_t> occupied =
      RasteriseBand(scene, raster, r->floor_z + params.body_z_min, r->floor_z + params.body_z_max);
  const std::vector<double> dist = SquaredDistanceToOccupied(occupied, raster.nx, raster.ny);
  // Free: clear of the robot's radius, centre inside the room.
  const double r2 = (params.robot_radius / raster.res) * (params.robot_radius / raster.res);
  std::vector<std::uint8_t> free(raster.Size(), 0);
  for (int j = 0; j < raster.ny; ++j)
    for (int i = 0; i < raster.nx; ++i) {
      const std::size_t k = raster.Index(i, j);
      free[k] = dist[k] > r2 && scenes::PointInPolygon(raster.Centre(i, j), r->polygon);
    }
  const FreeRegions regions = LabelFreeRegions(free, raster.nx, raster.ny);
  ReachableArea out;
  out.free_area = static_cast<double>(regions.best_size) * raster.res * raster.res;
  if (regions.best < 0) return out;
  out.positions = LatticeIn(raster, regions.label, regions.best, params.grid_step);
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

  const std::vector<int> part_element = PartElements(world.scene(), surfaces);
  const std::vector<Eigen::Vector2d>& pos = reachable.positions;
  const std::size_t np = pos.size();
  const std::vector<std::size_t> order = SpreadOrder(pos);
  const double z_scan = surfaces.floor_z + params.mast_height;
  std::vector<std::int32_t> unseen(nc);
  for (std::size_t k = 0; k < nc; ++k) unseen[k] = static_cast<std::int32_t>(k);
  // Rounds of 1, 2, 4, 8, then 16 positions; each (position, chunk of unseen cells) pair is a
  // task with its own result slot, merged in task order.
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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tasks, 1),
                      [&](const tbb::blocked_range<std::size_t>& rr) {
                        ChunkCaster caster(world, surfaces, part_element, params);
                        for (std::size_t task = rr.begin(); task != rr.end(); ++task) {
                          const std::size_t b = task / chunks, ch = task % chunks;
                          const Eigen::Vector2d& p = pos[order[next + b]];
                          const std::size_t k0 = ch * kChunk;
                          const std::size_t k1 = std::min(unseen.size(), k0 + kChunk);
                          rays[task] = caster.Cast(Eigen::Vector3d(p.x(), p.y(), z_scan),
                                                   unseen.data() + k0, k1 - k0, seen[task]);
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
