#pragma once
// The robot's room loop (paper §3.1, Figure 5, yellow part): it scans one room from positions
// it chooses itself until the stopping rule holds, building the RoomModel (SM1, RoI, voxels).
//
//   scan 1 where the robot stands -> RoomModel
//   loop: stopping rule (epsilon1 / epsilon2)? -> next best scan -> Navigator::NavigateTo
//         -> scan -> registration (AMCL prior, point-to-plane ICP against S(t-1), accepted by
//         the one policy of perception/registration.h) -> RoomModel.AddScan
//   detail pass (detail.enabled; autonomy/detail_pass.h): while SE cells are too sparse or
//         too grazing for SM5 and a candidate fixes enough of them, drive there (or stay) and
//         scan (possibly at a finer step) -> registration -> RoomModel.AddScan
//
// Robot side only: it drives an autonomy::Navigator and sees nothing of the world.
// Deterministic: same platform behaviour + params -> same outputs (timings aside).

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "autonomy/detail_pass.h"
#include "autonomy/navigator.h"
#include "autonomy/next_best_scan.h"
#include "autonomy/registration_target.h"
#include "common/frames.h"
#include "common/params.h"
#include "modelling/components.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/room_model.h"
#include "modelling/stopping.h"
#include "modelling/structural_model.h"
#include "perception/range_bias.h"
#include "perception/registration.h"

namespace mopad::autonomy {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct RoomScanParams {
  double scan_step_deg = 0.2;  ///< deg, TLS angular step of the room scans, [0.02, 5]
  int max_scans = 10;    ///< hard cap of scans in the room (beyond the paper's rule), [1, 100]
  int nav_attempts = 5;  ///< NBS candidates tried when driving to one fails, [1, 20]
  /// m, NBS candidates this close to a position whose scan could not be registered are not
  /// chosen again (the model did not change, so the same spot would win again), [0, 10]
  double failed_scan_exclusion = 1.0;
  /// A later scan the acceptance refuses still joins the room model (its points, coverage and
  /// SM data; not the registration target, which later scans must trust) at its prior when the
  /// prior is good enough: the localiser's largest x-y std at most `refused_scan_max_sigma`,
  /// its yaw std at most `refused_scan_max_sigma_deg` (the model's own accuracy: a wall placed
  /// within the evaluator's 1 cm d_h bound), and the scan at its prior is no evidence against
  /// it (free-space violation within the ICP's max_free_space_violation). 0 = off. m, [0, 1]
  double refused_scan_max_sigma = 0.01;
  double refused_scan_max_sigma_deg = 0.1;  ///< deg, [0, 10]
  /// Room scans register from odometry/AMCL priors against the room's own earlier scans, which
  /// overlap well: a stricter fitness than the navigator's door scans, the library's
  /// free-space bound.
  perception::IcpParams icp{.max_correspondence = kAmclPriorIcpStages, .min_fitness = 0.3};
  /// Fully `ok` registrations join the room model, and degenerate ones that fit: the ICP keeps
  /// the prior along the weak direction (solution remapping, and the slide rule), so what a
  /// corridor scan estimates is what it constrains, the rest the prior's (docs/registration.md);
  /// a creeping result would smear it. The prior may be far off (office rooms register from
  /// priors 1.2 m / 20 deg off): no correction bound.
  perception::RegistrationAcceptanceParams acceptance{
      .accept_degenerate = true,
      .creeping_step_factor = 0.0,
      .max_correction = 1000.0,
      .max_correction_deg = 180.0,
      .gate_sigmas = 0.0,
  };
  /// A room's first scan in a floor mission (taken just beyond the door it came through) is
  /// registered against the earlier rooms' scans with these: it sees them only through the
  /// door, so a door scan's ICP (NavigatorParams::icp) and a bounded correction of the
  /// localiser's prior.
  perception::IcpParams entry_icp{
      .max_correspondence = kAmclPriorIcpStages,
      .min_fitness = 0.15,
      .max_free_space_violation = 0.01,
  };
  /// Just beyond a door the localiser has little of the new room in its map: its yaw can be
  /// several degrees off (docs/floor-mission.md). The ICP's own checks (fitness, residual, free
  /// space, conditioning) reject wrong minima; the bounds only stop a jump to another door
  /// frame. The yaw bound moves the door frame the scan stands 1.3 m behind by at most
  /// sin(10 deg) x 1.3 m = 0.23 m, within the translation bound. Seeing the earlier rooms
  /// through one door often leaves one direction weak (along the door axis): the ICP keeps the
  /// prior there (solution remapping), so what it corrects is constrained, and a degenerate
  /// result is bounded like a constrained one. The localiser's own sigma is no gate here: it
  /// underreports its error just beyond a door.
  perception::RegistrationAcceptanceParams entry_acceptance{
      .max_correction = 0.3,
      .max_correction_deg = 10.0,
      .gate_sigmas = 0.0,
  };
  modelling::RoomModelParams model{};
  modelling::StoppingParams stopping{};
  /// The planner only accepts goals in known free space (unknown counts as obstacle there), so
  /// the NBS candidates must come from the same space.
  NextBestScanParams nbs{.unknown_is_obstacle = true};
  modelling::Sm3Params sm3{};
  modelling::OpeningParams sm4{};
  modelling::ComponentParams sm5{};
  /// Extra scans for SM5's data quality after the stopping rule (not counted by max_scans)
  DetailPassParams detail{};

  template <class V>
  void Visit(V& v) {
    v("scan_step_deg", scan_step_deg, Bounds{0.02, 5.0});
    v("max_scans", max_scans, Bounds{1, 100});
    v("nav_attempts", nav_attempts, Bounds{1, 20});
    v("failed_scan_exclusion", failed_scan_exclusion, Bounds{0.0, 10.0});
    v("refused_scan_max_sigma", refused_scan_max_sigma, Bounds{0.0, 1.0});
    v("refused_scan_max_sigma_deg", refused_scan_max_sigma_deg, Bounds{0.0, 10.0});
    v("icp", icp);
    v("registration_acceptance", acceptance);
    v("entry_icp", entry_icp);
    v("entry_registration_acceptance", entry_acceptance);
    v("room_model", model);
    v("stopping", stopping);
    v("nbs", nbs);
    v("sm3", sm3);
    v("sm4", sm4);
    v("sm5", sm5);
    v("detail", detail);
  }
};

/// One scan of the room mission, as logged (robot side, plus the timing of each step).
struct RoomScanLog {
  int index = 0;
  int session_scan = 0;                  ///< the navigator's scan index (the platform's scan order)
  bool detail = false;                   ///< a scan of the detail pass
  double step_deg = 0.0;                 ///< deg, its angular step
  double sim_time = 0.0;                 ///< s, when the scan was taken
  Pose3 X_MS_prior = Pose3::Identity();  ///< odometry/AMCL estimate
  Pose3 X_MS = Pose3::Identity();        ///< registered pose used for the model
  bool registered = true;  ///< false: ICP refused (or a detail scan moved the structure): left out
  /// Refused, yet in the room model at its prior (RoomScanParams::refused_scan_max_sigma)
  bool at_prior = false;
  perception::RegistrationResult registration;  ///< empty for the first scan
  /// Covariance of X_MS, coordinates as RegistrationResult::information_matrix (rad^2, m^2):
  /// the registration's where it constrains the pose, the localiser's elsewhere; zero for a
  /// scan not registered
  Mat6 covariance = Mat6::Zero();
  perception::RangeBiasEstimate range_bias;  ///< the scan's range offset (removed when ok)
  /// The gains (linear light, R G B) its colours were aligned to the room's by
  /// (RoomModel::ColourGains); 1, 1, 1 when left as scanned.
  std::array<double, 3> colour_gain{1.0, 1.0, 1.0};
  modelling::CoverageFigures coverage;
  std::string stop_message;  ///< the stopping rule's verdict after this scan
  // Next best scan chosen after this scan (none after the last one).
  bool has_next = false;
  Pose2 next_goal;             ///< base pose, map frame
  double expected_gain = 0.0;  ///< NBS certainty of the chosen candidate
  int candidates = 0;
  std::string nav_status;  ///< outcome of driving there
  std::string nav_message;
  // Wall-clock seconds of the processing steps (reporting only).
  double t_registration = 0.0, t_model = 0.0, t_nbs = 0.0, t_scan = 0.0, t_drive = 0.0;
};

struct RoomScanResult {
  /// The accepted scans' rays without a return, in the model's scan order (SM4's evidence of
  /// openings: a ray that returned nothing passed every plane it crossed).
  modelling::OrthoPoints no_return;
  std::vector<RoomScanLog> scans;
  std::string stop_reason;           ///< why the mission ended (stopping rule, cap, no candidate)
  bool registration_failed = false;  ///< some scan could not be registered
  double sim_time = 0.0, wall_time = 0.0;
  /// The detail pass: its scans (in `scans` too, flagged), the platform and wall seconds it
  /// took (drives, scans, registration, planning), and one line per planning round.
  int detail_scans = 0;
  double detail_sim_time = 0.0, detail_wall_time = 0.0;
  std::vector<std::string> detail_log;
};

/// Scans the room the robot stands in. `model` receives the final RoomModel. `on_scan`
/// (optional) sees every scan the model accepted, with the navigator's scan index.
/// `floor_target` (optional): the registration target of a floor mission, every scan of the
/// earlier rooms; then the room's first scan is registered against it too (entry_icp), and each
/// scan the room uses joins it. Without it the room's first scan defines the room's frame.
using ScanHook = std::function<void(int index, const interfaces::TlsScan& scan)>;
RoomScanResult RunRoomScan(Navigator& navigator, const RoomScanParams& params,
                           modelling::RoomModel& model, const ScanHook& on_scan = {},
                           RegistrationTarget* floor_target = nullptr);

/// Whether a refused scan may join the room model at its prior (RoomScanParams::
/// refused_scan_max_sigma): `loc_cov` is the localiser's (x, y, yaw) covariance (m^2, rad^2),
/// `violation_at_prior` the scan's free-space violation placed at its prior against the
/// registration target. `why` (optional) receives the one-line reason.
bool RefusedScanUsable(const RoomScanParams& params, const Eigen::Matrix3d& loc_cov,
                       double violation_at_prior, std::string* why = nullptr);

/// Registers the scan just taken (`navigator.LastScan()`) against `target` from its estimate
/// with `icp` through `acceptance` (the localiser's position std as the prior's sigma); a used
/// result corrects the navigator's pose, and the prior's uncertainty along the result's weak
/// directions is carried on to the localiser (Navigator::CorrectLastScanPose). Returns whether
/// the registered pose was used; `r` receives the registration, `covariance` (optional) the
/// used pose's covariance (perception::RegistrationCovariance with the localiser's covariance
/// as the prior's; the prior's when refused).
bool RegisterLastScan(Navigator& navigator, const perception::PointMap& target,
                      const perception::IcpParams& icp,
                      const perception::RegistrationAcceptanceParams& acceptance,
                      perception::RegistrationResult& r, Mat6* covariance = nullptr);

}  // namespace mopad::autonomy
