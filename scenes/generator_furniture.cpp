// The generator's furniture: desks, chairs, cabinets and shelves placed at random against walls,
// at desks or free in the room, each clear of doors, components and windows, and never cutting
// the 0.8 m path the robot needs between a room's doors (scenes/generator_internal.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>

#include "common/error.h"
#include "common/frames.h"
#include "scenes/generator_internal.h"

namespace mopad::scenes::gen {
namespace {

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

}  // namespace

Generator::FurnitureShape Generator::ShapeOf(const std::string& type, CounterRng& rng) {
  if (type == "desk") return {std::array{1.2, 1.4, 1.6}[rng.Below(3)], 0.7, 0.74};
  if (type == "cabinet")
    return {std::array{0.6, 0.8, 1.0}[rng.Below(3)], 0.45,
            std::array{0.75, 1.1, 1.9}[rng.Below(3)]};
  if (type == "shelf")
    return {std::array{0.8, 0.9, 1.2}[rng.Below(3)], 0.35, std::array{1.8, 2.0}[rng.Below(2)]};
  return {0.5, 0.5, 0.9};  // chair
}

void Generator::BuildFurnitureMesh(MeshPart* part, const std::string& type, const FurnitureShape& s,
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

void Generator::PlaceFurniture() {
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
      // goes around it (else an item beside the leaf's edge can cut the only way to a door).
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
            centre =
                dc + front * (0.35 + 0.25 + rng.Uniform(0.0, 0.15)) + side * rng.Uniform(-0.3, 0.3);
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
        throw InputError(
            fs.where,
            "cannot place " + fs.type + " #" + std::to_string(k + 1) + " in room '" + room.id + "'",
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

bool Generator::FurnitureSpotFree(int room, const Polygon2& fp, double height,
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

}  // namespace mopad::scenes::gen
