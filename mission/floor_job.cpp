#include "mission/floor_job.h"

#include <tbb/task_group.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/polygon.h"
#include "common/wall_clock.h"
#include "evaluation/truth_models.h"
#include "io/scan_io.h"
#include "io/text_file.h"
#include "mission/floor_model_job.h"
#include "mission/robot_catalogue.h"
#include "mission/run_checkpoint.h"
#include "runfolder/layout.h"
#include "runfolder/room_files.h"

namespace mopad::mission {
namespace {

namespace fs = std::filesystem;
// The truth room whose outline holds the world point `p`, else the one with the nearest edge.
std::string TruthRoomAt(const scenes::GroundTruth& truth, const Eigen::Vector2d& p) {
  std::string best;
  double best_d = 1e300;
  for (const scenes::Room& r : truth.rooms) {
    if (PointInPolygon(p, r.polygon)) return r.id;
    for (std::size_t i = 0; i < r.polygon.size(); ++i) {
      const double d = DistanceToSegment(p, r.polygon[i], r.polygon[(i + 1) % r.polygon.size()]);
      if (d < best_d) best_d = d, best = r.id;
    }
  }
  return best;
}

nlohmann::ordered_json DoorJson(const autonomy::DoorRecord& d) {
  nlohmann::ordered_json c = nlohmann::json::array();
  for (const Vec3& v : d.corners) c.push_back({v.x(), v.y(), v.z()});
  return {{"room", d.room},
          {"opening", d.opening},
          {"state", d.state},
          {"opening_angle_deg", d.opening_angle_deg},
          {"clear_width_m", d.clear_width_m},
          {"map_clear_width_m", d.map_clear_width_m},
          {"centre", {d.centre.x(), d.centre.y()}},
          {"corners", c}};
}

nlohmann::ordered_json DttJson(const autonomy::FloorScanResult& m,
                               const std::vector<FloorRoomJob>& rooms) {
  nlohmann::ordered_json nodes = nlohmann::json::array();
  for (const autonomy::TraversalNode& n : m.tree.Nodes()) {
    nlohmann::ordered_json j;
    j["id"] = n.id;
    j["room"] = n.room;
    for (const FloorRoomJob& r : rooms)
      if (!n.room.empty() && r.robot_room == n.room) j["scene_room"] = r.room;
    j["parent"] = n.parent;
    j["state"] = autonomy::ToString(n.state);
    j["reason"] = n.reason;
    j["visit_order"] = n.visit_order;
    j["entry_door"] = n.has_entry_door ? DoorJson(n.entry_door) : nlohmann::ordered_json();
    j["children"] = n.children;
    j["door_scans"] = {{"before", n.door_scan_before}, {"after", n.door_scan_after}};
    nodes.push_back(std::move(j));
  }
  nlohmann::ordered_json scans = nlohmann::json::array();
  for (const autonomy::DoorScan& d : m.door_scans)
    scans.push_back({{"index", d.index}, {"sim_time", d.sim_time}, {"room", d.room}});
  nlohmann::ordered_json j;
  j["format"] = "mopad-dtt";
  j["version"] = 1;
  j["frame"] = "map";
  j["nodes"] = std::move(nodes);
  j["door_scans"] = std::move(scans);
  j["events"] = m.events;
  j["end_reason"] = m.end_reason;
  j["scans"] = m.scans;
  return j;
}

// The world side of one mission: the truth labels of the current room's scans, and each
// visited room's files and evaluation.
class FloorWorld {
 public:
  FloorWorld(const sim::SceneWorld& mw, const FloorMissionParams& params, RobotSession& session,
             const std::string& dir, bool evaluate,
             const std::function<void(const RoomBoundary&)>& room_boundary)
      : mw_(mw),
        params_(params),
        session_(session),
        dir_(dir),
        evaluate_(evaluate),
        room_boundary_(room_boundary) {}

  autonomy::FloorScanHooks Hooks(const std::function<void(const std::string&)>& progress) {
    autonomy::FloorScanHooks h;
    h.room_started = [this](const std::string&) { Started(); };
    h.scan = [this](const std::string&, int index, const interfaces::TlsScan& scan) {
      if (labels_) hook_(index, scan);
    };
    h.room_done = [this](const autonomy::RoomVisit& v) { Done(v); };
    // A finished room's points are in its sm1.ply (written by Done): read back, not kept.
    h.room_points = [this](const std::string& robot_room) {
      for (const FloorRoomJob& r : rooms_)
        if (r.robot_room == robot_room && !r.dir.empty())
          return io::ReadPly((fs::path(dir_) / r.dir / runfolder::kSm1).string()).points;
      throw std::runtime_error("floor job: no model files of room " + robot_room);
    };
    h.progress = progress;
    return h;
  }
  std::vector<FloorRoomJob>& Rooms() { return rooms_; }

 private:
  void Started() {
    t_room_ = WallClock::now();
    t_begin_ = session_.SimTime();
    const Pose2 at = session_.TruePoseInWorld();
    room_ = TruthRoomAt(*mw_.truth, Eigen::Vector2d(at.x, at.y));
    // The truth side scores an open-plan room as the robot meets it (MergeOpenPlanRooms).
    if (!open_plan_) open_plan_ = evaluation::MergeOpenPlanRooms(*mw_.truth, /*join_faces=*/false);
    labels_ = std::make_unique<Sm1TruthCollector>(session_, open_plan_->truth,
                                                  open_plan_->room_of.at(room_));
    hook_ = labels_->Hook();
  }

  void Done(const autonomy::RoomVisit& v) {
    FloorRoomJob r;
    r.robot_room = v.room;
    r.room = room_;
    r.scans = static_cast<int>(v.scan.scans.size());
    r.door_scans = v.door_scan_before.index >= 0 ? 1 : 0;
    for (const autonomy::RoomScanLog& s : v.scan.scans)
      r.robot_coverage_per_scan.push_back(s.coverage.observable_ratio);
    if (!v.scan.scans.empty()) r.robot_coverage = v.scan.scans.back().coverage.observable_ratio;
    r.status = v.error.empty() ? "scanned" : "failed";
    r.reason = v.error.empty() ? v.scan.stop_reason : v.error;
    if (v.error.empty()) Write(v, r);
    r.seconds = SecondsSince(t_room_);
    r.sim_seconds = session_.SimTime() - t_begin_;
    r.detail_scans = v.scan.detail_scans;
    r.detail_sim_seconds = v.scan.detail_sim_time;
    r.detail_wall_seconds = v.scan.detail_wall_time;
    r.detail_log = v.scan.detail_log;
    rooms_.push_back(std::move(r));
    labels_.reset();
    // This room is scored: the next one's own scans (its door scan included) come later.
    session_.ReleaseScanTruthPoints();
    if (room_boundary_) room_boundary_(Boundary(rooms_.back()));
  }

  RoomBoundary Boundary(const FloorRoomJob& r) const {
    RoomBoundary b;
    b.robot_room = r.robot_room;
    b.room = r.room;
    b.scans = session_.ScanCount();
    b.sim_time = session_.SimTime();
    Fingerprint f;
    f.Add(rooms_.size()).Add(b.robot_room).Add(b.room).Add(b.scans).Add(b.sim_time);
    const Pose2 truth = session_.TruePoseInWorld(), estimate = session_.EstimatedPose();
    f.Add(truth.x).Add(truth.y).Add(truth.yaw).Add(estimate.x).Add(estimate.y).Add(estimate.yaw);
    f.Add(r.status).Add(r.reason).Add(r.scans).Add(r.robot_coverage);
    b.fingerprint = f.Hex();
    return b;
  }

  void Write(const autonomy::RoomVisit& v, FloorRoomJob& r) {
    std::string name = room_;
    while (used_.count(name)) name += "_" + v.room;  // the same scene room entered twice
    used_.insert(name);
    r.dir = std::string(runfolder::kRoomsDir) + "/" + name;
    const std::string dir = (fs::path(dir_) / r.dir).string();
    const modelling::RoomModel& model = *v.model;
    RoomWindow window;
    if (v.door_scan_before.index >= 0)
      window.door_scans.emplace_back(v.door_scan_before.sim_time, v.door_scan_before.X_MS);
    window.t_begin = t_begin_;
    window.t_end = session_.SimTime();
    const Pose3 X_WM = session_.X_MW().To3d().inverse();
    // The scan files are written while the room is scored (both only read the room, the
    // session and the truth); its scores follow. The models follow once the floor has settled
    // each door's state (RunFloorJob).
    const runfolder::RoomScanFiles files = ScanFilesOf(mw_, session_, params_.room, v.scan, model,
                                                       v.models, v.images, room_, window, {});
    tbb::task_group writing;
    writing.run([&] { runfolder::WriteRoomScanFiles(dir, files); });
    try {
      if (evaluate_)
        r.evaluation = evaluation::EvaluateRoom(
            *mw_.world, open_plan_->truth, open_plan_->room_of.at(room_), X_WM, LoggedScans(v.scan),
            session_.ScanTruths(), model, labels_->Labels());
    } catch (...) {
      writing.wait();
      throw;
    }
    writing.wait();
    if (r.evaluation)
      runfolder::WriteRoomEvaluation(dir, evaluation::ToJson(*r.evaluation).dump(2));
    r.openings = v.models.sm4.openings.size();
    r.sm4_seconds = v.models.sm4_seconds;
    const auto& truths = session_.ScanTruths();
    if (v.door_scan_before.index >= 0)
      r.door_scan_positions_W.push_back(
          truths.at(static_cast<std::size_t>(v.door_scan_before.index)).X_WS.translation());
    for (const auto& s : v.scan.scans)
      r.scan_positions_W.push_back(
          truths.at(static_cast<std::size_t>(s.session_scan)).X_WS.translation());
    r.plan_points_W = PlanPoints(model, X_WM);
  }

  const sim::SceneWorld& mw_;
  const FloorMissionParams& params_;
  RobotSession& session_;
  std::string dir_;
  bool evaluate_;
  std::function<void(const RoomBoundary&)> room_boundary_;
  std::optional<evaluation::OpenPlanTruth> open_plan_;  // before labels_: they refer to it
  std::unique_ptr<Sm1TruthCollector> labels_;
  autonomy::ScanHook hook_;
  std::string room_;  // the truth room of the room being scanned
  std::set<std::string> used_;
  WallClock::time_point t_room_;
  double t_begin_ = 0.0;
  std::vector<FloorRoomJob> rooms_;
};

}  // namespace

FloorJob RunFloorJob(const sim::SceneWorld& mw, const FloorMissionParams& params,
                     const std::optional<Pose2>& start_W, const std::string& dir, bool evaluate,
                     const std::function<void(const std::string&)>& progress,
                     const std::function<bool()>& stop_requested,
                     const std::function<void(const RoomBoundary&)>& room_boundary) {
  CheckJobRooms(mw, {});
  FloorJob job;
  // The harness's start (truth side, before any work): a given one checked, else chosen.
  const scenes::RobotFootprint body = sim::FootprintOf(params.room.drive.body);
  job.start = start_W ? scenes::CheckStart(mw.world->scene(), *mw.truth, body, *start_W)
                      : scenes::ChooseStart(mw.world->scene(), *mw.truth, body);
  job.start_W = job.start.X_WB;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": error: cannot create the output folder; " + ec.message());
  RobotSession session(*mw.world, params.room.drive, job.start_W, params.room.faults,
                       DoorFaultOf(mw, params.room.faults), params.room.realism,
                       PeopleOf(mw, params.room.realism));
  FloorWorld world(mw, params, session, dir, evaluate, room_boundary);
  autonomy::FloorScanHooks hooks = world.Hooks(progress);
  hooks.stop_requested = stop_requested;
  // The recogniser trains on first use, beside the robot (with the first room's SM5).
  job.mission = autonomy::RunFloorScan(session.Robot(), params.room.scan, params.floor, hooks,
                                       [] { return &RobotComponentRecogniser(); });
  job.rooms = std::move(world.Rooms());
  // SM5 came after each room's files (autonomy/background_sm5.h).
  for (FloorRoomJob& rj : job.rooms)
    for (const autonomy::FloorRoom& r : job.mission.rooms) {
      if (r.room != rj.robot_room || rj.dir.empty()) continue;
      rj.components = r.sm5.components.size();
      rj.sm5_seconds = r.sm5_seconds;
      if (!r.sm5_error.empty()) rj.reason += "; SM5 failed: " + r.sm5_error;
    }
  job.drive = session.Result();
  job.X_WM = session.X_MW().To3d().inverse();
  for (std::size_t k = 1; k < job.drive.truth.size(); ++k) {
    const Pose2& a = job.drive.truth[k - 1].pose;
    const Pose2& b = job.drive.truth[k].pose;
    job.max_true_step = std::max(job.max_true_step, std::hypot(b.x - a.x, b.y - a.y));
  }
  const fs::path d(dir);
  io::WriteTextFile(runfolder::Join(dir, runfolder::kTrajectoryEstimated),
                    ToTum(job.drive.estimated));
  io::WriteTextFile(runfolder::Join(dir, runfolder::kTrajectoryTrue), ToTum(job.drive.truth));
  job.dtt = DttJson(job.mission, job.rooms);
  io::WriteTextFile(runfolder::Join(dir, runfolder::kDtt), job.dtt.dump(2) + "\n");
  // Each room's models once the floor has settled its doors' states (one door, one state).
  WriteFloorModel(job.mission, params.floor_model, dir, progress);
  for (const FloorRoomJob& rj : job.rooms) {
    if (rj.dir.empty()) continue;
    for (const autonomy::FloorRoom& r : job.mission.rooms)
      if (r.room == rj.robot_room)
        runfolder::WriteRoomModelFiles((d / rj.dir).string(), {rj.room, &r.sm3, &r.sm4, &r.sm5});
  }
  return job;
}

}  // namespace mopad::mission
