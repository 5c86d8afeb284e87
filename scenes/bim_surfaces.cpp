// The room surfaces of a BIM import: convex clipping of the model's triangles, the wall faces on
// each room polygon edge, floors and ceilings cut to the room (made from the space footprint
// when asked and missing), columns, and the `other` leftovers (scenes/bim_import_internal.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "common/error.h"
#include "common/polygon.h"
#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {

namespace {

// Newell's vector (common/polygon.h) of `p` taken about its first vertex, which makes it the sum
// of a fan of triangles from that vertex: as precise 10 km from the origin (a georeferenced
// model) as at it. About the world origin, terms there reach 1e8 m^2 and their rounding errors
// 1e-8 m^2, kMinPieceArea.
Vector3d NewellAboutFirst(const Poly3& p) {
  if (p.empty()) return Vector3d::Zero();
  Poly3 q;
  q.reserve(p.size());
  for (const Vector3d& v : p) q.push_back(v - p[0]);
  return NewellVector(q);
}

}  // namespace

double Area(const Poly3& p) { return 0.5 * NewellAboutFirst(p).norm(); }

bool Solid(const Poly3& p) {
  const double area = Area(p);
  if (area <= kMinPieceArea) return false;
  double perimeter = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) perimeter += (p[(i + 1) % p.size()] - p[i]).norm();
  return area > 1e-6 * perimeter;
}

void Split(const Poly3& poly, const std::vector<HalfSpace>& region, Poly3* inside,
           std::vector<Poly3>* outside) {
  Poly3 rest = poly;
  for (const HalfSpace& h : region) {
    Poly3 out = ClipHalfSpace(rest, -h.n, -h.c);
    if (Solid(out)) outside->push_back(std::move(out));
    rest = ClipHalfSpace(rest, h.n, h.c);
    if (!Solid(rest)) {
      inside->clear();
      return;
    }
  }
  *inside = std::move(rest);
}

std::vector<HalfSpace> EarRegion(const std::vector<Vector2d>& poly, const Eigen::Vector3i& ear) {
  std::vector<HalfSpace> region;
  for (int k = 0; k < 3; ++k) {
    const Vector2d& a = poly[ear[k]];
    const Vector2d& b = poly[ear[(k + 1) % 3]];
    // Inside a CCW ear: left of every edge, i.e. (b - a)^perp . (x - a) >= 0.
    const Vector3d nn(b.y() - a.y(), -(b.x() - a.x()), 0.0);
    region.push_back({nn, nn.dot(Lift(a, 0.0))});
  }
  return region;
}

Vector3d NormalOf(const Poly3& p) {
  const Vector3d s = NewellAboutFirst(p);
  const double n = s.norm();
  return n > 0.0 ? Vector3d(s / n) : Vector3d::Zero();
}

void Importer::MakeFaces() {
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    const Polygon2& poly = rooms_[r].poly;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      Face f;
      f.room = static_cast<int>(r);
      f.edge = static_cast<int>(k);
      f.id = "wall_" + rooms_[r].room.id + "_" + std::to_string(k);
      const Vector2d a = poly[k], b = poly[(k + 1) % poly.size()];
      f.length = (b - a).norm();
      f.a = Lift(a, rooms_[r].room.floor_z);
      f.dir = Lift((b - a) / f.length, 0.0);
      f.n = Vector3d(-f.dir.y(), f.dir.x(), 0.0);
      f.z0 = rooms_[r].room.floor_z;
      f.z1 = rooms_[r].room.ceiling_z;
      faces_.push_back(f);
    }
  }
}

void Importer::Leftover(std::size_t e, int material, Poly3 piece) {
  const Element& el = elements_[e];
  out_bucket_.Get(el.node, ElementClass::kOther, el.ifc, "", material)
      .pieces.push_back(std::move(piece));
  other_ids_.insert(el.node);
}

// With wall_search: each room edge's wall plane is the plane of IfcWall triangles facing the
// room, over the edge, nearest the edge within the search distance and carrying at least
// min_face_area (planes within plane_tolerance of one another are one).
void Importer::FindWallPlanes() {
  if (!p_.as_is || p_.wall_search <= p_.plane_tolerance) return;
  for (Face& f : faces_) {
    std::vector<std::pair<double, double>> planes;  // (offset, area)
    for (const Element& e : elements_) {
      if (!e.in_storey || e.role != Role::kWall) continue;
      for (std::size_t pi : e.parts) {
        const MeshPart& part = scene_.parts[pi];
        for (const auto& t : part.triangles) {
          const Poly3 tri{part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                          part.positions[t[2]].cast<double>()};
          if (NormalOf(tri).dot(f.n) < kFacingCos) continue;
          const Vector3d c = (tri[0] + tri[1] + tri[2]) / 3.0;
          const double w = f.W(c);
          if (std::abs(w) > p_.wall_search || f.U(c) <= 0.0 || f.U(c) >= f.length ||
              c.z() <= f.z0 || c.z() >= f.z1)
            continue;
          planes.emplace_back(w, Area(tri));
        }
      }
    }
    std::sort(planes.begin(), planes.end(), [](const auto& a, const auto& b) {
      return std::abs(a.first) < std::abs(b.first) ||
             (std::abs(a.first) == std::abs(b.first) && a.first < b.first);
    });
    for (const auto& [w, area] : planes) {
      double sum = 0.0, moment = 0.0;
      for (const auto& [w2, a2] : planes)
        if (std::abs(w2 - w) <= p_.plane_tolerance) sum += a2, moment += a2 * w2;
      if (sum < p_.min_face_area) continue;
      f.w = moment / sum;
      if (std::abs(f.w) > p_.plane_tolerance)
        out_.report.push_back(f.id + ": wall face " + Fmt(100.0 * f.w, 1) +
                              " cm off the space's outline (as it is)");
      break;
    }
  }
}

// Faces on a room's wall planes onto its wall faces (from walls, and from whatever else
// forms the wall surface: coverings, parts, proxies, curtain-wall plates); slab faces onto
// floors and ceilings; the rest of these elements is `other`.
void Importer::DistributeStructure() {
  for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
    const Element& e = elements_[ei];
    if (!e.in_storey || (e.role != Role::kWall && e.role != Role::kSlab && e.role != Role::kOther))
      continue;
    for (std::size_t pi : e.parts) {
      const MeshPart& part = scene_.parts[pi];
      for (const auto& t : part.triangles) {
        std::vector<Poly3> rest{{part.positions[t[0]].cast<double>(),
                                 part.positions[t[1]].cast<double>(),
                                 part.positions[t[2]].cast<double>()}};
        const Vector3d n = NormalOf(rest[0]);
        if (n.isZero()) continue;
        if (std::abs(n.z()) < 1.0 - kFacingCos) {
          for (Face& f : faces_) {
            if (n.dot(f.n) < kFacingCos) continue;
            bool on = true;
            for (const auto& p : rest[0]) on = on && std::abs(f.W(p) - f.w) <= p_.plane_tolerance;
            if (!on) continue;
            std::vector<Poly3> next;
            for (const Poly3& piece : rest) {
              Poly3 in;
              Split(piece, f.Region(), &in, &next);
              if (!in.empty()) {
                if (NormalOf(in).dot(f.n) < 0.0) std::reverse(in.begin(), in.end());
                f.pieces.emplace_back(ei, std::move(in));
                f.materials.push_back(part.material);
              }
            }
            rest = std::move(next);
            if (rest.empty()) break;
          }
        } else if (e.role == Role::kSlab && n.z() <= -kSlopedCeilingCos && n.z() > -kFacingCos) {
          rest = SlopedCeilingPieces(part.material, n, std::move(rest));
        } else if (e.role == Role::kSlab) {
          for (std::size_t r = 0; r < rooms_.size() && !rest.empty(); ++r) {
            const RoomData& room = rooms_[r];
            const bool up = n.z() >= kFacingCos, down = n.z() <= -kFacingCos;
            if (!up && !down) break;
            const double z = up ? room.room.floor_z : room.room.ceiling_z;
            bool on = true;
            for (const auto& p : rest[0]) on = on && std::abs(p.z() - z) <= p_.plane_tolerance;
            if (!on) continue;
            for (const auto& ear : room.ears) {
              const std::vector<HalfSpace> region = EarRegion(room.poly, ear);
              std::vector<Poly3> next;
              for (const Poly3& piece : rest) {
                Poly3 in;
                Split(piece, region, &in, &next);
                if (!in.empty()) {
                  // Front faces into the room (docs/scene-format.md), whatever the file did.
                  if ((NormalOf(in).z() > 0.0) != up) std::reverse(in.begin(), in.end());
                  const std::string id = (up ? "floor_" : "ceiling_") + room.room.id;
                  (up ? floor_area_ : ceiling_area_)[r] += Area(in);
                  out_bucket_
                      .Get(id, up ? ElementClass::kFloor : ElementClass::kCeiling, "", room.room.id,
                           part.material)
                      .pieces.push_back(std::move(in));
                }
              }
              rest = std::move(next);
              if (rest.empty()) break;
            }
          }
        }
        for (Poly3& piece : rest) Leftover(ei, part.material, std::move(piece));
      }
    }
  }
}

void Importer::FinishFaces() {
  std::map<std::string, int> walls_per_room;
  for (Face& f : faces_) {
    f.area = 0.0;
    double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
    for (const auto& [e, poly] : f.pieces) {
      f.area += Area(poly);
      for (const auto& p : poly) {
        umin = std::min(umin, f.U(p));
        umax = std::max(umax, f.U(p));
        vmin = std::min(vmin, p.z());
        vmax = std::max(vmax, p.z());
      }
    }
    const RoomData& room = rooms_[f.room];
    if (f.area < p_.min_face_area) {
      for (std::size_t i = 0; i < f.pieces.size(); ++i)
        Leftover(f.pieces[i].first, f.materials[i], f.pieces[i].second);
      f.pieces.clear();
      out_.report.push_back("room " + room.room.id + " edge " + std::to_string(f.edge) + " (" +
                            Fmt(f.length, 2) +
                            " m): no wall face on it (open to a "
                            "neighbour, or the wall is not on the space boundary)");
      continue;
    }
    f.kept = true;
    for (const auto& piece : f.pieces)
      if (elements_[piece.first].role == Role::kWall) walls_with_faces_.insert(piece.first);
    f.umin = umin;
    f.umax = umax;
    f.vmin = vmin;
    f.vmax = vmax;
    for (std::size_t i = 0; i < f.pieces.size(); ++i)
      out_bucket_.Get(f.id, ElementClass::kWall, "", room.room.id, f.materials[i])
          .pieces.push_back(f.pieces[i].second);
    StructuralElement w;
    w.id = f.id;
    w.element_class = ElementClass::kWall;
    w.rooms = {room.room.id};
    // The faces' own plane (within plane_tolerance of the room edge; 0 for most files).
    double offset = 0.0, weight = 0.0;
    for (const auto& [el, poly] : f.pieces) {
      const double a = Area(poly);
      for (const auto& p : poly) offset += a * f.W(p) / static_cast<double>(poly.size());
      weight += a;
    }
    offset = weight > 0.0 ? offset / weight : 0.0;
    w.origin = f.a + umin * f.dir + offset * f.n + Vector3d(0, 0, vmin - f.a.z());
    w.u_axis = f.dir;
    w.normal = f.n;
    w.length = umax - umin;
    w.height = vmax - vmin;
    const Vector3d up(0, 0, w.height);
    const Vector3d along = w.length * f.dir;
    w.polygons = {{w.origin, w.origin + up, w.origin + along + up, w.origin + along}};
    walls_.push_back(w);
    ++walls_per_room[room.room.id];
  }
}

void Importer::FloorsAndCeilings() {
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    const RoomData& room = rooms_[r];
    const double area = SignedArea(room.poly);
    for (bool up : {true, false}) {
      const double have = (up ? floor_area_ : ceiling_area_)[r];
      const bool repair = up ? p_.floor_from_spaces : p_.ceiling_from_spaces;
      const std::string what = up ? "floor" : "ceiling";
      const std::string id = what + "_" + room.room.id;
      const ElementClass cls = up ? ElementClass::kFloor : ElementClass::kCeiling;
      const double z = up ? room.room.floor_z : room.room.ceiling_z;
      if (have < kFullCover * area) {
        Repair(what, room.room.id + " (" + NiceName(room.node) + ")",
               Fmt(100.0 * have / area, 1) + " % " + what + " geometry at z = " + Fmt(z) + " m",
               "the space footprint", repair || p_.repair, "--" + what + "-from-spaces");
        if (p_.as_is && !(repair || p_.repair)) continue;  // the model lacks it: left out
        // Replace what there is by the whole footprint (same plane: nothing is lost).
        for (Bucket& b : out_bucket_.buckets())
          if (b.id == id) b.pieces.clear();
        Bucket& b = out_bucket_.Get(id, cls, "", room.room.id, RepairMaterial(up));
        for (const auto& ear : room.ears) {
          Poly3 tri{Lift(room.poly[ear[0]], z), Lift(room.poly[ear[1]], z),
                    Lift(room.poly[ear[2]], z)};
          if (!up) std::swap(tri[1], tri[2]);
          b.pieces.push_back(tri);
        }
      }
      StructuralElement s;
      s.id = id;
      s.element_class = cls;
      s.rooms = {room.room.id};
      s.normal = up ? Vector3d::UnitZ() : Vector3d(-Vector3d::UnitZ());
      Poly3 poly;
      for (const auto& v : room.poly) poly.push_back(Lift(v, z));
      if (!up) std::reverse(poly.begin(), poly.end());
      s.polygons = {poly};
      (up ? floors_ : ceilings_).push_back(s);
    }
  }
}

int Importer::RepairMaterial(bool floor) {
  const std::string name = floor ? "repaired_floor" : "repaired_ceiling";
  for (std::size_t i = 0; i < scene_.materials.size(); ++i)
    if (scene_.materials[i].name == name) return static_cast<int>(i);
  Material m;
  m.name = name;
  m.base_color = floor ? Eigen::Vector4f(0.45f, 0.42f, 0.38f, 1.0f)
                       : Eigen::Vector4f(0.85f, 0.85f, 0.85f, 1.0f);
  scene_.materials.push_back(m);
  return static_cast<int>(scene_.materials.size()) - 1;
}

int Importer::RoomAt(const Vector3d& p) const {
  for (std::size_t r = 0; r < rooms_.size(); ++r)
    if (p.z() >= rooms_[r].room.floor_z - 0.05 && p.z() <= rooms_[r].room.ceiling_z + 0.05 &&
        PointInPolygon(p.head<2>(), rooms_[r].poly))
      return static_cast<int>(r);
  return -1;
}

void Importer::Columns() {
  for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
    const Element& e = elements_[ei];
    if (!e.in_storey || e.role != Role::kColumn) continue;
    const int r = RoomAt(e.box.center());
    if (r < 0) {
      for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
      out_.report.push_back(NiceName(e.node) + ": not inside a room; kept as other");
      continue;
    }
    StructuralElement c;
    c.id = "column_" + rooms_[r].room.id + "_" + std::to_string(++columns_in_[r]);
    c.element_class = ElementClass::kColumn;
    c.rooms = {rooms_[r].room.id};
    // One polygon per side plane: its extent along the horizontal tangent and z.
    std::map<std::array<long long, 4>, std::pair<Vector3d, Eigen::AlignedBox2d>> sides;
    for (std::size_t pi : e.parts) {
      const MeshPart& part = scene_.parts[pi];
      Bucket& b =
          out_bucket_.Get(c.id, ElementClass::kColumn, "", rooms_[r].room.id, part.material);
      for (const auto& t : part.triangles) {
        const Poly3 tri{part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                        part.positions[t[2]].cast<double>()};
        b.pieces.push_back(tri);
        const Vector3d n = NormalOf(tri);
        if (n.isZero() || std::abs(n.z()) > 0.01) continue;
        const std::array<long long, 4> key{std::llround(n.x() * 1e3), std::llround(n.y() * 1e3),
                                           std::llround(n.dot(tri[0]) * 1e3), 0};
        const Vector3d tan(-n.y(), n.x(), 0.0);
        auto& side = sides[key];
        side.first = n;
        for (const auto& p : tri) side.second.extend(Vector2d(tan.dot(p), p.z()));
      }
    }
    for (const auto& [key, side] : sides) {
      const Vector3d n = side.first, tan(-n.y(), n.x(), 0.0);
      const Vector3d o = n * (double(key[2]) * 1e-3);
      const auto& bx = side.second;
      auto P = [&](double s, double z) { return Vector3d(o + s * tan + Vector3d(0, 0, z)); };
      // CCW seen from outside (along n): tan is to the right of... order
      // (s0,z0),(s1,z0),(s1,z1),(s0,z1).
      Poly3 q{P(bx.min().x(), bx.min().y()), P(bx.max().x(), bx.min().y()),
              P(bx.max().x(), bx.max().y()), P(bx.min().x(), bx.max().y())};
      if (NormalOf(q).dot(n) < 0) std::reverse(q.begin(), q.end());
      c.polygons.push_back(q);
    }
    columns_.push_back(c);
  }
}

void Importer::AllToLeftover(std::size_t ei, std::size_t pi) {
  const MeshPart& part = scene_.parts[pi];
  for (const auto& t : part.triangles)
    Leftover(ei, part.material,
             {part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
              part.positions[t[2]].cast<double>()});
}

}  // namespace mopad::scenes::bim
