// From IfcSpace volumes to rooms: the storey to import, each space's footprint outline, the
// room's floor and ceiling heights (snapped to the slab faces that cover it), and the shift that
// puts the storey's lowest room floor at z = 0 (scenes/bim_import_internal.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common/error.h"
#include "scenes/assimp_loader.h"
#include "scenes/bim_import_internal.h"

namespace mopad::scenes::bim {

bool Footprint(const std::vector<Poly3>& tris, double z_min, double tol, Polygon2* out,
               std::string* why) {
  // The bottom face's triangles in plan (seen from above a downward face runs clockwise: the
  // boundary takes any winding). T-junctions, common in BRep spaces, are split there.
  std::vector<std::vector<Vector2d>> faces;
  for (const Poly3& t : tris) {
    if (NormalOf(t).z() > -kFacingCos) continue;
    bool low = true;
    for (const auto& p : t) low = low && std::abs(p.z() - z_min) <= tol;
    if (!low) continue;
    faces.push_back({t[0].head<2>(), t[1].head<2>(), t[2].head<2>()});
  }
  const TiledBoundary boundary = BoundaryOfTiledPolygons(faces, 1e-4);
  if (boundary.problem == TiledBoundary::kTouchesItself) {
    *why = "its bottom outline touches itself";
    return false;
  }
  if (boundary.problem == TiledBoundary::kNotClosed) {
    *why = "its bottom outline is not closed";
    return false;
  }
  if (boundary.loops.empty()) {
    *why = "no downward face at its lowest point";
    return false;
  }
  // The largest loop is the outline.
  Polygon2 best;
  for (const auto& loop : boundary.loops)
    if (std::abs(SignedArea(loop)) > std::abs(SignedArea(best))) best = loop;
  // Drop collinear vertices.
  for (bool changed = true; changed && best.size() > 3;) {
    changed = false;
    for (std::size_t i = 0; i < best.size() && best.size() > 3; ++i) {
      const Vector2d& p = best[(i + best.size() - 1) % best.size()];
      const Vector2d& c = best[i];
      const Vector2d& n = best[(i + 1) % best.size()];
      const Vector2d d1 = c - p, d2 = n - c;
      if (std::abs(d1.x() * d2.y() - d1.y() * d2.x()) <= 1e-6 * d1.norm() * d2.norm() + 1e-12) {
        best.erase(best.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  if (SignedArea(best) < 0.0) std::reverse(best.begin(), best.end());
  // Start at the lowest-leftmost vertex: independent of the file's vertex order.
  std::size_t s = 0;
  for (std::size_t i = 1; i < best.size(); ++i)
    if (best[i].y() < best[s].y() - 1e-9 ||
        (std::abs(best[i].y() - best[s].y()) <= 1e-9 && best[i].x() < best[s].x()))
      s = i;
  std::rotate(best.begin(), best.begin() + static_cast<long>(s), best.end());
  if (!IsSimplePolygon(best, why)) return false;
  if (boundary.loops.size() > 1)
    *why = std::to_string(boundary.loops.size()) + " outlines; the largest is used";
  *out = best;
  return true;
}

std::string Importer::StoreyOf(const std::string& node_path) {
  std::size_t start = 0;
  while (start <= node_path.size()) {
    std::size_t end = node_path.find('/', start);
    if (end == std::string::npos) end = node_path.size();
    const std::string seg = node_path.substr(start, end - start);
    if (IfcClassFromNodeName(seg) == "IfcBuildingStorey") return seg;
    start = end + 1;
  }
  return "";
}

void Importer::SelectStorey() {
  // Storeys in order of first appearance, with their lowest element.
  std::vector<std::string> storeys;
  std::map<std::string, double> low;
  for (std::size_t i = 0; i < scene_.parts.size(); ++i) {
    if (merged_parts_.count(i)) continue;
    const std::string s = StoreyOf(scene_.parts[i].name);
    if (s.empty()) continue;
    if (!low.count(s)) {
      storeys.push_back(s);
      low[s] = 1e300;
    }
    for (const auto& v : scene_.parts[i].positions) low[s] = std::min(low[s], double(v.z()));
  }
  std::sort(storeys.begin(), storeys.end(), [&](const std::string& a, const std::string& b) {
    return low[a] != low[b] ? low[a] < low[b] : a < b;
  });
  if (storeys.empty()) {
    if (!p_.storey.empty())
      throw InputError(path_, "the model names no storeys (no IfcBuildingStorey node paths)",
                       "--storey " + p_.storey, "no --storey for this file");
    out_.report.push_back(
        "no IfcBuildingStorey in the node paths: the whole model is one "
        "storey");
  } else if (p_.storey.empty()) {
    // The lowest storey with a space volume (foundation or site levels often have none).
    std::set<std::string> with_spaces;
    for (std::size_t i = 0; i < scene_.parts.size(); ++i)
      if (!merged_parts_.count(i) && scene_.parts[i].element_class == ElementClass::kSpace &&
          !scene_.parts[i].triangles.empty())
        with_spaces.insert(StoreyOf(scene_.parts[i].name));
    storey_ = storeys.front();
    for (const std::string& st : storeys)
      if (with_spaces.count(st)) {
        storey_ = st;
        break;
      }
    if (storeys.size() > 1)
      out_.report.push_back("storey " + StoreyName(storey_) + " (the lowest with spaces of " +
                            std::to_string(storeys.size()) + "; choose with --storey)");
  } else {
    std::string names;
    for (const std::string& s : storeys) {
      const std::string full = StoreyName(s);
      if (p_.storey == full || p_.storey == NodeLabel(s) || p_.storey == NodeGuid(s) ||
          p_.storey == s || NoSpaces(p_.storey) == NodeLabel(s))
        storey_ = s;
      names += (names.empty() ? "" : ", ") + std::string("'") + full + "'";
    }
    if (storey_.empty())
      throw InputError(path_, "no such storey", "'" + p_.storey + "'", "one of " + names);
  }
  const std::string guid = NodeGuid(storey_);
  out_.truth.storeys.push_back(
      {storey_.empty() ? "storey_0" : CleanUtf8(NoSpaces(StoreyName(storey_))), 0.0, 3.0});
  for (std::size_t i = 0; i < storeys.size(); ++i)
    if (storeys[i] == storey_ && i + 1 < storeys.size()) next_storey_low_ = low[storeys[i + 1]];
  for (std::size_t i = 0; i < scene_.parts.size(); ++i)
    if (storey_.empty() || StoreyOf(scene_.parts[i].name) == storey_) storey_parts_.insert(i);
  for (Element& e : elements_)
    for (std::size_t i : e.parts) e.in_storey = e.in_storey || storey_parts_.count(i) > 0;
}

std::string Importer::StoreyName(const std::string& node) const {
  const auto it = names_.find(NodeGuid(node));
  return it != names_.end() && !it->second.empty() ? it->second : NodeLabel(node);
}

std::vector<Poly3> Importer::Triangles(const Element& e) const {
  std::vector<Poly3> out;
  for (std::size_t i : e.parts) {
    const MeshPart& part = scene_.parts[i];
    for (const auto& t : part.triangles)
      out.push_back({part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                     part.positions[t[2]].cast<double>()});
  }
  return out;
}

void Importer::MakeRooms() {
  int spaces = 0;
  for (const Element& e : elements_) {
    if (e.role != Role::kSpace || !e.in_storey || Lower(e.ifc) != "ifcspace") continue;
    ++spaces;
    const std::vector<Poly3> tris = Triangles(e);
    if (tris.empty()) {
      out_.report.push_back(NiceName(e.node) + ": space without representation; no room");
      continue;
    }
    Polygon2 poly;
    std::string why;
    if (!Footprint(tris, e.box.min().z(), p_.plane_tolerance, &poly, &why)) {
      out_.report.push_back(NiceName(e.node) + ": no usable footprint (" + why + "); no room");
      continue;
    }
    if (!why.empty()) out_.report.push_back(NiceName(e.node) + ": " + why);
    RoomData r;
    r.node = e.node;
    r.poly = poly;
    r.room.id = "R" + std::to_string(rooms_.size() + 1);
    r.room.storey = out_.truth.storeys[0].id;
    r.room.floor_z = e.box.min().z();
    r.room.ceiling_z = e.box.max().z();
    rooms_.push_back(r);
    out_.report.push_back("room " + r.room.id + " = " + NiceName(e.node) + ", " +
                          std::to_string(poly.size()) + " corners, " + Fmt(SignedArea(poly), 2) +
                          " m2, height " + Fmt(r.room.ceiling_z - r.room.floor_z, 2) + " m");
  }
  // Spaces the STEP text puts on this storey that assimp gave no geometry at all.
  const auto listed = storey_spaces_.find(NodeGuid(storey_));
  if (listed != storey_spaces_.end())
    for (const std::string& guid : listed->second) {
      bool seen = false;
      for (const Element& e : elements_) seen = seen || NodeGuid(e.node) == guid;
      if (seen) continue;
      ++spaces;
      out_.report.push_back("IfcSpace '" + names_[guid] + "' (" + guid +
                            "): space without representation; no room");
    }
  // Elements the STEP text puts on this storey that assimp made no geometry for.
  static const std::set<std::string> kNoBody = {
      "IFCANNOTATION",       "IFCGRID",   "IFCVIRTUALELEMENT", "IFCOPENINGELEMENT", "IFCSPACE",
      "IFCDISTRIBUTIONPORT", "IFCSYSTEM", "IFCZONE",           "IFCGROUP",          "IFCPROXY"};
  const auto contained = storey_contained_.find(NodeGuid(storey_));
  if (contained != storey_contained_.end()) {
    std::set<std::string> with_geometry;
    for (const Element& e : elements_) with_geometry.insert(NodeGuid(e.node));
    for (const auto& [guid, entity] : contained->second)
      if (!kNoBody.count(entity) && !with_geometry.count(guid))
        out_.report.push_back(entity + " '" + CleanUtf8(names_[guid]) + "' (" + guid +
                              "): no geometry (assimp made none); left out");
  }
  if (rooms_.empty())
    throw InputError(path_,
                     storey_.empty()
                         ? std::string("no room can be made in the model")
                         : "no room can be made on storey '" + StoreyName(storey_) + "'",
                     std::to_string(spaces) + " IfcSpace(s), none with a usable volume",
                     "IfcSpace volumes (IFC 2x3, or glTF converted with its spaces kept)");
}

double Importer::SlabCover(std::size_t r, double z, bool up) const {
  const RoomData& room = rooms_[r];
  const std::vector<Eigen::Vector3i> ears = TriangulatePolygon(room.poly);
  double area = 0.0;
  for (const Element& e : elements_) {
    if (e.role != Role::kSlab || e.box.min().z() > z + p_.plane_tolerance ||
        e.box.max().z() < z - p_.plane_tolerance)
      continue;
    for (std::size_t pi : e.parts) {
      const MeshPart& part = scene_.parts[pi];
      for (const auto& t : part.triangles) {
        const Poly3 tri{part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                        part.positions[t[2]].cast<double>()};
        const Vector3d n = NormalOf(tri);
        if (up ? n.z() < kFacingCos : n.z() > -kFacingCos) continue;
        bool on = true;
        for (const auto& q : tri) on = on && std::abs(q.z() - z) <= p_.plane_tolerance;
        if (!on) continue;
        for (const auto& ear : ears) {
          const std::vector<HalfSpace> region = EarRegion(room.poly, ear);
          Poly3 in;
          std::vector<Poly3> outside;
          Split(tri, region, &in, &outside);
          area += Area(in);
        }
      }
    }
  }
  return area / SignedArea(room.poly);
}

// The building elements are the truth of the building, a space's box is an annotation. A space
// drawn into the slab above (to the next level, as some tools do), short of the ceiling, or
// floating above its floor (a space base at 1.22 m while the storey's walls and doors stand on
// the slab at 0): the room's ceiling (floor) is the fully covering slab face nearest to the
// space's top (bottom), within [floor + 1.8 m, top + 1 m] ([lowest wall or door foot of the
// storey - 0.3 m, bottom + 0.3 m]: walls and doors stand on the floor).
void Importer::ResolveHeights() {
  double feet = 1e300;  // the lowest foot of the storey's walls and doors
  for (const Element& e : elements_)
    if (e.in_storey && !e.merged && (e.role == Role::kWall || e.role == Role::kDoor) &&
        !e.box.isEmpty())
      feet = std::min(feet, e.box.min().z());
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    Room& room = rooms_[r].room;
    for (bool up : {true, false}) {
      const double z_space = up ? room.floor_z : room.ceiling_z;
      if (SlabCover(r, z_space, up) >= kFullCover) continue;
      const double lo = up ? std::min(z_space, feet) - 0.3 : room.floor_z + 1.8;
      const double hi = up ? z_space + 0.3 : z_space + 1.0;
      // Candidate planes (mm): slab faces facing the right way over the room's box.
      Eigen::AlignedBox2d room_box;
      for (const auto& v : rooms_[r].poly) room_box.extend(v);
      std::set<long long> heights;
      for (const Element& e : elements_) {
        if (e.role != Role::kSlab) continue;
        for (std::size_t pi : e.parts) {
          const MeshPart& part = scene_.parts[pi];
          for (const auto& t : part.triangles) {
            const Poly3 tri{part.positions[t[0]].cast<double>(),
                            part.positions[t[1]].cast<double>(),
                            part.positions[t[2]].cast<double>()};
            const Vector3d n = NormalOf(tri);
            if ((up ? n.z() < kFacingCos : n.z() > -kFacingCos) || tri[0].z() < lo ||
                tri[0].z() > hi)
              continue;
            Eigen::AlignedBox2d box;
            for (const auto& q : tri) box.extend(q.head<2>());
            if (box.intersects(room_box)) heights.insert(std::llround(tri[0].z() * 1000.0));
          }
        }
      }
      double best = 0.0, best_d = 1e300;
      for (long long h : heights) {
        // The exact height of that plane: a vertex's, not the rounded value.
        const double z = static_cast<double>(h) / 1000.0;
        const double d = std::abs(z - z_space);
        if (d < best_d && SlabCover(r, z, up) >= kFullCover) {
          best = z;
          best_d = d;
        }
      }
      if (best_d > 1e299) continue;  // FloorsAndCeilings refuses or repairs
      // Snap to the plane's own height (the vertices' mean within the tolerance).
      double sum = 0.0, n = 0.0;
      for (const Element& e : elements_) {
        if (e.role != Role::kSlab) continue;
        for (std::size_t pi : e.parts)
          for (const auto& v : scene_.parts[pi].positions)
            if (std::abs(v.z() - best) <= 1e-3) sum += v.z(), n += 1.0;
      }
      const double z = n > 0 ? sum / n : best;
      // Always applied: the slab is there; the space's box is not.
      Repair(up ? "floor height" : "ceiling height",
             room.id + " (" + NiceName(rooms_[r].node) + ")",
             Fmt(z_space) + " m (the space's " + (up ? "bottom" : "top") + ")",
             Fmt(z) + " m (the slab face " + (up ? "under" : "over") + " it)", true, "");
      (up ? room.floor_z : room.ceiling_z) = z;
    }
  }
}

void Importer::Shift() {
  z0_ = 1e300;
  double top = -1e300;
  for (const RoomData& r : rooms_) {
    z0_ = std::min(z0_, r.room.floor_z);
    top = std::max(top, r.room.ceiling_z);
  }
  // The storey's elements, and from elsewhere what reaches into its height band: the slab
  // above (its underside is the ceiling), the site, elements of no storey.
  const double lo = z0_ - 0.01, hi = top + 0.01;
  for (Element& e : elements_) {
    if (IfcClassFromNodeName(e.node) == "IfcSite" && !p_.keep_site) {
      if (!e.parts.empty() && !e.box.isEmpty())
        out_.report.push_back(NiceName(e.node) + ": terrain left out (--keep-site keeps it)");
      e.in_storey = false;
      continue;
    }
    if (e.in_storey || e.role == Role::kSpace) continue;
    const bool slab = e.role == Role::kSlab || IfcClassFromNodeName(e.node) == "IfcBeam";
    const double zmin = e.box.min().z(), zmax = e.box.max().z();
    e.in_storey = zmax >= lo && (slab ? zmin <= hi : zmin < top - 0.01);
    if (e.merged) e.in_storey = zmax >= lo && zmin <= hi;
  }
  const double lowest = z0_;
  if (p_.as_is) {  // the file's heights: only the band above used the lowest floor
    out_.report.push_back("storey floor at z = " + Fmt(z0_) + " m in the file: kept (as it is)");
    z0_ = 0.0;
  }
  for (MeshPart& part : scene_.parts)
    for (auto& v : part.positions) v.z() = static_cast<float>(v.z() - z0_);
  for (Element& e : elements_)
    if (!e.box.isEmpty()) e.box.translate(Vector3d(0, 0, -z0_));
  for (RoomData& r : rooms_) {
    r.room.floor_z -= z0_;
    r.room.ceiling_z -= z0_;
    r.room.polygon = r.poly;
    r.ears = TriangulatePolygon(r.poly);
    top_ = std::max(top_, r.room.ceiling_z);
  }
  Storey& s = out_.truth.storeys[0];
  s.elevation = p_.as_is ? lowest : 0.0;
  s.height = next_storey_low_ < 1e299 ? next_storey_low_ - z0_ : top_;
  if (!(s.height > 0.0)) s.height = top_;
  if (!p_.as_is)
    out_.report.push_back("storey floor at z = " + Fmt(z0_) + " m in the file: moved to 0");
}

}  // namespace mopad::scenes::bim
