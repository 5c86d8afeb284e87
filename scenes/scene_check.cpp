#include "scenes/scene_check.h"

#include <algorithm>
#include <cmath>
#include <Eigen/Eigenvalues>
#include <deque>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/format.h"
#include "common/frames.h"
#include "scenes/geometry.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kSurfaceTol = 1e-3;    // m, "on its host within 1 mm"
constexpr double kPlacementTol = 5e-3;  // m, BSC geometry centre/size vs its truth entry

constexpr double kOverlapArea = 1e-4;  // m^2, interiors of touching rooms (version 2)
// m: a leaf this much narrower or wider than its opening is hung in another hole (the leaves
// made for the truth are 6 mm narrower than the opening: 3 mm clearance at each jamb).
constexpr double kLeafWidthTol = 0.03;

Polygon2 ClipConvex(const Polygon2& p, const Vector2d& a, const Vector2d& b) {
  // Keeps the part of convex p left of the directed line a -> b.
  Polygon2 out;
  auto side = [&](const Vector2d& x) {
    const Vector2d d = b - a, e = x - a;
    return d.x() * e.y() - d.y() * e.x();
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vector2d& s = p[i];
    const Vector2d& q = p[(i + 1) % p.size()];
    const double ds = side(s), dq = side(q);
    if (ds >= 0.0) out.push_back(s);
    if ((ds > 0.0 && dq < 0.0) || (ds < 0.0 && dq > 0.0))
      out.push_back(s + ds / (ds - dq) * (q - s));
  }
  return out;
}

// Area of the intersection of two simple polygons (sum over pairs of their ear triangles).
double InteriorOverlapArea(const Polygon2& a_in, const Polygon2& b_in) {
  Polygon2 a = a_in, b = b_in;
  if (SignedArea(a) < 0) std::reverse(a.begin(), a.end());
  if (SignedArea(b) < 0) std::reverse(b.begin(), b.end());
  double area = 0.0;
  for (const auto& ta : TriangulatePolygon(a))
    for (const auto& tb : TriangulatePolygon(b)) {
      Polygon2 p{a[ta[0]], a[ta[1]], a[ta[2]]};
      for (int k = 0; k < 3 && p.size() >= 3; ++k) p = ClipConvex(p, b[tb[k]], b[tb[(k + 1) % 3]]);
      if (p.size() >= 3) area += std::abs(SignedArea(p));
    }
  return area;
}

using PartsOf = std::map<std::string, std::vector<const MeshPart*>>;

// A door without a leaf (a doorway: leaf_thickness 0) has no geometry of its own.
bool Leafless(const Opening& o) { return o.type == OpeningType::kDoor && o.leaf_thickness <= 0.0; }

void CountTruth(const Scene& scene, const GroundTruth& t, CheckReport* rep) {
  rep->triangles = scene.TriangleCount();
  rep->rooms = static_cast<int>(t.rooms.size());
  for (const auto& e : t.elements) {
    rep->walls += e.element_class == ElementClass::kWall;
    rep->floors += e.element_class == ElementClass::kFloor;
    rep->ceilings += e.element_class == ElementClass::kCeiling;
    rep->columns += e.element_class == ElementClass::kColumn;
  }
  for (const auto& o : t.openings) {
    if (o.type == OpeningType::kWindow) {
      ++rep->windows;
      continue;
    }
    ++rep->doors;
    rep->doors_open += o.state == DoorState::kOpen;
    rep->doors_semi_open += o.state == DoorState::kSemiOpen;
    rep->doors_closed += o.state == DoorState::kClosed;
  }
  rep->service_components = static_cast<int>(t.service_components.size());
  rep->furniture = static_cast<int>(t.furniture.size());
}

// 1. Ids both ways, and classes. Fills `parts_of` (truth id -> its parts).
void CheckIds(const Scene& scene, const GroundTruth& t, PartsOf* parts_of,
              std::vector<std::string>* errors) {
  enum class Kind { kElement, kOpening, kBsc, kFurniture, kDetail };
  std::map<std::string, std::pair<Kind, std::size_t>> truth_ids;
  for (std::size_t i = 0; i < t.elements.size(); ++i)
    truth_ids[t.elements[i].id] = {Kind::kElement, i};
  for (std::size_t i = 0; i < t.openings.size(); ++i)
    truth_ids[t.openings[i].id] = {Kind::kOpening, i};
  for (std::size_t i = 0; i < t.service_components.size(); ++i)
    truth_ids[t.service_components[i].id] = {Kind::kBsc, i};
  for (std::size_t i = 0; i < t.furniture.size(); ++i)
    truth_ids[t.furniture[i].id] = {Kind::kFurniture, i};
  for (std::size_t i = 0; i < t.details.size(); ++i)
    truth_ids[t.details[i].id] = {Kind::kDetail, i};
  for (const MeshPart& p : scene.parts) {
    if (p.triangles.empty()) continue;
    if (p.element_id.empty()) {
      errors->push_back("part '" + p.name + "' has no truth id");
      continue;
    }
    auto it = truth_ids.find(p.element_id);
    if (it == truth_ids.end()) {
      errors->push_back("part '" + p.name + "' has id '" + p.element_id +
                        "' that is not in the truth");
      continue;
    }
    (*parts_of)[p.element_id].push_back(&p);
    const auto [kind, idx] = it->second;
    const ElementClass c = p.element_class;
    bool ok = true;
    switch (kind) {
      case Kind::kElement:
        ok = c == t.elements[idx].element_class;
        break;
      case Kind::kOpening:
        ok = t.openings[idx].type == OpeningType::kDoor
                 ? (c == ElementClass::kDoorFrame || c == ElementClass::kDoorLeaf)
                 : (c == ElementClass::kWindowFrame || c == ElementClass::kWindowGlass);
        break;
      case Kind::kBsc:
        ok = c == ElementClass::kServiceComponent &&
             p.subclass == t.service_components[idx].bsc_class;
        break;
      case Kind::kFurniture:
        ok = c == ElementClass::kFurniture && p.subclass == t.furniture[idx].type;
        break;
      case Kind::kDetail:
        ok = c == ElementClass::kClutter && p.subclass == t.details[idx].type;
        break;
    }
    if (!ok)
      errors->push_back("part '" + p.name + "' class '" + std::string(ToString(c)) + "/" +
                        p.subclass + "' disagrees with the truth of '" + p.element_id + "'");
  }
  for (const auto& [id, kind] : truth_ids)
    if (!parts_of->count(id) &&
        !(kind.first == Kind::kOpening && Leafless(t.openings[kind.second])))
      errors->push_back("truth id '" + id + "' has no triangles");
}

// 2. Openings cut into their walls.
void CheckOpeningsCut(const GroundTruth& t, PartsOf* parts_of, std::vector<std::string>* errors) {
  for (const Opening& o : t.openings) {
    for (const std::string& wid : o.host_walls) {
      const StructuralElement* w = t.FindElement(wid);
      if (!w) {
        errors->push_back("opening '" + o.id + "' host wall '" + wid + "' missing");
        continue;
      }
      auto uv = [&](const Vector3d& p) {
        return Vector2d((p - w->origin).dot(w->u_axis), p.z() - w->origin.z());
      };
      Eigen::AlignedBox2d rect;
      for (const auto& c : o.corners) rect.extend(uv(c));
      const Polygon2 inner{{rect.min().x() + kSurfaceTol, rect.min().y() + kSurfaceTol},
                           {rect.max().x() - kSurfaceTol, rect.min().y() + kSurfaceTol},
                           {rect.max().x() - kSurfaceTol, rect.max().y() - kSurfaceTol},
                           {rect.min().x() + kSurfaceTol, rect.max().y() - kSurfaceTol}};
      int covering = 0;
      for (const MeshPart* p : (*parts_of)[wid]) {
        for (const auto& tri : p->triangles) {
          Polygon2 q;
          for (int k = 0; k < 3; ++k) q.push_back(uv(p->positions[tri[k]].cast<double>()));
          if (std::abs(SignedArea(q)) < 1e-12) continue;
          if (ConvexOverlap(q, inner)) ++covering;
        }
      }
      if (covering > 0)
        errors->push_back("opening '" + o.id + "' is not cut into wall '" + wid +
                          "': " + std::to_string(covering) + " wall triangle(s) cover it");
    }
  }
}

// 3. BSCs on their host surface, inside its extent, not over an opening.
void CheckServiceComponents(const GroundTruth& t, const PartsOf& parts_of,
                            std::vector<std::string>* errors) {
  for (const ServiceComponent& b : t.service_components) {
    const StructuralElement* h = t.FindElement(b.host);
    if (!h) {
      errors->push_back("bsc '" + b.id + "' host '" + b.host + "' missing");
      continue;
    }
    const auto it = parts_of.find(b.id);
    if (it == parts_of.end()) continue;
    double dmin = 1e9;
    bool outside = false;
    Eigen::AlignedBox2d footprint;
    if (h->element_class == ElementClass::kWall) {
      for (const MeshPart* p : it->second)
        for (const auto& v : p->positions) {
          const Vector3d q = v.cast<double>();
          dmin = std::min(dmin, (q - h->origin).dot(h->normal));
          const Vector2d uv((q - h->origin).dot(h->u_axis), q.z() - h->origin.z());
          footprint.extend(uv);
          outside = outside || uv.x() < -kSurfaceTol || uv.x() > h->length + kSurfaceTol ||
                    uv.y() < -kSurfaceTol || uv.y() > h->height + kSurfaceTol;
        }
      if (std::abs((b.centre - h->origin).dot(h->normal)) > kSurfaceTol)
        errors->push_back("bsc '" + b.id + "' truth centre is not on wall '" + h->id + "'");
      // The geometry sits where the truth says: footprint centre and size in the wall's (u, v).
      const Vector2d c_uv((b.centre - h->origin).dot(h->u_axis), b.centre.z() - h->origin.z());
      if (!footprint.isEmpty() && ((footprint.center() - c_uv).norm() > kPlacementTol ||
                                   std::abs(footprint.sizes().x() - b.size.x()) > kPlacementTol ||
                                   std::abs(footprint.sizes().y() - b.size.y()) > kPlacementTol))
        errors->push_back(
            "bsc '" + b.id + "' geometry does not match its truth centre/size on wall '" + h->id +
            "'; got centre offset " +
            FormatNumbers("%.4g", (footprint.center() - c_uv).norm() * 1000.0) + " mm");
      for (const Opening& o : t.openings) {
        if (o.host_walls.empty()) continue;
        bool hosted = false;
        for (const auto& wid : o.host_walls) hosted = hosted || wid == h->id;
        if (!hosted) continue;
        Eigen::AlignedBox2d r;
        for (const auto& c : o.corners)
          r.extend(Vector2d((c - h->origin).dot(h->u_axis), c.z() - h->origin.z()));
        if (!r.intersection(footprint).isEmpty() && r.intersection(footprint).volume() > 1e-8)
          errors->push_back("bsc '" + b.id + "' overlaps opening '" + o.id + "'");
      }
    } else if (h->element_class == ElementClass::kCeiling && !h->polygons.empty()) {
      const double zc = h->polygons[0][0].z();
      Polygon2 poly;
      for (const auto& p : h->polygons[0]) poly.emplace_back(p.x(), p.y());
      if (SignedArea(poly) < 0) std::reverse(poly.begin(), poly.end());
      for (const MeshPart* p : it->second)
        for (const auto& v : p->positions) {
          dmin = std::min(dmin, zc - static_cast<double>(v.z()));
          const Vector2d xy(v.x(), v.y());
          outside =
              outside || (!PointInPolygon(xy, poly) && DistanceToBoundary(xy, poly) > kSurfaceTol);
        }
      Eigen::AlignedBox2d xy_box;
      for (const MeshPart* p : it->second)
        for (const auto& v : p->positions) xy_box.extend(Vector2d(v.x(), v.y()));
      if (!xy_box.isEmpty() && (xy_box.center() - b.centre.head<2>()).norm() > kPlacementTol)
        errors->push_back(
            "bsc '" + b.id + "' geometry does not match its truth centre on ceiling '" + h->id +
            "'; got centre offset " +
            FormatNumbers("%.4g", (xy_box.center() - b.centre.head<2>()).norm() * 1000.0) + " mm");
      if (std::abs(b.centre.z() - zc) > kSurfaceTol)
        errors->push_back("bsc '" + b.id + "' truth centre is not on ceiling '" + h->id + "'");
    } else {
      errors->push_back("bsc '" + b.id + "' host '" + h->id + "' is neither a wall nor a ceiling");
      continue;
    }
    if (std::abs(dmin) > kSurfaceTol)
      errors->push_back("bsc '" + b.id + "' back is " + FormatNumbers("%.4g", dmin * 1000.0) +
                        " mm from its host '" + h->id + "'");
    if (outside) errors->push_back("bsc '" + b.id + "' extends outside its host '" + h->id + "'");
  }
}

// 4. Rooms do not overlap. Version 1 (walls between all rooms): not even touch. Version 2
// (open passages): rooms may share a boundary, their interiors must not overlap.
void CheckRoomsApart(const GroundTruth& t, std::vector<std::string>* errors) {
  for (std::size_t i = 0; i < t.rooms.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const Polygon2& a = t.rooms[i].polygon;
      const Polygon2& b = t.rooms[j].polygon;
      if (a.size() < 3 || b.size() < 3) continue;
      bool overlap = PolygonsIntersect(a, b);
      if (overlap && t.format_version >= kTruthFormatVersionPassages) {
        try {
          overlap = InteriorOverlapArea(a, b) > kOverlapArea;
        } catch (const std::invalid_argument&) {  // not simple: keep the strict answer
        }
      }
      if (overlap)
        errors->push_back("rooms '" + t.rooms[i].id + "' and '" + t.rooms[j].id + "' overlap");
    }
}

// 5. Reachability through open doors wide enough for the robot. A room no such door reaches is
// a property of the building (a locked room, a door drawn closed, a room reached by stairs), not
// a defect of the scene: a warning.
void CheckReachable(const GroundTruth& t, std::vector<std::string>* warnings, int* unreachable) {
  if (!t.rooms.empty()) {
    std::map<std::string, std::vector<std::string>> graph = OpenDoorGraph(t);
    std::set<std::string> seen{t.rooms[0].id};
    std::deque<std::string> queue{t.rooms[0].id};
    while (!queue.empty()) {
      const std::string r = queue.front();
      queue.pop_front();
      for (const auto& n : graph[r])
        if (seen.insert(n).second) queue.push_back(n);
    }
    for (const Room& r : t.rooms)
      if (!seen.count(r.id) && ++*unreachable)
        warnings->push_back("room '" + r.id + "' is not reachable from '" + t.rooms[0].id +
                            "' through open doors of clear width >= " +
                            FormatNumbers("%.4g", kMinClearDoorWidth) +
                            " m (a property of the building: the robot cannot visit it)");
  }
}

// 6. Door leaves at their angle; states consistent. The leaf's angle is the direction of its
// own width (the principal horizontal axis of its vertices, pointing away from the hinge), so a
// leaf narrower or wider than its opening (a BIM leaf hung in a hole measured on the other side
// of the wall) is still measured at its true angle; that mismatch is a warning.
void CheckDoorLeaves(const GroundTruth& t, const PartsOf& parts_of,
                     std::vector<std::string>* errors, std::vector<std::string>* warnings) {
  for (const Opening& o : t.openings) {
    if (o.type != OpeningType::kDoor) continue;
    if (o.state != DoorStateFromAngle(o.opening_angle))
      errors->push_back("door '" + o.id + "' state '" + std::string(ToString(o.state)) +
                        "' does not match its angle " +
                        FormatNumbers("%.4g", RadToDeg(o.opening_angle)) + " deg");
    const StructuralElement* w = o.host_walls.empty() ? nullptr : t.FindElement(o.host_walls[0]);
    if (!w) continue;
    std::vector<Vector2d> xy;
    const auto it = parts_of.find(o.id);
    if (it != parts_of.end())
      for (const MeshPart* p : it->second) {
        if (p->element_class != ElementClass::kDoorLeaf) continue;
        for (const auto& v : p->positions) xy.emplace_back(v.x(), v.y());
      }
    if (xy.empty()) {
      if (!Leafless(o)) errors->push_back("door '" + o.id + "' has no leaf");
      continue;
    }
    Vector2d c = Vector2d::Zero();
    for (const auto& p : xy) c += p;
    c /= static_cast<double>(xy.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : xy) cov += (p - c) * (p - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    Vector2d axis = eig.eigenvectors().col(1);  // largest eigenvalue: the leaf's width
    if (axis.dot(c - o.hinge_point.head<2>()) < 0.0) axis = -axis;
    double width = 0.0, lo = 1e300, hi = -1e300;
    for (const auto& p : xy) {
      lo = std::min(lo, axis.dot(p));
      hi = std::max(hi, axis.dot(p));
    }
    width = hi - lo;
    const double u_c = 0.5 * (o.u0 + o.u1);
    const double u_h = (o.hinge_point - w->origin).dot(w->u_axis);
    const Vector3d d = w->u_axis * (u_c > u_h ? 1.0 : -1.0);
    const Vector3d nn = o.hinge_axis.cross(d);
    const Vector3d a3(axis.x(), axis.y(), 0.0);
    const double measured = std::atan2(a3.dot(nn), a3.dot(d));
    if (std::abs(WrapAngle(measured - o.opening_angle)) > DegToRad(0.5))
      errors->push_back("door '" + o.id + "' leaf is at " +
                        FormatNumbers("%.4g", RadToDeg(measured)) + " deg, expected " +
                        FormatNumbers("%.4g", RadToDeg(o.opening_angle)) + " deg");
    if (std::abs(width - (o.u1 - o.u0)) > kLeafWidthTol)
      warnings->push_back("door '" + o.id + "' leaf is " + FormatNumbers("%.3g", width) +
                          " m wide in an opening " + FormatNumbers("%.3g", o.u1 - o.u0) +
                          " m wide");
  }
}

}  // namespace

std::map<std::string, std::vector<std::string>> OpenDoorGraph(const GroundTruth& t) {
  std::map<std::string, std::vector<std::string>> graph;
  for (const RoomConnection& c : t.connections) {
    if (c.room_b.empty()) continue;
    if (!c.door.empty()) {  // else an open passage (format version 2)
      const Opening* o = t.FindOpening(c.door);
      if (!o || o->state != DoorState::kOpen ||
          (o->u1 - o->u0) - o->leaf_thickness < kMinClearDoorWidth)
        continue;
    }
    graph[c.room_a].push_back(c.room_b);
    graph[c.room_b].push_back(c.room_a);
  }
  return graph;
}

std::string CheckReport::Summary() const {
  std::ostringstream s;
  s << "rooms " << rooms << ", walls " << walls << ", floors " << floors << ", ceilings "
    << ceilings << ", columns " << columns << "\n"
    << "doors " << doors << " (open " << doors_open << ", semi-open " << doors_semi_open
    << ", closed " << doors_closed << "), windows " << windows << "\n"
    << "service components " << service_components << ", furniture " << furniture << ", triangles "
    << triangles << "\n";
  for (const auto& e : errors) s << "error: " << e << "\n";
  for (const auto& w : warnings) s << "warning: " << w << "\n";
  s << (errors.empty() ? "valid" : "INVALID: " + std::to_string(errors.size()) + " error(s)")
    << "\n";
  return s.str();
}

CheckReport CheckScene(const Scene& scene, const GroundTruth& t) {
  CheckReport rep;
  CountTruth(scene, t, &rep);
  PartsOf parts_of;
  CheckIds(scene, t, &parts_of, &rep.errors);
  CheckOpeningsCut(t, &parts_of, &rep.errors);
  CheckServiceComponents(t, parts_of, &rep.errors);
  CheckRoomsApart(t, &rep.errors);
  CheckReachable(t, &rep.warnings, &rep.unreachable_rooms);
  CheckDoorLeaves(t, parts_of, &rep.errors, &rep.warnings);
  return rep;
}

}  // namespace mopad::scenes
