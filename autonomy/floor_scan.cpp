#include "autonomy/floor_scan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>

#include "autonomy/exploration.h"
#include "common/error.h"
#include "common/format.h"
#include "common/polygon.h"
#include "common/wall_clock.h"
#include "perception/point_cloud_ops.h"

namespace mopad::autonomy {
namespace {

double YawOf(const Vec2& d) { return std::atan2(d.y(), d.x()); }

constexpr double kOnWall = 0.3;     // m, an opening this near a gap's wall line lies on it
constexpr double kGapHeight = 2.0;  // m, nominal top of a gap's door record
// The reason of the doors not entered when the robot is shut in a room, before its name.
const std::string kShutIn = "not entered: the robot is shut in ";
const std::string kOutside = "leads outside: ";

class FloorMission {
 public:
  FloorMission(Navigator& nav, const RoomScanParams& rp, const FloorScanParams& p,
               const FloorScanHooks& hooks, const RecogniserSource& recogniser)
      : nav_(nav),
        rp_(rp),
        p_(p),
        hooks_(hooks),
        with_sm5_(static_cast<bool>(recogniser)),
        sm5_(recogniser, rp.sm5),
        target_(rp.icp) {}

  FloorScanResult Run() {
    const auto t0 = WallClock::now();
    res_.tree.AddRoot("room_1");
    if (with_sm5_) sm5_.Prepare();
    VisitRoom(0, DoorScan{});
    int current = 0;
    while (true) {
      DropExploredChildren(current);
      const std::vector<int> kids = res_.tree.UnvisitedChildren(current);
      if (kids.empty()) {
        if (current == 0) {
          res_.end_reason =
              "done: no door of a visited room leads to unexplored space" + NotEnteredSummary();
          break;
        }
        const std::string shut = ReturnToParent(current);
        if (!shut.empty()) {
          for (const TraversalNode& n : res_.tree.Nodes())
            if (n.state == NodeState::kUnvisited)
              res_.tree.MarkSeenNotEntered(n.id, kShutIn + res_.tree.Node(current).room);
          res_.end_reason =
              "stop: shut in " + res_.tree.Node(current).room + ": " + shut + NotEnteredSummary();
          break;
        }
        current = res_.tree.Node(current).parent;
        continue;
      }
      if (res_.tree.VisitedCount() >= p_.max_rooms) {
        for (const TraversalNode& n : res_.tree.Nodes())
          if (n.state == NodeState::kUnvisited)
            res_.tree.MarkSeenNotEntered(n.id, "room cap reached");
        res_.end_reason = "stop: room cap of " + std::to_string(p_.max_rooms) + " reached";
        break;
      }
      if (hooks_.stop_requested && hooks_.stop_requested()) {
        res_.end_reason = "stop: requested by the operator after " +
                          std::to_string(res_.tree.VisitedCount()) + " rooms";
        break;
      }
      const int kid = NearestChild(kids);
      DoorScan before;
      if (!EnterThroughDoor(kid, before)) continue;
      VisitRoom(kid, before);
      current = kid;
    }
    CollectSm5();
    DoorsFromLaterRooms();
    res_.scans = nav_.ScanCount();
    res_.sim_time = nav_.Time();
    res_.wall_time = SecondsSince(t0);
    return std::move(res_);
  }

 private:
  void Progress(const std::string& line) const {
    if (hooks_.progress) hooks_.progress(line);
  }

  // The room loop where the robot stands, the room's models, its doors into the tree.
  void VisitRoom(int node, DoorScan before) {
    if (node != 0)
      res_.tree.MarkVisited(node, "room_" + std::to_string(res_.tree.VisitedCount() + 1));
    RoomVisit v;
    v.node = node;
    v.room = res_.tree.Node(node).room;
    if (before.index >= 0) {
      // The door scan counts for the room it looked into.
      for (DoorScan& d : res_.door_scans)
        if (d.index == before.index) d.room = v.room;
      before.room = v.room;
      v.door_scan_before = before;
      res_.tree.Node(node).door_scan_before = before.index;
    }
    if (hooks_.room_started) hooks_.room_started(v.room);
    auto owned = std::make_unique<modelling::RoomModel>(rp_.model);
    modelling::RoomModel& model = *owned;
    const ScanHook on_scan = [&](int index, const interfaces::TlsScan& scan) {
      if (res_.tree.Node(node).door_scan_after < 0 && node != 0)
        res_.tree.Node(node).door_scan_after = index;
      if (hooks_.scan) hooks_.scan(v.room, index, scan);
      Progress(v.room + ": scan " + std::to_string(model.ScanCount()) + ", sensed " +
               FormatFixed(model.Coverage().ratio, 3) + " of the modelled structure");
    };
    try {
      v.scan = RunRoomScan(nav_, rp_, model, on_scan, &target_);
      // The rooms modelled before: their doors on this room's walls are hints (a leaf opened
      // into this room can hide its own doorway's frame from it).
      std::vector<modelling::Sm4Model> neighbours;
      for (const FloorRoom& r : res_.rooms)
        if (r.error.empty()) neighbours.push_back(r.sm4);
      v.models = modelling::BuildRoomModels(model, std::move(v.scan.no_return), rp_.sm3, rp_.sm4,
                                            rp_.sm5, v.room, &v.images, nullptr, neighbours);
    } catch (const std::exception& e) {
      v.error = e.what();
    }
    v.model = &model;
    // The last room's SM5 is done by now, as a rule (it ran while this room was scanned).
    CollectSm5();
    if (hooks_.room_done) hooks_.room_done(v);
    FloorRoom r;
    r.node = node;
    r.room = v.room;
    r.scans = static_cast<int>(v.scan.scans.size());
    r.stop_reason = v.error.empty() ? v.scan.stop_reason : "failed: " + v.error;
    if (!v.scan.scans.empty()) r.coverage = v.scan.scans.back().coverage.observable_ratio;
    if (model.ScanCount() > 0) r.perimeter = model.Perimeter();
    r.sm3 = v.models.sm3;
    r.sm4 = v.models.sm4;
    r.sm5 = v.models.sm5;  // its room named; the detection follows
    r.error = v.error;
    if (r.error.empty()) {
      const modelling::OpeningParams& op = rp_.sm4;
      r.leaf_z0 = r.sm3.floor_z + op.leaf_v_low * op.door_min_height;
      r.leaf_z1 = r.sm3.floor_z + op.door_max_height + op.lintel_search;
      if (!hooks_.room_points) r.leaf_points = LeafBand(model.Points(), r);
    }
    res_.tree.Node(node).reason = r.stop_reason;
    res_.rooms.push_back(std::move(r));
    // SM5 while the robot goes on; it keeps the room model (SM5's points) until it is done.
    if (res_.rooms.back().error.empty() && with_sm5_)
      sm5_.Start(res_.rooms.size() - 1, std::move(owned), std::move(v.models.sm3),
                 std::move(v.models.sm4), std::move(v.models.ortho));
    if (res_.rooms.back().error.empty()) AddChildren(node, res_.rooms.back());
  }

  // The SM5 of the room started last, into its FloorRoom.
  void CollectSm5() {
    std::optional<BackgroundSm5::Result> done = sm5_.Finish();
    if (!done) return;
    FloorRoom& r = res_.rooms.at(done->key);
    r.sm5 = std::move(done->sm5);
    r.sm5_seconds = done->seconds;
    r.sm5_error = std::move(done->error);
  }

  // A door a later room found on a wall it shares with an earlier room that did not show it
  // there (its leaf, opened into the earlier room, hid the doorway's frame): the earlier room
  // measures the leaf in its kept points (the later rooms had it as a hint already).
  void DoorsFromLaterRooms() {
    for (std::size_t i = 0; i < res_.rooms.size(); ++i) {
      FloorRoom& r = res_.rooms[i];
      if (!r.error.empty()) continue;
      std::vector<modelling::Sm4Model> later;
      for (std::size_t j = i + 1; j < res_.rooms.size(); ++j)
        if (res_.rooms[j].error.empty()) later.push_back(res_.rooms[j].sm4);
      if (hooks_.room_points) r.leaf_points = LeafBand(hooks_.room_points(r.room), r);
      modelling::OrthoPoints pts;
      pts.points = &r.leaf_points;
      r.doors_from_later_rooms =
          modelling::AddDoorsFromNeighbours(r.sm3, r.sm4, pts, later, rp_.sm4);
      std::vector<Eigen::Vector3f>().swap(r.leaf_points);
    }
  }

  // The points of `all` in the room's leaf band, in order.
  static std::vector<Eigen::Vector3f> LeafBand(const std::vector<Eigen::Vector3f>& all,
                                               const FloorRoom& r) {
    std::vector<Eigen::Vector3f> out;
    for (const Eigen::Vector3f& q : all)
      if (q.z() >= r.leaf_z0 && q.z() <= r.leaf_z1) out.push_back(q);
    return out;
  }

  // "; K doors not entered (closed: a, too narrow: b, unreachable: c)" or "".
  std::string NotEnteredSummary() const {
    int closed = 0, narrow = 0, unreachable = 0, shut_in = 0, outside = 0;
    for (const TraversalNode& n : res_.tree.Nodes()) {
      if (n.state == NodeState::kUnreachable) ++unreachable;
      if (n.state != NodeState::kSeenNotEntered) continue;
      if (n.reason.rfind(kOutside, 0) == 0) ++outside;
      if (n.reason.rfind("door closed", 0) == 0) ++closed;
      if (n.reason.rfind("door too narrow", 0) == 0) ++narrow;
      if (n.reason.rfind(kShutIn, 0) == 0) ++shut_in;
    }
    const std::string out = outside > 0
                                ? "; " + std::to_string(outside) + " door" +
                                      (outside > 1 ? "s" : "") + " to the outside not entered"
                                : std::string();
    if (closed + narrow + unreachable + shut_in == 0) return out;
    return out + "; " + std::to_string(closed + narrow + unreachable + shut_in) +
           " doors to unexplored space not entered (closed: " + std::to_string(closed) +
           ", too narrow: " + std::to_string(narrow) +
           ", unreachable: " + std::to_string(unreachable) +
           (shut_in > 0 ? ", left when shut in: " + std::to_string(shut_in) : std::string()) +
           "; dtt.json gives each reason)";
  }

  // The visited room whose perimeter holds `p`, or "".
  std::string VisitedRoomAt(const Vec2& p) const {
    for (const FloorRoom& r : res_.rooms)
      if (r.perimeter.size() >= 3 && PointInPolygon(p, r.perimeter)) return r.room;
    return "";
  }

  Vec2 Beyond(const DoorRecord& d) const { return d.centre - p_.beyond_probe * d.inward; }

  // Each door of the room's SM4 that leads to space no visited room covers, and that no node
  // holds yet (the same door found from its other side), becomes a child.
  void AddChildren(int node, const FloorRoom& room) {
    for (const modelling::DetectedOpening& o : room.sm4.openings) {
      if (o.type != modelling::OpeningType::kDoor) continue;
      DoorRecord d = DoorOf(o, room.room);
      if (!VisitedRoomAt(Beyond(d)).empty() || KnownDoor(d)) continue;
      d.map_clear_width_m = MapClearWidth(d);
      const bool sm4_passable =
          o.state != modelling::DoorState::kClosed && o.clear_width_m >= p_.min_clear_width;
      // The map's own evidence: a route through known free space from in front of the door to
      // beyond it, as wide as the robot needs (the scans saw through the door).
      const bool map_passable = MapPassage(d);
      // Rays that rose through an open door came back from a room's walls and ceiling; from the
      // outside (the sky, or a storey standing in nothing) they do not: the mission explores
      // the building, not its surroundings. (A closed door's dark leaf returns nothing either.)
      if ((sm4_passable || map_passable) && o.sky_share >= p_.outside_sky_share) {
        res_.tree.AddChild(
            node, d, NodeState::kSeenNotEntered,
            kOutside + FormatNumbers("%.2f of the rays that rose through it returned nothing",
                                     o.sky_share));
        continue;
      }
      if (sm4_passable || map_passable) {
        res_.tree.AddChild(node, d, NodeState::kUnvisited,
                           sm4_passable
                               ? ""
                               : "SM4 says " + d.state +
                                     FormatNumbers(", clear width %.2f m; the map shows a passage",
                                                   o.clear_width_m));
      } else if (o.state == modelling::DoorState::kClosed) {
        res_.tree.AddChild(
            node, d, NodeState::kSeenNotEntered,
            FormatNumbers("door closed (opening angle %.0f deg)", d.opening_angle_deg));
      } else {
        res_.tree.AddChild(node, d, NodeState::kSeenNotEntered,
                           FormatNumbers("door too narrow: clear width %.2f m < %.2f m",
                                         o.clear_width_m, p_.min_clear_width));
      }
    }
    // Doorways SM4 did not model that the map shows: gaps in the walls the scans saw through.
    int k = 0;
    for (const WallGap& g : WallGaps(nav_.Map(), room.perimeter, p_.gaps)) {
      if (OverlapsOpening(g, room.sm4)) continue;
      DoorRecord d = GapRecord(g, room.room, ++k);
      if (!VisitedRoomAt(Beyond(d)).empty() || KnownDoor(d)) continue;
      d.map_clear_width_m = MapClearWidth(d);
      const std::string what = FormatNumbers(
          "no SM4 opening here: a %.2f m gap in the wall that the scans saw through", d.width);
      if (d.width >= p_.min_clear_width)
        res_.tree.AddChild(node, d, NodeState::kUnvisited, what);
      else
        res_.tree.AddChild(node, d, NodeState::kSeenNotEntered,
                           what + FormatNumbers(", too narrow (< %.2f m)", p_.min_clear_width));
    }
  }

  // True when an SM4 opening (door or window) of the room lies on the gap's stretch of wall.
  static bool OverlapsOpening(const WallGap& g, const modelling::Sm4Model& sm4) {
    const Vec2 t = (g.b - g.a).normalized();
    const double len = g.width();
    for (const modelling::DetectedOpening& o : sm4.openings) {
      const Vec2 c0 = o.corners[0].head<2>(), c1 = o.corners[1].head<2>();
      if (std::abs((c0 - g.a).dot(g.inward)) > kOnWall ||
          std::abs((c1 - g.a).dot(g.inward)) > kOnWall)
        continue;
      const double u0 = (c0 - g.a).dot(t), u1 = (c1 - g.a).dot(t);
      if (std::max(u0, u1) > 0.0 && std::min(u0, u1) < len) return true;
    }
    return false;
  }

  // The door record of a gap: its plan ends on the wall line, corners up to kGapHeight (the map
  // measures no height), counter-clockwise seen from the room.
  static DoorRecord GapRecord(const WallGap& g, const std::string& room, int k) {
    DoorRecord d;
    d.room = room;
    d.opening = "gap_" + std::to_string(k);
    d.state = "gap";
    d.centre = g.centre();
    d.inward = g.inward;
    d.width = g.width();
    d.clear_width_m = d.width;
    const Vec2 t(-g.inward.y(), g.inward.x());  // (c1 - c0) x up points into the room
    const bool forward = (g.b - g.a).dot(t) > 0.0;
    const Vec2 a = forward ? g.a : g.b, b = forward ? g.b : g.a;
    d.corners = {Vec3(a.x(), a.y(), 0.0), Vec3(b.x(), b.y(), 0.0), Vec3(b.x(), b.y(), kGapHeight),
                 Vec3(a.x(), a.y(), kGapHeight)};
    return d;
  }

  // A route with half the minimum clear width of clearance from occupied cells (the jambs, an
  // opened leaf), from in front of the door to beyond it, no longer than a detour around the
  // leaf: the gap the scans saw is as wide as the robot needs. Space beyond the door that no
  // scan saw yet does not block it (the robot scans there before it drives on).
  bool MapPassage(const DoorRecord& d) const {
    const Vec2 from = Approach(d), to = d.centre - p_.door_exit * d.inward;
    const double len = RouteLengths(nav_.Map(), from, {to}, 0.5 * p_.min_clear_width,
                                    /*through_unknown=*/true)
                           .front();
    return len < 2.0 * (p_.door_approach + p_.door_exit);
  }

  // A node's door within half a door width of `d` (the same door seen from the other room).
  bool KnownDoor(const DoorRecord& d) const {
    for (const TraversalNode& n : res_.tree.Nodes())
      if (n.has_entry_door && (n.entry_door.centre - d.centre).norm() < 0.5 * d.width) return true;
    return false;
  }

  // Children whose far side a room visited since covers were explored through another door.
  void DropExploredChildren(int node) {
    for (int c : res_.tree.UnvisitedChildren(node)) {
      const std::string room = VisitedRoomAt(Beyond(res_.tree.Node(c).entry_door));
      if (!room.empty())
        res_.tree.MarkSeenNotEntered(c, "leads to " + room + ", entered through another door");
    }
  }

  Vec2 Approach(const DoorRecord& d) const { return d.centre + p_.door_approach * d.inward; }

  // m, the clear width of the door's doorway in the robot's map now (autonomy/doorway.h).
  double MapClearWidth(const DoorRecord& d) const {
    return DoorwayClearWidth(nav_.Map(), d.corners[0].head<2>(), d.corners[1].head<2>(), d.inward,
                             p_.doorway);
  }

  // When the map showed the door's doorway passable when the door was found and shows it
  // narrower than the robot needs and than doorway.shut_ratio of that now: why (its widths then
  // and now, the time), else "". The door was closed since it was mapped (someone shut it), or
  // something stands in it. The ratio tells a leaf swung across the doorway from a semi-open
  // leaf seen better from in front than when it was mapped; a door the robot `drove_through`
  // was passable, and narrower than the robot needs is closed since.
  std::string ClosedSinceMapped(const DoorRecord& d, bool drove_through = false) const {
    if (d.map_clear_width_m < p_.min_clear_width) return "";
    const double now = MapClearWidth(d);
    if (now >= p_.min_clear_width ||
        (!drove_through && now >= p_.doorway.shut_ratio * d.map_clear_width_m))
      return "";
    return FormatNumbers("its doorway was %.2f m clear in the map when ", d.map_clear_width_m) +
           d.room +
           FormatNumbers(" found it, %.2f m at %.1f s (< %.2f m)", now, nav_.Time(),
                         p_.min_clear_width);
  }

  // The unvisited child whose door the robot reaches by the shortest route in its map (ties
  // and unreachable ones: in the order they were added).
  int NearestChild(const std::vector<int>& kids) const {
    std::vector<Vec2> goals;
    for (int k : kids) goals.push_back(Approach(res_.tree.Node(k).entry_door));
    const Pose2 here = nav_.EstimatedPose();
    const std::vector<double> len =
        RouteLengths(nav_.Map(), Vec2(here.x, here.y), goals, p_.door_pose_clearance);
    std::size_t best = 0;
    for (std::size_t i = 1; i < kids.size(); ++i)
      if (len[i] < len[best]) best = i;
    return kids[best];
  }

  // Drives to a door scan pose on the door's axis, `depth` m from its wall plane on the side
  // `side` points to (or the nearest point with clearance), facing `yaw`. A small room may have
  // no such spot that far: nearer ones (down to 0.6 m) and then half the minimum clear width of
  // clearance are tried before giving up. Empty on arrival, else the reason.
  std::string DriveNear(const DoorRecord& d, const Vec2& side, double depth, double yaw,
                        const char* what) {
    const perception::DistanceField known(nav_.Map(), /*unknown_is_obstacle=*/true);
    std::optional<Vec2> goal;
    for (const double clearance : {p_.door_pose_clearance, 0.5 * p_.min_clear_width})
      for (double x = depth; !goal && x >= 0.6 - 1e-9; x -= 0.1)
        goal = NearestClearPoint(nav_.Map(), known, d.centre + x * side, p_.door_pose_search,
                                 clearance);
    if (!goal)
      return FormatNumbers("no free spot with %.2f m clearance 0.6-%.1f m from the door plane on ",
                           0.5 * p_.min_clear_width, depth) +
             "the " + what;
    const DriveStatus st = nav_.NavigateTo(Pose2{goal->x(), goal->y(), yaw});
    if (st == DriveStatus::kArrived) return "";
    return std::string("drive to the ") + what + ": " + ToString(st) + " (" + nav_.Log().message +
           ")";
  }

  // MoPAD's door passage: a scan in front of the door frame, then the base just beyond it,
  // where the room loop takes its first scan. False (node unreachable, explained) on failure.
  bool EnterThroughDoor(int kid, DoorScan& before) {
    const DoorRecord d = res_.tree.Node(kid).entry_door;
    const double yaw = YawOf(-d.inward);
    Progress("to the door " + d.opening + " of " + d.room +
             FormatNumbers(" (%.1f, %.1f)", d.centre.x(), d.centre.y()));
    std::string why = DriveNear(d, d.inward, p_.door_approach, yaw, "door's front");
    if (!why.empty()) {
      res_.tree.MarkUnreachable(kid, why);
      return false;
    }
    const interfaces::TlsScan& scan = nav_.TakeScan(rp_.scan_step_deg);
    // In the room it leaves: registered as that room's scans are, and then part of the target
    // the next room's first scan is registered against.
    perception::RegistrationResult reg;
    if (RegisterLastScan(nav_, target_.Map(), rp_.icp, rp_.acceptance, reg))
      target_.Add(perception::ScanPoints(scan), reg.X_MS);
    before = DoorScan{nav_.ScanCount() - 1, nav_.Time(), scan.X_MS_estimate, d.room};
    res_.door_scans.push_back(before);
    // The door scan is in the map now: a door shut since the room found it open is seen here.
    if (const std::string shut = ClosedSinceMapped(d); !shut.empty()) {
      DoorClosed(kid, "door closed since it was mapped: " + shut + ", after the door scan");
      return false;
    }
    why = DriveNear(d, -d.inward, p_.door_exit, yaw, "space beyond the door");
    if (!why.empty()) {
      const Pose2 at = nav_.EstimatedPose();
      const double depth = (Vec2(at.x, at.y) - d.centre).dot(-d.inward);
      if (depth < 0.5 * p_.door_exit) {
        if (const std::string shut = ClosedSinceMapped(d); !shut.empty())
          DoorClosed(kid, "door closed while the robot passed it: " + shut + "; " + why);
        else
          res_.tree.MarkUnreachable(kid, why);
        return false;
      }
    }
    return true;
  }

  // The door of `kid` found closed since it was mapped: a leaf, not entered, with `why`; one
  // line of the mission's events.
  void DoorClosed(int kid, const std::string& why) {
    const DoorRecord& d = res_.tree.Node(kid).entry_door;
    res_.tree.MarkSeenNotEntered(kid, why);
    res_.events.push_back(d.room + ": " + d.opening + ": " + why);
  }

  // Back through the entry door of `node` to its parent's side. "" when the robot got there or
  // failed for a reason the map does not show (an event, the mission goes on); the reason when
  // the door was shut behind the robot: then it is shut in.
  std::string ReturnToParent(int node) {
    const TraversalNode& n = res_.tree.Node(node);
    const DoorRecord& d = n.entry_door;
    Progress(n.room + " done; back through " + d.opening + " to " + d.room);
    const std::string why =
        DriveNear(d, d.inward, p_.door_approach, YawOf(d.inward), "parent's side of the door");
    if (why.empty()) return "";
    res_.events.push_back(n.room + ": return to " + d.room + ": " + why);
    const std::string shut = ClosedSinceMapped(d, /*drove_through=*/true);
    if (shut.empty()) return "";
    return "the door it came through (" + d.opening + " of " + d.room +
           ") was closed behind it: " + shut;
  }

  Navigator& nav_;
  const RoomScanParams& rp_;
  const FloorScanParams& p_;
  const FloorScanHooks& hooks_;
  bool with_sm5_;
  BackgroundSm5 sm5_;  // the SM5 of the room left last, beside the robot's next steps
  FloorScanResult res_;
  RegistrationTarget target_;  // every registered scan of the mission (the floor's S(t-1))
};

}  // namespace

DoorRecord DoorOf(const modelling::DetectedOpening& o, const std::string& room) {
  DoorRecord d;
  d.room = room;
  d.opening = o.id;
  d.state = modelling::ToString(o.state);
  d.opening_angle_deg = std::isfinite(o.opening_angle_deg) ? o.opening_angle_deg : 0.0;
  d.clear_width_m = o.clear_width_m;
  d.corners = o.corners;
  const Vec3 c0 = o.corners[0], c1 = o.corners[1], c3 = o.corners[3];
  d.centre = 0.5 * (c0 + c1).head<2>();
  d.width = (c1 - c0).head<2>().norm();
  const Vec2 n = (c1 - c0).cross(c3 - c0).head<2>();
  d.inward = n.norm() > 0 ? Vec2(n.normalized()) : Vec2::UnitX();
  return d;
}

FloorScanResult RunFloorScan(Navigator& navigator, const RoomScanParams& room_params,
                             const FloorScanParams& params, const FloorScanHooks& hooks,
                             const RecogniserSource& recogniser) {
  ValidateParams(params, "floor.");
  return FloorMission(navigator, room_params, params, hooks, recogniser).Run();
}

}  // namespace mopad::autonomy
