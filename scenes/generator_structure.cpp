// The generator's building structure: rooms and their wall faces (one per polygon edge), which
// faces look at another room across one wall thickness, columns, and the geometry and truth of
// walls, facades, floors, ceilings and columns (scenes/generator_internal.h).
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/generator_internal.h"

namespace mopad::scenes::gen {

void Generator::BuildRooms() {
  for (const auto& rs : spec_.rooms) {
    RoomData r;
    r.spec = &rs;
    r.id = rs.id;
    r.poly = rs.polygon;
    r.z0 = 0.0;
    r.z1 = rs.ceiling_height > 0.0 ? rs.ceiling_height : spec_.ceiling_height;
    r.area = SignedArea(r.poly);
    const int ri = static_cast<int>(rooms_.size());
    for (std::size_t e = 0; e < r.poly.size(); ++e) {
      Face f;
      f.id = "wall_" + r.id + "_" + std::to_string(e);
      f.room = ri;
      f.edge = static_cast<int>(e);
      f.a = r.poly[e];
      f.b = r.poly[(e + 1) % r.poly.size()];
      f.length = (f.b - f.a).norm();
      f.dir = (f.b - f.a) / f.length;
      f.n_in = Vector2d(-f.dir.y(), f.dir.x());
      f.z0 = r.z0;
      f.z1 = r.z1;
      r.perimeter += f.length;
      r.faces.push_back(static_cast<int>(faces_.size()));
      faces_.push_back(f);
    }
    rooms_.push_back(r);
    room_index_[r.id] = ri;
  }
}

void Generator::ComputeAdjacency() {
  for (std::size_t i = 0; i < faces_.size(); ++i) {
    for (std::size_t j = 0; j < faces_.size(); ++j) {
      Face& f = faces_[i];
      const Face& g = faces_[j];
      if (f.room == g.room) continue;
      if (f.dir.dot(g.dir) > -1.0 + 1e-9) continue;  // not antiparallel
      // g's line must lie at the wall thickness behind f.
      const double da = (g.a - f.a).dot(f.n_in), db = (g.b - f.a).dot(f.n_in);
      if (std::abs(da + t_) > kAdjacencyTol || std::abs(db + t_) > kAdjacencyTol) continue;
      const double ua = (g.a - f.a).dot(f.dir), ub = (g.b - f.a).dot(f.dir);
      const double s0 = std::max(0.0, std::min(ua, ub)), s1 = std::min(f.length, std::max(ua, ub));
      if (s1 - s0 < 1e-3) continue;
      f.adj.push_back({s0, s1, static_cast<int>(j), (f.a - g.a).dot(g.dir)});
    }
    std::sort(faces_[i].adj.begin(), faces_[i].adj.end(),
              [](const Adjacency& x, const Adjacency& y) { return x.s0 < y.s0; });
  }
}

std::vector<std::pair<double, double>> Generator::OuterPortions(const Face& f) const {
  std::vector<std::pair<double, double>> out;
  double u = 0.0;
  for (const auto& ad : f.adj) {
    if (ad.s0 > u + 1e-6) out.emplace_back(u, ad.s0);
    u = std::max(u, ad.s1);
  }
  if (f.length > u + 1e-6) out.emplace_back(u, f.length);
  return out;
}

Polygon2 Generator::ColumnFootprint(const ColumnSpec& c) const {
  Polygon2 poly;
  if (c.shape == "round") {
    for (int i = 0; i < c.segments; ++i) {
      const double a = 2.0 * kPi * i / c.segments;
      poly.emplace_back(c.position.x() + c.radius * std::cos(a),
                        c.position.y() + c.radius * std::sin(a));
    }
    return poly;
  }
  return OrientedRect(c.position, DegToRad(c.yaw_deg), c.size.x(), c.size.y());
}

void Generator::CheckColumns() {
  for (const auto& c : spec_.columns) {
    const int r = RoomIndex(c.room);
    const Polygon2 fp = ColumnFootprint(c);
    for (int di : DoorsOfRoom(r))
      if (ConvexOverlap(fp, DoorZone(doors_[di], r)))
        throw InputError(
            c.where, "column '" + c.id + "' stands in front of door '" + doors_[di].spec->id + "'");
    columns_.push_back({r, fp});
  }
}

void Generator::EmitWalls() {
  const int mat = Mat("wall", spec_.materials.wall);
  for (const Face& f : faces_) {
    const RoomData& r = rooms_[f.room];
    MeshPart part = NewPart(f.id, f.id, ElementClass::kWall, "", r.id, mat);
    PartBuilder pb(&part);
    std::vector<Vector2d> pts;
    std::vector<Eigen::Vector3i> tris;
    TriangulateRectWithHoles(f.length, f.height(), f.holes, &pts, &tris);
    for (const auto& p : pts) pb.AddVertex(f.P(p.x(), p.y()));
    // (u, v) is CCW seen from behind the wall: flip so the front faces into the room.
    for (const auto& t : tris) part.triangles.emplace_back(t[0], t[2], t[1]);
    Push(std::move(part));

    StructuralElement e;
    e.id = f.id;
    e.element_class = ElementClass::kWall;
    e.rooms = {r.id};
    e.polygons = {{f.P(0, 0), f.P(0, f.height()), f.P(f.length, f.height()), f.P(f.length, 0)}};
    e.normal = Flat(f.n_in);
    e.origin = f.P(0, 0);
    e.u_axis = Flat(f.dir);
    e.length = f.length;
    e.height = f.height();
    out_.truth.elements.push_back(e);
  }
}

double Generator::VertexExtension(const Face& f, bool at_end) const {
  const RoomData& r = rooms_[f.room];
  const std::size_t n = r.poly.size();
  const int nb_edge = at_end ? (f.edge + 1) % static_cast<int>(n)
                             : (f.edge + static_cast<int>(n) - 1) % static_cast<int>(n);
  const Face& g = faces_[r.faces[static_cast<std::size_t>(nb_edge)]];
  const Vector2d d1 = at_end ? f.dir : g.dir, d2 = at_end ? g.dir : f.dir;
  const double phi = std::atan2(d1.x() * d2.y() - d1.y() * d2.x(), d1.dot(d2));
  double ext = t_ * std::tan(0.5 * phi);
  const double u_shared = at_end ? 0.0 : g.length;
  for (const auto& ad : g.adj)
    if (ad.s0 - 1e-6 <= u_shared && u_shared <= ad.s1 + 1e-6) ext *= 0.5;
  return ext;
}

void Generator::EmitFacades() {
  const int mat = Mat("facade", spec_.materials.facade);
  const double h = spec_.storey_height;
  for (const Face& f : faces_) {
    const RoomData& r = rooms_[f.room];
    const std::string id = "facade_" + r.id + "_" + std::to_string(f.edge);
    MeshPart part = NewPart(id, id, ElementClass::kOther, "facade", r.id, mat);
    PartBuilder pb(&part);
    StructuralElement e;
    e.id = id;
    e.element_class = ElementClass::kOther;
    e.rooms = {r.id};
    e.normal = -Flat(f.n_in);
    for (const auto& [p0, p1] : OuterPortions(f)) {
      const double e0 = p0 < 1e-6 ? p0 - VertexExtension(f, false) : p0 + t_;
      const double e1 = p1 > f.length - 1e-6 ? p1 + VertexExtension(f, true) : p1 - t_;
      if (e1 - e0 < 1e-3) continue;
      std::vector<Rect2> holes;
      for (const auto& hole : f.holes)
        if (hole.u0 >= e0 - kTol && hole.u1 <= e1 + kTol && hole.u0 >= p0 - kTol &&
            hole.u1 <= p1 + kTol)
          holes.push_back({hole.u0 - e0, hole.u1 - e0, hole.v0, hole.v1});
      std::vector<Vector2d> pts;
      std::vector<Eigen::Vector3i> tris;
      TriangulateRectWithHoles(e1 - e0, h, holes, &pts, &tris);
      const int base = static_cast<int>(part.positions.size());
      for (const auto& p : pts) pb.AddVertex(f.P(e0 + p.x(), p.y(), -t_));
      for (const auto& t : tris) part.triangles.emplace_back(base + t[0], base + t[1], base + t[2]);
      e.polygons.push_back({f.P(e0, 0, -t_), f.P(e1, 0, -t_), f.P(e1, h, -t_), f.P(e0, h, -t_)});
    }
    if (part.triangles.empty()) continue;
    Push(std::move(part));
    facades_.push_back(e);
  }
}

void Generator::EmitFloorsAndCeilings() {
  const int fm = Mat("floor", spec_.materials.floor);
  const int cm = Mat("ceiling", spec_.materials.ceiling);
  for (const RoomData& r : rooms_) {
    const auto tris = TriangulatePolygon(r.poly);
    for (int k = 0; k < 2; ++k) {
      const bool floor = k == 0;
      const std::string id = (floor ? "floor_" : "ceiling_") + r.id;
      const double z = floor ? r.z0 : r.z1;
      MeshPart part = NewPart(id, id, floor ? ElementClass::kFloor : ElementClass::kCeiling, "",
                              r.id, floor ? fm : cm);
      PartBuilder pb(&part);
      for (const auto& p : r.poly) pb.AddVertex(Lift(p, z));
      for (const auto& t : tris)
        part.triangles.push_back(floor ? t : Eigen::Vector3i(t[0], t[2], t[1]));
      Push(std::move(part));
      StructuralElement e;
      e.id = id;
      e.element_class = floor ? ElementClass::kFloor : ElementClass::kCeiling;
      e.rooms = {r.id};
      std::vector<Vector3d> poly;
      for (const auto& p : r.poly) poly.push_back(Lift(p, z));
      if (!floor) std::reverse(poly.begin(), poly.end());
      e.polygons = {poly};
      e.normal = floor ? Vector3d::UnitZ() : Vector3d(-Vector3d::UnitZ());
      out_.truth.elements.push_back(e);
    }
  }
}

void Generator::EmitColumns() {
  const int mat = Mat("column", spec_.materials.column);
  for (std::size_t i = 0; i < spec_.columns.size(); ++i) {
    const ColumnSpec& c = spec_.columns[i];
    const RoomData& r = rooms_[columns_[i].room];
    const Polygon2& fp = columns_[i].footprint;
    MeshPart part = NewPart(c.id, c.id, ElementClass::kColumn, c.shape, r.id, mat);
    PartBuilder(&part).AddPrism(fp, r.z0, r.z1, false);
    Push(std::move(part));
    StructuralElement e;
    e.id = c.id;
    e.element_class = ElementClass::kColumn;
    e.rooms = {r.id};
    for (std::size_t k = 0; k < fp.size(); ++k) {
      const Vector2d &a = fp[k], &b = fp[(k + 1) % fp.size()];
      e.polygons.push_back({Lift(a, r.z0), Lift(b, r.z0), Lift(b, r.z1), Lift(a, r.z1)});
    }
    e.normal = Vector3d::UnitZ();
    out_.truth.elements.push_back(e);
  }
}

}  // namespace mopad::scenes::gen
