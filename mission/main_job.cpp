#include "mission/main_job.h"

#include <tbb/task_group.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "common/format.h"
#include "common/params.h"
#include "common/wall_clock.h"
#include "evaluation/run_evaluation.h"
#include "exports/exports.h"
#include "io/text_file.h"
#include "mission/room_job.h"
#include "mission/run_checkpoint.h"
#include "runfolder/layout.h"

namespace mopad::mission {
namespace {

// What the job collected, whichever mode ran.
struct JobTables {
  report::ReportTable rooms{"Rooms (robot side)", {}, {}, ""};
  report::ReportTable eval{"Evaluation against the truth",
                           {"room", "coverage of observable", "coverage of total",
                            "registration error max (mm / deg)", "SM1 labels agree"},
                           {},
                           ""};
  nlohmann::ordered_json rooms_json = nlohmann::json::array();
  nlohmann::ordered_json mission_json;  ///< floor mode only
  report::ReportTable tree;             ///< floor mode only
  int rooms_failed = 0;
  std::string subtitle;
};

void AddEvaluation(const std::string& room, const evaluation::RoomEvaluation& e, JobTables& t,
                   const MainJobOptions& o) {
  if (o.print)
    o.print(FormatNumbers("  evaluation: %.3f of observable, %.3f of total, ",
                          e.coverage.room.ShareOfObservable(), e.coverage.room.ShareOfTotal()) +
            FormatNumbers("registration max %.1f mm / %.3f deg, labels %.4f",
                          1000 * e.max_translation_error, e.max_rotation_error_deg,
                          e.labels.Accuracy()));
  t.eval.rows.push_back({room, FormatFixed(e.coverage.room.ShareOfObservable(), 3),
                         FormatFixed(e.coverage.room.ShareOfTotal(), 3),
                         FormatFixed(1000 * e.max_translation_error, 1) + " / " +
                             FormatFixed(e.max_rotation_error_deg, 3),
                         FormatFixed(e.labels.Accuracy(), 4)});
}

void AddScans(const std::string& room, const std::vector<Eigen::Vector3d>& positions,
              const std::vector<Eigen::Vector2f>& plan_points, report::ReportInput& report) {
  for (std::size_t k = 0; k < positions.size(); ++k) {
    report::ReportScan rs;
    rs.name = room + "/" + std::to_string(k);
    rs.position = positions[k];
    if (k == 0) rs.plan_points = plan_points;
    report.scans.push_back(std::move(rs));
  }
}

// Per-room mode: each room is a fresh robot; its boundary is the room's own figures.
RoomBoundary PerRoomBoundary(const std::string& id, const RoomJob* job) {
  RoomBoundary b;
  b.robot_room = b.room = id;
  Fingerprint f;
  f.Add(id).Add(job ? 1 : 0);
  if (job) {
    b.scans = static_cast<int>(job->mission.scans.size());
    f.Add(b.scans).Add(job->mission.stop_reason).Add(job->path_length).Add(job->points);
  }
  b.fingerprint = f.Hex();
  return b;
}

void RunPerRoom(const sim::SceneWorld& mw, const FloorMissionParams& params,
                const MainJobOptions& o, JobTables& t, report::ReportInput& report) {
  t.rooms.header = {"room", "scans", "robot coverage", "stop reason", "path (m)", "SM1 points"};
  bool stopped = false;
  for (const std::string& id : o.rooms) {
    if (stopped || (o.stop_requested && o.stop_requested())) {
      // An explained status for every listed room, also those the operator's stop left out.
      stopped = true;
      const std::string why = "not run: the operator stopped the job before this room";
      if (o.print) o.print("room " + id + ": " + why);
      t.rooms.rows.push_back({id, "-", "-", why, "-", "-"});
      t.rooms_json.push_back({{"room", id}, {"status", "not run"}, {"reason", why}});
      continue;
    }
    const auto t0 = WallClock::now();
    const std::string room_dir = runfolder::RoomDir(o.dir, id);
    std::optional<RoomJob> job;
    try {
      job = RunRoomJob(mw, id, params.room, std::nullopt, room_dir, true);
    } catch (const std::exception& ex) {
      if (o.print) o.print("room " + id + ": failed: " + ex.what());
      t.rooms.rows.push_back({id, "-", "-", std::string("failed: ") + ex.what(), "-", "-"});
      t.rooms_json.push_back({{"room", id},
                              {"status", "failed"},
                              {"reason", ex.what()},
                              {"seconds", SecondsSince(t0)}});
      ++t.rooms_failed;
      if (o.checkpoint) o.checkpoint->RoomDone(PerRoomBoundary(id, nullptr));
      continue;
    }
    const auto& m = job->mission;
    const double cov = m.scans.empty() ? 0.0 : m.scans.back().coverage.observable_ratio;
    if (o.print)
      o.print("room " + id + ": " + std::to_string(m.scans.size()) + " scans, robot coverage " +
              FormatFixed(cov, 3) + " (" + FormatFixed(SecondsSince(t0), 1) + " s)");
    t.rooms.rows.push_back({id, std::to_string(m.scans.size()), FormatFixed(cov, 3), m.stop_reason,
                            FormatFixed(job->path_length, 2), std::to_string(job->points)});
    AddEvaluation(id, *job->evaluation, t, o);
    AddScans(id, job->scan_positions_W, job->plan_points_W, report);
    report::ReportCoverage rc{id, {}, job->evaluation->coverage_per_scan};
    for (const RoomScanLog& s : m.scans) rc.robot.push_back(s.coverage.observable_ratio);
    report.coverage.push_back(std::move(rc));
    nlohmann::ordered_json rj;
    rj["room"] = id;
    rj["status"] = "scanned";
    rj["dir"] = std::string(runfolder::kRoomsDir) + "/" + id;
    rj["scans"] = m.scans.size();
    rj["stop_reason"] = m.stop_reason;
    rj["registration_failed"] = m.registration_failed;
    rj["robot_coverage"] = cov;
    rj["sm4_seconds"] = job->sm4_seconds;
    rj["sm5_seconds"] = job->sm5_seconds;
    rj["components"] = job->components;
    if (!job->fault_events.empty()) rj["faults"] = job->fault_events;
    rj["evaluation"] = evaluation::ToJson(*job->evaluation);
    rj["seconds"] = SecondsSince(t0);
    t.rooms_json.push_back(std::move(rj));
    if (o.checkpoint) o.checkpoint->RoomDone(PerRoomBoundary(id, &*job));
  }
  t.subtitle =
      "A fresh robot placed at a harness-chosen free spot of each listed room scans it "
      "from positions it chooses itself (next best scan, paper §3.1).";
}

// The detail pass's scans of the mission (of its `scans`; autonomy/detail_pass.h).
int DetailScans(const FloorJob& job) {
  int n = 0;
  for (const FloorRoomJob& r : job.rooms) n += r.detail_scans;
  return n;
}

nlohmann::ordered_json MissionJson(const FloorJob& job) {
  const auto& m = job.mission;
  const DriveResult& d = job.drive;
  nlohmann::ordered_json j;
  j["start_W"] = {job.start_W.x, job.start_W.y, job.start_W.yaw};
  j["start"] = {{"room", job.start.room}, {"how", job.start.how},
                {"clearance_m", job.start.clearance}};
  j["rooms_visited"] = m.tree.VisitedCount();
  j["rooms_known"] = m.tree.Nodes().size();
  j["scans"] = m.scans;
  j["door_scans"] = m.door_scans.size();
  j["detail_scans"] = DetailScans(job);
  j["end_reason"] = m.end_reason;
  j["events"] = m.events;
  j["path_length_m"] = d.path_length;
  j["contacts"] = d.contacts;
  j["localisation_rms_m"] = d.loc_rms;
  j["localisation_max_m"] = d.loc_max;
  j["max_true_step_m"] = job.max_true_step;
  if (!d.fault_events.empty()) j["faults"] = d.fault_events;  // the world's injected faults
  if (d.people > 0) {                                         // people walking (realism.people)
    j["people"] = {{"count", d.people},
                   {"contacts", d.person_contacts},
                   {"closest_m", d.person_closest},
                   {"contact_events", d.person_contact_events}};
  }
  j["sim_time_s"] = m.sim_time;
  j["wall_time_s"] = m.wall_time;
  j["files"] = {{"dtt", runfolder::kDtt},
                {"trajectory_true", runfolder::kTrajectoryTrue},
                {"trajectory_estimated", runfolder::kTrajectoryEstimated}};
  return j;
}

// The true path (every 0.5 s) and the tree's edges on the plan (world frame).
void AddMissionDrawing(const FloorJob& job, report::ReportInput& report) {
  for (std::size_t k = 0; k < job.drive.truth.size(); k += 25) {
    const Pose2& p = job.drive.truth[k].pose;
    report.path.push_back((job.X_WM * Vec3(p.x, p.y, 0.0)).head<2>());
  }
  auto first_scan_W = [&](const std::string& robot_room) -> std::optional<Eigen::Vector2d> {
    for (const FloorRoomJob& r : job.rooms)
      if (r.robot_room == robot_room && !r.scan_positions_W.empty())
        return r.scan_positions_W.front().head<2>();
    return std::nullopt;
  };
  for (const auto& n : job.mission.tree.Nodes()) {
    if (n.parent < 0 || !n.has_entry_door) continue;
    const auto from = first_scan_W(job.mission.tree.Node(n.parent).room);
    if (!from) continue;
    const Eigen::Vector2d via =
        (job.X_WM * Vec3(n.entry_door.centre.x(), n.entry_door.centre.y(), 0.0)).head<2>();
    const auto to = first_scan_W(n.room);
    report.tree_edges.push_back({*from, via, to ? *to : via,
                                 n.entry_door.room + " " + n.entry_door.opening + ": " +
                                     autonomy::ToString(n.state) +
                                     (n.reason.empty() ? "" : " (" + n.reason + ")")});
  }
}

void RunFloor(const sim::SceneWorld& mw, const FloorMissionParams& params, const MainJobOptions& o,
              JobTables& t, report::ReportInput& report) {
  t.rooms.header = {"robot room",     "scene room",  "scans (+ door)",
                    "robot coverage", "stop reason", "openings"};
  std::function<void(const RoomBoundary&)> boundary;
  if (o.checkpoint) boundary = [&o](const RoomBoundary& b) { o.checkpoint->RoomDone(b); };
  const FloorJob job =
      RunFloorJob(mw, params, o.start_W, o.dir, true, o.progress, o.stop_requested, boundary);
  for (const FloorRoomJob& r : job.rooms) {
    if (o.print)
      o.print(r.robot_room + " (" + r.room + "): " + r.status + ", " + std::to_string(r.scans) +
              " scans + " + std::to_string(r.door_scans) + " door scan, robot coverage " +
              FormatFixed(r.robot_coverage, 3) + "; " + r.reason + "; " +
              std::to_string(r.detail_scans) + " detail scans (" +
              FormatFixed(r.detail_sim_seconds, 1) + " s platform, " +
              FormatFixed(r.detail_wall_seconds, 1) + " s wall); room " +
              FormatFixed(r.sim_seconds, 1) + " s platform, " + FormatFixed(r.seconds, 1) +
              " s wall");
    t.rooms.rows.push_back(
        {r.robot_room, r.room, std::to_string(r.scans) + " + " + std::to_string(r.door_scans),
         FormatFixed(r.robot_coverage, 3), r.reason, std::to_string(r.openings)});
    nlohmann::ordered_json rj;
    rj["room"] = r.room;
    rj["robot_room"] = r.robot_room;
    rj["status"] = r.status;
    if (!r.dir.empty()) rj["dir"] = r.dir;
    rj["scans"] = r.scans;
    rj["door_scans"] = r.door_scans;
    rj[r.status == "failed" ? "reason" : "stop_reason"] = r.reason;
    rj["robot_coverage"] = r.robot_coverage;
    rj["openings"] = r.openings;
    rj["components"] = r.components;
    rj["sm4_seconds"] = r.sm4_seconds;
    rj["sm5_seconds"] = r.sm5_seconds;
    if (r.evaluation) {
      AddEvaluation(r.room, *r.evaluation, t, o);
      rj["evaluation"] = evaluation::ToJson(*r.evaluation);
    }
    rj["seconds"] = r.seconds;
    rj["sim_seconds"] = r.sim_seconds;
    rj["detail"] = {{"scans", r.detail_scans},
                    {"sim_time", r.detail_sim_seconds},
                    {"wall_time", r.detail_wall_seconds},
                    {"log", r.detail_log}};
    t.rooms_json.push_back(std::move(rj));
    if (r.status == "failed") ++t.rooms_failed;
    if (!r.robot_coverage_per_scan.empty())
      report.coverage.push_back(
          {r.room + " (" + r.robot_room + ")", r.robot_coverage_per_scan,
           r.evaluation ? r.evaluation->coverage_per_scan : std::vector<double>{}});
    AddScans(r.room, r.scan_positions_W, r.plan_points_W, report);
    for (const Eigen::Vector3d& p : r.door_scan_positions_W) {
      report::ReportScan rs;
      rs.name = r.room + "/door";
      rs.position = p;
      rs.door = true;
      report.scans.push_back(std::move(rs));
    }
  }
  AddMissionDrawing(job, report);
  t.mission_json = MissionJson(job);
  t.tree.title = "Dynamic Traversal Tree (dtt.json)";
  t.tree.header = {"node", "room", "scene room", "parent", "state", "entry door", "reason"};
  for (const auto& n : job.mission.tree.Nodes()) {
    std::string scene_room;
    for (const FloorRoomJob& r : job.rooms)
      if (!n.room.empty() && r.robot_room == n.room) scene_room = r.room;
    t.tree.rows.push_back({std::to_string(n.id), n.room, scene_room, std::to_string(n.parent),
                           autonomy::ToString(n.state),
                           n.has_entry_door ? n.entry_door.room + "/" + n.entry_door.opening +
                                                  " (" + n.entry_door.state + ", " +
                                                  FormatFixed(n.entry_door.clear_width_m, 2) + " m)"
                                            : "-",
                           n.state == autonomy::NodeState::kVisited ? "" : n.reason});
  }
  if (o.print) {
    for (const std::string& e : job.drive.fault_events) o.print("world: " + e);
    const auto& m = job.mission;
    o.print("mission: " + m.tree.Summary() + ", " + std::to_string(m.scans) + " scans (" +
            std::to_string(m.door_scans.size()) + " door scans, " +
            std::to_string(DetailScans(job)) + " detail scans), " +
            FormatNumbers("path %.1f m, contacts %.0f, localisation RMS %.1f cm max %.1f cm, ",
                          job.drive.path_length, job.drive.contacts, 100 * job.drive.loc_rms,
                          100 * job.drive.loc_max) +
            FormatNumbers("largest true step %.3f m; ", job.max_true_step) + m.end_reason);
  }
  t.subtitle =
      "One robot explores the floor from its start pose room by room through the doors "
      "it finds (Dynamic Traversal Tree, paper §2), scanning each room from positions "
      "it chooses itself (next best scan, §3.1).";
}

// A mission whose every room failed (or that was stopped before its first) modelled nothing:
// a robot outcome the rooms' reasons explain, with nothing to score or export.
constexpr const char* kNothingModelled =
    "no room was modelled (rooms[].reason says why each failed)";

// The robot's models scored against the truth and exported.
struct ScoredRun {
  bool modelled = false;            ///< false: kNothingModelled, nothing scored or exported
  evaluation::RunEvaluation eval;   ///< summary {"error": defect} when the evaluator refused
  std::string defect;               ///< the first refusal ("" none): an internal error
  std::string exports_error;        ///< the exporters' refusal ("" none)
  double t_eval = 0, t_export = 0;  ///< s, wall clock
};

// The models against the truth (`mopad eval` over every room, eval/) and the deliverables
// (docs/exports.md: export/model.ifc, model.glb, sm1.las). The robot's model files are this
// job's own output: one the evaluator or an exporter refuses is a defect of this program, not
// bad input. The job still writes the summary and the report (with the reason) and then ends
// with an internal error.
ScoredRun ScoreAndExport(const MainJobOptions& o, const JobTables& t) {
  ScoredRun s;
  s.modelled = std::any_of(t.rooms_json.begin(), t.rooms_json.end(),
                           [](const nlohmann::ordered_json& r) { return r.contains("dir"); });
  if (!s.modelled) {
    if (o.print) o.print(std::string("models against the truth: skipped; ") + kNothingModelled);
    return s;
  }
  if (o.print) o.print("models against the truth (mopad eval):");
  // The evaluation and the deliverables read the run folder's files and write folders of their
  // own (eval/, export/): they run side by side; what they print comes in the order below.
  std::string export_summary;
  tbb::task_group exports;
  exports.run([&] {
    const auto t0 = WallClock::now();
    try {
      export_summary = exports::WriteAllExports(o.dir).summary;
    } catch (const std::exception& e) {
      s.exports_error = std::string("the deliverables could not be written: ") + e.what();
    }
    s.t_export = SecondsSince(t0);
  });
  const auto t0 = WallClock::now();
  try {
    s.eval = evaluation::EvaluateRun(o.dir, "", "", runfolder::Join(o.dir, runfolder::kEvalDir));
  } catch (const std::exception& e) {
    s.defect = std::string("the models could not be evaluated: ") + e.what();
    s.eval.summary = {{"error", s.defect}};
  }
  s.t_eval = SecondsSince(t0);
  exports.wait();
  if (o.print) o.print(s.defect.empty() ? s.eval.tables : s.defect);
  if (s.defect.empty()) s.defect = s.exports_error;
  if (o.print) o.print(s.exports_error.empty() ? export_summary : s.exports_error);
  return s;
}

}  // namespace

bool RunMainJob(const sim::SceneWorld& mw, const FloorMissionParams& params,
                const MainJobOptions& options) {
  // Bad input ends the job before any work (the floor mission checks its start first thing).
  CheckJobRooms(mw, options.rooms);
  // The job stopped early when the operator's stop was asked for and granted (the missions
  // end at the first true answer).
  bool stopped = false;
  MainJobOptions o = options;
  if (options.stop_requested)
    o.stop_requested = [&stopped, ask = options.stop_requested] {
      if (ask()) stopped = true;
      return stopped;
    };
  const auto t_start = WallClock::now();
  report::ReportInput report;
  report.title = "OpenMoPAD run: " + o.scene_name;
  report.truth = &*mw.truth;
  report.coverage_threshold = params.room.scan.stopping.epsilon1;
  JobTables t;
  if (o.rooms.empty())
    RunFloor(mw, params, o, t, report);
  else
    RunPerRoom(mw, params, o, t, report);
  const double t_mission = SecondsSince(t_start);

  const ScoredRun scored = ScoreAndExport(o, t);

  nlohmann::ordered_json j;
  j["job"] = "run";
  j["mode"] = o.rooms.empty() ? "floor" : "rooms";
  j["scene"] = o.scene_json;
  j["seed"] = params.room.drive.seed;
  j["tls_step_deg"] = params.room.scan.scan_step_deg;
  if (o.rooms.empty()) j["mission"] = t.mission_json;
  j["rooms"] = t.rooms_json;
  j["rooms_failed"] = t.rooms_failed;
  const bool evaluated = scored.modelled && !scored.eval.summary.contains("error");
  if (!scored.modelled)
    j["models_evaluation"] = {{"skipped", kNothingModelled}};
  else if (!evaluated)
    j["models_evaluation"] = {{"error", scored.eval.summary["error"]}};
  else
    j["models_evaluation"] = {{"file", "eval/evaluation.json"}, {"summary", scored.eval.summary}};
  if (!scored.modelled) j["exports_skipped"] = kNothingModelled;
  if (!scored.exports_error.empty()) j["exports_error"] = scored.exports_error;
  j["seconds"] = {{"generate", o.t_generate},
                  {"mission", t_mission},
                  {"eval", scored.t_eval},
                  {"export", scored.t_export},
                  {"total", SecondsSince(t_start) + o.t_generate}};
  io::WriteTextFile(runfolder::Join(o.dir, runfolder::kSummary), j.dump(2) + "\n");
  io::WriteTextFile(runfolder::Join(o.dir, runfolder::kEffectiveConfig),
                    YAML::Dump(SaveParams(params)) + "\n");

  report.subtitle = t.subtitle + " Seed " + std::to_string(params.room.drive.seed) + ", TLS step " +
                    FormatFixed(params.room.scan.scan_step_deg, 3) + " deg.";
  report.tables.push_back(o.scene_table);
  report.tables.push_back(std::move(t.rooms));
  if (!t.tree.rows.empty()) report.tables.push_back(std::move(t.tree));
  report.tables.push_back(std::move(t.eval));
  if (!scored.modelled)
    report.tables.push_back({"Models against the truth", {"skipped"}, {{kNothingModelled}}, ""});
  else if (!evaluated)
    report.tables.push_back({"Models against the truth", {"error"}, {{scored.defect}}, ""});
  else
    report.tables.push_back(report::ModelScoresTable(scored.eval.summary));
  if (scored.eval.components) {
    const evaluation::ComponentTableText c = evaluation::ComponentsTable(*scored.eval.components);
    report.tables.push_back({"SM5 service components against the truth (paper Table 3, all rooms)",
                             c.header, c.rows, c.centre_errors});
  }
  report.tables.push_back({"Timing",
                           {"step", "seconds"},
                           {{"generate scene", FormatFixed(o.t_generate, 2)},
                            {"mission", FormatFixed(t_mission, 2)},
                            {"evaluate models", FormatFixed(scored.t_eval, 2)},
                            {"exports", FormatFixed(scored.t_export, 2)},
                            {"total", FormatFixed(SecondsSince(t_start) + o.t_generate, 2)}},
                           ""});
  report::WriteHtmlReport(report, runfolder::Join(o.dir, runfolder::kReportHtml));
  report::WriteMarkdownReport(report, runfolder::Join(o.dir, runfolder::kReportMarkdown));
  if (o.checkpoint) {
    if (stopped)
      o.checkpoint->MarkStopped();
    else
      o.checkpoint->MarkComplete();
  }
  if (!scored.defect.empty())
    throw std::runtime_error(scored.defect + " (summary.json and the report were written)");
  return !stopped;
}

}  // namespace mopad::mission
