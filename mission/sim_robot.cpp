#include "mission/sim_robot.h"

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "common/format.h"
#include "common/rng.h"
#include "perception/point_cloud_ops.h"
#include "sim/lrf.h"
#include "sim/people.h"
#include "sim/scene_world.h"
#include "sim/tls_scanner.h"

namespace mopad::mission {

std::optional<PeopleWorld> PeopleOf(const sim::SceneWorld& mw, const sim::RealismParams& realism) {
  if (!realism.people.Enabled()) return std::nullopt;
  if (!mw.truth)
    throw InputError(mw.source, "realism.people needs the scene's truth (people walk in its rooms)",
                     "a scene without scene.truth.json", "a generated or imported scene");
  return PeopleWorld{mw.world.get(), &*mw.truth};
}

namespace {

using perception::Compose;
using perception::Inverse;
using Clock = std::chrono::steady_clock;

// Poses per person over a TLS scan (Embree's most): at the robot's 0.2 deg, 3 s, one per 23 ms.
constexpr int kMoverKnots = 129;

}  // namespace

struct SimRobot::Impl {
  const sim::EmbreeWorld& world;
  DriveParams params;
  std::uint64_t seed;
  Clock::time_point wall_start = Clock::now();
  std::optional<sim::RobotBody> body;
  std::optional<sim::TlsScanner> tls;
  std::optional<sim::LrfSimulator> lrf_top, lrf_base;
  Pose2 X_MW;  // evaluation only: truth into the map frame
  std::vector<sim::TlsTruth> truths;
  bool keep_truths = true;
  std::optional<std::pair<double, Pose2>> teleport;  // (time, X_WB)
  FaultParams faults;
  std::vector<std::string> fault_events;
  bool lrf_silent = false, slipping = false, kidnapped = false;
  // Once the wheels have slipped, the odometry the robot reads is integrated here from the
  // body's own readings (before, it is the body's reading itself, untouched).
  std::optional<interfaces::Odometry> slipped_odometry;
  Pose2 last_body_odometry;
  // The door fault: the leaf is a box of the body's (RobotBody::AddDoorLeaf), not part of its
  // static mesh, so that it can swing.
  std::optional<DoorFaultWorld> door;
  int leaf = -1;
  Eigen::Isometry3d X_WD_open = Eigen::Isometry3d::Identity();
  bool door_closed = false, door_waiting = false;
  // People walking: movers of `people_world` (the robot's world), stepped with the body.
  std::optional<sim::People> people;
  sim::EmbreeWorld* people_world = nullptr;
  std::vector<bool> touching;  // per person: the base touches them now
  int person_contacts = 0;
  std::vector<std::string> person_events;
  double person_closest = std::numeric_limits<double>::infinity();

  double t = 0.0;
  std::uint64_t steps = 0, scans = 0;
  std::uint64_t base_seq = 0, top_seq = 0;
  double base_period = 0.0, top_period = 0.0;
  double next_base = 0.0, next_top = 0.0;
  interfaces::LrfScan base_scan, top_scan;

  // ---- World-side log.
  std::vector<autonomy::TrajectorySample> truth;
  Pose2 last_true{};
  double path_length = 0.0;
  int lrf_sweeps = 0, teleports = 0;
  double tls_time = 0.0, tls_wall = 0.0;

  Impl(const sim::EmbreeWorld& w, const DriveParams& p, const Pose2& X_WB_start, std::uint64_t s,
       const FaultParams& f, const std::optional<DoorFaultWorld>& d,
       const sim::RealismParams& realism, const std::optional<PeopleWorld>& pw)
      : world(w), params(p), seed(s), faults(f), door(d) {
    ValidateParams(params, "drive.");
    ValidateParams(realism, "realism.");
    ValidateParams(faults, "faults.");
    faults.Validate();
    if (door && door->world != &world)
      throw std::logic_error("SimRobot: the door fault's world is not the robot's");
    std::vector<Eigen::Vector3f> vertices, leaf_vertices;
    std::vector<std::uint32_t> triangles;
    for (const auto& part : world.scene().parts) {
      if (door && part.element_class == scenes::ElementClass::kDoorLeaf &&
          part.element_id == door->door.id) {
        leaf_vertices.insert(leaf_vertices.end(), part.positions.begin(), part.positions.end());
        continue;
      }
      const auto base = static_cast<std::uint32_t>(vertices.size());
      vertices.insert(vertices.end(), part.positions.begin(), part.positions.end());
      for (const auto& tri : part.triangles)
        for (int k = 0; k < 3; ++k) triangles.push_back(base + static_cast<std::uint32_t>(tri[k]));
    }
    body.emplace(params.body, vertices, triangles, X_WB_start, seed);
    if (door) AddSwingingLeaf(leaf_vertices);
    if (body->InCollision(X_WB_start)) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "drive: start pose (%.3f, %.3f) is in collision with the scene", X_WB_start.x,
                    X_WB_start.y);
      throw InputError(buf);
    }
    if (realism.people.Enabled() && pw) AddPeople(*pw, realism.people, X_WB_start);
    sim::TlsParams tls_params =
        sim::RealisticTls(sim::TlsProfile(params.tls_profile), realism.scanner, seed);
    tls_params.step_deg = params.navigator.tls_step_deg;
    tls.emplace(world, tls_params);
    for (const auto& lp : sim::PaperLrfRig(params.lrf_profile)) {
      if (lp.frame == "lrf_top") lrf_top.emplace(world, lp);
      if (lp.frame == "lrf_base") lrf_base.emplace(world, lp);
    }
    if (!lrf_top || !lrf_base) throw std::runtime_error("drive: LRF rig lacks lrf_top/lrf_base");
    base_period = 1.0 / lrf_base->params().rate_hz;
    top_period = 1.0 / lrf_top->params().rate_hz;
    X_MW = Inverse(X_WB_start);
    last_true = X_WB_start;
  }

  // People in the robot's world, before its sensors are made (they read the world's parts).
  void AddPeople(const PeopleWorld& pw, const sim::PeopleParams& p, const Pose2& start) {
    if (pw.world != &world || !pw.truth)
      throw std::logic_error("SimRobot: the people's world is not the robot's");
    people.emplace(world, *pw.truth, p, p.seed ? p.seed : seed, Vec2(start.x, start.y));
    if (people->size() == 0) return;
    people_world = pw.world;
    people_world->AddMovers(people->Models());
    touching.assign(people->size(), false);
    PlacePeople();
  }

  // Everybody standing where they are now, for the sweeps of this step.
  void PlacePeople() {
    std::vector<std::vector<sim::MoverPose>> now;
    for (const sim::MoverPose& p : people->Poses()) now.push_back({p});
    people_world->SetMoverTrack(t, t, now);
  }

  // People walk on a step; the base touching one (its footprint within 0.25 m of a person's
  // centre) counts once per episode.
  void StepPeople() {
    const Pose2 X_WB = body->TruePose();
    people->Step(params.control_dt, Vec2(X_WB.x, X_WB.y));
    PlacePeople();
    const auto& fp = params.body;
    const std::vector<sim::MoverPose> poses = people->Poses();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Vec2 d(poses[i].x - X_WB.x, poses[i].y - X_WB.y);
      const double c = std::cos(X_WB.yaw), s = std::sin(X_WB.yaw);
      const Vec2 q(c * d.x() + s * d.y() - fp.footprint_offset_x, -s * d.x() + c * d.y());
      const Vec2 outside(std::max(0.0, std::abs(q.x()) - 0.5 * fp.footprint_length),
                         std::max(0.0, std::abs(q.y()) - 0.5 * fp.footprint_width));
      const double gap = outside.norm() - 0.25;
      person_closest = std::min(person_closest, std::max(0.0, gap));
      const bool touch = gap <= 0.0;
      if (touch && !touching[i]) {
        ++person_contacts;
        person_events.push_back(FormatNumbers("%.2f s: the base touched ", t) + "person_" +
                                std::to_string(i + 1) +
                                FormatNumbers(" at (%.2f, %.2f)", poses[i].x, poses[i].y));
      }
      touching[i] = touch;
    }
  }

  // The door fault's leaf as a box (its vertices' bounding box along their main horizontal
  // direction), at the scene's angle; the world's leaf back at that angle too.
  void AddSwingingLeaf(const std::vector<Eigen::Vector3f>& vertices) {
    if (vertices.empty())
      throw InputError("faults", "parameter 'door_close_id' names a door without leaf geometry",
                       "'" + door->door.id + "'", "a door whose leaf the scene holds");
    door->world->SetDoorAngle(door->door.id, door->door.opening_angle);
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& v : vertices) mean += v.head<2>().cast<double>();
    mean /= static_cast<double>(vertices.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& v : vertices) {
      const Eigen::Vector2d q = v.head<2>().cast<double>() - mean;
      cov += q * q.transpose();
    }
    const Eigen::Vector2d e =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvectors().col(1);
    Eigen::Matrix3d R;
    R << e.x(), -e.y(), 0.0, e.y(), e.x(), 0.0, 0.0, 0.0, 1.0;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& v : vertices) {
      const Eigen::Vector3d q = R.transpose() * v.cast<double>();
      lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    }
    X_WD_open.linear() = R;
    X_WD_open.translation() = R * (0.5 * (lo + hi));
    const Eigen::Vector3d half = (0.5 * (hi - lo)).cwiseMax(0.005);  // a leaf has thickness
    leaf = body->AddDoorLeaf(half, X_WD_open);
  }

  // The door fault, from its time on: the leaf swings shut unless the base stands in its way.
  void CloseDoor() {
    const Eigen::Isometry3d X_WD_closed =
        SwungLeaf(door->door, X_WD_open, door->door.opening_angle, 0.0);
    body->SetDoorLeafPose(leaf, X_WD_closed);
    if (body->InCollision(body->TruePose())) {
      body->SetDoorLeafPose(leaf, X_WD_open);
      if (!door_waiting)
        Event("fault: door " + door->door.id + " cannot close yet: the base is in its way");
      door_waiting = true;
      return;
    }
    door->world->SetDoorAngle(door->door.id, 0.0);
    door_closed = true;
    Event("fault: door " + door->door.id +
          FormatNumbers(" closed (its leaf swung from %.0f deg to 0)",
                        RadToDeg(door->door.opening_angle)));
  }

  void Event(const std::string& what) {
    fault_events.push_back(FormatNumbers("%.2f s: ", t) + what);
  }

  // Both LRFs at their profile rates (rays in the scene at the true pose). Silent LRFs (a
  // fault) keep their schedule but deliver nothing; the sweeps before the first scan are
  // always taken.
  bool Sweep(bool force) {
    const bool silent = !force && faults.LrfSilentAt(t);
    if (silent != lrf_silent) {
      lrf_silent = silent;
      Event(silent ? "fault: both LRFs silent (no new sweeps) for " +
                         FormatNumbers("%.2f s", faults.lrf_silent_for)
                   : "fault: the LRFs sweep again");
    }
    const Pose3 X_WB = body->TruePose().To3d();
    bool top_new = false;
    if (force || t + 1e-9 >= next_base) {
      if (!silent) {
        base_scan = lrf_base->Scan(X_WB, seed, base_seq++, t);
        ++lrf_sweeps;
      }
      next_base += base_period;
    }
    if (force || t + 1e-9 >= next_top) {
      if (!silent) {
        top_scan = lrf_top->Scan(X_WB, seed, top_seq++, t);
        ++lrf_sweeps;
        top_new = true;
      }
      next_top += top_period;
    }
    return top_new;
  }

  // The odometry the robot reads after a body step: the body's own, or, once the wheels have
  // slipped, its motions integrated with the slipping ones scaled.
  void UpdateOdometry() {
    const interfaces::Odometry& body_odometry = body->Odometry();
    const bool slip = faults.SlipAt(t);
    if (slip != slipping) {
      slipping = slip;
      Event(slip ? FormatNumbers("fault: wheels slip, odometry reports %.2f x the motion",
                                 faults.slip_factor) +
                       FormatNumbers(" for %.2f s", faults.slip_for)
                 : "fault: the wheels grip again");
    }
    if (slip && !slipped_odometry) {
      slipped_odometry = body_odometry;
      slipped_odometry->X_OB = last_body_odometry;
    }
    if (slipped_odometry) {
      Pose2 delta = Compose(Inverse(last_body_odometry), body_odometry.X_OB);
      double v = body_odometry.v, w = body_odometry.w;
      if (slip) {
        delta = SlippedMotion(delta, faults.slip_factor);
        v *= faults.slip_factor, w *= faults.slip_factor;
      }
      slipped_odometry->X_OB = Compose(slipped_odometry->X_OB, delta);
      slipped_odometry->timestamp = body_odometry.timestamp;
      slipped_odometry->v = v;
      slipped_odometry->w = w;
    }
    last_body_odometry = body_odometry.X_OB;
  }

  // The push of the kidnap fault (once, at its time): the body slides to the free pose nearest
  // the target; the odometry does not see it.
  void Kidnap() {
    kidnapped = true;
    const Pose2 from = body->TruePose();
    const double direction = CounterRng(seed, "mission/fault/kidnap").Uniform(0.0, 2.0 * kPi);
    Pose2 to;
    const bool found = KidnapTarget(
        from, direction, faults.kidnap_distance,
        [this](const Pose2& p) { return !body->InCollision(p); }, &to);
    if (!found) {
      Event(FormatNumbers("fault: kidnap not applied: no free pose within %.2f m of the target",
                          kKidnapSearchRadius) +
            FormatNumbers(" %.2f m from (%.2f, %.2f)", faults.kidnap_distance, from.x, from.y));
      return;
    }
    body->Teleport(to);
    last_true = to;
    ++teleports;
    Event(FormatNumbers("fault: kidnap: the base pushed %.3f m from (%.3f, %.3f) ",
                        std::hypot(to.x - from.x, to.y - from.y), from.x, from.y) +
          FormatNumbers("to (%.3f, %.3f) (world), the odometry unaware", to.x, to.y));
  }

  void RecordTruth() { truth.push_back({t, Compose(X_MW, body->TruePose())}); }

  bool Step(const interfaces::VelocityCommand& cmd) {
    body->Step(cmd, params.control_dt);
    t += params.control_dt;
    ++steps;
    if (faults.slip_at >= 0.0) UpdateOdometry();
    if (faults.kidnap_at >= 0.0 && !kidnapped && t + 1e-9 >= faults.kidnap_at) Kidnap();
    if (door && !door_closed && t + 1e-9 >= faults.door_close_at) CloseDoor();
    if (people_world) StepPeople();
    if (teleport && t + 1e-9 >= teleport->first) {
      body->Teleport(teleport->second);  // kidnapping: odometry does not see it
      last_true = teleport->second;
      teleport.reset();
      ++teleports;
    }
    const Pose2 now_true = body->TruePose();
    path_length += std::hypot(now_true.x - last_true.x, now_true.y - last_true.y);
    last_true = now_true;
    const bool top_new = Sweep(false);
    RecordTruth();
    if (params.navigator.trace && truth.size() % 50 == 1) {
      const Pose2& tm = truth.back().pose;
      std::fprintf(stderr, "   true (%.2f %.2f %.2f)\n", tm.x, tm.y, tm.yaw);
    }
    return top_new;
  }

  interfaces::TlsScan Scan(double step_deg, double* still_for) {
    const bool first = scans == 0 && steps == 0;
    if (first) Sweep(true);
    const auto wall0 = Clock::now();
    std::optional<sim::TlsScanner> custom;
    if (step_deg > 0.0 && step_deg != tls->params().step_deg) {
      sim::TlsParams p = tls->params();
      p.step_deg = step_deg;
      custom.emplace(world, p);
    }
    const sim::TlsScanner& scanner = custom ? *custom : *tls;
    sim::ScanRequest req;
    req.seed = seed;
    req.scan_id = scans;
    req.start_time = t;
    req.X_WB = body->TruePose().To3d();
    req.X_MS_estimate = Eigen::Isometry3d::Identity();  // the platform knows no map pose
    sim::TlsTruth scan_truth;
    const double duration = static_cast<double>(scanner.pulses()) / scanner.params().pulse_rate_hz;
    if (people_world) {
      // Where everybody walks while the head turns (the base stands still), as the steps after
      // the scan will walk them.
      const Pose2 X_WB = body->TruePose();
      people_world->SetMoverTrack(
          t, t + duration,
          people->Track(duration, params.control_dt, kMoverKnots, Vec2(X_WB.x, X_WB.y)));
    }
    interfaces::TlsScan scan = scanner.Scan(req, keep_truths ? &scan_truth : nullptr);
    if (people_world) PlacePeople();
    if (const ScanFault fault = ScanFaultOf(faults, scans); fault != ScanFault::kNone) {
      const std::size_t lost = ApplyScanFault(fault, faults.tls_partial_fraction, scan,
                                              keep_truths ? &scan_truth : nullptr);
      Event("fault: TLS scan " + std::to_string(scans) +
            (fault == ScanFault::kEmpty
                 ? " returned nothing"
                 : FormatNumbers(" returned only the first %.3f of its sweep",
                                 faults.tls_partial_fraction)) +
            " (" + std::to_string(lost) + " returns lost)");
    }
    if (keep_truths) truths.push_back(std::move(scan_truth));
    tls_wall += std::chrono::duration<double>(Clock::now() - wall0).count();
    ++scans;
    if (first) RecordTruth();
    tls_time += duration;
    if (still_for) *still_for = params.tls_scan_takes_time ? duration : 0.0;
    return scan;
  }
};

SimRobot::SimRobot(const sim::EmbreeWorld& world, const DriveParams& params,
                   const Pose2& X_WB_start, std::uint64_t seed, const FaultParams& faults,
                   const std::optional<DoorFaultWorld>& door, const sim::RealismParams& realism,
                   const std::optional<PeopleWorld>& people)
    : impl_(
          std::make_unique<Impl>(world, params, X_WB_start, seed, faults, door, realism, people)) {}
SimRobot::~SimRobot() = default;

double SimRobot::Time() const { return impl_->t; }
double SimRobot::ControlPeriod() const { return impl_->params.control_dt; }
bool SimRobot::Step(const interfaces::VelocityCommand& cmd) { return impl_->Step(cmd); }
const interfaces::Odometry& SimRobot::WheelOdometry() const {
  return impl_->slipped_odometry ? *impl_->slipped_odometry : impl_->body->Odometry();
}
const interfaces::LrfScan& SimRobot::BaseSweep() const { return impl_->base_scan; }
const interfaces::LrfScan& SimRobot::TopSweep() const { return impl_->top_scan; }
interfaces::TlsScan SimRobot::Scan(double step_deg, double* still_for) {
  return impl_->Scan(step_deg, still_for);
}

Pose2 SimRobot::X_MW() const { return impl_->X_MW; }
Pose2 SimRobot::TruePoseInWorld() const { return impl_->body->TruePose(); }
Pose2 SimRobot::TruePoseInMap() const { return Compose(impl_->X_MW, impl_->body->TruePose()); }
const std::vector<autonomy::TrajectorySample>& SimRobot::TrueTrajectory() const {
  return impl_->truth;
}
const std::vector<sim::TlsTruth>& SimRobot::ScanTruths() const { return impl_->truths; }
void SimRobot::SetKeepScanTruths(bool keep) { impl_->keep_truths = keep; }
void SimRobot::ReleaseScanTruthPoints() {
  for (sim::TlsTruth& t : impl_->truths) std::vector<sim::TlsPointTruth>().swap(t.points);
}
void SimRobot::ScheduleTeleport(double t, const Pose2& X_WB) { impl_->teleport.emplace(t, X_WB); }
const DriveParams& SimRobot::Params() const { return impl_->params; }
const std::vector<std::string>& SimRobot::FaultEvents() const { return impl_->fault_events; }

void SimRobot::FillResult(DriveResult& res) const {
  const Impl& m = *impl_;
  res.truth = m.truth;
  res.sim_time = m.t;
  res.final_true_M = TruePoseInMap();
  res.goal_error_xy =
      std::hypot(res.final_true_M.x - res.goal_M.x, res.final_true_M.y - res.goal_M.y);
  res.goal_error_yaw_deg = RadToDeg(std::abs(WrapAngle(res.final_true_M.yaw - res.goal_M.yaw)));
  // Localisation error: the estimate against the truth, sample for sample.
  double loc_sq = 0.0, yaw_sq = 0.0;
  res.loc_max = res.loc_yaw_max_deg = 0.0;
  const std::size_t n = std::min(res.estimated.size(), m.truth.size());
  for (std::size_t k = 0; k < n; ++k) {
    const Pose2& est = res.estimated[k].pose;
    const Pose2& tru = m.truth[k].pose;
    const double e = std::hypot(est.x - tru.x, est.y - tru.y);
    const double ey = std::abs(WrapAngle(est.yaw - tru.yaw));
    loc_sq += e * e;
    yaw_sq += ey * ey;
    res.loc_max = std::max(res.loc_max, e);
    res.loc_yaw_max_deg = std::max(res.loc_yaw_max_deg, RadToDeg(ey));
  }
  res.loc_rms = n ? std::sqrt(loc_sq / n) : 0.0;
  res.loc_yaw_rms_deg = RadToDeg(n ? std::sqrt(yaw_sq / n) : 0.0);
  res.contacts = m.body->ContactCount();
  res.contact_events = m.body->Contacts();
  res.blocked_steps = m.body->BlockedSteps();
  res.path_length = m.path_length;
  res.lrf_sweeps = m.lrf_sweeps;
  res.teleports = m.teleports;
  res.fault_events = m.fault_events;
  res.people = m.people ? static_cast<int>(m.people->size()) : 0;
  res.person_contacts = m.person_contacts;
  res.person_contact_events = m.person_events;
  res.person_closest = m.person_closest;
  res.tls_time = m.tls_time;
  res.tls_wall_time = m.tls_wall;
  res.wall_time = std::chrono::duration<double>(Clock::now() - m.wall_start).count();
}

}  // namespace mopad::mission
