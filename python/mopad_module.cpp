// `import mopad` (the compiled part, mopad._mopad): OpenMoPAD's world, sensors, simulated robot
// and evaluator from Python, as numpy arrays (docs/python.md). Thin: every call is one C++ call
// of the libraries the CLI uses, so a Python caller gets the CLI's bytes for the same inputs.
//
// World side (truth): World (a scene with its truth), scan(world, ...) with its per-point truth
// as separate arrays, Robot's true_* methods, evaluate(). Robot side: Robot's step(), odometry(),
// base_sweep(), top_sweep(), scan() — what interfaces::RobotPlatform gives a brain, no truth.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/frames.h"
#include "common/wall_clock.h"
#include "evaluation/run_evaluation.h"
#include "io/text_file.h"
#include "io/tum.h"
#include "mission/drive_mission.h"
#include "mission/run_job.h"
#include "mission/sim_robot.h"
#include "runfolder/keep.h"
#include "scenes/generator.h"
#include "scenes/random_floor.h"
#include "scenes/scene_spec.h"
#include "scenes/start_spot.h"
#include "sim/scene_world.h"
#include "sim/tls_params.h"
#include "sim/tls_scanner.h"
#include "sim/tls_truth.h"

namespace py = pybind11;
using namespace mopad;

namespace {

// A scene loaded once: its world and its truth (shared by robots made from it).
struct World {
  std::shared_ptr<sim::SceneWorld> w;
};

World LoadWorld(const std::string& scene, const std::vector<std::string>& doors) {
  return {std::make_shared<sim::SceneWorld>(sim::LoadSceneWorld(scene, doors))};
}

// A start argument (x m, y m, yaw deg) in the world.
Pose2 PoseOf(const std::array<double, 3>& p) { return Pose2{p[0], p[1], DegToRad(p[2])}; }

template <class T>
py::array_t<T> Array(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<double> Matrix(const Pose3& X) {
  py::array_t<double> a({4, 4});
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a.mutable_at(r, c) = X.matrix()(r, c);
  return a;
}

// The valid points of `scan` column by column (the PLY order of `mopad scan`), as arrays; with
// `truth`, its per-point truth under "truth".
py::dict ScanArrays(const interfaces::TlsScan& scan, const sim::TlsTruth* truth) {
  std::vector<float> xyz, intensity, true_range;
  std::vector<std::uint8_t> rgb, label;
  std::vector<std::uint32_t> row, column;
  std::vector<std::int32_t> element;
  std::vector<double> time;
  for (std::uint32_t c = 0; c < scan.columns; ++c)
    for (std::uint32_t r = 0; r < scan.rows; ++r) {
      const interfaces::TlsPoint& p = scan.at(r, c);
      if (!p.valid()) continue;
      xyz.insert(xyz.end(), {p.x, p.y, p.z});
      rgb.insert(rgb.end(), {p.r, p.g, p.b});
      intensity.push_back(p.intensity);
      row.push_back(r);
      column.push_back(c);
      time.push_back(p.timestamp);
      if (truth) {
        const sim::TlsPointTruth& t = truth->at(r, c);
        element.push_back(t.element);
        label.push_back(t.element_class);
        true_range.push_back(t.true_range);
      }
    }
  const py::ssize_t n = static_cast<py::ssize_t>(intensity.size());
  py::dict d;
  d["xyz"] = Array(xyz, {n, 3});
  d["rgb"] = Array(rgb, {n, 3});
  d["intensity"] = Array(intensity, {n});
  d["row"] = Array(row, {n});
  d["column"] = Array(column, {n});
  d["time"] = Array(time, {n});
  d["rows"] = scan.rows;
  d["columns"] = scan.columns;
  d["scan_id"] = scan.scan_id;
  d["X_BS"] = Matrix(scan.X_BS);
  if (truth) {
    py::dict t;
    t["element"] = Array(element, {n});
    t["label"] = Array(label, {n});
    t["true_range"] = Array(true_range, {n});
    t["element_ids"] = truth->element_ids;
    t["X_WS"] = Matrix(truth->X_WS);
    d["truth"] = t;
  }
  return d;
}

py::dict Scan(const World& world, std::array<double, 4> pose, std::optional<double> step_deg,
              std::uint64_t seed, std::uint64_t scan_id, const std::string& profile) {
  sim::TlsParams params = sim::TlsProfile(profile);
  if (step_deg) params.step_deg = *step_deg;
  params.Validate();
  sim::ScanRequest req;
  req.seed = seed;
  req.scan_id = scan_id;
  req.X_WB = Pose2{pose[0], pose[1], DegToRad(pose[3])}.To3d(pose[2]);
  sim::TlsTruth truth;
  interfaces::TlsScan scan;
  {
    py::gil_scoped_release release;
    const sim::TlsScanner scanner(*world.w->world, params);
    scan = scanner.Scan(req, &truth);
  }
  return ScanArrays(scan, &truth);
}

py::dict SweepDict(const interfaces::LrfScan& s) {
  py::dict d;
  d["frame"] = s.frame;
  d["seq"] = s.seq;
  d["timestamp"] = s.timestamp;
  d["angle_min"] = s.angle_min;
  d["angle_increment"] = s.angle_increment;
  d["range_min"] = s.range_min;
  d["range_max"] = s.range_max;
  d["ranges"] = Array(s.ranges, {static_cast<py::ssize_t>(s.ranges.size())});
  d["intensities"] = Array(s.intensities, {static_cast<py::ssize_t>(s.intensities.size())});
  d["X_BL"] = Matrix(s.X_BL);
  return d;
}

// The simulated robot (mission::SimRobot) as a step API.
class Robot {
 public:
  Robot(const World& world, std::uint64_t seed, std::optional<std::array<double, 3>> start)
      : world_(world.w) {
    if (!world_->truth) throw InputError(world_->source, "the scene has no truth sidecar");
    params_.seed = seed;
    Pose2 X_WB;
    if (start) {
      X_WB = PoseOf(*start);
    } else {
      X_WB = scenes::ChooseStart(world_->world->scene(), *world_->truth,
                                 sim::FootprintOf(params_.body))
                 .X_WB;
    }
    robot_ = std::make_unique<mission::SimRobot>(*world_->world, params_, X_WB, seed);
  }
  double Time() const { return robot_->Time(); }
  double ControlPeriod() const { return robot_->ControlPeriod(); }
  bool Step(double v, double w) {
    py::gil_scoped_release release;
    return robot_->Step({v, w});
  }
  py::dict Odometry() const {
    const interfaces::Odometry& o = robot_->WheelOdometry();
    py::dict d;
    d["timestamp"] = o.timestamp;
    d["x"] = o.X_OB.x;
    d["y"] = o.X_OB.y;
    d["yaw"] = o.X_OB.yaw;
    d["v"] = o.v;
    d["w"] = o.w;
    return d;
  }
  py::dict BaseSweep() const { return SweepDict(robot_->BaseSweep()); }
  py::dict TopSweep() const { return SweepDict(robot_->TopSweep()); }
  py::dict RobotScan(double step_deg) {
    double still_for = 0.0;
    interfaces::TlsScan scan;
    {
      py::gil_scoped_release release;
      scan = robot_->Scan(step_deg, &still_for);
    }
    py::dict d = ScanArrays(scan, nullptr);
    d["still_for"] = still_for;
    return d;
  }
  // World side.
  std::array<double, 3> TruePoseInWorld() const {
    const Pose2 p = robot_->TruePoseInWorld();
    return {p.x, p.y, p.yaw};
  }
  // The true trajectory (map frame) as TUM text, io::TumLinePlanar per sample.
  std::string TrueTrajectoryTum() const {
    std::string out;
    for (const auto& s : robot_->TrueTrajectory())
      out += io::TumLinePlanar(s.t, s.pose.x, s.pose.y, s.pose.yaw);
    return out;
  }

 private:
  std::shared_ptr<sim::SceneWorld> world_;
  mission::DriveParams params_;
  std::unique_ptr<mission::SimRobot> robot_;
};

// The main job (`mopad run`, mission/run_job.h) into `out`, or, with `resume`, the run killed in
// that folder; returns its summary.json. Ctrl-C (SIGINT), or an exception of `log`, stops it
// before its next room as a signal stops `mopad run`: the rooms done are written (the
// checkpoint says "stopped"; resume= finishes the run) and the exception is raised after.
py::object Run(const std::string& out, const std::string& spec, const std::string& scene,
               const std::string& config, std::optional<std::uint64_t> seed,
               std::optional<double> step_deg, const std::vector<std::string>& rooms,
               std::optional<std::array<double, 3>> start, const std::string& resume,
               const std::string& keep, const std::optional<std::string>& realism,
               const py::object& log) {
  const runfolder::KeepLevel keep_level = runfolder::ParseKeepLevel(keep, "keep");
  const auto t_start = WallClock::now();
  const std::string dir = resume.empty() ? out : resume;
  std::optional<mission::RunCheckpoint> ck;
  if (!resume.empty()) {
    ck = mission::RunCheckpoint::Open(resume);
    if (ck->Complete()) ck.reset();
  } else {
    mission::RunRequest r;
    r.out = out;
    r.spec_path = spec;
    r.scene_dir = scene;
    r.config = config;
    r.seed = seed;
    r.step_deg = step_deg;
    r.realism = realism;
    r.rooms = rooms;
    if (start) r.start_W = PoseOf(*start);
    ck = mission::StartRun(r);
  }
  std::optional<py::error_already_set> interrupted;
  if (ck) {
    mission::RunHooks hooks;
    if (!log.is_none()) {
      // An exception of `log` (KeyboardInterrupt among them) stops the run as Ctrl-C does.
      hooks.progress = hooks.print = [&log, &interrupted](const std::string& line) {
        py::gil_scoped_acquire gil;
        if (interrupted) return;
        try {
          log(line);
        } catch (py::error_already_set& e) {
          interrupted.emplace(std::move(e));
        }
      };
    }
    hooks.stop_requested = [&interrupted] {
      py::gil_scoped_acquire gil;
      if (!interrupted && PyErr_CheckSignals() != 0) interrupted.emplace();  // takes the error
      return interrupted.has_value();
    };
    py::gil_scoped_release release;
    // False only when stop_requested said so, that is when `interrupted` holds the exception.
    (void)mission::RunFromCheckpoint(*ck, dir, hooks, t_start);
  }
  runfolder::PruneRunFolder(dir, keep_level);
  if (interrupted) throw std::move(*interrupted);
  const std::string summary = io::ReadTextFile(dir + "/summary.json");
  return py::module_::import("json").attr("loads")(summary);
}

py::object Evaluate(const std::string& run_dir, const std::string& truth, const std::string& out) {
  const evaluation::RunEvaluation e = evaluation::EvaluateRun(run_dir, truth, "", out);
  return py::module_::import("json").attr("loads")(e.summary.dump());
}

}  // namespace

PYBIND11_MODULE(_mopad, m) {
  m.doc() = "OpenMoPAD's world, sensors, simulated robot and evaluator (docs/python.md)";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  m.def(
      "generate_scene",
      [](const std::string& spec, const std::string& out) {
        scenes::WriteGeneratedScene(scenes::Generate(scenes::LoadSceneSpec(spec)), out);
      },
      py::arg("spec"), py::arg("out"),
      "Generates the scene of a spec .yaml into folder `out` (scene.glb, scene.truth.json).");

  py::class_<World>(m, "World", "A scene (folder, scene file or spec .yaml) with its truth.")
      .def(py::init(&LoadWorld), py::arg("scene"), py::arg("doors") = std::vector<std::string>{})
      .def_property_readonly("source", [](const World& w) { return w.w->source; })
      .def_property_readonly("rooms",
                             [](const World& w) {
                               std::vector<std::string> ids;
                               if (w.w->truth)
                                 for (const auto& r : w.w->truth->rooms) ids.push_back(r.id);
                               return ids;
                             })
      .def_property_readonly("element_ids",
                             [](const World& w) { return w.w->world->ElementIds(); });

  m.def("scan", &Scan, py::arg("world"), py::arg("pose"), py::arg("step_deg") = py::none(),
        py::arg("seed") = 1, py::arg("scan_id") = 0, py::arg("profile") = "riegl_vz400",
        "One TLS scan from base pose (x, y, z, yaw_deg) in the world, as `mopad scan` makes it: "
        "a dict of arrays of the valid points column by column (xyz in the scanner frame, rgb, "
        "intensity, row, column, time) and, under 'truth', the per-point truth (element index "
        "into element_ids, label = scene element class, true_range).");

  py::class_<Robot>(m, "Robot",
                    "The simulated robot as a step API: step(v, w), odometry(), base_sweep(), "
                    "top_sweep(), scan(step_deg) give what a robot brain may see; true_* are "
                    "the world side's.")
      .def(py::init<const World&, std::uint64_t, std::optional<std::array<double, 3>>>(),
           py::arg("world"), py::arg("seed") = 1, py::arg("start") = py::none())
      .def("time", &Robot::Time)
      .def("control_period", &Robot::ControlPeriod)
      .def("step", &Robot::Step, py::arg("v"), py::arg("w"),
           "Applies (v m/s, w rad/s) for one control period; True when a top sweep arrived.")
      .def("odometry", &Robot::Odometry)
      .def("base_sweep", &Robot::BaseSweep)
      .def("top_sweep", &Robot::TopSweep)
      .def("scan", &Robot::RobotScan, py::arg("step_deg"),
           "A TLS scan in the scanner frame (no truth); 'still_for': seconds to stand still.")
      .def("true_pose", &Robot::TruePoseInWorld, "World side: (x, y, yaw rad) in the world.")
      .def("true_trajectory_tum", &Robot::TrueTrajectoryTum,
           "World side: the true trajectory in the map frame as TUM text.");

  m.def("run", &Run, py::kw_only(), py::arg("out") = "out/run", py::arg("spec") = "",
        py::arg("scene") = "", py::arg("config") = "", py::arg("seed") = py::none(),
        py::arg("step_deg") = py::none(), py::arg("rooms") = std::vector<std::string>{},
        py::arg("start") = py::none(), py::arg("resume") = "", py::arg("keep") = "all",
        py::arg("realism") = py::none(), py::arg("log") = py::none(),
        "`mopad run`: the main job on the default scene (or spec=YAML, or scene=FOLDER) into "
        "out, or resume=DIR to finish a killed run; start=(x, y, yaw_deg), rooms=[...] for the "
        "per-room mode, keep='summary'|'models'|'all', realism='ideal'|'typical'|'hard' (the "
        "config's otherwise), log=callable(str) for its lines. "
        "Returns summary.json; the run folder holds the same bytes as `mopad run`'s.");

  m.def("evaluate", &Evaluate, py::arg("run_dir"), py::arg("truth") = "", py::arg("out") = "",
        "`mopad eval RUN_DIR`: writes the evaluator's files and returns its summary.");
}
