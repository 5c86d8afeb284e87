// The generator's doors and windows: where each sits on its wall (holes, keep-out zones), a door
// leaf at its opening angle and the floor it sweeps, the zones kept free in front of doors, and
// the geometry and truth of frames, leaves and glass (scenes/generator_internal.h).
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/format.h"
#include "common/frames.h"
#include "scenes/generator_internal.h"

namespace mopad::scenes::gen {

void AddOrientedBox(PartBuilder& pb, const Vector3d& o, Vector3d ex, const Vector3d& ey,
                    const Vector3d& ez, Vector3d lo, Vector3d hi, int skip) {
  if (ex.cross(ey).dot(ez) < 0.0) {
    ex = -ex;
    const double l = lo.x(), h = hi.x();
    lo.x() = -h;
    hi.x() = -l;
    skip = (skip & ~3) | ((skip & 1) << 1) | ((skip & 2) >> 1);
  }
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear().col(0) = ex;
  X.linear().col(1) = ey;
  X.linear().col(2) = ez;
  X.translation() = o;
  pb.AddBox(X, lo, hi, skip);
}

void AppendNumber(double v, std::string* name) {
  *name += '_';
  *name += FormatFixed(v, 3);
}

namespace {

void AddQuadFacing(PartBuilder& pb, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                   const Vector3d& d, const Vector3d& n) {
  if ((b - a).cross(c - a).dot(n) < 0.0)
    pb.AddQuad(a, d, c, b);
  else
    pb.AddQuad(a, b, c, d);
}

}  // namespace

std::pair<int, double> Generator::LocateOpening(int room, const WallPosition& pos, double width,
                                                int other_room, double end_margin,
                                                const std::string& what,
                                                const std::string& where) const {
  const RoomData& r = rooms_[room];
  auto fits = [&](const Face& f, double u) {
    const double u0 = u - 0.5 * width - end_margin, u1 = u + 0.5 * width + end_margin;
    if (u0 < -kTol || u1 > f.length + kTol) return false;
    if (other_room >= 0) return f.AdjacentTo(u0, u1, other_room, faces_) != nullptr;
    for (const auto& [p0, p1] : OuterPortions(f))
      if (p0 <= u0 + kTol && u1 <= p1 + kTol) return true;
    return false;
  };
  const std::string target =
      other_room >= 0 ? "a wall shared with room '" + rooms_[other_room].id + "'" : "an outer wall";
  if (pos.wall >= 0) {
    const int fi = r.faces[static_cast<std::size_t>(pos.wall)];
    if (!fits(faces_[fi], pos.offset))
      throw InputError(where, what + " is not on " + target + " with room for its frame",
                       "wall " + std::to_string(pos.wall) + " of room '" + r.id + "' at offset " +
                           FormatFixed(pos.offset, 3) + " m",
                       "a position on " + target);
    return {fi, pos.offset};
  }
  int best = -1;
  double best_d = 0.5 + t_;
  double best_u = 0.0;
  for (int fi : r.faces) {
    const Face& f = faces_[fi];
    const double u = (pos.at - f.a).dot(f.dir);
    const double d = std::abs((pos.at - f.a).dot(f.n_in));
    if (u < 0.0 || u > f.length || !fits(f, u)) continue;
    if (d < best_d) {
      best_d = d;
      best = fi;
      best_u = u;
    }
  }
  if (best < 0)
    throw InputError(where, what + " is not on " + target + " of room '" + r.id + "'",
                     "at [" + FormatFixed(pos.at.x(), 3) + ", " + FormatFixed(pos.at.y(), 3) + "]",
                     "a point within " + FormatFixed(0.5 + t_, 3) + " m of " + target +
                         " with room for the opening and its frame");
  return {best, best_u};
}

void Generator::AddHole(int face, const Rect2& hole, double frame, const std::string& id,
                        const std::string& where) {
  Face& f = faces_[face];
  const Rect2 zone{hole.u0 - frame - kOpeningMargin, hole.u1 + frame + kOpeningMargin,
                   hole.v0 - frame, hole.v1 + frame};
  for (std::size_t k = 0; k < f.keep_out.size(); ++k)
    if (zone.Overlaps(f.keep_out[k]))
      throw InputError(where,
                       "opening '" + id + "' overlaps another opening on wall '" + f.id + "'");
  f.holes.push_back(hole);
  f.keep_out.push_back(Rect2{hole.u0 - frame - kBscMargin, hole.u1 + frame + kBscMargin,
                             hole.v0 - frame - kBscMargin, hole.v1 + frame + kBscMargin});
}

void Generator::ResolveDoors() {
  for (const auto& ds : spec_.doors) {
    DoorData d;
    d.spec = &ds;
    const int ra = RoomIndex(ds.room_a);
    const int rb = ds.room_b == "outside" ? -1 : RoomIndex(ds.room_b);
    const double margin = ds.frame_width + kOpeningMargin + (rb < 0 ? t_ : 0.0);
    const auto [fi, u] =
        LocateOpening(ra, ds.position, ds.width, rb, margin, "door '" + ds.id + "'", ds.where);
    d.face = fi;
    d.hole = {u - 0.5 * ds.width, u + 0.5 * ds.width, 0.0, ds.height};
    if (rb >= 0) {
      const Adjacency* ad = faces_[fi].AdjacentTo(d.hole.u0, d.hole.u1, rb, faces_);
      d.other = ad->other;
      d.c = ad->c;
    }
    d.swing_into_a = ds.swing_into.empty() || ds.swing_into == ds.room_a;
    d.lambda = DegToRad(ds.angle_deg);
    // Hinge end on `face` (see the leaf construction in EmitDoors for the derivation):
    // left hinge seen from room a -> hinge at high u; seen from room b -> low u.
    const bool left = ds.hinge == "left";
    d.hinge_high_u = d.swing_into_a ? left : !left;
    // A leaf opened past 90 deg sweeps beyond its hinge jamb: keep that wall stretch clear.
    double sweep = 0.0;
    if (d.lambda > kPi / 2) sweep = (ds.width - 2 * kLeafGap) * -std::cos(d.lambda) + 0.05;
    auto add = [&](int face, const Rect2& hole, bool swing_face, bool hinge_high) {
      AddHole(face, hole, ds.frame_width, ds.id, ds.where);
      if (swing_face && sweep > 0.0) {
        Face& f = faces_[face];
        const double h0 = hinge_high ? hole.u1 : hole.u0;
        const double ext0 = hinge_high ? h0 : h0 - sweep, ext1 = hinge_high ? h0 + sweep : h0;
        if (ext0 < 0.0 || ext1 > f.length)
          throw InputError(ds.where, "door '" + ds.id + "' opened to " +
                                         FormatFixed(ds.angle_deg, 3) +
                                         " deg hits the end of wall '" + f.id + "'");
        f.keep_out.push_back({ext0, ext1, 0.0, f.height()});
      }
    };
    add(d.face, d.hole, d.swing_into_a, d.hinge_high_u);
    if (d.other >= 0) {
      const Rect2 h2{d.c - d.hole.u1, d.c - d.hole.u0, 0.0, ds.height};
      add(d.other, h2, !d.swing_into_a, !d.hinge_high_u);
    }
    doors_.push_back(d);
  }
  // Two leaves swinging into the same room must not sweep the same floor.
  for (std::size_t i = 0; i < doors_.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const int ri = SwingRoom(doors_[i]), rj = SwingRoom(doors_[j]);
      if (ri < 0 || ri != rj || doors_[i].lambda <= 0.0 || doors_[j].lambda <= 0.0) continue;
      if (ConvexOverlap(SwingZone(doors_[i]), SwingZone(doors_[j])))
        throw InputError(doors_[i].spec->where, "door '" + doors_[i].spec->id +
                                                    "' swings into the leaf of door '" +
                                                    doors_[j].spec->id + "'");
    }
}

Generator::Leaf Generator::LeafOf(const DoorData& d) const {
  const DoorSpec& ds = *d.spec;
  const Face& f = faces_[d.face];
  const Vector3d n = d.swing_into_a ? Flat(f.n_in) : Vector3d(-Flat(f.n_in));
  const Vector3d dd = d.hinge_high_u ? Vector3d(-Flat(f.dir)) : Flat(f.dir);
  const double fp = std::max(ds.frame_protrusion, 0.002) + 0.001;
  const double w_plane = d.swing_into_a ? fp : -t_ - fp;
  const double u_h = d.hinge_high_u ? d.hole.u1 - kLeafGap : d.hole.u0 + kLeafGap;
  Leaf l;
  l.hinge = f.P(u_h, 0.0, w_plane);
  l.axis = dd.cross(n).normalized();
  l.width = ds.width - 2 * kLeafGap;
  l.thickness = std::min(ds.leaf_thickness, t_);
  l.rd = std::cos(d.lambda) * dd + std::sin(d.lambda) * n;
  l.rn = std::cos(d.lambda) * n - std::sin(d.lambda) * dd;
  return l;
}

Polygon2 Generator::LeafFootprint(const DoorData& d) const {
  const Leaf l = LeafOf(d);
  const Vector2d h = l.hinge.head<2>(), a = l.rd.head<2>(), b = l.rn.head<2>();
  return {h, h + l.width * a, h + l.width * a - l.thickness * b, h - l.thickness * b};
}

int Generator::SwingRoom(const DoorData& d) const {
  if (d.swing_into_a) return faces_[d.face].room;
  return d.other >= 0 ? faces_[d.other].room : -1;
}

Polygon2 Generator::SwingZone(const DoorData& d) const {
  const int face = d.swing_into_a ? d.face : d.other;
  const Face& f = faces_[face];
  const auto [h, high] = DoorOnFace(d, face);
  const double w = d.spec->width;
  const double back = d.lambda > kPi / 2 ? w * -std::cos(d.lambda) : 0.0;
  const double u0 = high ? h.u0 : h.u0 - back, u1 = high ? h.u1 + back : h.u1;
  const double depth = w * (d.lambda >= kPi / 2 ? 1.0 : std::sin(d.lambda)) + 0.05;
  return {f.Plan(u0 + 0.01, 0.01), f.Plan(u1 - 0.01, 0.01), f.Plan(u1 - 0.01, depth),
          f.Plan(u0 + 0.01, depth)};
}

void Generator::ResolveWindows() {
  for (const auto& ws : spec_.windows) {
    WindowData w;
    w.spec = &ws;
    const int r = RoomIndex(ws.room);
    const auto [fi, u] =
        LocateOpening(r, ws.position, ws.width, -1, ws.frame_width + kOpeningMargin + t_,
                      "window '" + ws.id + "'", ws.where);
    w.face = fi;
    w.hole = {u - 0.5 * ws.width, u + 0.5 * ws.width, ws.sill_height, ws.sill_height + ws.height};
    AddHole(fi, w.hole, ws.frame_width, ws.id, ws.where);
    windows_.push_back(w);
  }
}

Polygon2 Generator::DoorZone(const DoorData& d, int room) const {
  const bool on_a = faces_[d.face].room == room;
  const Face& f = faces_[on_a ? d.face : d.other];
  const Rect2 h = on_a ? d.hole : Rect2{d.c - d.hole.u1, d.c - d.hole.u0, 0, 0};
  const double w = d.spec->width;
  double depth = std::max(kDoorZoneDepth, w + 0.15);
  double u0 = h.u0 - d.spec->frame_width - 0.05, u1 = h.u1 + d.spec->frame_width + 0.05;
  const bool swing_here = on_a == d.swing_into_a;
  if (swing_here && d.lambda > kPi / 2) {
    const bool high = on_a ? d.hinge_high_u : !d.hinge_high_u;
    const double sweep = w * -std::cos(d.lambda);
    if (high)
      u1 += sweep;
    else
      u0 -= sweep;
    depth = std::max(depth, w + 0.15);
  }
  return {f.Plan(u0, 0.0), f.Plan(u1, 0.0), f.Plan(u1, depth), f.Plan(u0, depth)};
}

Vector2d Generator::DoorSeed(const DoorData& d, int room) const {
  const bool on_a = faces_[d.face].room == room;
  const Face& f = faces_[on_a ? d.face : d.other];
  const double u = on_a ? 0.5 * (d.hole.u0 + d.hole.u1) : d.c - 0.5 * (d.hole.u0 + d.hole.u1);
  return f.Plan(u, kRobotInflation + 0.1);
}

std::vector<int> Generator::DoorsOfRoom(int room) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < doors_.size(); ++i) {
    const DoorData& d = doors_[i];
    if (faces_[d.face].room == room || (d.other >= 0 && faces_[d.other].room == room))
      out.push_back(static_cast<int>(i));
  }
  return out;
}

std::pair<Rect2, bool> Generator::DoorOnFace(const DoorData& d, int face) const {
  if (face == d.face) return {d.hole, d.hinge_high_u};
  return {Rect2{d.c - d.hole.u1, d.c - d.hole.u0, d.hole.v0, d.hole.v1}, !d.hinge_high_u};
}

void Generator::AddCasing(PartBuilder& pb, const Face& f, const Rect2& h, double fw, double w_lo,
                          double w_hi, int back_skip, bool door) {
  const Vector3d o = f.P(0, 0), ex = Flat(f.dir), ey = Flat(f.n_in), ez = Vector3d::UnitZ();
  const double vb = door ? 0.0 : h.v0 - fw;
  AddOrientedBox(pb, o, ex, ey, ez, {h.u0 - fw, w_lo, vb}, {h.u0, w_hi, h.v1},
                 back_skip | (door ? 16 : 0));
  AddOrientedBox(pb, o, ex, ey, ez, {h.u1, w_lo, vb}, {h.u1 + fw, w_hi, h.v1},
                 back_skip | (door ? 16 : 0));
  AddOrientedBox(pb, o, ex, ey, ez, {h.u0 - fw, w_lo, h.v1}, {h.u1 + fw, w_hi, h.v1 + fw},
                 back_skip);
  if (!door)
    AddOrientedBox(pb, o, ex, ey, ez, {h.u0, w_lo, h.v0 - fw}, {h.u1, w_hi, h.v0}, back_skip);
}

void Generator::AddReveals(PartBuilder& pb, const Face& f, const Rect2& h) const {
  const Vector3d n_dir = Flat(f.dir);
  AddQuadFacing(pb, f.P(h.u0, h.v0, 0), f.P(h.u0, h.v0, -t_), f.P(h.u0, h.v1, -t_),
                f.P(h.u0, h.v1, 0), n_dir);
  AddQuadFacing(pb, f.P(h.u1, h.v0, 0), f.P(h.u1, h.v0, -t_), f.P(h.u1, h.v1, -t_),
                f.P(h.u1, h.v1, 0), -n_dir);
  AddQuadFacing(pb, f.P(h.u0, h.v1, 0), f.P(h.u1, h.v1, 0), f.P(h.u1, h.v1, -t_),
                f.P(h.u0, h.v1, -t_), -Vector3d::UnitZ());
  AddQuadFacing(pb, f.P(h.u0, h.v0, 0), f.P(h.u1, h.v0, 0), f.P(h.u1, h.v0, -t_),
                f.P(h.u0, h.v0, -t_), Vector3d::UnitZ());
}

void Generator::EmitDoors() {
  for (const DoorData& d : doors_) {
    const DoorSpec& ds = *d.spec;
    const Face& f = faces_[d.face];
    const RoomData& ra = rooms_[f.room];
    const std::string room_b = d.other >= 0 ? rooms_[faces_[d.other].room].id : "";
    const DoorLook look = LookOfDoor(ds);
    MaterialSpec fm = spec_.materials.door_frame;
    std::string fm_name = "door_frame";
    if (ds.has_frame_colour) {
      fm.colour = ds.frame_colour;
      for (double c : fm.colour) AppendNumber(c, &fm_name);
    } else if (look.frame_shade > 0.0) {
      // Painted in the wall's paint, a shade off and satin.
      for (int k = 0; k < 3; ++k) fm.colour[k] = look.frame_shade * spec_.materials.wall.colour[k];
      fm.roughness = 0.5;
      fm.metallic = 0.0;
      fm_name = "door_frame_wall";
      AppendNumber(look.frame_shade, &fm_name);
    }
    MaterialSpec lm = spec_.materials.door_leaf;
    std::string lm_name = "door_leaf";
    if (ds.has_leaf_colour) {
      lm.colour = ds.leaf_colour;
      for (double c : lm.colour) AppendNumber(c, &lm_name);
    }
    // Frame: lining through the wall and a protruding casing on both faces.
    MeshPart frame =
        NewPart(ds.id + "/frame", ds.id, ElementClass::kDoorFrame, "door", ra.id, Mat(fm_name, fm));
    PartBuilder pb(&frame);
    AddReveals(pb, f, d.hole);
    const double cp = std::max(ds.frame_protrusion, 0.002);
    AddCasing(pb, f, d.hole, ds.frame_width, 0.0, cp, 4, true);
    AddCasing(pb, f, d.hole, ds.frame_width, -t_ - cp, -t_, 8, true);
    Push(std::move(frame));

    const Leaf l = LeafOf(d);
    MeshPart leaf = NewPart(ds.id + "/leaf", ds.id, ElementClass::kDoorLeaf, "door",
                            d.swing_into_a ? ra.id : room_b, Mat(lm_name, lm));
    PartBuilder lb(&leaf);
    const double top = ds.height - kLeafGap;
    if (!look.glazed) {
      AddOrientedBox(lb, l.hinge, l.rd, l.rn, Vector3d::UnitZ(), {0.0, -l.thickness, 0.01},
                     {l.width, 0.0, top});
    } else {
      // Stiles and rails round a pane in the leaf's middle plane.
      const Glazing g = GlazingOf(l.width, top);
      const Vector3d o = l.hinge, z = Vector3d::UnitZ();
      AddOrientedBox(lb, o, l.rd, l.rn, z, {0.0, -l.thickness, 0.01}, {g.a0, 0.0, top});
      AddOrientedBox(lb, o, l.rd, l.rn, z, {g.a1, -l.thickness, 0.01}, {l.width, 0.0, top});
      AddOrientedBox(lb, o, l.rd, l.rn, z, {g.a0, -l.thickness, 0.01}, {g.a1, 0.0, g.z0}, 1 | 2);
      AddOrientedBox(lb, o, l.rd, l.rn, z, {g.a0, -l.thickness, g.z1}, {g.a1, 0.0, top}, 1 | 2);
      MeshPart pane = NewPart(ds.id + "/glass", ds.id, ElementClass::kDoorLeaf, "door", leaf.room,
                              Mat("glass", spec_.materials.glass));
      PartBuilder gb(&pane);
      const double bc = -0.5 * l.thickness;
      AddOrientedBox(gb, o, l.rd, l.rn, z, {g.a0, bc - 0.5 * g.pane, g.z0},
                     {g.a1, bc + 0.5 * g.pane, g.z1}, 1 | 2 | 16 | 32);
      Push(std::move(pane));
    }
    Push(std::move(leaf));

    Opening o;
    o.id = ds.id;
    o.type = OpeningType::kDoor;
    o.host_walls = {f.id};
    o.rooms = {ra.id};
    if (d.other >= 0) {
      o.host_walls.push_back(faces_[d.other].id);
      o.rooms.push_back(room_b);
    }
    o.u0 = d.hole.u0;
    o.u1 = d.hole.u1;
    o.v0 = d.hole.v0;
    o.v1 = d.hole.v1;
    o.corners = {f.P(o.u0, o.v0), f.P(o.u0, o.v1), f.P(o.u1, o.v1), f.P(o.u1, o.v0)};
    o.hinge_side = ds.hinge;
    o.swing_room = d.swing_into_a ? ra.id : room_b;
    o.opening_angle = d.lambda;
    o.state = DoorStateFromAngle(d.lambda);
    o.hinge_point = l.hinge;
    o.hinge_axis = l.axis;
    o.leaf_thickness = l.thickness;
    out_.truth.openings.push_back(o);
    out_.truth.connections.push_back({ds.id, ra.id, room_b});
  }
}

void Generator::EmitWindows() {
  for (const WindowData& w : windows_) {
    const WindowSpec& ws = *w.spec;
    const Face& f = faces_[w.face];
    const RoomData& r = rooms_[f.room];
    const Rect2& h = w.hole;
    const double fw = ws.frame_width;
    MeshPart frame = NewPart(ws.id + "/frame", ws.id, ElementClass::kWindowFrame, "window", r.id,
                             Mat("window_frame", spec_.materials.window_frame));
    PartBuilder pb(&frame);
    AddReveals(pb, f, h);
    AddCasing(pb, f, h, fw, 0.0, std::max(ws.frame_protrusion, 0.002), 4, false);
    // Frame bars around the pane, in the middle of the wall.
    const double depth = std::min(0.06, 0.8 * t_);
    const double wc = -0.5 * t_, w0 = wc - 0.5 * depth, w1 = wc + 0.5 * depth;
    const Vector3d o = f.P(0, 0), ex = Flat(f.dir), ey = Flat(f.n_in), ez = Vector3d::UnitZ();
    AddOrientedBox(pb, o, ex, ey, ez, {h.u0, w0, h.v0}, {h.u0 + fw, w1, h.v1}, 1 | 16 | 32);
    AddOrientedBox(pb, o, ex, ey, ez, {h.u1 - fw, w0, h.v0}, {h.u1, w1, h.v1}, 2 | 16 | 32);
    AddOrientedBox(pb, o, ex, ey, ez, {h.u0 + fw, w0, h.v0}, {h.u1 - fw, w1, h.v0 + fw},
                   1 | 2 | 16);
    AddOrientedBox(pb, o, ex, ey, ez, {h.u0 + fw, w0, h.v1 - fw}, {h.u1 - fw, w1, h.v1},
                   1 | 2 | 32);
    Push(std::move(frame));

    MaterialSpec gm = spec_.materials.glass;
    std::string gname = "glass";
    if (ws.transmission >= 0.0 && ws.transmission != gm.transmission) {
      gm.transmission = ws.transmission;
      AppendNumber(gm.transmission, &gname);
    }
    MeshPart glass = NewPart(ws.id + "/glass", ws.id, ElementClass::kWindowGlass, "window", r.id,
                             Mat(gname, gm));
    PartBuilder gb(&glass);
    AddQuadFacing(gb, f.P(h.u0 + fw, h.v0 + fw, wc), f.P(h.u1 - fw, h.v0 + fw, wc),
                  f.P(h.u1 - fw, h.v1 - fw, wc), f.P(h.u0 + fw, h.v1 - fw, wc), Flat(f.n_in));
    Push(std::move(glass));

    Opening op;
    op.id = ws.id;
    op.type = OpeningType::kWindow;
    op.host_walls = {f.id};
    op.rooms = {r.id};
    op.u0 = h.u0;
    op.u1 = h.u1;
    op.v0 = h.v0;
    op.v1 = h.v1;
    op.corners = {f.P(h.u0, h.v0), f.P(h.u0, h.v1), f.P(h.u1, h.v1), f.P(h.u1, h.v0)};
    op.sill_height = ws.sill_height;
    out_.truth.openings.push_back(op);
  }
}

}  // namespace mopad::scenes::gen
