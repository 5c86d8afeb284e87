#include "mission/room_job.h"

#include <yaml-cpp/yaml.h>

#include "common/error.h"
#include "common/params.h"
#include "evaluation/truth_models.h"
#include "mission/robot_catalogue.h"
#include "runfolder/layout.h"

namespace mopad::mission {

autonomy::ScanHook Sm1TruthCollector::Hook() {
  return [this](int index, const interfaces::TlsScan& scan) {
    const auto& truths = session_.ScanTruths();
    if (index < 0 || static_cast<std::size_t>(index) >= truths.size())
      throw std::runtime_error("room eval: no truth kept for scan " + std::to_string(index));
    const std::vector<evaluation::Sm1Label> grid =
        evaluation::TruthLabels(scan, truths[static_cast<std::size_t>(index)], truth_, room_);
    // RoomModel keeps every valid return column by column (the PLY order).
    const std::vector<evaluation::Sm1Label> valid = evaluation::InPlyOrder(scan, grid);
    labels_.insert(labels_.end(), valid.begin(), valid.end());
  };
}

std::vector<evaluation::LoggedScan> LoggedScans(const RoomMissionResult& log) {
  std::vector<evaluation::LoggedScan> out;
  for (const RoomScanLog& s : log.scans)
    out.push_back({s.X_MS, s.registered || s.at_prior, static_cast<std::size_t>(s.session_scan)});
  return out;
}

std::vector<Eigen::Vector2f> PlanPoints(const modelling::RoomModel& model, const Pose3& X_WM) {
  std::vector<Eigen::Vector2f> out;
  const auto& pts = model.Points();
  const double z_lo = model.FloorZ() + kPlanBandLow, z_hi = model.FloorZ() + kPlanBandHigh;
  for (std::size_t i = 0; i < pts.size(); i += kPlanPointStride) {
    if (pts[i].z() < z_lo || pts[i].z() > z_hi) continue;
    const Eigen::Vector3d w = X_WM * pts[i].cast<double>();
    out.emplace_back(static_cast<float>(w.x()), static_cast<float>(w.y()));
  }
  return out;
}

runfolder::RoomScanFiles ScanFilesOf(
    const sim::SceneWorld& mw, const RobotSession& session, const RoomMissionParams& params,
    const RoomMissionResult& log, const modelling::RoomModel& model,
    const modelling::RoomModels& models,
    const std::vector<std::pair<std::string, modelling::Orthoimage>>& images,
    const std::string& scene_room, const RoomWindow& window,
    const nlohmann::ordered_json& evaluation) {
  const DriveResult drive = session.Result();
  auto in_window = [&](const std::vector<TrajectorySample>& all) {
    std::vector<TrajectorySample> out;
    for (const auto& x : all)
      if (x.t >= window.t_begin && x.t <= window.t_end) out.push_back(x);
    return ToTum(out);
  };
  runfolder::RoomScanFiles f;
  f.model = &model;
  f.room = models.sm3.room;
  f.dsm3 = &models.dsm3;
  f.images = &images;
  f.log = &log;
  f.door_scans = window.door_scans;
  f.drive = {drive.path_length, drive.contacts, drive.loc_rms, drive.loc_max};
  f.trajectory_estimated_tum = in_window(drive.estimated);
  f.trajectory_true_tum = in_window(drive.truth);
  f.map = &session.Map();
  f.effective_config_yaml = YAML::Dump(SaveParams(params));
  f.run.scene = mw.source;
  f.run.doors = mw.door_overrides;
  f.run.room = scene_room;
  f.run.seed = params.drive.seed;
  f.run.X_WM = session.X_MW().To3d().inverse();
  if (!evaluation.is_null()) f.evaluation_json = evaluation.dump(2);
  return f;
}

void CheckJobRooms(const sim::SceneWorld& mw, const std::vector<std::string>& rooms) {
  if (!mw.truth || mw.truth->rooms.empty())
    throw InputError(
        "error: the scene has no truth rooms; expected a generated or imported scene with rooms "
        "(scene.truth.json)");
  for (const std::string& room : rooms) {
    if (mw.truth->FindRoom(room)) continue;
    std::string ids;
    for (const auto& x : mw.truth->rooms) ids += (ids.empty() ? "" : ", ") + x.id;
    throw InputError("--room: error: unknown room; got '" + room + "', expected one of " + ids);
  }
}

RoomJob RunRoomJob(const sim::SceneWorld& mw, const std::string& room,
                   const RoomMissionParams& params, const std::optional<Pose2>& start_W,
                   const std::string& dir, bool evaluate) {
  CheckJobRooms(mw, {room});
  RoomJob job;
  job.room = room;
  const scenes::RobotFootprint body = sim::FootprintOf(params.drive.body);
  job.start_W = start_W ? scenes::CheckStart(mw.world->scene(), *mw.truth, body, *start_W).X_WB
                        : scenes::StartInRoom(mw.world->scene(), *mw.truth, body, room).X_WB;
  RobotSession session(*mw.world, params.drive, job.start_W, params.faults,
                       DoorFaultOf(mw, params.faults), params.realism,
                       PeopleOf(mw, params.realism));
  modelling::RoomModel model(params.scan.model);
  // The truth side scores an open-plan room (spaces joined by open passages) as the robot
  // meets it: one room (evaluation/truth_models.h, MergeOpenPlanRooms).
  const evaluation::OpenPlanTruth open_plan =
      evaluation::MergeOpenPlanRooms(*mw.truth, /*join_faces=*/false);
  const std::string truth_room = open_plan.room_of.at(room);
  Sm1TruthCollector labels(session, open_plan.truth, truth_room);
  job.mission =
      RunRoomMission(session, params, model, evaluate ? labels.Hook() : autonomy::ScanHook{});
  std::vector<std::pair<std::string, modelling::Orthoimage>> images;
  // SM5 (paper §3.4) with the recogniser trained from the robot's catalogue (once a process).
  const modelling::RoomModels models = modelling::BuildRoomModels(
      model, std::move(job.mission.no_return), params.scan.sm3, params.scan.sm4, params.scan.sm5,
      room, &images, &RobotComponentRecogniser());
  job.sm4_seconds = models.sm4_seconds;
  job.openings = models.sm4.openings.size();
  job.sm5_seconds = models.sm5_seconds;
  job.components = models.sm5.components.size();
  const Pose3 X_WM = session.X_MW().To3d().inverse();
  if (evaluate)
    job.evaluation = evaluation::EvaluateRoom(*mw.world, open_plan.truth, truth_room, X_WM,
                                              LoggedScans(job.mission), session.ScanTruths(), model,
                                              labels.Labels());
  runfolder::WriteRoomFiles(
      dir,
      ScanFilesOf(mw, session, params, job.mission, model, models, images, room, RoomWindow{},
                  job.evaluation ? evaluation::ToJson(*job.evaluation) : nlohmann::ordered_json()),
      {room, &models.sm3, &models.sm4, &models.sm5});
  for (const auto& t : session.ScanTruths()) job.scan_positions_W.push_back(t.X_WS.translation());
  job.plan_points_W = PlanPoints(model, X_WM);
  job.labels = model.CountLabels();
  job.path_length = session.Result().path_length;
  job.fault_events = session.World().FaultEvents();
  job.points = model.PointCount();
  return job;
}

}  // namespace mopad::mission
