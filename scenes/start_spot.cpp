#include "scenes/start_spot.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "common/polygon.h"
#include "scenes/scene_check.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kMargin = 0.5;  // m of grid around the rooms' bounding box

// Squared distance transform of one row (Felzenszwalb and Huttenlocher, "Distance Transforms
// of Sampled Functions", 2012): d[i] = min_j (i - j)^2 + f[j].
void Edt1d(const std::vector<double>& f, std::vector<double>* d) {
  const int n = static_cast<int>(f.size());
  std::vector<int> v(static_cast<std::size_t>(n));
  std::vector<double> z(static_cast<std::size_t>(n) + 1);
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    double s = 0.0;
    while (true) {
      const int p = v[static_cast<std::size_t>(k)];
      s = ((f[static_cast<std::size_t>(q)] + double(q) * q) -
           (f[static_cast<std::size_t>(p)] + double(p) * p)) /
          (2.0 * (q - p));
      if (s <= z[static_cast<std::size_t>(k)] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  d->assign(static_cast<std::size_t>(n), 0.0);
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k) + 1] < q) ++k;
    const int p = v[static_cast<std::size_t>(k)];
    (*d)[static_cast<std::size_t>(q)] = double(q - p) * (q - p) + f[static_cast<std::size_t>(p)];
  }
}

// The part of triangle `t` between heights z0 and z1, projected to the plan.
std::vector<Vector2d> SliceInPlan(const std::vector<Vector3d>& t, double z0, double z1) {
  std::vector<Vector3d> poly = t;
  for (const auto& [sign, c] : {std::pair{1.0, z1}, std::pair{-1.0, -z0}}) {
    std::vector<Vector3d> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vector3d& p = poly[i];
      const Vector3d& q = poly[(i + 1) % poly.size()];
      const double dp = sign * p.z() - c, dq = sign * q.z() - c;
      if (dp <= 0.0) out.push_back(p);
      if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0))
        out.push_back(p + dp / (dp - dq) * (q - p));
    }
    poly = std::move(out);
    if (poly.empty()) return {};
  }
  std::vector<Vector2d> plan;
  for (const auto& p : poly) plan.push_back(p.head<2>());
  return plan;
}

// Distance from `p` to a plan polygon (0 inside), any winding, degenerate ones included.
double DistanceToPolygon(const Vector2d& p, const std::vector<Vector2d>& poly) {
  if (poly.size() >= 3 && std::abs(SignedArea(poly)) > 1e-12 && PointInPolygon(p, poly))
    return 0.0;
  double d = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i)
    d = std::min(d, DistanceToSegment(p, poly[i], poly[(i + 1) % poly.size()]));
  return d;
}

std::string Xy(const Vector2d& p) { return FormatNumbers("%.2f", p.x()) + "," +
                                           FormatNumbers("%.2f", p.y()); }

}  // namespace

double RobotFootprint::TurnRadius() const {
  return std::hypot(0.5 * length + std::abs(offset_x), 0.5 * width);
}

FreeSpace::FreeSpace(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot)
    : truth_(truth), robot_(robot) {
  Eigen::AlignedBox2d box;
  double floor = 1e300;
  for (const Room& r : truth.rooms) {
    for (const auto& p : r.polygon) box.extend(p);
    floor = std::min(floor, r.floor_z);
  }
  if (box.isEmpty()) throw InputError("", "the scene's truth has no rooms", "", "rooms");
  origin_ = box.min() - Vector2d(kMargin, kMargin);
  nx_ = static_cast<int>(std::ceil((box.sizes().x() + 2 * kMargin) / kCell));
  ny_ = static_cast<int>(std::ceil((box.sizes().y() + 2 * kMargin) / kCell));
  const std::size_t n = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  room_.assign(n, -1);
  blocker_.assign(n, -1);
  for (int iy = 0; iy < ny_; ++iy)
    for (int ix = 0; ix < nx_; ++ix)
      for (std::size_t r = 0; r < truth.rooms.size(); ++r)
        if (PointInPolygon(Centre(ix, iy), truth.rooms[r].polygon)) {
          room_[static_cast<std::size_t>(Index(ix, iy))] = static_cast<int>(r);
          break;
        }
  // Blocked cells: what the body would touch between its clearance and its top.
  const double z0 = floor + robot.ground_clearance, z1 = floor + robot.body_height;
  const double reach = 0.5 * std::sqrt(2.0) * kCell;
  std::map<std::string, int> id_index;
  for (const MeshPart& part : scene.parts) {
    for (const auto& t : part.triangles) {
      const std::vector<Vector3d> tri{part.positions[t[0]].cast<double>(),
                                      part.positions[t[1]].cast<double>(),
                                      part.positions[t[2]].cast<double>()};
      const std::vector<Vector2d> plan = SliceInPlan(tri, z0, z1);
      if (plan.empty()) continue;
      Eigen::AlignedBox2d b;
      for (const auto& p : plan) b.extend(p);
      const int x0 = std::max(0, static_cast<int>(std::floor((b.min().x() - reach - origin_.x()) / kCell)));
      const int x1 = std::min(nx_ - 1, static_cast<int>(std::floor((b.max().x() + reach - origin_.x()) / kCell)));
      const int y0 = std::max(0, static_cast<int>(std::floor((b.min().y() - reach - origin_.y()) / kCell)));
      const int y1 = std::min(ny_ - 1, static_cast<int>(std::floor((b.max().y() + reach - origin_.y()) / kCell)));
      for (int iy = y0; iy <= y1; ++iy)
        for (int ix = x0; ix <= x1; ++ix) {
          int& cell = blocker_[static_cast<std::size_t>(Index(ix, iy))];
          if (cell >= 0 || DistanceToPolygon(Centre(ix, iy), plan) > reach) continue;
          const std::string id = part.element_id.empty() ? part.name : part.element_id;
          auto [it, fresh] = id_index.emplace(id, static_cast<int>(blocker_ids_.size()));
          if (fresh) blocker_ids_.push_back(id);
          cell = it->second;
        }
    }
  }
  // Clearance: the exact Euclidean distance to the nearest blocked or outside cell.
  const double inf = 1e18;
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = (blocker_[i] >= 0 || room_[i] < 0) ? 0.0 : inf;
  std::vector<double> col(static_cast<std::size_t>(ny_)), row(static_cast<std::size_t>(nx_)), d;
  for (int ix = 0; ix < nx_; ++ix) {
    for (int iy = 0; iy < ny_; ++iy) col[static_cast<std::size_t>(iy)] = f[static_cast<std::size_t>(Index(ix, iy))];
    Edt1d(col, &d);
    for (int iy = 0; iy < ny_; ++iy) f[static_cast<std::size_t>(Index(ix, iy))] = d[static_cast<std::size_t>(iy)];
  }
  clearance_.assign(n, 0.0);
  for (int iy = 0; iy < ny_; ++iy) {
    for (int ix = 0; ix < nx_; ++ix) row[static_cast<std::size_t>(ix)] = f[static_cast<std::size_t>(Index(ix, iy))];
    Edt1d(row, &d);
    for (int ix = 0; ix < nx_; ++ix)
      clearance_[static_cast<std::size_t>(Index(ix, iy))] = std::sqrt(d[static_cast<std::size_t>(ix)]) * kCell;
  }
}

Vector2d FreeSpace::Centre(int ix, int iy) const {
  return origin_ + Vector2d((ix + 0.5) * kCell, (iy + 0.5) * kCell);
}

bool FreeSpace::Cell(const Vector2d& p, int* ix, int* iy) const {
  *ix = static_cast<int>(std::floor((p.x() - origin_.x()) / kCell));
  *iy = static_cast<int>(std::floor((p.y() - origin_.y()) / kCell));
  return *ix >= 0 && *iy >= 0 && *ix < nx_ && *iy < ny_;
}

double FreeSpace::Clearance(const Vector2d& p) const {
  int ix = 0, iy = 0;
  return Cell(p, &ix, &iy) ? clearance_[static_cast<std::size_t>(Index(ix, iy))] : 0.0;
}

bool FreeSpace::Free(const Vector2d& p) const {
  int ix = 0, iy = 0;
  return Cell(p, &ix, &iy) && room_[static_cast<std::size_t>(Index(ix, iy))] >= 0 &&
         clearance_[static_cast<std::size_t>(Index(ix, iy))] >= robot_.TurnRadius();
}

std::string FreeSpace::Problem(const Pose2& X_WB) const {
  const Vector2d ex(std::cos(X_WB.yaw), std::sin(X_WB.yaw)), ey(-ex.y(), ex.x());
  const Vector2d c = Vector2d(X_WB.x, X_WB.y) + robot_.offset_x * ex;
  // The cells whose centre lies in the footprint shrunk by the rasterisation's reach: what is
  // surely under the body (the simulator's exact check follows at the start).
  const double reach = 0.5 * std::sqrt(2.0) * kCell;
  const double hl = 0.5 * robot_.length - reach, hw = 0.5 * robot_.width - reach;
  const double r = std::hypot(hl, hw);
  int cx = 0, cy = 0;
  if (!Cell(c, &cx, &cy)) return "outside the building (no room holds it)";
  const int k = static_cast<int>(std::ceil(r / kCell)) + 1;
  bool outside = false;
  int hit = -1;  // the blocker nearest to the footprint's centre
  double hit_d = 1e300;
  for (int iy = cy - k; iy <= cy + k; ++iy)
    for (int ix = cx - k; ix <= cx + k; ++ix) {
      if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) continue;
      const Vector2d q = Centre(ix, iy) - c;
      if (std::abs(q.dot(ex)) > hl || std::abs(q.dot(ey)) > hw) continue;
      const std::size_t i = static_cast<std::size_t>(Index(ix, iy));
      if (blocker_[i] >= 0 && q.squaredNorm() < hit_d - 1e-12) {
        hit_d = q.squaredNorm();
        hit = blocker_[i];
      }
      outside = outside || room_[i] < 0;
    }
  if (hit >= 0)
    return "in collision with the scene (" + blocker_ids_[static_cast<std::size_t>(hit)] + ")";
  if (room_[static_cast<std::size_t>(Index(cx, cy))] < 0)
    return "outside the building (no room holds it)";
  return outside ? "partly outside the building (no room holds all of it)" : "";
}

bool FreeSpace::NearestFree(const Vector2d& p, Vector2d* out) const {
  double best = 1e300;
  for (int iy = 0; iy < ny_; ++iy)
    for (int ix = 0; ix < nx_; ++ix) {
      const Vector2d c = Centre(ix, iy);
      const double d = (c - p).squaredNorm();
      if (d < best - 1e-12 && Free(c)) {
        best = d;
        *out = c;
      }
    }
  return best < 1e299;
}

bool FreeSpace::BestSpotIn(const std::string& room_id, Vector2d* out, double* area) const {
  int r = -1;
  for (std::size_t k = 0; k < truth_.rooms.size(); ++k)
    if (truth_.rooms[k].id == room_id) r = static_cast<int>(k);
  double best = -1.0;
  int free = 0;
  for (int iy = 0; iy < ny_; ++iy)
    for (int ix = 0; ix < nx_; ++ix) {
      const std::size_t i = static_cast<std::size_t>(Index(ix, iy));
      if (room_[i] != r || clearance_[i] < robot_.TurnRadius()) continue;
      ++free;
      if (clearance_[i] > best + 1e-9) {
        best = clearance_[i];
        *out = Centre(ix, iy);
      }
    }
  if (area) *area = free * kCell * kCell;
  return free > 0;
}

StartSpot ChooseStart(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot) {
  const FreeSpace space(scene, truth, robot);
  const std::map<std::string, std::vector<std::string>> graph = OpenDoorGraph(truth);
  // Spaces: rooms joined by open passages are one space (the robot meets them as one room).
  std::map<std::string, std::vector<std::string>> open_to;
  for (const RoomConnection& c : truth.connections)
    if (c.door.empty() && !c.room_b.empty()) {
      open_to[c.room_a].push_back(c.room_b);
      open_to[c.room_b].push_back(c.room_a);
    }
  // Flood fill in truth order: `of` maps a room to its group (doors) or space (passages).
  auto flood = [&](const std::map<std::string, std::vector<std::string>>& g) {
    std::map<std::string, int> of;
    int n = 0;
    for (const Room& r : truth.rooms) {
      if (of.count(r.id)) continue;
      std::deque<std::string> queue{r.id};
      of[r.id] = n;
      while (!queue.empty()) {
        const std::string a = queue.front();
        queue.pop_front();
        const auto it = g.find(a);
        if (it == g.end()) continue;
        for (const std::string& b : it->second)
          if (of.emplace(b, n).second) queue.push_back(b);
      }
      ++n;
    }
    return of;
  };
  const std::map<std::string, int> group = flood(graph), space_of = flood(open_to);
  std::map<int, int> group_size;
  for (const auto& [room, g] : group) ++group_size[g];
  int best_group = -1;
  for (const Room& r : truth.rooms)  // the largest group, the first in truth order on a tie
    if (best_group < 0 || group_size[group.at(r.id)] > group_size[best_group])
      best_group = group.at(r.id);
  // Per room of that group: its free area, best spot, and the rooms outside its own space one
  // open door away; per space: the sums.
  struct RoomInfo {
    std::string id;
    Eigen::Vector2d spot;
    double area = 0.0;
    std::set<std::string> neighbours;
  };
  std::vector<RoomInfo> rooms;
  std::map<int, double> space_area;
  std::map<int, std::set<std::string>> space_neighbours;
  for (const Room& r : truth.rooms) {
    if (group.at(r.id) != best_group) continue;
    RoomInfo info;
    info.id = r.id;
    if (!space.BestSpotIn(r.id, &info.spot, &info.area)) continue;
    const auto it = graph.find(r.id);
    if (it != graph.end())
      for (const std::string& b : it->second)
        if (space_of.at(b) != space_of.at(r.id)) info.neighbours.insert(b);
    space_area[space_of.at(r.id)] += info.area;
    space_neighbours[space_of.at(r.id)].insert(info.neighbours.begin(), info.neighbours.end());
    rooms.push_back(info);
  }
  if (rooms.empty())
    throw InputError("", "no room of the scene has a free spot for the robot", "",
                     "a room with " + FormatNumbers("%.2f", robot.TurnRadius()) +
                         " m clearance around a point");
  // The space with the most floor a first look reaches: its own free floor times the rooms one
  // open door away (plus itself). A hall or corridor connected to many rooms wins over a large
  // dead-end room; a stair hall crowded to a few square metres or a closet does not win over
  // the large room next to it. Ties: the larger space, then truth order.
  auto score = [&](int sp) {
    return space_area[sp] * static_cast<double>(space_neighbours[sp].size() + 1);
  };
  int best_space = -1;
  for (const RoomInfo& r : rooms) {
    const int sp = space_of.at(r.id);
    if (best_space < 0 || score(sp) > score(best_space) + 1e-9 ||
        (std::abs(score(sp) - score(best_space)) <= 1e-9 &&
         space_area[sp] > space_area[best_space] + 1e-9))
      best_space = sp;
  }
  // In that space, the room with the most doors to others (ties: the larger room).
  const RoomInfo* best = nullptr;
  for (const RoomInfo& r : rooms) {
    if (space_of.at(r.id) != best_space) continue;
    if (!best || r.neighbours.size() > best->neighbours.size() ||
        (r.neighbours.size() == best->neighbours.size() && r.area > best->area + 1e-9))
      best = &r;
  }
  StartSpot s;
  s.X_WB = Pose2{best->spot.x(), best->spot.y(), 0.0};
  s.room = best->id;
  s.clearance = space.Clearance(best->spot);
  s.how = "room " + best->id + ": of the " + std::to_string(group_size[best_group]) + " of " +
          std::to_string(truth.rooms.size()) +
          " rooms that open doors connect, in the space with the most free floor times rooms "
          "reached (" + FormatNumbers("%.1f", space_area[best_space]) + " m2 x (" +
          std::to_string(space_neighbours[best_space].size()) +
          " + 1)), its room with the most doors (" + std::to_string(best->neighbours.size()) +
          "); the spot farthest from obstacles (" + FormatNumbers("%.2f", s.clearance) + " m)";
  return s;
}

StartSpot StartInRoom(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot,
                      const std::string& room_id) {
  const FreeSpace space(scene, truth, robot);
  Eigen::Vector2d spot;
  double area = 0.0;
  if (!space.BestSpotIn(room_id, &spot, &area))
    throw InputError("", "room " + room_id + " has no free spot for the robot", "",
                     FormatNumbers("%.2f", robot.TurnRadius()) + " m clearance around a point");
  StartSpot s;
  s.X_WB = Pose2{spot.x(), spot.y(), 0.0};
  s.room = room_id;
  s.clearance = space.Clearance(spot);
  s.how = "room " + room_id + ": its spot farthest from obstacles (" +
          FormatNumbers("%.2f", s.clearance) + " m)";
  return s;
}

StartSpot CheckStart(const Scene& scene, const GroundTruth& truth, const RobotFootprint& robot,
                     const Pose2& X_WB, const std::string& flag) {
  const FreeSpace space(scene, truth, robot);
  const std::string problem = space.Problem(X_WB);
  const Vector2d p(X_WB.x, X_WB.y);
  if (!problem.empty()) {
    Vector2d near;
    const std::string hint =
        space.NearestFree(p, &near) ? "; nearest free spot " + Xy(near) : "; no free spot at all";
    throw InputError(flag + " " + Xy(p) + "," + FormatNumbers("%.1f", RadToDeg(X_WB.yaw)) +
                     ": error: " + problem + hint);
  }
  StartSpot s;
  s.X_WB = X_WB;
  for (const Room& r : truth.rooms)
    if (PointInPolygon(p, r.polygon)) {
      s.room = r.id;
      break;
    }
  s.clearance = space.Clearance(p);
  s.how = "given by " + flag;
  return s;
}

}  // namespace mopad::scenes
