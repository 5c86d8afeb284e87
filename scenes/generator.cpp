#include "scenes/generator.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "common/frames.h"
#include "common/rng.h"
#include "scenes/bsc_catalogue.h"
#include "scenes/geometry.h"
#include "scenes/gltf_writer.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Tuning choices of the generator, in one place (docs/scene-spec.md explains them).
constexpr double kTol = 1e-6;            // m, geometric comparisons of spec coordinates
constexpr double kAdjacencyTol = 1e-4;   // m, wall-thickness match for facing room edges
constexpr double kOpeningMargin = 0.02;  // m, casing to wall end / other openings
constexpr double kBscMargin = 0.03;      // m, BSC to BSC / opening frame on a wall
constexpr double kRobotInflation = 0.4;  // m, half of the 0.8 m free path kept for the robot
constexpr double kGridRes = 0.1;         // m, free-path grid cell
constexpr double kSeedReach = 1.2;       // m, farthest free cell taken for a door's seed
constexpr double kLeafGap = 0.003;       // m, leaf-to-frame clearance
constexpr double kDoorZoneDepth = 1.0;   // m, furniture-free depth in front of every door
constexpr int kPlacementAttempts = 400;  // random tries per BSC / furniture item

Vector3d Lift(const Vector2d& p, double z) { return {p.x(), p.y(), z}; }
Vector3d Flat(const Vector2d& p) { return {p.x(), p.y(), 0.0}; }

/// Part of one face that faces another room across the wall: u in [s0, s1] on this face maps
/// to u' = c - u on face `other`.
struct Adjacency {
  double s0 = 0.0, s1 = 0.0;
  int other = -1;
  double c = 0.0;
};

/// One interior wall face (one room polygon edge): the paper's wall_1A.
struct Face {
  std::string id;
  int room = -1;
  int edge = -1;
  Vector2d a, b, dir, n_in;
  double length = 0.0;
  double z0 = 0.0, z1 = 0.0;
  std::vector<Adjacency> adj;
  std::vector<Rect2> holes;     // cut-outs, (u, v above the floor)
  std::vector<Rect2> keep_out;  // BSC placement: openings with frames, placed BSCs

  double height() const { return z1 - z0; }
  Vector2d Plan(double u, double w = 0.0) const { return a + u * dir + w * n_in; }
  /// Point at u along the face, v above the floor, w along the inward normal.
  Vector3d P(double u, double v, double w = 0.0) const { return Lift(Plan(u, w), z0 + v); }
  const Adjacency* AdjacentTo(double u0, double u1, int other_room,
                              const std::vector<Face>& faces) const {
    for (const auto& ad : adj)
      if (faces[ad.other].room == other_room && ad.s0 <= u0 + kTol && u1 <= ad.s1 + kTol)
        return &ad;
    return nullptr;
  }
};

struct RoomData {
  const RoomSpec* spec = nullptr;
  std::string id;
  Polygon2 poly;
  double z0 = 0.0, z1 = 0.0;
  std::vector<int> faces;
  double area = 0.0, perimeter = 0.0;
};

struct DoorData {
  const DoorSpec* spec = nullptr;
  int face = -1;   // host face in room_a
  int other = -1;  // host face in room_b, -1 for doors to the outside
  Rect2 hole;      // on `face`
  double c = 0.0;  // u' = c - u on `other`
  bool swing_into_a = true;
  bool hinge_high_u = true;  // hinge at hole.u1 of `face` (else at hole.u0)
  double lambda = 0.0;       // rad
};

struct WindowData {
  const WindowSpec* spec = nullptr;
  int face = -1;
  Rect2 hole;
};

struct WallBsc {
  std::string id, cls, room;
  int face = -1;
  Rect2 rect;  // footprint on the face
  double depth = 0.0;
  bool stacked = false;  // another BSC was placed above it
  int reservation = -1;  // keep_out index held free for the BSC to be stacked above it
};

struct CeilingBsc {
  int room = -1;
  Vector2d p;
};

struct FurnitureBox {
  int room = -1;
  Polygon2 footprint;  // CCW
};

/// Oriented box: lo/hi in the frame (o; ex, ey, ez); a left-handed frame is mirrored so the
/// faces still point outward.
void AddOrientedBox(PartBuilder& pb, const Vector3d& o, Vector3d ex, const Vector3d& ey,
                    const Vector3d& ez, Vector3d lo, Vector3d hi, int skip = 0) {
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

void AddQuadFacing(PartBuilder& pb, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                   const Vector3d& d, const Vector3d& n) {
  if ((b - a).cross(c - a).dot(n) < 0.0)
    pb.AddQuad(a, d, c, b);
  else
    pb.AddQuad(a, b, c, d);
}

Polygon2 OrientedRect(const Vector2d& c, double yaw, double w, double d) {
  const Vector2d ex(std::cos(yaw), std::sin(yaw)), ey(-std::sin(yaw), std::cos(yaw));
  return {c - 0.5 * w * ex - 0.5 * d * ey, c + 0.5 * w * ex - 0.5 * d * ey,
          c + 0.5 * w * ex + 0.5 * d * ey, c - 0.5 * w * ex + 0.5 * d * ey};
}

double DistanceToConvex(const Vector2d& p, const Polygon2& poly) {
  if (PointInPolygon(p, poly)) return 0.0;
  return DistanceToBoundary(p, poly);
}

std::size_t PickWeighted(CounterRng& rng, const std::vector<double>& w) {
  double total = 0.0;
  for (double x : w) total += x;
  double r = rng.Uniform() * total;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (r < w[i]) return i;
    r -= w[i];
  }
  return w.size() - 1;
}

/// Free-space grid of one room for the robot-path rule: a cell is free when its centre is at
/// least kRobotInflation from walls, columns and furniture, so connected free cells form
/// a path at least 0.8 m wide.
class RoomGrid {
 public:
  explicit RoomGrid(const Polygon2& poly) {
    Eigen::AlignedBox2d box;
    for (const auto& p : poly) box.extend(p);
    x0_ = box.min().x();
    y0_ = box.min().y();
    nx_ = static_cast<int>(std::ceil(box.sizes().x() / kGridRes));
    ny_ = static_cast<int>(std::ceil(box.sizes().y() / kGridRes));
    free_.assign(static_cast<std::size_t>(nx_ * ny_), 0);
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i) {
        const Vector2d c = Centre(i, j);
        free_[Idx(i, j)] =
            PointInPolygon(c, poly) && DistanceToBoundary(c, poly) >= kRobotInflation;
      }
  }
  void Block(const Polygon2& obstacle, std::vector<std::uint8_t>* cells) const {
    Eigen::AlignedBox2d box;
    for (const auto& p : obstacle) box.extend(p);
    const int i0 =
        std::max(0, static_cast<int>((box.min().x() - kRobotInflation - x0_) / kGridRes) - 1);
    const int i1 =
        std::min(nx_ - 1, static_cast<int>((box.max().x() + kRobotInflation - x0_) / kGridRes) + 1);
    const int j0 =
        std::max(0, static_cast<int>((box.min().y() - kRobotInflation - y0_) / kGridRes) - 1);
    const int j1 =
        std::min(ny_ - 1, static_cast<int>((box.max().y() + kRobotInflation - y0_) / kGridRes) + 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if ((*cells)[Idx(i, j)] && DistanceToConvex(Centre(i, j), obstacle) < kRobotInflation)
          (*cells)[Idx(i, j)] = 0;
  }
  void Commit(const Polygon2& obstacle) { Block(obstacle, &free_); }
  /// True if all seeds lie in one connected free region once `extra` is blocked too.
  bool Connected(const std::vector<Vector2d>& seeds, const Polygon2* extra) const {
    std::vector<std::uint8_t> cells = free_;
    if (extra) Block(*extra, &cells);
    std::vector<int> seed_cells;
    for (const auto& s : seeds) {
      const int c = Nearest(s, cells);
      if (c < 0) return false;
      seed_cells.push_back(c);
    }
    if (seed_cells.size() < 2) return true;
    std::vector<std::uint8_t> seen(cells.size(), 0);
    std::deque<int> queue{seed_cells[0]};
    seen[seed_cells[0]] = 1;
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      const int i = c % nx_, j = c / nx_;
      const int nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const auto& d : nb) {
        const int ii = i + d[0], jj = j + d[1];
        if (ii < 0 || jj < 0 || ii >= nx_ || jj >= ny_) continue;
        const int n = static_cast<int>(Idx(ii, jj));
        if (cells[n] && !seen[n]) {
          seen[n] = 1;
          queue.push_back(n);
        }
      }
    }
    for (int c : seed_cells)
      if (!seen[c]) return false;
    return true;
  }

 private:
  std::size_t Idx(int i, int j) const { return static_cast<std::size_t>(j * nx_ + i); }
  Vector2d Centre(int i, int j) const {
    return {x0_ + (i + 0.5) * kGridRes, y0_ + (j + 0.5) * kGridRes};
  }
  // The free cell nearest to a door seed, within kSeedReach: a leaf opened into the room
  // blocks the cells around its own door's seed, and the path then reaches the door past the
  // leaf's edge.
  int Nearest(const Vector2d& p, const std::vector<std::uint8_t>& cells) const {
    int best = -1;
    double best_d = kSeedReach;
    const int ci = static_cast<int>((p.x() - x0_) / kGridRes),
              cj = static_cast<int>((p.y() - y0_) / kGridRes);
    const int reach = static_cast<int>(std::ceil(kSeedReach / kGridRes));
    for (int j = cj - reach; j <= cj + reach; ++j)
      for (int i = ci - reach; i <= ci + reach; ++i) {
        if (i < 0 || j < 0 || i >= nx_ || j >= ny_ || !cells[Idx(i, j)]) continue;
        const double d = (Centre(i, j) - p).norm();
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(Idx(i, j));
        }
      }
    return best;
  }
  double x0_ = 0.0, y0_ = 0.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> free_;
};

class Generator {
 public:
  explicit Generator(const SceneSpec& spec) : spec_(spec), t_(spec.wall_thickness) {}

  GeneratedScene Run() {
    ValidateSceneSpec(spec_);
    out_.spec = spec_;
    out_.scene.source = "generated:" + spec_.name;
    out_.truth.scene_name = spec_.name;
    out_.truth.storeys.push_back({"storey_0", 0.0, spec_.storey_height});
    BuildRooms();
    ComputeAdjacency();
    ResolveDoors();
    ResolveWindows();
    CheckColumns();
    EmitWalls();
    EmitFacades();
    EmitFloorsAndCeilings();
    EmitColumns();
    EmitDoors();
    EmitWindows();
    PlaceBscs();
    PlaceFurniture();
    Finish();
    return std::move(out_);
  }

 private:
  // ---- materials and parts --------------------------------------------------------------------

  int Mat(const std::string& name, const MaterialSpec& m) {
    auto it = materials_.find(name);
    if (it != materials_.end()) return it->second;
    Material mat;
    mat.name = name;
    mat.base_color =
        Eigen::Vector4f(static_cast<float>(m.colour[0]), static_cast<float>(m.colour[1]),
                        static_cast<float>(m.colour[2]), 1.0f);
    mat.roughness = static_cast<float>(m.roughness);
    mat.metallic = static_cast<float>(m.metallic);
    mat.transmission = static_cast<float>(m.transmission);
    mat.nir_reflectance = static_cast<float>(m.nir_reflectance);
    mat.double_sided = true;
    const int idx = static_cast<int>(out_.scene.materials.size());
    out_.scene.materials.push_back(mat);
    materials_[name] = idx;
    return idx;
  }

  static MeshPart NewPart(const std::string& name, const std::string& id, ElementClass cls,
                          const std::string& subclass, const std::string& room, int material) {
    MeshPart p;
    p.name = name;
    p.element_id = id;
    p.element_class = cls;
    p.subclass = subclass;
    p.room = room;
    p.material = material;
    return p;
  }
  void Push(MeshPart&& p) {
    if (!p.triangles.empty()) out_.scene.parts.push_back(std::move(p));
  }

  // ---- rooms and walls ------------------------------------------------------------------------

  void BuildRooms() {
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

  void ComputeAdjacency() {
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
        const double s0 = std::max(0.0, std::min(ua, ub)),
                     s1 = std::min(f.length, std::max(ua, ub));
        if (s1 - s0 < 1e-3) continue;
        f.adj.push_back({s0, s1, static_cast<int>(j), (f.a - g.a).dot(g.dir)});
      }
      std::sort(faces_[i].adj.begin(), faces_[i].adj.end(),
                [](const Adjacency& x, const Adjacency& y) { return x.s0 < y.s0; });
    }
  }

  /// Outer (non-adjacent) intervals of a face.
  std::vector<std::pair<double, double>> OuterPortions(const Face& f) const {
    std::vector<std::pair<double, double>> out;
    double u = 0.0;
    for (const auto& ad : f.adj) {
      if (ad.s0 > u + 1e-6) out.emplace_back(u, ad.s0);
      u = std::max(u, ad.s1);
    }
    if (f.length > u + 1e-6) out.emplace_back(u, f.length);
    return out;
  }

  int RoomIndex(const std::string& id) const { return room_index_.at(id); }

  // ---- openings -------------------------------------------------------------------------------

  /// Finds the face of `room` and the centre u for an opening of `width` described by `pos`.
  /// other_room = -1: must be on an outer portion; otherwise on a wall shared with it.
  std::pair<int, double> LocateOpening(int room, const WallPosition& pos, double width,
                                       int other_room, double end_margin, const std::string& what,
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
    const std::string target = other_room >= 0
                                   ? "a wall shared with room '" + rooms_[other_room].id + "'"
                                   : "an outer wall";
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
      throw InputError(
          where, what + " is not on " + target + " of room '" + r.id + "'",
          "at [" + FormatFixed(pos.at.x(), 3) + ", " + FormatFixed(pos.at.y(), 3) + "]",
          "a point within " + FormatFixed(0.5 + t_, 3) + " m of " + target +
              " with room for the opening and its frame");
    return {best, best_u};
  }

  void AddHole(int face, const Rect2& hole, double frame, const std::string& id,
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

  void ResolveDoors() {
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

  /// Door `d`'s leaf at its opening angle. Hinged on the swing-room face: with n the normal
  /// into the swing room and d the direction from the hinge jamb to the latch jamb, "left"
  /// (hinge on the left seen from the swing room, facing the door) gives d = z x n. The leaf
  /// spans a in [0, width] along rd = cos(lambda) d + sin(lambda) n and b in [-thickness, 0]
  /// along rn = cos(lambda) n - sin(lambda) d; the hinge axis is d x n, so +lambda opens the
  /// leaf into the swing room. The hinge stands just in front of the casing (at the floor) so
  /// the opened leaf clears it.
  struct Leaf {
    Vector3d hinge, rd, rn, axis;
    double width = 0.0, thickness = 0.0;  // m
  };
  Leaf LeafOf(const DoorData& d) const {
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
  /// Plan footprint of an opened leaf (in its swing room).
  Polygon2 LeafFootprint(const DoorData& d) const {
    const Leaf l = LeafOf(d);
    const Vector2d h = l.hinge.head<2>(), a = l.rd.head<2>(), b = l.rn.head<2>();
    return {h, h + l.width * a, h + l.width * a - l.thickness * b, h - l.thickness * b};
  }

  int SwingRoom(const DoorData& d) const {
    if (d.swing_into_a) return faces_[d.face].room;
    return d.other >= 0 ? faces_[d.other].room : -1;
  }

  /// Plan rectangle bounding the floor the leaf sweeps from closed to its angle (shrunk by
  /// 1 cm so that neighbouring zones may touch).
  Polygon2 SwingZone(const DoorData& d) const {
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

  void ResolveWindows() {
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

  /// Plan rectangle kept free of furniture and columns in front of a door, in room `room`.
  Polygon2 DoorZone(const DoorData& d, int room) const {
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

  /// Point inside `room` in front of a door, where the robot enters.
  Vector2d DoorSeed(const DoorData& d, int room) const {
    const bool on_a = faces_[d.face].room == room;
    const Face& f = faces_[on_a ? d.face : d.other];
    const double u = on_a ? 0.5 * (d.hole.u0 + d.hole.u1) : d.c - 0.5 * (d.hole.u0 + d.hole.u1);
    return f.Plan(u, kRobotInflation + 0.1);
  }

  std::vector<int> DoorsOfRoom(int room) const {
    std::vector<int> out;
    for (std::size_t i = 0; i < doors_.size(); ++i) {
      const DoorData& d = doors_[i];
      if (faces_[d.face].room == room || (d.other >= 0 && faces_[d.other].room == room))
        out.push_back(static_cast<int>(i));
    }
    return out;
  }

  Polygon2 ColumnFootprint(const ColumnSpec& c) const {
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

  void CheckColumns() {
    for (const auto& c : spec_.columns) {
      const int r = RoomIndex(c.room);
      const Polygon2 fp = ColumnFootprint(c);
      for (int di : DoorsOfRoom(r))
        if (ConvexOverlap(fp, DoorZone(doors_[di], r)))
          throw InputError(c.where, "column '" + c.id + "' stands in front of door '" +
                                        doors_[di].spec->id + "'");
      columns_.push_back({r, fp});
    }
  }

  // ---- emitting geometry and truth ------------------------------------------------------------

  void EmitWalls() {
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

  /// Signed extension of an exterior face beyond a polygon vertex (mitre), halved when the
  /// neighbouring edge is shared with another room at that vertex.
  double VertexExtension(const Face& f, bool at_end) const {
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

  void EmitFacades() {
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
        for (const auto& t : tris)
          part.triangles.emplace_back(base + t[0], base + t[1], base + t[2]);
        e.polygons.push_back({f.P(e0, 0, -t_), f.P(e1, 0, -t_), f.P(e1, h, -t_), f.P(e0, h, -t_)});
      }
      if (part.triangles.empty()) continue;
      Push(std::move(part));
      facades_.push_back(e);
    }
  }

  void EmitFloorsAndCeilings() {
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

  void EmitColumns() {
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

  /// Casing boxes around a hole on one side of the wall; `w_lo..w_hi` is the box extent along
  /// face `f`'s inward normal, `back_skip` the bit of the face against the wall.
  static void AddCasing(PartBuilder& pb, const Face& f, const Rect2& h, double fw, double w_lo,
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

  /// Lining of the opening through the wall thickness (jambs, head, sill/threshold).
  void AddReveals(PartBuilder& pb, const Face& f, const Rect2& h) const {
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

  void EmitDoors() {
    for (const DoorData& d : doors_) {
      const DoorSpec& ds = *d.spec;
      const Face& f = faces_[d.face];
      const RoomData& ra = rooms_[f.room];
      const std::string room_b = d.other >= 0 ? rooms_[faces_[d.other].room].id : "";
      MaterialSpec fm = spec_.materials.door_frame;
      std::string fm_name = "door_frame";
      if (ds.has_frame_colour) {
        fm.colour = ds.frame_colour;
        fm_name += "_" + FormatFixed(fm.colour[0], 3) + "_" + FormatFixed(fm.colour[1], 3) + "_" +
                   FormatFixed(fm.colour[2], 3);
      }
      MaterialSpec lm = spec_.materials.door_leaf;
      std::string lm_name = "door_leaf";
      if (ds.has_leaf_colour) {
        lm.colour = ds.leaf_colour;
        lm_name += "_" + FormatFixed(lm.colour[0], 3) + "_" + FormatFixed(lm.colour[1], 3) + "_" +
                   FormatFixed(lm.colour[2], 3);
      }
      // Frame: lining through the wall and a protruding casing on both faces.
      MeshPart frame = NewPart(ds.id + "/frame", ds.id, ElementClass::kDoorFrame, "door", ra.id,
                               Mat(fm_name, fm));
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
      AddOrientedBox(lb, l.hinge, l.rd, l.rn, Vector3d::UnitZ(), {0.0, -l.thickness, 0.01},
                     {l.width, 0.0, ds.height - kLeafGap});
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

  void EmitWindows() {
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
        gname += "_" + FormatFixed(gm.transmission, 3);
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

  // ---- building service components ------------------------------------------------------------

  /// Adds the catalogue model of `cls` (materials and textures once per class) transformed by
  /// (origin; ex, ey, ez) with ex x ey = ez (the model's own right-handed frame).
  void AddBscGeometry(const std::string& id, const std::string& cls, const std::string& room,
                      const Vector3d& o, const Vector3d& ex, const Vector3d& ey,
                      const Vector3d& ez) {
    auto it = bsc_models_.find(cls);
    if (it == bsc_models_.end()) {
      Scene model = BuildBscModel(cls);
      const int tex_base = static_cast<int>(out_.scene.textures.size());
      for (auto& t : model.textures) out_.scene.textures.push_back(t);
      std::vector<int> mat_map;
      for (auto m : model.materials) {
        if (m.base_color_texture >= 0) m.base_color_texture += tex_base;
        mat_map.push_back(static_cast<int>(out_.scene.materials.size()));
        out_.scene.materials.push_back(m);
      }
      for (auto& p : model.parts) p.material = p.material >= 0 ? mat_map[p.material] : -1;
      it = bsc_models_.emplace(cls, std::move(model)).first;
    }
    for (const MeshPart& mp : it->second.parts) {
      MeshPart p = mp;
      std::string suffix = mp.name;
      if (suffix.rfind(cls, 0) == 0) suffix = suffix.substr(cls.size());
      if (!suffix.empty() && suffix[0] == '_') suffix = suffix.substr(1);
      p.name = id + "/" + (suffix.empty() ? "body" : suffix);
      p.element_id = id;
      p.element_class = ElementClass::kServiceComponent;
      p.subclass = cls;
      p.room = room;
      for (auto& v : p.positions) {
        const Vector3d l = v.cast<double>();
        v = (o + l.x() * ex + l.y() * ey + l.z() * ez).cast<float>();
      }
      Push(std::move(p));
    }
  }

  std::string NextBscId(const std::string& cls) {
    return cls + "_" + std::to_string(++bsc_counts_[cls]);
  }

  bool WallSpotFree(int face, const Rect2& rect, double depth) const {
    const Face& f = faces_[face];
    const double end = depth + 0.05;
    if (rect.u0 < end || rect.u1 > f.length - end || rect.v0 < 0.05 || rect.v1 > f.height() - 0.05)
      return false;
    for (const auto& k : f.keep_out)
      if (rect.Overlaps(k)) return false;
    const Vector2d c = f.Plan(0.5 * (rect.u0 + rect.u1), 0.5 * depth);
    for (const auto& col : columns_)
      if (col.room == f.room &&
          DistanceToConvex(c, col.footprint) < 0.5 * (rect.u1 - rect.u0) + depth + 0.15)
        return false;
    return true;
  }

  /// Where a BSC of class `stack` (placement `above`) would go over one at `rect`.
  static Rect2 StackRect(const Rect2& rect, const BscSpec& stack, double v_default) {
    const double v = std::max(v_default, rect.v1 + kBscMargin + 0.07 + 0.5 * stack.height);
    const double u = 0.5 * (rect.u0 + rect.u1);
    return {u - 0.5 * stack.width, u + 0.5 * stack.width, v - 0.5 * stack.height,
            v + 0.5 * stack.height};
  }

  /// The later entry that stacks components above class `cls`, or nullptr.
  const BscSpecEntry* StackedOver(const std::string& cls, std::size_t after) const {
    for (std::size_t i = after + 1; i < spec_.bscs.size(); ++i)
      if (spec_.bscs[i].placement == "above" && spec_.bscs[i].above == cls) return &spec_.bscs[i];
    return nullptr;
  }

  void PlaceWallBsc(const BscSpec& cat, int face, double u, double v, const std::string& room,
                    const Rect2* reserve = nullptr) {
    Face& f = faces_[face];
    WallBsc b;
    b.id = NextBscId(cat.class_name);
    b.cls = cat.class_name;
    b.room = room;
    b.face = face;
    b.rect = {u - 0.5 * cat.width, u + 0.5 * cat.width, v - 0.5 * cat.height, v + 0.5 * cat.height};
    b.depth = cat.depth;
    f.keep_out.push_back(b.rect.Expanded(kBscMargin));
    if (reserve) {
      b.reservation = static_cast<int>(f.keep_out.size());
      f.keep_out.push_back(reserve->Expanded(kBscMargin));
    }
    // Model frame: x to the right seen from the room (= -dir), y up, z into the room.
    const Vector3d o = f.P(u, v, 0.0);
    AddBscGeometry(b.id, b.cls, room, o, -Flat(f.dir), Vector3d::UnitZ(), Flat(f.n_in));
    ServiceComponent sc;
    sc.id = b.id;
    sc.bsc_class = b.cls;
    sc.host = f.id;
    sc.room = room;
    sc.centre = o;
    sc.normal = Flat(f.n_in);
    sc.size = {cat.width, cat.height, cat.depth};
    out_.truth.service_components.push_back(sc);
    wall_bscs_.push_back(b);
  }

  void PlaceCeilingBsc(const BscSpec& cat, int room, const Vector2d& p) {
    const RoomData& r = rooms_[room];
    const std::string id = NextBscId(cat.class_name);
    const Vector3d o = Lift(p, r.z1);
    // Model frame: z down out of the ceiling; x = world x, y = -world y (right-handed).
    AddBscGeometry(id, cat.class_name, r.id, o, Vector3d::UnitX(), -Vector3d::UnitY(),
                   -Vector3d::UnitZ());
    ServiceComponent sc;
    sc.id = id;
    sc.bsc_class = cat.class_name;
    sc.host = "ceiling_" + r.id;
    sc.room = r.id;
    sc.centre = o;
    sc.normal = -Vector3d::UnitZ();
    sc.size = {cat.width, cat.height, cat.depth};
    out_.truth.service_components.push_back(sc);
    ceiling_bscs_.push_back({room, p});
  }

  bool CeilingSpotFree(int room, const Vector2d& p, const BscSpec& cat) const {
    const RoomData& r = rooms_[room];
    if (!PointInPolygon(p, r.poly) || DistanceToBoundary(p, r.poly) < 0.5 + cat.width) return false;
    for (const auto& c : ceiling_bscs_)
      if (c.room == room && (c.p - p).norm() < 1.0) return false;
    for (const auto& col : columns_)
      if (col.room == room && DistanceToConvex(p, col.footprint) < 0.4) return false;
    return true;
  }

  std::vector<int> CandidateRooms(const BscSpecEntry& e) const {
    std::vector<int> out;
    if (e.rooms.empty()) {
      for (std::size_t i = 0; i < rooms_.size(); ++i) out.push_back(static_cast<int>(i));
    } else {
      for (const auto& id : e.rooms) out.push_back(RoomIndex(id));
    }
    return out;
  }

  [[noreturn]] void CannotPlace(const BscSpecEntry& e, int k, const std::string& why) const {
    throw InputError(e.where, "cannot place bsc '" + e.class_name + "' #" + std::to_string(k + 1) +
                                  " of " + std::to_string(e.count) + ": " + why);
  }

  /// Hole of door `d` on face `face` and whether its hinge is at the high-u end there.
  std::pair<Rect2, bool> DoorOnFace(const DoorData& d, int face) const {
    if (face == d.face) return {d.hole, d.hinge_high_u};
    return {Rect2{d.c - d.hole.u1, d.c - d.hole.u0, d.hole.v0, d.hole.v1}, !d.hinge_high_u};
  }

  void PlaceBscs() {
    for (std::size_t ei = 0; ei < spec_.bscs.size(); ++ei) {
      const BscSpecEntry& e = spec_.bscs[ei];
      const BscSpec& cat = *FindBsc(e.class_name);
      const double v_default = e.height >= 0.0 ? e.height : cat.default_mount_height;
      const std::string stream = "bsc/" + std::to_string(ei);
      if (e.is_explicit) {
        const int r = RoomIndex(e.room);
        if (cat.mounting == interfaces::Mounting::kCeiling) {
          if (!CeilingSpotFree(r, e.position, cat)) CannotPlace(e, 0, "ceiling spot not free");
          PlaceCeilingBsc(cat, r, e.position);
        } else {
          const int face = rooms_[r].faces[static_cast<std::size_t>(e.wall)];
          const Rect2 rect{e.u - 0.5 * cat.width, e.u + 0.5 * cat.width,
                           v_default - 0.5 * cat.height, v_default + 0.5 * cat.height};
          if (!WallSpotFree(face, rect, cat.depth))
            CannotPlace(e, 0, "wall spot on '" + faces_[face].id + "' is not free");
          PlaceWallBsc(cat, face, e.u, v_default, rooms_[r].id);
        }
        continue;
      }
      const std::vector<int> rooms = CandidateRooms(e);
      const std::string placement =
          !e.placement.empty()
              ? e.placement
              : (cat.mounting == interfaces::Mounting::kCeiling ? "ceiling" : "wall");
      if (placement == "wall" || placement == "ceiling") {
        const BscSpecEntry* stack = StackedOver(e.class_name, ei);
        for (int k = 0; k < e.count; ++k) {
          CounterRng rng(spec_.seed, stream, static_cast<std::uint64_t>(k));
          bool ok = false;
          for (int attempt = 0; attempt < kPlacementAttempts && !ok; ++attempt) {
            if (placement == "ceiling") {
              std::vector<double> w;
              for (int r : rooms) w.push_back(rooms_[r].area);
              const int r = rooms[PickWeighted(rng, w)];
              Eigen::AlignedBox2d box;
              for (const auto& p : rooms_[r].poly) box.extend(p);
              const Vector2d p(rng.Uniform(box.min().x(), box.max().x()),
                               rng.Uniform(box.min().y(), box.max().y()));
              if (CeilingSpotFree(r, p, cat)) {
                PlaceCeilingBsc(cat, r, p);
                ok = true;
              }
            } else {
              std::vector<int> faces;
              std::vector<double> w;
              for (int r : rooms)
                for (int fi : rooms_[r].faces) {
                  faces.push_back(fi);
                  w.push_back(faces_[fi].length);
                }
              const int fi = faces[PickWeighted(rng, w)];
              const Face& f = faces_[fi];
              const double u = rng.Uniform(0.0, f.length);
              const Rect2 rect{u - 0.5 * cat.width, u + 0.5 * cat.width,
                               v_default - 0.5 * cat.height, v_default + 0.5 * cat.height};
              if (!WallSpotFree(fi, rect, cat.depth)) continue;
              if (stack) {
                const BscSpec& sc = *FindBsc(stack->class_name);
                const Rect2 sr = StackRect(
                    rect, sc, stack->height >= 0 ? stack->height : sc.default_mount_height);
                if (!WallSpotFree(fi, sr, sc.depth)) continue;
                PlaceWallBsc(cat, fi, u, v_default, rooms_[f.room].id, &sr);
              } else {
                PlaceWallBsc(cat, fi, u, v_default, rooms_[f.room].id);
              }
              ok = true;
            }
          }
          if (!ok) CannotPlace(e, k, "no free " + placement + " space in its rooms");
        }
        continue;
      }
      // Rules relative to openings or other components: a deterministic shuffled candidate
      // list, taken in order.
      struct Spot {
        int face;
        double u, v;
        int target;  // wall_bscs_ index for "above"
      };
      std::vector<Spot> spots, second;  // second: less preferred spots (hinge side)
      std::set<int> in_rooms(rooms.begin(), rooms.end());
      for (std::size_t di = 0; di < doors_.size(); ++di) {
        const DoorData& d = doors_[di];
        for (int fi : {d.face, d.other}) {
          if (fi < 0 || !in_rooms.count(faces_[fi].room)) continue;
          const auto [h, hinge_high] = DoorOnFace(d, fi);
          const double fw = d.spec->frame_width;
          if (placement == "beside_door") {
            const double off = fw + kBscMargin + 0.08 + 0.5 * cat.width;
            const Spot lo{fi, h.u0 - off, v_default, -1}, hi{fi, h.u1 + off, v_default, -1};
            spots.push_back(hinge_high ? lo : hi);
            second.push_back(hinge_high ? hi : lo);
          } else if (placement == "above_door") {
            const double v = std::max(v_default, h.v1 + fw + kBscMargin + 0.02 + 0.5 * cat.height);
            spots.push_back({fi, 0.5 * (h.u0 + h.u1), v, -1});
          }
        }
      }
      if (placement == "under_window") {
        for (const auto& w : windows_) {
          if (!in_rooms.count(faces_[w.face].room)) continue;
          const double top = w.hole.v0 - w.spec->frame_width - kBscMargin - 0.02;
          spots.push_back({w.face, 0.5 * (w.hole.u0 + w.hole.u1),
                           std::min(v_default, top - 0.5 * cat.height), -1});
        }
      } else if (placement == "above") {
        for (std::size_t bi = 0; bi < wall_bscs_.size(); ++bi) {
          const WallBsc& t = wall_bscs_[bi];
          if (t.cls != e.above || !in_rooms.count(faces_[t.face].room)) continue;
          const Rect2 sr = StackRect(t.rect, cat, v_default);
          spots.push_back(
              {t.face, 0.5 * (sr.u0 + sr.u1), 0.5 * (sr.v0 + sr.v1), static_cast<int>(bi)});
        }
      }
      CounterRng shuffle(spec_.seed, stream + "/shuffle");
      for (auto* list : {&spots, &second})
        for (std::size_t i = list->size(); i > 1; --i)
          std::swap((*list)[i - 1], (*list)[shuffle.Below(i)]);
      spots.insert(spots.end(), second.begin(), second.end());
      std::size_t next = 0;
      for (int k = 0; k < e.count; ++k) {
        bool ok = false;
        while (next < spots.size() && !ok) {
          const Spot& s = spots[next++];
          if (s.target >= 0 && wall_bscs_[s.target].stacked) continue;
          const Rect2 rect{s.u - 0.5 * cat.width, s.u + 0.5 * cat.width, s.v - 0.5 * cat.height,
                           s.v + 0.5 * cat.height};
          // Release the space held for this component above its target.
          Rect2 held{};
          const int res = s.target >= 0 ? wall_bscs_[s.target].reservation : -1;
          if (res >= 0) {
            held = faces_[s.face].keep_out[res];
            faces_[s.face].keep_out[res] = Rect2{-10, -10, -10, -10};
          }
          if (!WallSpotFree(s.face, rect, cat.depth)) {
            if (res >= 0) faces_[s.face].keep_out[res] = held;
            continue;
          }
          if (res >= 0) wall_bscs_[s.target].reservation = -1;
          if (s.target >= 0) wall_bscs_[s.target].stacked = true;
          PlaceWallBsc(cat, s.face, s.u, s.v, rooms_[faces_[s.face].room].id);
          ok = true;
        }
        if (!ok) CannotPlace(e, k, "no free '" + placement + "' spot left");
      }
    }
  }

  // ---- furniture ------------------------------------------------------------------------------

  struct FurnitureShape {
    double w, d, h;
  };

  static FurnitureShape ShapeOf(const std::string& type, CounterRng& rng) {
    if (type == "desk") return {std::array{1.2, 1.4, 1.6}[rng.Below(3)], 0.7, 0.74};
    if (type == "cabinet")
      return {std::array{0.6, 0.8, 1.0}[rng.Below(3)], 0.45,
              std::array{0.75, 1.1, 1.9}[rng.Below(3)]};
    if (type == "shelf")
      return {std::array{0.8, 0.9, 1.2}[rng.Below(3)], 0.35, std::array{1.8, 2.0}[rng.Below(2)]};
    return {0.5, 0.5, 0.9};  // chair
  }

  void BuildFurnitureMesh(MeshPart* part, const std::string& type, const FurnitureShape& s,
                          const Vector2d& c, double yaw, double z0) const {
    PartBuilder pb(part);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = Lift(c, z0);
    X.linear() = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
    const double hw = 0.5 * s.w, hd = 0.5 * s.d;
    auto legs = [&](double size, double inset, double top) {
      for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
          const double x = sx * (hw - inset - 0.5 * size), y = sy * (hd - inset - 0.5 * size);
          pb.AddBox(X, {x - 0.5 * size, y - 0.5 * size, 0.0}, {x + 0.5 * size, y + 0.5 * size, top},
                    16 | 32);
        }
    };
    if (type == "desk") {
      pb.AddBox(X, {-hw, -hd, s.h - 0.03}, {hw, hd, s.h});
      legs(0.05, 0.03, s.h - 0.03);
    } else if (type == "cabinet") {
      pb.AddBox(X, {-hw, -hd, 0.0}, {hw, hd, s.h}, 16);
    } else if (type == "shelf") {
      const double th = 0.02;
      pb.AddBox(X, {-hw, -hd, 0.0}, {-hw + th, hd, s.h}, 16);  // sides
      pb.AddBox(X, {hw - th, -hd, 0.0}, {hw, hd, s.h}, 16);
      pb.AddBox(X, {-hw + th, -hd, 0.0}, {hw - th, -hd + 0.01, s.h}, 1 | 2 | 16);  // back
      const int boards = static_cast<int>(s.h / 0.38);
      for (int i = 0; i <= boards; ++i) {
        const double z = std::min(s.h - th, 0.05 + i * (s.h - 0.05 - th) / boards);
        pb.AddBox(X, {-hw + th, -hd + 0.01, z}, {hw - th, hd, z + th}, 1 | 2 | 4);
      }
    } else {  // chair: seat, back at -y, four legs
      pb.AddBox(X, {-hw, -hd, 0.42}, {hw, hd, 0.46});
      pb.AddBox(X, {-hw, -hd, 0.46}, {hw, -hd + 0.04, s.h}, 16);
      legs(0.03, 0.02, 0.42);
    }
  }

  void PlaceFurniture() {
    // Per room: free-space grid with columns, door zones and door seeds.
    std::vector<RoomGrid> grids;
    std::vector<std::vector<Polygon2>> zones(rooms_.size());
    std::vector<std::vector<Vector2d>> seeds(rooms_.size());
    for (std::size_t r = 0; r < rooms_.size(); ++r) {
      grids.emplace_back(rooms_[r].poly);
      for (const auto& c : columns_)
        if (c.room == static_cast<int>(r)) grids[r].Commit(c.footprint);
      for (int di : DoorsOfRoom(static_cast<int>(r))) {
        zones[r].push_back(DoorZone(doors_[di], static_cast<int>(r)));
        seeds[r].push_back(DoorSeed(doors_[di], static_cast<int>(r)));
        // An opened leaf stands in the room like furniture: the 0.8 m path between the doors
        // goes around it (a chair 0.24 m from a leaf's edge cut the only way to a door).
        if (doors_[di].lambda > 0.0 && SwingRoom(doors_[di]) == static_cast<int>(r))
          grids[r].Commit(LeafFootprint(doors_[di]));
      }
    }
    std::map<std::string, int> counts;
    std::vector<std::pair<Polygon2, Vector2d>> desks_front;  // desk footprint, front direction
    std::vector<int> desk_room;
    for (std::size_t ei = 0; ei < spec_.furniture.size(); ++ei) {
      const FurnitureSpec& fs = spec_.furniture[ei];
      const int r = RoomIndex(fs.room);
      const RoomData& room = rooms_[r];
      const std::string stream = "furniture/" + std::to_string(ei);
      for (int k = 0; k < fs.count; ++k) {
        CounterRng rng(spec_.seed, stream, static_cast<std::uint64_t>(k));
        const FurnitureShape shape = ShapeOf(fs.type, rng);
        bool ok = false;
        Vector2d centre;
        double yaw = 0.0;
        Polygon2 fp;
        int against_face = -1;
        for (int attempt = 0; attempt < kPlacementAttempts && !ok; ++attempt) {
          against_face = -1;
          if (fs.has_position) {
            if (attempt > 0) break;
            centre = fs.position;
            yaw = DegToRad(fs.yaw_deg);
          } else {
            const double mode = rng.Uniform();
            const bool wall =
                fs.type == "cabinet" || fs.type == "shelf" || (fs.type == "desk" && mode < 0.6);
            std::vector<int> room_desks;
            for (std::size_t di = 0; di < desks_front.size(); ++di)
              if (desk_room[di] == r) room_desks.push_back(static_cast<int>(di));
            if (wall) {
              std::vector<double> w;
              for (int fi : room.faces) w.push_back(faces_[fi].length);
              against_face = room.faces[PickWeighted(rng, w)];
              const Face& f = faces_[against_face];
              if (f.length < shape.w + 0.2) continue;
              const double u = rng.Uniform(0.5 * shape.w + 0.1, f.length - 0.5 * shape.w - 0.1);
              centre = f.Plan(u, 0.5 * shape.d + 0.01);
              yaw = std::atan2(f.n_in.y(), f.n_in.x()) - 0.5 * kPi;  // local +y (front) = n_in
            } else if (fs.type == "chair" && !room_desks.empty() && mode < 0.8) {
              const auto& [dfp, front] = desks_front[room_desks[rng.Below(room_desks.size())]];
              Vector2d dc = Vector2d::Zero();
              for (const auto& p : dfp) dc += 0.25 * p;
              const Vector2d side(-front.y(), front.x());
              centre = dc + front * (0.35 + 0.25 + rng.Uniform(0.0, 0.15)) +
                       side * rng.Uniform(-0.3, 0.3);
              yaw = std::atan2(-front.y(), -front.x()) - 0.5 * kPi;  // chair front faces desk
            } else {
              Eigen::AlignedBox2d box;
              for (const auto& p : room.poly) box.extend(p);
              centre = {rng.Uniform(box.min().x(), box.max().x()),
                        rng.Uniform(box.min().y(), box.max().y())};
              const Vector2d e0 = faces_[room.faces[0]].dir;
              yaw = std::atan2(e0.y(), e0.x()) + 0.5 * kPi * static_cast<double>(rng.Below(4));
            }
          }
          fp = OrientedRect(centre, yaw, shape.w, shape.d);
          if (!PolygonInside(fp, room.poly)) continue;
          if (against_face < 0 && !fs.has_position) {
            double dmin = 1e9;
            for (const auto& p : fp) dmin = std::min(dmin, DistanceToBoundary(p, room.poly));
            for (const auto& p : room.poly) dmin = std::min(dmin, DistanceToConvex(p, fp));
            if (dmin < (fs.type == "chair" ? 0.25 : 0.6)) continue;
          }
          if (!FurnitureSpotFree(r, fp, shape.h, zones[r])) continue;
          if (!grids[r].Connected(seeds[r], &fp)) continue;
          ok = true;
        }
        if (!ok)
          throw InputError(fs.where,
                           "cannot place " + fs.type + " #" + std::to_string(k + 1) + " in room '" +
                               room.id + "'",
                           "", "space clear of doors, walls' components and a 0.8 m path");
        grids[r].Commit(fp);
        furniture_.push_back({r, fp});
        if (fs.type == "desk") {
          desks_front.emplace_back(fp, Vector2d(-std::sin(yaw), std::cos(yaw)));
          desk_room.push_back(r);
        }
        const std::string id =
            fs.type + "_" + room.id + "_" + std::to_string(++counts[fs.type + "/" + room.id]);
        MeshPart part = NewPart(id, id, ElementClass::kFurniture, fs.type, room.id,
                                Mat(fs.type, fs.type == "desk"      ? spec_.materials.desk
                                             : fs.type == "cabinet" ? spec_.materials.cabinet
                                             : fs.type == "shelf"   ? spec_.materials.shelf
                                                                    : spec_.materials.chair));
        BuildFurnitureMesh(&part, fs.type, shape, centre, yaw, room.z0);
        Push(std::move(part));
        FurnitureItem item;
        item.id = id;
        item.type = fs.type;
        item.room = room.id;
        item.centre = Lift(centre, room.z0 + 0.5 * shape.h);
        item.yaw = yaw;
        item.size = {shape.w, shape.d, shape.h};
        out_.truth.furniture.push_back(item);
      }
    }
  }

  /// Furniture footprint clear of other furniture, columns, door zones, BSCs it would hit or
  /// hide (any wall BSC whose bottom is below the item's top + 0.1 m, within 0.6 m of its wall)
  /// and windows it would block.
  bool FurnitureSpotFree(int room, const Polygon2& fp, double height,
                         const std::vector<Polygon2>& zones) const {
    // Grow the footprint by ~5 cm on every side (corners moved 7 cm diagonally).
    Polygon2 grown = fp;
    Vector2d c = Vector2d::Zero();
    for (const auto& p : fp) c += 0.25 * p;
    for (auto& p : grown) p += (p - c).normalized() * 0.07;
    for (const auto& f : furniture_)
      if (f.room == room && ConvexOverlap(grown, f.footprint)) return false;
    for (const auto& col : columns_)
      if (col.room == room && ConvexOverlap(grown, col.footprint)) return false;
    for (const auto& z : zones)
      if (ConvexOverlap(fp, z)) return false;
    for (const auto& b : wall_bscs_) {
      const Face& f = faces_[b.face];
      if (f.room != room || b.rect.v0 > height + 0.1) continue;
      const Polygon2 zone{f.Plan(b.rect.u0 - 0.05, 0), f.Plan(b.rect.u1 + 0.05, 0),
                          f.Plan(b.rect.u1 + 0.05, std::max(0.6, b.depth)),
                          f.Plan(b.rect.u0 - 0.05, std::max(0.6, b.depth))};
      if (ConvexOverlap(fp, zone)) return false;
    }
    for (const auto& w : windows_) {
      const Face& f = faces_[w.face];
      if (f.room != room || w.hole.v0 - w.spec->frame_width > height + 0.05) continue;
      const double fw = w.spec->frame_width;
      const Polygon2 zone{f.Plan(w.hole.u0 - fw, 0), f.Plan(w.hole.u1 + fw, 0),
                          f.Plan(w.hole.u1 + fw, 0.6), f.Plan(w.hole.u0 - fw, 0.6)};
      if (ConvexOverlap(fp, zone)) return false;
    }
    return true;
  }

  /// Appends facades and rooms to the truth and checks that all ids are unique.
  void Finish() {
    // Facade elements go last so that walls, floors, ceilings and columns keep their order.
    for (auto& e : facades_) out_.truth.elements.push_back(std::move(e));
    std::set<std::string> ids;
    auto add = [&](const std::string& id) {
      if (!ids.insert(id).second)
        throw InputError(spec_.source, "generated id '" + id + "' is not unique", "",
                         "spec ids that do not clash with generated ones");
    };
    for (const auto& e : out_.truth.elements) add(e.id);
    for (const auto& o : out_.truth.openings) add(o.id);
    for (const auto& b : out_.truth.service_components) add(b.id);
    for (const auto& f : out_.truth.furniture) add(f.id);
    for (const RoomData& r : rooms_) {
      Room room;
      room.id = r.id;
      room.storey = "storey_0";
      room.polygon = r.poly;
      room.floor_z = r.z0;
      room.ceiling_z = r.z1;
      out_.truth.rooms.push_back(room);
    }
  }

  const SceneSpec& spec_;
  const double t_;
  GeneratedScene out_;
  std::vector<RoomData> rooms_;
  std::map<std::string, int> room_index_;
  std::vector<Face> faces_;
  std::vector<DoorData> doors_;
  std::vector<WindowData> windows_;
  std::vector<FurnitureBox> columns_;
  std::vector<FurnitureBox> furniture_;
  std::vector<WallBsc> wall_bscs_;
  std::vector<CeilingBsc> ceiling_bscs_;
  std::vector<StructuralElement> facades_;
  std::map<std::string, int> materials_;
  std::map<std::string, Scene> bsc_models_;
  std::map<std::string, int> bsc_counts_;
};

}  // namespace

GeneratedScene Generate(const SceneSpec& spec) { return Generator(spec).Run(); }

void WriteGeneratedScene(const GeneratedScene& generated, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory", ec.message());
  const std::filesystem::path d(dir);
  WriteGlb(generated.scene, (d / "scene.glb").string());
  WriteGroundTruth(generated.truth, (d / "scene.truth.json").string());
  const std::string spec_path = (d / "spec.effective.yaml").string();
  std::ofstream out(spec_path, std::ios::binary | std::ios::trunc);
  out << "# Effective scene spec (defaults filled in); regenerate with\n"
      << "#   mopad scene generate spec.effective.yaml -o DIR\n"
      << SceneSpecToYaml(generated.spec);
  if (!out) throw InputError(spec_path, "write failed");
}

}  // namespace mopad::scenes
