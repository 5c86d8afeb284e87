// Doors, windows and open passages of a BIM import: each opening's hole in the room-side wall
// faces, the window kept as modelled, the door's BIM leaf replaced by a generated leaf hinged at
// a jamb and opened to the requested angle, and the wall-less stretches rooms share
// (scenes/bim_import_internal.h).
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "common/frames.h"
#include "common/polygon.h"
#include "scenes/bim_import_internal.h"
#include "scenes/scene_check.h"

namespace mopad::scenes::bim {

std::vector<std::pair<double, double>> Coverage(const Face& f, bool vertical, double at) {
  std::vector<std::pair<double, double>> iv;
  for (const auto& [e, poly] : f.pieces) {
    double lo = 1e300, hi = -1e300;
    const std::size_t k = poly.size();
    for (std::size_t i = 0; i < k; ++i) {
      const Vector3d& p = poly[i];
      const Vector3d& q = poly[(i + 1) % k];
      const double sp = vertical ? f.U(p) : p.z(), sq = vertical ? f.U(q) : q.z();
      const double op = vertical ? p.z() : f.U(p), oq = vertical ? q.z() : f.U(q);
      if ((sp - at) * (sq - at) > 0.0) continue;
      if (sp == sq) {
        lo = std::min({lo, op, oq});
        hi = std::max({hi, op, oq});
        continue;
      }
      const double t = (at - sp) / (sq - sp);
      const double o = op + t * (oq - op);
      lo = std::min(lo, o);
      hi = std::max(hi, o);
    }
    if (lo < hi) iv.emplace_back(lo, hi);
  }
  std::sort(iv.begin(), iv.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& i : iv) {
    if (!merged.empty() && i.first <= merged.back().second + 1e-5)
      merged.back().second = std::max(merged.back().second, i.second);
    else
      merged.push_back(i);
  }
  return merged;
}

bool GapAround(const std::vector<std::pair<double, double>>& cov, double x, double lo, double hi,
               double* g0, double* g1) {
  *g0 = lo;
  *g1 = hi;
  for (const auto& [a, b] : cov) {
    if (a <= x && x <= b) return false;
    if (b < x) *g0 = std::max(*g0, b);
    if (a > x) *g1 = std::min(*g1, a);
  }
  return *g1 > *g0;
}

std::vector<Importer::Hole> Importer::HolesAround(const Element& e) const {
  const Vector3d c = e.box.center();
  std::vector<Hole> holes;
  for (std::size_t fi = 0; fi < faces_.size(); ++fi) {
    const Face& f = faces_[fi];
    if (!f.kept) continue;
    const double w = f.W(c), u = f.U(c);
    if (w > 0.3 || w < -kOpeningReach || u < 0.0 || u > f.length) continue;
    const double v = std::clamp(c.z(), f.vmin + 0.05, f.vmax - 0.05);
    Hole h{fi, 0, 0, 0, 0, std::abs(w)};
    // The element's own extent along the face bounds the hole (an opening at an open edge).
    double eu0 = 1e300, eu1 = -1e300;
    for (int k = 0; k < 8; ++k) {
      const Vector3d corner = e.box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
      eu0 = std::min(eu0, f.U(corner));
      eu1 = std::max(eu1, f.U(corner));
    }
    if (!GapAround(Coverage(f, false, v), u, std::max(0.0, eu0 - 0.1),
                   std::min(f.length, eu1 + 0.1), &h.u0, &h.u1))
      continue;
    if (!GapAround(Coverage(f, true, 0.5 * (h.u0 + h.u1)), v, f.vmin, f.vmax, &h.v0, &h.v1))
      continue;
    if (h.u1 - h.u0 < 0.05 || h.v1 - h.v0 < 0.05) continue;
    holes.push_back(h);
  }
  std::stable_sort(holes.begin(), holes.end(),
                   [](const Hole& a, const Hole& b) { return a.dist < b.dist; });
  return holes;
}

const StructuralElement& Importer::WallOf(const Face& f) const {
  for (const auto& w : walls_)
    if (w.id == f.id) return w;
  throw std::logic_error("face without wall");
}

void Importer::FillRect(Opening* o, const Hole& h) const {
  const Face& f = faces_[h.face];
  const StructuralElement& w = WallOf(f);
  o->u0 = h.u0 - f.umin;
  o->u1 = h.u1 - f.umin;
  o->v0 = h.v0 - w.origin.z();
  o->v1 = h.v1 - w.origin.z();
  auto P = [&](double u, double v) {
    return Vector3d(w.origin + u * w.u_axis + Vector3d(0, 0, v));
  };
  o->corners = {P(o->u0, o->v0), P(o->u0, o->v1), P(o->u1, o->v1), P(o->u1, o->v0)};
}

double Importer::DoorAngleDeg(const std::string& id, const Element& e) const {
  for (const std::string& key :
       {id, NodeGuid(e.node), NodeLabel(e.node), e.node, NiceNameOnly(e.node)}) {
    const auto it = p_.door_angles_deg.find(key);
    if (!key.empty() && it != p_.door_angles_deg.end()) {
      used_door_keys_.insert(it->first);
      return it->second;
    }
  }
  return p_.door_angle_deg;
}

int Importer::LeafMaterial() {
  for (std::size_t i = 0; i < scene_.materials.size(); ++i)
    if (scene_.materials[i].name == "door_leaf") return static_cast<int>(i);
  Material m;
  m.name = "door_leaf";
  m.base_color = Eigen::Vector4f(0.55f, 0.40f, 0.25f, 1.0f);
  scene_.materials.push_back(m);
  return static_cast<int>(scene_.materials.size()) - 1;
}

void Importer::Openings() {
  int windows = 0;
  for (std::size_t ei = 0; ei < elements_.size(); ++ei) {
    const Element& e = elements_[ei];
    if (!e.in_storey || (e.role != Role::kDoor && e.role != Role::kWindow)) continue;
    const bool door = e.role == Role::kDoor;
    std::vector<Hole> holes = HolesAround(e);
    if (holes.empty()) {
      for (std::size_t pi : e.parts) AllToLeftover(ei, pi);
      out_.report.push_back(NiceName(e.node) +
                            ": no hole in a room wall of this storey "
                            "around it; kept as other");
      continue;
    }
    ReconcileHole(e, door, &holes);
    ReportHoleShape(e, holes[0]);
    Opening o;
    o.id = door ? "D" + std::to_string(++doors_) : "W" + std::to_string(++windows);
    if (const std::string guid = NodeGuid(e.node); !guid.empty()) out_.opening_guids[o.id] = guid;
    o.type = door ? OpeningType::kDoor : OpeningType::kWindow;
    const Face& f0 = faces_[holes[0].face];
    const RoomData& r0 = rooms_[f0.room];
    o.host_walls = {f0.id};
    o.rooms = {r0.room.id};
    FillRect(&o, holes[0]);
    for (const Hole& h : holes) holes_.push_back(h);
    if (door)
      AddDoor(e, holes, &o);
    else
      AddWindow(e, f0, &o);
    FillHole(o, holes[0], door);
  }
}

namespace {
constexpr double kCutTolerance = 0.03;  // m: a cut this much larger than its body is the reader's
}  // namespace

// IfcRelFillsElement says the door or window fills its IfcOpeningElement; the STEP text gives
// that opening's body. A reader's boolean cut larger than the body by more than kCutTolerance
// (assimp 5.2.5 cuts FZK-Haus AC14's EG-Fenster-6, a 1.2 m window on a 0.8 m sill, down to the
// floor) leaves a hole the building does not have: the wall is restored around the body on
// every face the hole was found in, with the opening's sill, head and jambs and, where no room
// lies behind, the wall's outside; the holes shrink to the body. The body is trusted only where
// it holds the element and the cut holds it (a frame mismatch would put it elsewhere).
void Importer::ReconcileHole(const Element& e, bool door, std::vector<Hole>* holes) {
  constexpr double kHoldMargin = 0.05;        // m: the element lies within its opening's body
  constexpr double kContainTolerance = 0.01;  // m: the body lies within the cut
  constexpr double kUnknownReach = 1.0;       // m: an unread body this near may be in the cut
  const std::string guid = NodeGuid(e.node);
  std::size_t own = opening_bodies_.size();
  for (std::size_t k = 0; k < opening_bodies_.size(); ++k)
    if (!guid.empty() && opening_bodies_[k].filling == guid) {
      if (own != opening_bodies_.size()) return;  // two openings filled by one element
      own = k;
    }
  if (own == opening_bodies_.size() || !opening_bodies_[own].complete || holes->empty()) return;
  std::vector<Vector3d> body = opening_bodies_[own].corners;
  for (Vector3d& c : body) c.z() -= z0_;
  const Face& f0 = faces_[(*holes)[0].face];
  double ou0 = 1e300, ou1 = -1e300, ov0 = 1e300, ov1 = -1e300, ow0 = 1e300;
  for (const Vector3d& c : body) {
    ou0 = std::min(ou0, f0.U(c));
    ou1 = std::max(ou1, f0.U(c));
    ov0 = std::min(ov0, c.z());
    ov1 = std::max(ov1, c.z());
    ow0 = std::min(ow0, f0.W(c));
  }
  const Vector3d ec = e.box.center();
  if (f0.U(ec) < ou0 - kHoldMargin || f0.U(ec) > ou1 + kHoldMargin || ec.z() < ov0 - kHoldMargin ||
      ec.z() > ov1 + kHoldMargin)
    return;
  // An over-cut holds the body: a body out of the cut anywhere is a frame that disagrees
  // (georeferenced files, which assimp computes partly in float), not a cut too large.
  const Hole& h0 = (*holes)[0];
  if (ou0 < h0.u0 - kContainTolerance || ou1 > h0.u1 + kContainTolerance ||
      ov0 < h0.v0 - kContainTolerance || ov1 > h0.v1 + kContainTolerance)
    return;
  // A stretch of the cut beyond the body is wall unless another opening's body is there (a
  // door beside a window in one hole, an unfilled opening under a window) or may be there (a
  // body not read, placed nearby).
  auto no_other_body = [&](double ua, double ub, double va, double vb) {
    for (std::size_t k = 0; k < opening_bodies_.size(); ++k) {
      if (k == own) continue;
      const OpeningBody& other = opening_bodies_[k];
      const double m = other.complete ? 0.0 : kUnknownReach;
      double b0 = 1e300, b1 = -1e300, c0 = 1e300, c1 = -1e300, w0 = 1e300, w1 = -1e300;
      for (const Vector3d& c : other.corners) {
        b0 = std::min(b0, f0.U(c));
        b1 = std::max(b1, f0.U(c));
        c0 = std::min(c0, c.z() - z0_);
        c1 = std::max(c1, c.z() - z0_);
        w0 = std::min(w0, f0.W(c));
        w1 = std::max(w1, f0.W(c));
      }
      if (w1 < ow0 - kHoldMargin - m || w0 > f0.w + kHoldMargin + m) continue;  // another wall
      if (b0 - m < ub - 1e-3 && b1 + m > ua + 1e-3 && c0 - m < vb - 1e-3 && c1 + m > va + 1e-3)
        return false;
    }
    return true;
  };
  const bool below = h0.v0 < ov0 - kCutTolerance && no_other_body(h0.u0, h0.u1, h0.v0, ov0);
  const bool above = h0.v1 > ov1 + kCutTolerance && no_other_body(h0.u0, h0.u1, ov1, h0.v1);
  const bool left = h0.u0 < ou0 - kCutTolerance && no_other_body(h0.u0, ou0, ov0, ov1);
  const bool right = h0.u1 > ou1 + kCutTolerance && no_other_body(ou1, h0.u1, ov0, ov1);
  if (!below && !above && !left && !right) return;
  Repair(door ? "door hole" : "window hole", NiceName(e.node) + " in " + f0.id,
         "cut u " + Fmt(h0.u0 - f0.umin, 2) + " to " + Fmt(h0.u1 - f0.umin, 2) + " m, z " +
             Fmt(h0.v0, 2) + " to " + Fmt(h0.v1, 2) + " m, its IfcOpeningElement u " +
             Fmt(ou0 - f0.umin, 2) + " to " + Fmt(ou1 - f0.umin, 2) + " m, z " + Fmt(ov0, 2) +
             " to " + Fmt(ov1, 2) + " m",
         "the wall restored around the opening", p_.repair, "--repair");
  if (p_.repair) RestoreAroundBody(body, {left, right, below, above}, holes);
}

// ReconcileHole's repair: on every face the hole was found in, the wall where the cut exceeds
// the body on the given sides of the first face, and the hole shrunk to the body.
void Importer::RestoreAroundBody(const std::vector<Vector3d>& body, const Sides& sides,
                                 std::vector<Hole>* holes) {
  const Face& f0 = faces_[(*holes)[0].face];
  const bool left = sides.left, right = sides.right, below = sides.below, above = sides.above;
  double ov0 = 1e300, ov1 = -1e300;
  for (const Vector3d& c : body) {
    ov0 = std::min(ov0, c.z());
    ov1 = std::max(ov1, c.z());
  }
  const Vector3d z = Vector3d::UnitZ();
  for (std::size_t k = 0; k < holes->size(); ++k) {
    Hole& h = (*holes)[k];
    Face& f = faces_[h.face];
    // This face's frame: the body's extent along it, the wall's depth behind it.
    double a0 = 1e300, a1 = -1e300, wmin = 1e300;
    for (const Vector3d& c : body) {
      a0 = std::min(a0, f.U(c));
      a1 = std::max(a1, f.U(c));
      wmin = std::min(wmin, f.W(c));
    }
    double depth = std::clamp(f.w - wmin, 0.0, kOpeningReach);
    // The wall's own far face, where its mesh has one about the cut (the cut's corners lie on
    // both faces): an opening's body may be drawn deeper than its wall.
    if (!f.pieces.empty()) {
      double far = 1e300;
      for (std::size_t pi : elements_[f.pieces.front().first].parts)
        for (const auto& v : scene_.parts[pi].positions) {
          const Vector3d q = v.cast<double>();
          const double u = f.U(q), w = f.W(q);
          if (u >= h.u0 - 0.01 && u <= h.u1 + 0.01 && q.z() >= h.v0 - 0.01 &&
              q.z() <= h.v1 + 0.01 && w < f.w - 0.01 && w >= f.w - kOpeningReach)
            far = std::min(far, w);
        }
      if (far < 1e299) depth = f.w - far;
    }
    bool room_behind = false;
    for (const Hole& g : *holes) {
      const Face& b = faces_[g.face];
      if (&b == &f || b.n.dot(f.n) > -kFacingCos) continue;
      const double d = f.w - f.W(b.a + b.w * b.n);
      if (d > 0.0 && d <= kOpeningReach) {
        depth = d;
        room_behind = true;
      }
    }
    const bool reversed = f.dir.dot(f0.dir) < 0.0;  // the wall's other side runs the other way
    const bool lo = reversed ? right : left, hi = reversed ? left : right;
    const double u0 = lo ? std::max(h.u0, a0) : h.u0, u1 = hi ? std::min(h.u1, a1) : h.u1;
    const double v0 = below ? std::max(h.v0, ov0) : h.v0, v1 = above ? std::min(h.v1, ov1) : h.v1;
    if (!(u1 > u0 && v1 > v0)) continue;
    const Vector3d base(f.a.x(), f.a.y(), 0.0);
    // A point of the face frame: along the face u, height v, behind the face by `back`.
    auto P = [&](double u, double v, double back) {
      return Vector3d(base + u * f.dir + (f.w - back) * f.n + v * z);
    };
    // A rectangle [ua, ub] x [va, vb] of the face (room side, facing the room: n = z x dir)
    // and, behind it, the wall's outside (facing away); sill, head and jambs face the opening,
    // across the wall's whole depth: made from the first face only (a wall between two rooms
    // has the hole on both faces).
    std::vector<Poly3> face_pieces, other_pieces;
    auto rect = [&](double ua, double ub, double va, double vb) {
      if (ub - ua < 1e-4 || vb - va < 1e-4) return;
      face_pieces.push_back({P(ua, va, 0), P(ua, vb, 0), P(ub, vb, 0), P(ub, va, 0)});
      if (!room_behind)
        other_pieces.push_back(
            {P(ua, va, depth), P(ub, va, depth), P(ub, vb, depth), P(ua, vb, depth)});
    };
    if (h.v0 < v0 - kCutTolerance) {
      rect(h.u0, h.u1, h.v0, v0);  // under the opening, and its sill
      if (k == 0)
        other_pieces.push_back({P(u0, v0, 0), P(u0, v0, depth), P(u1, v0, depth), P(u1, v0, 0)});
    }
    if (h.v1 > v1 + kCutTolerance) {
      rect(h.u0, h.u1, v1, h.v1);  // over it, and its head
      if (k == 0)
        other_pieces.push_back({P(u0, v1, 0), P(u1, v1, 0), P(u1, v1, depth), P(u0, v1, depth)});
    }
    if (h.u0 < u0 - kCutTolerance) {
      rect(h.u0, u0, v0, v1);  // beside it, and its jambs
      if (k == 0)
        other_pieces.push_back({P(u0, v0, 0), P(u0, v1, 0), P(u0, v1, depth), P(u0, v0, depth)});
    }
    if (h.u1 > u1 + kCutTolerance) {
      rect(u1, h.u1, v0, v1);
      if (k == 0)
        other_pieces.push_back({P(u1, v0, 0), P(u1, v0, depth), P(u1, v1, depth), P(u1, v1, 0)});
    }
    if (f.pieces.empty()) continue;
    const std::size_t wall = f.pieces.front().first;
    const int material = f.materials.front();
    const std::string room = rooms_[f.room].room.id;
    for (Poly3& piece : face_pieces) {
      out_bucket_.Get(f.id, ElementClass::kWall, "", room, material).pieces.push_back(piece);
      f.pieces.emplace_back(wall, std::move(piece));
      f.materials.push_back(material);
    }
    // A reveal or outside the reader did make (assimp cuts the sill right, and the faces wrong)
    // is not made twice: a piece half covered by the wall's own coplanar triangles is left out.
    for (Poly3& piece : other_pieces)
      if (OwnCover(elements_[wall], piece) < 0.5 * Area(piece))
        Leftover(wall, material, std::move(piece));
    h.u0 = u0;
    h.u1 = u1;
    h.v0 = v0;
    h.v1 = v1;
  }
}

// The area of e's own triangles lying in the plane of the convex polygon `piece` (within
// 1 mm) and inside it: how much of it the element's mesh already has.
double Importer::OwnCover(const Element& e, const Poly3& piece) const {
  constexpr double kOnPlane = 1e-3;  // m
  const Vector3d n = NormalOf(piece);
  if (n.isZero()) return 0.0;
  const double d = n.dot(piece[0]);
  double covered = 0.0;
  for (std::size_t pi : e.parts) {
    const MeshPart& part = scene_.parts[pi];
    for (const auto& t : part.triangles) {
      const Vector3d a = part.positions[t[0]].cast<double>(),
                     b = part.positions[t[1]].cast<double>(),
                     c = part.positions[t[2]].cast<double>();
      if (std::abs(n.dot(a) - d) > kOnPlane || std::abs(n.dot(b) - d) > kOnPlane ||
          std::abs(n.dot(c) - d) > kOnPlane)
        continue;
      Poly3 tri{a, b, c};
      // Clipped by each side of the piece (its edges' inward half-spaces).
      for (std::size_t k = 0; k < piece.size() && !tri.empty(); ++k) {
        const Vector3d& p = piece[k];
        const Vector3d& q = piece[(k + 1) % piece.size()];
        const Vector3d in = n.cross(q - p).normalized();
        tri = ClipHalfSpace(tri, -in, -in.dot(p));
      }
      covered += Area(tri);
    }
  }
  return covered;
}

// An element that fills only part of its hole leaves the rest open (a window in an opening cut
// down to the floor): said in one line.
void Importer::ReportHoleShape(const Element& e, const Hole& h) {
  if (e.box.min().z() > h.v0 + 0.05 || e.box.max().z() < h.v1 - 0.05)
    out_.report.push_back(NiceName(e.node) + ": fills z " + Fmt(e.box.min().z(), 2) + " to " +
                          Fmt(e.box.max().z(), 2) + " m of its hole's " + Fmt(h.v0, 2) + " to " +
                          Fmt(h.v1, 2) + " m; the rest of the hole is open");
}

// The format's openings are rectangles. Wall inside an opening's rectangle on any of its host
// faces (a round window's corners, a threshold or a lintel step 1 cm into a door's hole) is
// part of the opening: with --repair it becomes the opening's frame, so that no wall triangle
// covers the opening (docs/scene-format.md); else it is a repair the file needs.
void Importer::FillHole(const Opening& o, const Hole& /*h*/, bool door) {
  for (const std::string& wid : o.host_walls) {
    std::size_t fi = faces_.size();
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (faces_[k].id == wid) fi = k;
    if (fi == faces_.size()) continue;
    Face& f = faces_[fi];
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const Vector3d& c : o.corners) {
      u0 = std::min(u0, f.U(c));
      u1 = std::max(u1, f.U(c));
      v0 = std::min(v0, c.z());
      v1 = std::max(v1, c.z());
    }
    auto rect = [&](double m) {
      return std::vector<HalfSpace>{{-f.dir, -f.dir.dot(f.a) - (u0 + m)},
                                    {f.dir, f.dir.dot(f.a) + (u1 - m)},
                                    {-Vector3d::UnitZ(), -(v0 + m)},
                                    {Vector3d::UnitZ(), v1 - m}};
    };
    // What validate sees: wall inside the rectangle shrunk by 1 mm.
    double covered = 0.0;
    for (const auto& [el, piece] : f.pieces) {
      Poly3 in;
      std::vector<Poly3> outside;
      Split(piece, rect(1e-3), &in, &outside);
      covered += Area(in);
    }
    if (covered <= kMinPieceArea) continue;
    const double share = covered / ((u1 - u0) * (v1 - v0));
    Repair(door ? "door hole" : "window hole", o.id + " in " + f.id,
           Fmt(100.0 * share, 1) + " % of its rectangle " + Fmt(u1 - u0, 2) + " x " +
               Fmt(v1 - v0, 2) + " m is wall",
           "that wall is the " + std::string(door ? "door's" : "window's") + " frame", p_.repair,
           "--repair");
    if (!p_.repair) continue;
    std::vector<std::pair<std::size_t, Poly3>> kept;
    std::vector<int> kept_materials;
    const ElementClass frame = door ? ElementClass::kDoorFrame : ElementClass::kWindowFrame;
    const std::string room = rooms_[f.room].room.id;
    for (std::size_t i = 0; i < f.pieces.size(); ++i) {
      Poly3 in;
      std::vector<Poly3> outside;
      Split(f.pieces[i].second, rect(0.0), &in, &outside);
      if (!in.empty())
        out_bucket_.Get(o.id, frame, door ? "door" : "window", room, f.materials[i])
            .pieces.push_back(std::move(in));
      else
        outside = {f.pieces[i].second};
      for (Poly3& piece : outside) {
        kept.emplace_back(f.pieces[i].first, std::move(piece));
        kept_materials.push_back(f.materials[i]);
      }
    }
    f.pieces = std::move(kept);
    f.materials = std::move(kept_materials);
    for (Bucket& b : out_bucket_.buckets())
      if (b.id == f.id && b.cls == ElementClass::kWall) b.pieces.clear();
    for (std::size_t i = 0; i < f.pieces.size(); ++i)
      out_bucket_.Get(f.id, ElementClass::kWall, "", room, f.materials[i])
          .pieces.push_back(f.pieces[i].second);
  }
}

// A window keeps its BIM geometry: glass parts (transmissive materials) and frame.
void Importer::AddWindow(const Element& e, const Face& f0, Opening* o) {
  const RoomData& r0 = rooms_[f0.room];
  o->sill_height = o->v0 + (WallOf(f0).origin.z() - r0.room.floor_z);
  for (std::size_t pi : e.parts) {
    const MeshPart& part = scene_.parts[pi];
    const bool glass = part.material >= 0 && scene_.materials[part.material].transmission > 0;
    Bucket& b =
        out_bucket_.Get(o->id, glass ? ElementClass::kWindowGlass : ElementClass::kWindowFrame,
                        "window", r0.room.id, part.material);
    for (const auto& t : part.triangles)
      b.pieces.push_back({part.positions[t[0]].cast<double>(), part.positions[t[1]].cast<double>(),
                          part.positions[t[2]].cast<double>()});
  }
  out_.report.push_back("window " + o->id + " = " + NiceName(e.node) + " in " + f0.id + ", " +
                        Fmt(o->u1 - o->u0, 2) + " x " + Fmt(o->v1 - o->v0, 2) + " m");
  out_.truth.openings.push_back(*o);
}

// Door: the BIM leaf and frame are replaced by a leaf hinged at a jamb of the hole
// (docs/scene-import.md). holes[0] is on the first room's side; the nearest hole facing it from
// another room, if any, is the second room's side.
void Importer::AddDoor(const Element& e, const std::vector<Hole>& holes, Opening* o) {
  const Face& f0 = faces_[holes[0].face];
  const RoomData& r0 = rooms_[f0.room];
  std::string room_b;
  std::size_t hole_b = holes.size();
  for (std::size_t k = 1; k < holes.size(); ++k) {
    const Face& fk = faces_[holes[k].face];
    if (fk.n.dot(f0.n) < -kFacingCos && fk.room != f0.room) {
      o->host_walls.push_back(fk.id);
      room_b = rooms_[fk.room].room.id;
      o->rooms.push_back(room_b);
      hole_b = k;
      break;
    }
  }
  const double deg = DoorAngleDeg(o->id, e);
  const double lambda = DegToRad(deg);
  const Swing sw = ChooseSwing(e, holes, hole_b);
  const Vector3d axis = sw.dd.cross(sw.n).normalized();
  const std::string swing_room = rooms_[sw.f->room].room.id;
  AddLeaf(*o, sw, lambda, swing_room);
  o->hinge_side = sw.left ? "left" : "right";
  o->swing_room = swing_room;
  o->hinge_point = sw.hinge;
  o->hinge_axis = axis;
  o->opening_angle = lambda;
  o->state = DoorStateFromAngle(lambda);
  o->leaf_thickness = p_.leaf_thickness;
  out_.truth.openings.push_back(*o);
  out_.truth.connections.push_back({o->id, r0.room.id, room_b});
  out_.report.push_back("door " + o->id + " = " + NiceName(e.node) + " between " + r0.room.id +
                        " and " + (room_b.empty() ? "outside" : room_b) + ", " +
                        Fmt(o->u1 - o->u0, 2) + " x " + Fmt(o->v1 - o->v0, 2) + " m, at " +
                        Fmt(deg, 1) + " deg, hinged " + o->hinge_side + " into " + swing_room +
                        " (BIM leaf replaced)");
}

// The leaf on side `k` (an index into `holes`) with a left or right hinge.
Importer::Swing Importer::MakeSwing(const std::vector<Hole>& holes, std::size_t k,
                                    bool left) const {
  const Hole& h = holes[k];
  const Face& f = faces_[h.face];
  Swing sw{&f, &h, left, f.n, Vector3d::Zero(), Vector3d::Zero(), 0.0};
  // Left hinge seen from the swing room: hinge -> latch = z x n = -dir, hinge at u1.
  sw.dd = left ? Vector3d(Vector3d::UnitZ().cross(f.n)) : Vector3d(f.n.cross(Vector3d::UnitZ()));
  const double u_h = left ? h.u1 - kLeafGap : h.u0 + kLeafGap;
  sw.hinge = f.a + u_h * f.dir + 0.001 * f.n + Vector3d(0, 0, h.v0 - f.a.z());
  sw.lw = h.u1 - h.u0 - 2 * kLeafGap;
  return sw;
}

// The opened leaf's swept square (three sample points) lies in its swing room.
bool Importer::SwingFits(const Swing& sw) const {
  const Polygon2& poly = rooms_[sw.f->room].poly;
  for (const auto& [a, b] : {std::pair{0.02, 1.0}, std::pair{1.0, 1.0}, std::pair{0.5, 0.5}})
    if (!PointInPolygon((sw.hinge + sw.lw * (a * sw.dd + b * sw.n)).head<2>(), poly)) return false;
  return true;
}

// Where the leaf swings: the first of (larger room, smaller room) x (left, right hinge) whose
// swept square fits in that room; else the nearest room, hinged left.
Importer::Swing Importer::ChooseSwing(const Element& e, const std::vector<Hole>& holes,
                                      std::size_t hole_b) {
  const RoomData& r0 = rooms_[faces_[holes[0].face].room];
  std::vector<std::size_t> sides{0};
  if (hole_b < holes.size()) {
    sides.push_back(hole_b);
    if (SignedArea(rooms_[faces_[holes[hole_b].face].room].poly) > SignedArea(r0.poly))
      std::swap(sides[0], sides[1]);
  }
  Swing sw = MakeSwing(holes, 0, true);
  bool fitted = false;
  for (std::size_t k : sides) {
    for (bool left : {true, false}) {
      const Swing c = MakeSwing(holes, k, left);
      if (SwingFits(c)) {
        sw = c;
        fitted = true;
        break;
      }
    }
    if (fitted) break;
  }
  if (!fitted)
    out_.report.push_back(NiceName(e.node) +
                          ": its leaf fits in neither room when open; "
                          "it swings into " +
                          r0.room.id);
  return sw;
}

// The generated leaf: a box leaf_thickness thick, from 1 cm above the hole's sill to kLeafGap
// below its head, turned by `lambda` about the hinge.
void Importer::AddLeaf(const Opening& o, const Swing& sw, double lambda,
                       const std::string& swing_room) {
  const double lt = p_.leaf_thickness;
  const Vector3d n = sw.n, dd = sw.dd;
  const Vector3d rd = std::cos(lambda) * dd + std::sin(lambda) * n;
  const Vector3d rn = std::cos(lambda) * n - std::sin(lambda) * dd;
  Bucket& leaf = out_bucket_.Get(o.id, ElementClass::kDoorLeaf, "door", swing_room, LeafMaterial(),
                                 o.id + "/leaf");
  MeshPart box;
  PartBuilder pb(&box);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  // A left hinge makes (rd, rn, z) left-handed (rd x rn = dd x n = -z): mirror x then.
  const bool mirror = rd.cross(rn).z() < 0.0;
  X.linear().col(0) = mirror ? Vector3d(-rd) : rd;
  X.linear().col(1) = rn;
  X.linear().col(2) = Vector3d::UnitZ();
  X.translation() = sw.hinge;
  const double top = sw.h->v1 - sw.h->v0 - kLeafGap;
  if (mirror)
    pb.AddBox(X, {-sw.lw, -lt, 0.01}, {0.0, 0.0, top});
  else
    pb.AddBox(X, {0.0, -lt, 0.01}, {sw.lw, 0.0, top});
  for (const auto& t : box.triangles)
    leaf.pieces.push_back({box.positions[t[0]].cast<double>(), box.positions[t[1]].cast<double>(),
                           box.positions[t[2]].cast<double>()});
}

// A hole through a wall between two rooms that no door or window fills (an IfcOpeningElement
// alone, a doorway): on a room's wall face, a gap in the wall at 1 m above the floor, reaching
// down to the floor and at least kDoorwayHeight high, facing a gap of another room's wall face
// no deeper than kDoorwayDepth behind it. It is a door without a leaf (leaf_thickness 0, open
// at 180 deg) and connects the two rooms (docs/scene-format.md).
void Importer::Doorways() {
  constexpr double kDoorwayHeight = 1.8;  // m: a passage people walk through
  constexpr double kDoorwayDepth = 0.6;   // m: the thickest wall between two rooms
  constexpr double kMinWidth = 0.3;       // m: narrower gaps are joints, not openings
  for (std::size_t fi = 0; fi < faces_.size(); ++fi) {
    const Face& f = faces_[fi];
    if (!f.kept) continue;
    const double v = std::min(f.z0 + 1.0, 0.5 * (f.vmin + f.vmax));
    const std::vector<std::pair<double, double>> cov = Coverage(f, false, v);
    for (std::size_t k = 0; k + 1 < cov.size(); ++k) {
      double g0 = cov[k].second, g1 = cov[k + 1].first;
      if (g1 - g0 < kMinWidth) continue;
      bool taken = false;
      for (const Hole& h : holes_)
        taken = taken || (h.face == fi && h.u0 < g1 - 1e-3 && h.u1 > g0 + 1e-3);
      if (taken) continue;
      const double um = 0.5 * (g0 + g1);
      double v0 = 0.0, v1 = 0.0;
      if (!GapAround(Coverage(f, true, um), v, f.vmin, f.vmax, &v0, &v1) || v0 > f.z0 + 0.05 ||
          v1 - v0 < kDoorwayHeight)
        continue;
      // The other room's face behind it, with a gap there too.
      const Vector3d mid = f.a + um * f.dir + Vector3d(0, 0, v - f.a.z());
      std::size_t gi = faces_.size();
      double ga = 0.0, gb = 0.0;
      for (std::size_t k2 = 0; k2 < faces_.size(); ++k2) {
        const Face& g = faces_[k2];
        if (!g.kept || g.room == f.room || g.n.dot(f.n) > -kFacingCos) continue;
        const double depth = -f.W(g.a);
        const double ug = g.U(mid);
        if (depth < -p_.plane_tolerance || depth > kDoorwayDepth || ug < 0.0 || ug > g.length)
          continue;
        if (GapAround(Coverage(g, false, v), ug, 0.0, g.length, &ga, &gb)) gi = k2;
        if (gi != faces_.size()) break;
      }
      if (gi == faces_.size() || gi < fi) continue;  // each doorway once, from its first face
      const Face& g = faces_[gi];
      // The clear hole: where both sides are open.
      const double fa = f.U(g.a + ga * g.dir), fb = f.U(g.a + gb * g.dir);
      g0 = std::max(g0, std::min(fa, fb));
      g1 = std::min(g1, std::max(fa, fb));
      double gv0 = 0.0, gv1 = 0.0;
      if (g1 - g0 < kMinWidth || !GapAround(Coverage(g, true, g.U(f.a + 0.5 * (g0 + g1) * f.dir)),
                                            v, g.vmin, g.vmax, &gv0, &gv1))
        continue;
      v1 = std::min(v1, gv1);
      Opening o;
      o.id = "D" + std::to_string(++doors_);
      o.type = OpeningType::kDoor;
      o.host_walls = {f.id, g.id};
      o.rooms = {rooms_[f.room].room.id, rooms_[g.room].room.id};
      const Hole h{fi, g0, g1, v0, v1, 0.0};
      FillRect(&o, h);
      holes_.push_back(h);
      o.opening_angle = kPi;
      o.state = DoorStateFromAngle(o.opening_angle);
      o.leaf_thickness = 0.0;
      o.hinge_side = "left";
      o.swing_room = o.rooms[0];
      o.hinge_point = o.corners[0];
      o.hinge_axis = Vector3d::UnitZ();
      out_.truth.openings.push_back(o);
      out_.truth.connections.push_back({o.id, o.rooms[0], o.rooms[1]});
      FillHole(o, h, true);
      out_.report.push_back("doorway " + o.id + " between " + o.rooms[0] + " and " + o.rooms[1] +
                            ": a " + Fmt(g1 - g0, 2) + " x " + Fmt(v1 - v0, 2) + " m hole in " +
                            f.id + " and " + g.id + " that no door or window fills (no leaf)");
    }
  }
}

// Rooms sharing a boundary stretch without a wall (open-plan spaces): open passages.
void Importer::Passages() {
  std::set<std::pair<int, int>> done;
  for (std::size_t fi = 0; fi < faces_.size(); ++fi)
    for (std::size_t gi = fi + 1; gi < faces_.size(); ++gi) {
      const Face& f = faces_[fi];
      const Face& g = faces_[gi];
      if (f.room == g.room || f.n.dot(g.n) > -kFacingCos ||
          std::abs(f.W(g.a)) > kPassageTolerance || done.count({f.room, g.room}))
        continue;
      const double g0 = f.U(g.a), g1 = f.U(g.a + g.length * g.dir);
      const double s0 = std::max(0.0, std::min(g0, g1)), s1 = std::min(f.length, std::max(g0, g1));
      if (s1 - s0 < kMinClearDoorWidth) continue;
      const double v = f.z0 + 0.5 * (std::min(f.z1, g.z1) - f.z0);
      std::vector<std::pair<double, double>> cov = Coverage(f, false, v);
      for (const Hole& h : holes_)
        if (h.face == fi) cov.emplace_back(h.u0, h.u1);  // doors and windows are not passages
      std::sort(cov.begin(), cov.end());
      double widest = 0.0, at = s0;
      for (const auto& [a, b] : cov) {
        if (b <= at) continue;
        widest = std::max(widest, std::min(a, s1) - at);
        at = std::max(at, b);
        if (at >= s1) break;
      }
      widest = std::max(widest, s1 - at);
      if (widest < kMinClearDoorWidth) continue;
      done.insert({f.room, g.room});
      done.insert({g.room, f.room});
      out_.truth.connections.push_back({"", rooms_[f.room].room.id, rooms_[g.room].room.id});
      out_.truth.format_version = kTruthFormatVersionPassages;
      out_.report.push_back("open passage between " + rooms_[f.room].room.id + " and " +
                            rooms_[g.room].room.id + ": " + Fmt(widest, 2) +
                            " m of shared boundary without a wall");
    }
}

}  // namespace mopad::scenes::bim
