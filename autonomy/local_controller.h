#pragma once
// Local control along a global path (paper §3.1 step (2): MoPAD used a TEB local planner;
// here a pure-pursuit follower instead). A pure-pursuit follower (Coulter 1992) with:
//  - speed limits, acceleration limits on speeding up, slow approach and final rotation to the
//    goal yaw;
//  - a forward collision check of the rectangular footprint (plus a margin) swept along the
//    commanded arc against the base LRF's points: obstacles the map lacks slow the base and
//    then stop it with status kBlocked (explained, never a silent stop);
//  - a door-passage mode for the passages the planner found on the map (GlobalPlan::passages):
//    reduced speed, stop and align with the passage axis before entering (first driving onto
//    the axis when the approach left the base farther off it than the crossing can correct),
//    then cross centred between the jambs seen by the LRF, checking the clearance on both
//    sides;
//  - recovery when blocked for `blocked_wait` or making no progress for `stuck_timeout`:
//    alternately back up or rotate in place, then ask the replanner (the owner's callback,
//    usually GlobalPlanner with the LRF obstacles added) for a new path; an unreachable
//    replan ends in kUnreachable, exhausted recoveries in kBlocked. A base that cannot turn
//    on the spot toward its path (stopped in the mouth of a niche) first looks for an escape
//    manoeuvre: at most two arcs, forward or back, checked against the LRF and the map, after
//    which it can turn (a three-point turn, as a driver leaves a parking bay);
//  - localisation: while AMCL reports lost / re-localising the base rotates slowly in place to
//    give the filter new views (kLocalisationLost), and gives up after `lost_timeout`.
//
// Frames: path and pose in `map` (REP-105), scan points projected into base_link via the
// scan's X_BL. Time is simulation time passed in by the loop (no wall clock). Units SI.
// Not thread-safe.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "autonomy/global_planner.h"
#include "common/frames.h"
#include "common/params.h"
#include "interfaces/lrf_scan.h"
#include "interfaces/odometry.h"
#include "perception/amcl.h"

namespace mopad::autonomy {

struct LocalControllerParams {
  double max_linear_speed = 0.5;          ///< m/s, (0, 5]
  double max_angular_speed = 1.0;         ///< rad/s, (0, 10]
  double max_linear_acceleration = 0.8;   ///< m/s^2, speeding up only, (0, 20]
  double max_angular_acceleration = 2.0;  ///< rad/s^2, speeding up only, (0, 50]
  double lookahead = 0.5;                 ///< m, pure-pursuit lookahead, (0, 5]
  double rotate_in_place_deg = 40.0;      ///< deg, heading error above which it turns on the spot
  double heading_gain = 2.0;              ///< 1/s, yaw-rate per radian of heading error, (0, 20]
  double approach_distance = 0.8;         ///< m, slow down within this of the goal, (0, 10]
  double min_speed = 0.05;                ///< m/s, floor of the slowed speed, (0, max]
  double goal_tolerance_xy = 0.04;        ///< m, position tolerance at the goal, (0, 1]
  double goal_tolerance_yaw_deg = 2.0;    ///< deg, yaw tolerance at the goal, (0, 90]
  double footprint_length = 0.6;          ///< m, along base_link x, (0, 5]
  double footprint_width = 0.5;           ///< m, along base_link y, (0, 5]
  double footprint_offset_x = 0.0;        ///< m, footprint centre ahead of base_link, [-2, 2]
  double safety_margin = 0.06;            ///< m, added around the footprint when checking, [0, 1]
  double collision_horizon = 2.0;         ///< s, forward simulation of the command, (0, 20]
  double stop_distance = 0.04;            ///< m, free travel below which the base stops, [0, 1]
  double slowdown_distance = 0.8;         ///< m, free travel below which speed scales down
  double passage_speed = 0.2;             ///< m/s, speed through passages, (0, max]
  double passage_align_deg = 4.0;         ///< deg, heading tolerance before entering, (0, 45]
  double passage_entry_distance = 0.7;    ///< m before the narrowest point where it aligns
  double passage_side_margin = 0.03;      ///< m, minimum side clearance while crossing, [0, 1]
  /// m: while crossing, the LRF returns beside the body centre the base unless their gap
  /// exceeds the map's passage width by more than this (then they are not its jambs, and the
  /// base follows the map's passage centre line). The map's cell size plus the LRF's noise.
  /// (0, 2]
  double passage_width_tolerance = 0.15;
  double centring_gain = 2.0;  ///< rad/s per m of off-centre, [0, 50]
  /// Before aligning with a passage the path goes through, a base farther off its axis than
  /// this share of the crossing's side slack ((passage width - footprint width) / 2 -
  /// passage_side_margin, at least 2 cm) first drives onto the axis: while crossing, the
  /// centring corrects an offset over about heading_gain / centring_gain metres of travel,
  /// longer than the approach, so a diagonal approach to a gap a few centimetres wider than
  /// the base meets its side. [0, 10]
  double passage_axis_share = 0.5;
  double blocked_wait = 2.0;        ///< s blocked before a recovery starts, [0, 600]
  double stuck_timeout = 4.0;       ///< s without progress before a recovery, (0, 600]
  double progress_distance = 0.05;  ///< m of motion that counts as progress, (0, 5]
  double backup_distance = 0.25;    ///< m, recovery back-up length, (0, 5]
  double backup_speed = 0.12;       ///< m/s, (0, 1]; also the escape manoeuvre's speed
  double escape_arc_length = 0.8;   ///< m, longest arc of an escape manoeuvre; 0 = none
  int max_recoveries = 4;           ///< recoveries before giving up as blocked, [0, 100]
  double replan_radius = 2.5;       ///< m, LRF points within this are passed to replans
  /// Each LRF range is replaced by the median of this many neighbours (odd; 1 = raw) before
  /// any check, as a laser median filter does. [1, 31]
  int range_median_window = 5;
  double lost_rotation_speed = 0.3;  ///< rad/s while localisation is lost, [0, 5]
  double lost_timeout = 30.0;        ///< s lost before giving up, (0, 3600]
  double lost_turn_check = 0.3;  ///< rad of turn that must be free to rotate while lost, (0, 6.3]
  double min_recovery_rotation_speed = 0.3;  ///< rad/s, floor of the recovery rotation, [0, 5]
  double min_turn_speed = 0.08;      ///< rad/s, floor of alignment and final-rotation turns, [0, 5]
  double min_path_turn_speed = 0.1;  ///< rad/s, floor of a turn on the spot toward the path, [0, 5]
  double min_turn_check = 0.15;  ///< rad, a turn on the spot must have at least this free, (0, 6.3]
  double path_search_window =
      2.0;  ///< m of path ahead of the last closest point searched, (0, 100]
  /// m: farther than this from the closest point of that window, the whole path is searched
  /// (the estimate jumped). (0, 100]
  double path_reacquire_distance = 1.0;
  double recovery_reset_progress =
      1.0;  ///< m of path made good after which recoveries count from 0, (0, 100]
  double final_approach_distance =
      0.3;                            ///< m from the goal where the final approach starts, (0, 5]
  double final_approach_speed = 0.1;  ///< m/s, largest speed of the final approach, (0, 1]
  double final_approach_turn_rate =
      0.6;  ///< rad/s, largest turn rate of the final approach, (0, 10]
  /// The final rotation gives way to following again beyond this many goal_tolerance_xy. [1, 100]
  double final_rotate_release = 2.5;
  /// m the body's rear must be past a passage's narrowest point for the crossing to end, [0, 5]
  double passage_exit_clearance = 0.2;
  double progress_turn = 0.1;  ///< rad of turn that counts as progress, (0, 6.3]
  /// s free after which a base blocked at the edge of the stop distance stops counting as
  /// blocked for the recovery timer, [0, 600]
  double blocked_release_time = 1.0;

  template <class V>
  void Visit(V& v) {
    v("max_linear_speed", max_linear_speed, Bounds{1e-3, 5.0});
    v("max_angular_speed", max_angular_speed, Bounds{1e-3, 10.0});
    v("max_linear_acceleration", max_linear_acceleration, Bounds{1e-3, 20.0});
    v("max_angular_acceleration", max_angular_acceleration, Bounds{1e-3, 50.0});
    v("lookahead", lookahead, Bounds{1e-3, 5.0});
    v("rotate_in_place_deg", rotate_in_place_deg, Bounds{1.0, 180.0});
    v("heading_gain", heading_gain, Bounds{1e-3, 20.0});
    v("approach_distance", approach_distance, Bounds{1e-3, 10.0});
    v("min_speed", min_speed, Bounds{1e-3, 5.0});
    v("goal_tolerance_xy", goal_tolerance_xy, Bounds{1e-4, 1.0});
    v("goal_tolerance_yaw_deg", goal_tolerance_yaw_deg, Bounds{1e-2, 90.0});
    v("footprint_length", footprint_length, Bounds{1e-3, 5.0});
    v("footprint_width", footprint_width, Bounds{1e-3, 5.0});
    v("footprint_offset_x", footprint_offset_x, Bounds{-2.0, 2.0});
    v("safety_margin", safety_margin, Bounds{0.0, 1.0});
    v("collision_horizon", collision_horizon, Bounds{1e-3, 20.0});
    v("stop_distance", stop_distance, Bounds{0.0, 1.0});
    v("slowdown_distance", slowdown_distance, Bounds{0.0, 10.0});
    v("passage_speed", passage_speed, Bounds{1e-3, 5.0});
    v("passage_align_deg", passage_align_deg, Bounds{1e-2, 45.0});
    v("passage_entry_distance", passage_entry_distance, Bounds{0.0, 5.0});
    v("passage_side_margin", passage_side_margin, Bounds{0.0, 1.0});
    v("passage_width_tolerance", passage_width_tolerance, Bounds{1e-3, 2.0});
    v("centring_gain", centring_gain, Bounds{0.0, 50.0});
    v("passage_axis_share", passage_axis_share, Bounds{0.0, 10.0});
    v("blocked_wait", blocked_wait, Bounds{0.0, 600.0});
    v("stuck_timeout", stuck_timeout, Bounds{1e-3, 600.0});
    v("progress_distance", progress_distance, Bounds{1e-3, 5.0});
    v("backup_distance", backup_distance, Bounds{1e-3, 5.0});
    v("backup_speed", backup_speed, Bounds{1e-3, 1.0});
    v("escape_arc_length", escape_arc_length, Bounds{0.0, 3.0});
    v("max_recoveries", max_recoveries, Bounds{0, 100});
    v("replan_radius", replan_radius, Bounds{0.0, 100.0});
    v("range_median_window", range_median_window, Bounds{1, 31});
    v("lost_rotation_speed", lost_rotation_speed, Bounds{0.0, 5.0});
    v("lost_timeout", lost_timeout, Bounds{1e-3, 3600.0});
    v("lost_turn_check", lost_turn_check, Bounds{1e-3, 6.3});
    v("min_recovery_rotation_speed", min_recovery_rotation_speed, Bounds{0.0, 5.0});
    v("min_turn_speed", min_turn_speed, Bounds{0.0, 5.0});
    v("min_path_turn_speed", min_path_turn_speed, Bounds{0.0, 5.0});
    v("min_turn_check", min_turn_check, Bounds{1e-3, 6.3});
    v("path_search_window", path_search_window, Bounds{1e-3, 100.0});
    v("path_reacquire_distance", path_reacquire_distance, Bounds{1e-3, 100.0});
    v("recovery_reset_progress", recovery_reset_progress, Bounds{1e-3, 100.0});
    v("final_approach_distance", final_approach_distance, Bounds{1e-3, 5.0});
    v("final_approach_speed", final_approach_speed, Bounds{1e-3, 1.0});
    v("final_approach_turn_rate", final_approach_turn_rate, Bounds{1e-3, 10.0});
    v("final_rotate_release", final_rotate_release, Bounds{1.0, 100.0});
    v("passage_exit_clearance", passage_exit_clearance, Bounds{0.0, 5.0});
    v("progress_turn", progress_turn, Bounds{1e-3, 6.3});
    v("blocked_release_time", blocked_release_time, Bounds{0.0, 600.0});
  }
  /// ValidateParams plus cross-field checks; throws InputError.
  void Validate() const;
};

/// Why the controller commands what it commands. Terminal ones end the run (finished = true).
enum class NavStatus {
  kIdle,              ///< no path
  kFollowing,         ///< following the path (includes the final rotation)
  kDoorPassage,       ///< aligning with or crossing a narrow passage
  kRecovering,        ///< backing up / rotating / replanning
  kBlocked,           ///< an obstacle stops the base (waiting; terminal once recoveries run out)
  kArrived,           ///< terminal: at the goal within tolerance
  kUnreachable,       ///< terminal: the replanner found no route
  kLocalisationLost,  ///< rotating to re-localise; terminal after lost_timeout
};
const char* ToString(NavStatus s);

/// One arc of a manoeuvre: speed v (m/s, < 0 backwards), yaw rate w (rad/s), length (m).
struct ArcMove {
  double v = 0.0, w = 0.0, length = 0.0;
};

struct ControlOutput {
  interfaces::VelocityCommand cmd;
  NavStatus status = NavStatus::kIdle;
  std::string message;  ///< one line: what and why (distances in m)
  bool finished = false;
  int recoveries = 0;  ///< recoveries used so far on this goal
};

/// Replanner callback: a new plan from `X_MB` to the goal, avoiding `obstacles_M` (LRF points
/// in the map frame that the map may lack).
using ReplanFn = std::function<GlobalPlan(const Pose2& X_MB, const std::vector<Vec2>& obstacles_M)>;
/// Map obstacles callback: occupied points of the robot's map (map frame) within `radius` of
/// `X_MB`, for the motions the LRFs do not cover.
using MapObstaclesFn = std::function<std::vector<Vec2>(const Pose2& X_MB, double radius)>;

class LocalController {
 public:
  /// Throws InputError for invalid params.
  explicit LocalController(const LocalControllerParams& params);
  LocalController(const LocalController&) = default;
  LocalController& operator=(const LocalController&) = default;
  LocalController(LocalController&&) noexcept = default;
  LocalController& operator=(LocalController&&) noexcept = default;

  /// Starts following `plan` (status must be kFound); resets recoveries and terminal state.
  /// `align_yaw` false: arrival needs only the position (a scan stop, where the heading does
  /// not matter and a doorway may leave no room to turn).
  void SetPlan(const GlobalPlan& plan, bool align_yaw = true);
  /// Optional: used by recoveries. Without it recoveries only back up / rotate.
  void SetReplanner(ReplanFn replan) { replan_ = std::move(replan); }
  /// Optional: the map's obstacles join the LRF returns in the checks of backing up (the
  /// LRFs do not see behind the base) and of turning in place (a desk top or chair seat above
  /// the base LRF's plane sweeps into the turning corners).
  void SetMapObstacles(MapObstaclesFn map_obstacles) { map_obstacles_ = std::move(map_obstacles); }

  /// One control step at simulation time `time` (s) with the pose estimate `X_MB`, the
  /// localiser's status and the latest base LRF scan.
  ControlOutput Update(double time, const Pose2& X_MB, perception::LocalisationStatus loc,
                       const interfaces::LrfScan& scan);

  const std::vector<PathPoint>& Path() const { return path_; }
  const LocalControllerParams& Params() const { return params_; }

  /// Distance (m) the footprint inflated by `margin` can travel along the arc (v, w) before
  /// touching one of `points_B` (base_link), up to `horizon` m; for v = 0 the arc is a
  /// rotation and the result is in rad of yaw. A point already within the margin at the start
  /// counts only once the motion brings it closer (backing away from it is free). Exposed for
  /// tests and the integration step.
  double FreeTravel(const std::vector<Vec2>& points_B, double v, double w, double margin,
                    double horizon) const;

  /// Escape manoeuvre from a spot where the base cannot turn: the shortest sequence of at
  /// most two arcs (forward or back at backup_speed, radius 0.3 m to straight, each at most
  /// escape_arc_length, a second arc costing 0.3 m more) that keeps stop_distance from
  /// `points_B` (base_link) and ends where the base can turn on the spot toward `target_B`
  /// (base_link), or already faces it within rotate_in_place_deg with 0.3 m free ahead.
  /// Empty when there is none. Exposed for tests.
  std::vector<ArcMove> EscapeManoeuvre(const std::vector<Vec2>& points_B,
                                       const Vec2& target_B) const;

  /// The scan's returns in base_link, each range the median of its neighbours'
  /// (range_median_window).
  std::vector<Vec2> BasePoints(const interfaces::LrfScan& scan) const;
  /// True if the base at `X_MB` can turn on the spot by `angle` (rad; its sign the direction)
  /// with no return of `scan` nor obstacle of the map (SetMapObstacles) coming within
  /// passage_side_margin of the footprint.
  bool CanTurn(const Pose2& X_MB, const interfaces::LrfScan& scan, double angle) const;

  /// The scan's ranges, each the median of the valid ones among its `window` neighbours; an
  /// invalid return (no echo, out of range) stays NaN.
  static std::vector<double> MedianFiltered(const interfaces::LrfScan& scan, int window);
  /// Lateral distance (m) of the jamb on one side (+1 left, -1 right) from the base_link x
  /// axis: the median of the returns beside the body that lie near its nearest surface
  /// (within -5/+8 cm of their 10th percentile); infinity when none is beside the body.
  /// Exposed for tests.
  double JambDistance(const std::vector<Vec2>& points_B, double side) const;

 private:
  enum class Mode { kFollow, kFinalRotate, kBackUp, kRotate, kEscape, kDone };
  struct PassageState {
    Passage passage;
    bool on_axis = false;  // the base drove onto the axis, or needed not
    bool aligned = false;
    bool done = false;
  };

  /// What one Update sees: its time, pose, the LRF returns in base_link and, looked up on
  /// demand, those plus the map's obstacles near the base (Around).
  struct Step {
    double time = 0.0, dt = 0.0;
    Pose2 X_MB;
    std::vector<Vec2> pts;
    std::optional<std::vector<Vec2>> around;
  };
  Step BeginStep(double time, const Pose2& X_MB, const interfaces::LrfScan& scan);
  const std::vector<Vec2>& Around(Step& c) const;
  ControlOutput Emit(const Step& c, ControlOutput out, bool limit = true);
  /// A turn on the spot towards a heading error (rad): heading_gain, clamped to
  /// max_angular_speed, at least min_turn_speed.
  interfaces::VelocityCommand TurnOnTheSpot(double heading_error) const;
  void ResetAnchor(const Step& c);
  std::optional<ControlOutput> LocalisationStep(Step& c, perception::LocalisationStatus loc);
  ControlOutput BackUpStep(Step& c);
  ControlOutput EscapeStep(Step& c);
  ControlOutput RotateStep(Step& c);
  void TrackProgress(const Pose2& X_MB);
  PassageState* CurrentPassage(const Vec2& here, double s_here);
  void PassageStep(const Step& c, PassageState& passage, double s_here, ControlOutput& out,
                   double& margin, double& turn_needed) const;
  void PursuitStep(const Step& c, double s_here, double d_goal, ControlOutput& out,
                   double& turn_needed) const;
  void CheckMotion(Step& c, ControlOutput& out, double margin, double turn_needed);
  ControlOutput BlockedOrStuck(Step& c, ControlOutput out);

  ControlOutput Finish(NavStatus s, const std::string& message);
  ControlOutput StartRecovery(double time, const Pose2& X_MB, const std::string& reason,
                              const std::vector<Vec2>& points_B);
  /// The base, at path length `s`, is within the approach of passage `p` (aligns with it).
  bool Approaching(const PassageState& p, double s) const {
    return s >= p.passage.s - params_.passage_entry_distance - 0.05;
  }
  /// Where the base should head from here (map): a point on the path a metre ahead of the
  /// closest one, or along the axis of a passage it is aligning with.
  Vec2 HeadingTarget(const Pose2& X_MB) const;
  ControlOutput AfterRecoveryMotion(double time, const Pose2& X_MB,
                                    const std::vector<Vec2>& points_B);
  void InstallPlan(const GlobalPlan& plan);
  /// Distance of a base_link point outside the footprint rectangle, max of the axis gaps
  /// (negative inside): within `margin` of it means inside the rectangle grown by `margin`.
  double BoxDistance(const Vec2& q_B) const;
  interfaces::VelocityCommand Limit(interfaces::VelocityCommand cmd, double dt) const;

  LocalControllerParams params_;
  ReplanFn replan_;
  MapObstaclesFn map_obstacles_;
  std::vector<PathPoint> path_;
  std::vector<PassageState> passages_;
  Pose2 goal_;
  bool align_yaw_ = true;
  Mode mode_ = Mode::kDone;
  std::size_t closest_ = 0;
  std::optional<double> last_time_;
  interfaces::VelocityCommand last_cmd_;
  // Progress, blocking, recovery and localisation bookkeeping.
  Pose2 anchor_pose_;
  double anchor_time_ = 0.0;
  std::optional<double> blocked_since_;
  double last_blocked_time_ = -1e9;
  std::optional<double> lost_since_;
  int recoveries_ = 0;
  double s_at_last_recovery_ = 0.0;
  Pose2 recovery_start_;
  double recovery_turned_ = 0.0, recovery_last_yaw_ = 0.0;
  std::string recovery_reason_;
  bool turn_blocked_ = false;    // the last blocked step was a turn on the spot
  std::vector<ArcMove> escape_;  // the escape manoeuvre under way
  std::size_t escape_arc_ = 0;
  Pose2 escape_arc_start_;
  double escape_deadline_ = 0.0;
  ControlOutput terminal_;
};

}  // namespace mopad::autonomy
