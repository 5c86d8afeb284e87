// Sloped ceilings of a BIM import: the underside of a roof over an attic is the room's ceiling,
// one truth element per plane, each cut to where it is the lowest of the room's ceiling planes,
// and the room's wall faces end under it (a gable wall is a pentagon, a knee wall a strip)
// (scenes/bim_import_internal.h, docs/scene-import.md).
#include <algorithm>
#include <cmath>

#include "common/polygon.h"
#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {

namespace {

// Inside the CCW triangle `ear` of `poly`, in plan (the ear region of bim_surfaces.cpp).
std::vector<HalfSpace> EarRegion(const Polygon2& poly, const Eigen::Vector3i& ear) {
  std::vector<HalfSpace> region;
  for (int k = 0; k < 3; ++k) {
    const Vector2d& a = poly[ear[k]];
    const Vector2d& b = poly[ear[(k + 1) % 3]];
    const Vector3d nn(b.y() - a.y(), -(b.x() - a.x()), 0.0);
    region.push_back({nn, nn.dot(Lift(a, 0.0))});
  }
  return region;
}

// `poly` (plan, z = 0) within the half-plane a . p <= d.
Poly3 ClipPlan(const Poly3& poly, const Vector2d& a, double d) {
  return Clip(poly, Lift(a, 0.0), d);
}

// Where `p` is lower than or level with `q`: (p.ZAt(x) - q.ZAt(x)) <= 0, linear in plan.
// False when the planes are parallel in plan (they never cross; the hulls decide).
bool LowerHalfPlane(const CeilingPlane& p, const CeilingPlane& q, Vector2d* a, double* d) {
  // z(x, y) = c / nz - (nx / nz) x - (ny / nz) y
  *a = Vector2d(q.n.x() / q.n.z() - p.n.x() / p.n.z(), q.n.y() / q.n.z() - p.n.y() / p.n.z());
  *d = q.c / q.n.z() - p.c / p.n.z();
  return a->norm() > 1e-9;
}

// The u in [0, length] where the segment a + u dir crosses an edge of `poly`.
std::vector<double> Crossings(const Polygon2& poly, const Vector2d& a, const Vector2d& dir,
                              double length) {
  std::vector<double> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vector2d p = poly[i], e = poly[(i + 1) % poly.size()] - p;
    const double den = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Vector2d w = p - a;
    const double u = (w.x() * e.y() - w.y() * e.x()) / den;
    const double t = (w.x() * dir.y() - w.y() * dir.x()) / den;
    if (u > 0.0 && u < length && t >= 0.0 && t <= 1.0) out.push_back(u);
  }
  return out;
}

// The wall face `w` ended under the ceiling planes over it: along its foot, the top is the
// plane whose region holds the foot (1 cm into the room), else the face's own top. Unchanged
// where no plane comes under that top.
void EndUnder(const std::vector<CeilingPlane>& planes, const std::vector<Polygon2>& regions,
              StructuralElement* w) {
  const Vector2d foot = w->origin.head<2>();
  const Vector2d a = (w->origin + 0.01 * w->normal).head<2>();
  const Vector2d dir = w->u_axis.head<2>().normalized();
  std::vector<double> cuts{0.0, w->length};
  for (const auto& region : regions) {
    const std::vector<double> c = Crossings(region, a, dir, w->length);
    cuts.insert(cuts.end(), c.begin(), c.end());
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(),
                         [](double x, double y) { return std::abs(x - y) < 1e-6; }),
             cuts.end());
  std::vector<Vector2d> outline{Vector2d(0.0, 0.0)};  // (u, v), then along the top, u ascending
  bool cut = false;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const Vector2d mid = a + 0.5 * (cuts[k] + cuts[k + 1]) * dir;
    const CeilingPlane* over = nullptr;
    for (std::size_t i = 0; i < planes.size(); ++i)
      if (regions[i].size() >= 3 && PointInPolygon(mid, regions[i]) &&
          (over == nullptr || planes[i].ZAt(mid) < over->ZAt(mid)))
        over = &planes[i];
    for (double u : {cuts[k], cuts[k + 1]}) {
      double v = w->height;
      if (over != nullptr)
        v = std::clamp(over->ZAt(foot + u * dir) - w->origin.z(), 0.0, w->height);
      cut = cut || v < w->height - 1e-6;
      if ((outline.back() - Vector2d(u, v)).norm() > 1e-6) outline.emplace_back(u, v);
    }
  }
  if (!cut) return;
  outline.emplace_back(w->length, 0.0);
  RemoveShallowVertices(outline, 1e-6);
  Poly3 poly;
  for (const auto& p : outline)
    poly.push_back(w->origin + p.x() * w->u_axis + Vector3d(0.0, 0.0, p.y()));
  w->polygons = {poly};
}

}  // namespace

std::vector<Poly3> Importer::SlopedCeilingPieces(int material, const Vector3d& n,
                                                 std::vector<Poly3> pieces) {
  for (std::size_t r = 0; r < rooms_.size() && !pieces.empty(); ++r) {
    const RoomData& room = rooms_[r];
    for (const auto& ear : room.ears) {
      std::vector<HalfSpace> region = EarRegion(room.poly, ear);
      // Under the room's top (a roof over a flat ceiling is not the room's), over its floor.
      region.push_back({Vector3d::UnitZ(), room.room.ceiling_z + p_.plane_tolerance});
      region.push_back({-Vector3d::UnitZ(), -room.room.floor_z});
      std::vector<Poly3> next;
      for (const Poly3& piece : pieces) {
        Poly3 in;
        Split(piece, region, &in, &next);
        if (in.empty()) continue;
        if (NormalOf(in).z() > 0.0) std::reverse(in.begin(), in.end());
        std::vector<CeilingPlane>& planes = slopes_[r];
        auto it = std::find_if(planes.begin(), planes.end(), [&](const CeilingPlane& q) {
          if (q.n.dot(n) < kFacingCos) return false;
          for (const auto& v : in)
            if (std::abs(q.n.dot(v) - q.c) > p_.plane_tolerance) return false;
          return true;
        });
        if (it == planes.end()) {
          CeilingPlane q;
          q.n = n;
          q.c = n.dot(in[0]);
          q.id = "ceiling_" + room.room.id + "_" + std::to_string(planes.size() + 1);
          planes.push_back(q);
          it = planes.end() - 1;
        }
        const double plan = Area(in) * std::abs(n.z());
        it->plan_area += plan;
        for (const auto& v : in) it->plan.push_back(v.head<2>());
        ceiling_area_[r] += plan;
        out_bucket_.Get(it->id, ElementClass::kCeiling, "", room.room.id, material)
            .pieces.push_back(std::move(in));
      }
      pieces = std::move(next);
      if (pieces.empty()) break;
    }
  }
  return pieces;
}

void Importer::SlopedCeilings() {
  for (auto& [r, sloped] : slopes_) {
    const RoomData& room = rooms_[r];
    // The room's planes: the sloped ones, and the level ceiling where it has geometry.
    std::vector<CeilingPlane> planes = sloped;
    const std::string flat_id = "ceiling_" + room.room.id;
    for (const Bucket& b : out_bucket_.buckets()) {
      if (b.id != flat_id || b.pieces.empty()) continue;
      CeilingPlane q;
      q.n = -Vector3d::UnitZ();
      q.c = -room.room.ceiling_z;
      q.id = flat_id;
      for (const auto& piece : b.pieces) {
        q.plan_area += Area(piece);
        for (const auto& v : piece) q.plan.push_back(v.head<2>());
      }
      planes.push_back(q);
      break;
    }
    StructuralElement* level = nullptr;
    for (StructuralElement& c : ceilings_)
      if (c.id == flat_id) level = &c;
    if (level != nullptr && planes.size() == sloped.size()) level->polygons.clear();
    // Each plane where its pieces are (their plan hull) and it is the lowest.
    std::vector<Polygon2> regions(planes.size());
    for (std::size_t i = 0; i < planes.size(); ++i) {
      Poly3 plan;
      for (const auto& v : room.poly) plan.push_back(Lift(v, 0.0));
      const Polygon2 hull = ConvexHull(planes[i].plan, 1e-9);
      for (std::size_t k = 0; k < hull.size() && hull.size() >= 3 && !plan.empty(); ++k) {
        const Vector2d e = hull[(k + 1) % hull.size()] - hull[k];
        const Vector2d nn(e.y(), -e.x());
        plan = ClipPlan(plan, nn, nn.dot(hull[k]));
      }
      for (std::size_t j = 0; j < planes.size() && !plan.empty(); ++j) {
        Vector2d a;
        double d = 0.0;
        if (j != i && LowerHalfPlane(planes[i], planes[j], &a, &d)) plan = ClipPlan(plan, a, d);
      }
      Polygon2 region;
      for (const auto& v : plan) region.push_back(v.head<2>());
      if (region.size() < 3 || std::abs(SignedArea(region)) < p_.min_face_area) continue;
      regions[i] = region;
      if (std::abs(std::abs(SignedArea(region)) - planes[i].plan_area) > 0.05 * planes[i].plan_area)
        out_.report.push_back(planes[i].id + ": its slab faces cover " +
                              Fmt(planes[i].plan_area, 2) + " m2 seen from below, where it is " +
                              "the room's lowest ceiling " + Fmt(std::abs(SignedArea(region)), 2) +
                              " m2 (the truth takes the latter)");
    }
    // The truth elements: each plane's region lifted onto it, facing down into the room.
    for (std::size_t i = 0; i < planes.size(); ++i) {
      Poly3 poly;
      for (const auto& v : regions[i]) poly.push_back(Lift(v, planes[i].ZAt(v)));
      if (!poly.empty() && NormalOf(poly).dot(planes[i].n) < 0.0)
        std::reverse(poly.begin(), poly.end());
      if (planes[i].id == flat_id) {
        if (level == nullptr) continue;
        level->polygons.clear();
        if (!poly.empty()) level->polygons.push_back(poly);
        continue;
      }
      if (poly.empty()) continue;
      StructuralElement s;
      s.id = planes[i].id;
      s.element_class = ElementClass::kCeiling;
      s.rooms = {room.room.id};
      s.normal = planes[i].n;
      s.polygons = {poly};
      sloped_ceilings_.push_back(s);
    }
    // The room's wall faces end under the planes over them.
    for (StructuralElement& w : walls_)
      if (!w.rooms.empty() && w.rooms[0] == room.room.id) EndUnder(planes, regions, &w);
  }
}

}  // namespace mopad::scenes::bim
