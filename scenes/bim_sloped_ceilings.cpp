// Sloped ceilings of a BIM import: the underside of a roof over an attic is the room's ceiling,
// one truth element per plane, each cut to where it is the lowest of the room's ceiling planes,
// and the room's wall faces end under it (a gable wall is a pentagon, a knee wall a strip)
// (scenes/bim_import_internal.h, common/ceiling_planes.h, docs/scene-import.md).
#include <algorithm>
#include <cmath>

#include "common/polygon.h"
#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {

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
        std::vector<CeilingFaces>& planes = slopes_[r];
        auto it = std::find_if(planes.begin(), planes.end(), [&](const CeilingFaces& q) {
          if (q.plane.n.dot(n) < kFacingCos) return false;
          for (const auto& v : in)
            if (std::abs(q.plane.n.dot(v) - q.plane.c) > p_.plane_tolerance) return false;
          return true;
        });
        if (it == planes.end()) {
          CeilingFaces q;
          q.plane.n = n;
          q.plane.c = n.dot(in[0]);
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
    std::vector<CeilingFaces> faces = sloped;
    const std::string flat_id = "ceiling_" + room.room.id;
    for (const Bucket& b : out_bucket_.buckets()) {
      if (b.id != flat_id || b.pieces.empty()) continue;
      CeilingFaces q;
      q.plane.n = -Vector3d::UnitZ();
      q.plane.c = -room.room.ceiling_z;
      q.id = flat_id;
      for (const auto& piece : b.pieces) {
        q.plan_area += Area(piece);
        for (const auto& v : piece) q.plan.push_back(v.head<2>());
      }
      faces.push_back(q);
      break;
    }
    StructuralElement* level = nullptr;
    for (StructuralElement& c : ceilings_)
      if (c.id == flat_id) level = &c;
    if (level != nullptr && faces.size() == sloped.size()) level->polygons.clear();
    // Each plane where its faces are (their plan hull) and it is the lowest.
    std::vector<CeilingPlane> planes;
    std::vector<Polygon2> hulls;
    for (const CeilingFaces& f : faces) {
      planes.push_back(f.plane);
      hulls.push_back(ConvexHull(f.plan, 1e-9));
    }
    const std::vector<Polygon2> regions =
        LowestCeilingRegions(room.poly, planes, &hulls, p_.min_face_area);
    for (std::size_t i = 0; i < faces.size(); ++i) {
      if (regions[i].empty()) continue;
      const double area = std::abs(SignedArea(regions[i]));
      if (std::abs(area - faces[i].plan_area) > 0.05 * faces[i].plan_area)
        out_.report.push_back(faces[i].id + ": its slab faces cover " + Fmt(faces[i].plan_area, 2) +
                              " m2 seen from below, where it is " + "the room's lowest ceiling " +
                              Fmt(area, 2) + " m2 (the truth takes the latter)");
    }
    // The truth elements: each plane's region lifted onto it, facing down into the room.
    for (std::size_t i = 0; i < faces.size(); ++i) {
      Poly3 poly;
      for (const auto& v : regions[i]) poly.push_back(Lift(v, planes[i].ZAt(v)));
      if (!poly.empty() && NormalOf(poly).dot(planes[i].n) < 0.0)
        std::reverse(poly.begin(), poly.end());
      if (faces[i].id == flat_id) {
        if (level == nullptr) continue;
        level->polygons.clear();
        if (!poly.empty()) level->polygons.push_back(poly);
        continue;
      }
      if (poly.empty()) continue;
      double lo = 1e300, hi = -1e300;
      for (const auto& v : poly) lo = std::min(lo, v.z()), hi = std::max(hi, v.z());
      out_.report.push_back("sloped ceiling " + faces[i].id + " of " + room.room.id + ": " +
                            Fmt(std::acos(std::min(1.0, -planes[i].n.z())) * 180.0 / M_PI, 1) +
                            " deg, " + Fmt(lo) + " to " + Fmt(hi) + " m, " +
                            Fmt(std::abs(SignedArea(regions[i])), 2) + " m2 in plan");
      StructuralElement s;
      s.id = faces[i].id;
      s.element_class = ElementClass::kCeiling;
      s.rooms = {room.room.id};
      s.normal = planes[i].n;
      s.polygons = {poly};
      sloped_ceilings_.push_back(s);
    }
    // The room's wall faces end under the planes over them.
    for (StructuralElement& w : walls_) {
      if (w.rooms.empty() || w.rooms[0] != room.room.id) continue;
      const std::vector<Vector2d> outline = WallUnderCeilings(
          w.origin.head<2>(), w.u_axis.head<2>().normalized(), w.normal.head<2>().normalized(),
          w.length, w.origin.z(), w.height, planes, regions);
      if (outline.empty()) continue;
      Poly3 poly;
      for (const auto& p : outline)
        poly.push_back(w.origin + p.x() * w.u_axis + Vector3d(0.0, 0.0, p.y()));
      w.polygons = {poly};
    }
  }
}

}  // namespace mopad::scenes::bim
