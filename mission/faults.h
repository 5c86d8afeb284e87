#pragma once
// Faults of the simulated world (`faults:` of the mission config, docs/reliability.md "Fault
// injection"): what a real robot meets — a TLS scan that returns nothing or only part of its
// sweep, LRFs that go silent, wheels that slip, a push that moves the base while the odometry
// says nothing, a door that closes. They are properties of the world, applied by mission::SimRobot;
// the robot's brain sees only their effect on its sensors and never knows that a fault was
// injected.
//
// All off by default. With every fault off (or no `faults:` section) none of this acts: the
// scans, the odometry and the models are those of the fault-free world. Times are simulation time
// (s) from the robot's placement; scan indices count the TLS scans of one robot (the mission's scan
// index in a floor mission, a room's in the per-room mode), 0 = the first. Random draws (the
// kidnap's direction) come from the run's seed (stream "mission/fault/kidnap"), so a faulted run is
// as deterministic as any.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/tls_scan.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"
#include "sim/scene_world.h"
#include "sim/tls_truth.h"

namespace mopad::mission {

struct FaultParams {
  /// Scan indices whose TLS scan returns nothing: every cell is a no-return (range 0), as if
  /// the scanner's data were lost; the scan still takes its time. Each >= 0.
  std::vector<int> tls_empty_scans;
  /// Scan indices whose TLS scan returns only the first `tls_partial_fraction` of its azimuth
  /// sweep (the columns after it are no-returns: the head stalled, the data link dropped).
  /// Each >= 0; a scan in both lists returns nothing.
  std::vector<int> tls_partial_scans;
  double tls_partial_fraction = 1.0 / 3.0;  ///< share of the columns that return, [0, 1]

  /// s, from when both LRFs go silent: no new sweep (the robot keeps the last ones and Step
  /// reports no new top sweep); negative: never. The sweeps before the first scan are always
  /// taken. [-1, 1e6]
  double lrf_silent_at = -1.0;
  double lrf_silent_for = 0.0;  ///< s, how long they stay silent, [0, 1e6]

  /// s, from when the wheels slip: the odometry reports `slip_factor` times the motion the
  /// base made (1.5: half as much again as it moved; 0: no motion at all); negative: never.
  /// [-1, 1e6]
  double slip_at = -1.0;
  double slip_for = 0.0;     ///< s, how long the wheels slip, [0, 1e6]
  double slip_factor = 1.0;  ///< reported / true motion during the slip, [0, 10]

  /// s, when the base is pushed (kidnapped): it moves `kidnap_distance` along a direction drawn
  /// from the seed, keeping its heading, while the odometry says nothing; negative: never.
  /// The push slides the body along the floor: it ends at the pose nearest the target that is
  /// free and reached by a straight slide without a collision (none within
  /// kKidnapSearchRadius of the target: no push, and the event says so). [-1, 1e6]
  double kidnap_at = -1.0;
  double kidnap_distance = 0.5;  ///< m, [0, 5]

  /// The door (its truth id, e.g. "D3") that closes at `door_close_at`: its leaf swings to
  /// 0 deg in the world, so the sensors see it and the base collides with it. While the closed
  /// leaf would overlap the base it waits (a door does not close through the robot). Each
  /// robot starts with the door as the scene has it. "": never.
  std::string door_close_id;
  double door_close_at = -1.0;  ///< s; negative: never, [-1, 1e6]

  template <class V>
  void Visit(V& v) {
    v("tls_empty_scans", tls_empty_scans, Bounds{0, 1e6});
    v("tls_partial_scans", tls_partial_scans, Bounds{0, 1e6});
    v("tls_partial_fraction", tls_partial_fraction, Bounds{0.0, 1.0});
    v("lrf_silent_at", lrf_silent_at, Bounds{-1.0, 1e6});
    v("lrf_silent_for", lrf_silent_for, Bounds{0.0, 1e6});
    v("slip_at", slip_at, Bounds{-1.0, 1e6});
    v("slip_for", slip_for, Bounds{0.0, 1e6});
    v("slip_factor", slip_factor, Bounds{0.0, 10.0});
    v("kidnap_at", kidnap_at, Bounds{-1.0, 1e6});
    v("kidnap_distance", kidnap_distance, Bounds{0.0, 5.0});
    v("door_close_id", door_close_id);
    v("door_close_at", door_close_at, Bounds{-1.0, 1e6});
  }
  /// InputError for a fault switched on that cannot act: LRF silence or slip of zero duration,
  /// a slip with factor 1, a kidnap of zero distance, a door to close without a time or a
  /// time without a door.
  void Validate() const;

  /// True when some fault is on (then the run reports its fault events).
  bool Any() const;
  bool LrfSilentAt(double t) const {
    return lrf_silent_at >= 0.0 && t >= lrf_silent_at && t < lrf_silent_at + lrf_silent_for;
  }
  bool SlipAt(double t) const { return slip_at >= 0.0 && t >= slip_at && t < slip_at + slip_for; }
};

/// The world side of the door fault: the world whose leaf it swings (the one the robot's
/// sensors cast their rays in) and the door's truth (hinge, modelled angle).
struct DoorFaultWorld {
  sim::EmbreeWorld* world = nullptr;
  scenes::Opening door;
};

/// The door fault's world for `faults` in `mw`, or none when the fault is off. InputError
/// naming the id and the scene's doors when the scene has no such door with a hinge.
std::optional<DoorFaultWorld> DoorFaultOf(const sim::SceneWorld& mw, const FaultParams& faults);

/// The pose (world) of a door leaf's box after the door swings from `from_angle` to `to_angle`
/// (rad) about its hinge, given the box at `X_WD` for `from_angle`.
Eigen::Isometry3d SwungLeaf(const scenes::Opening& door, const Eigen::Isometry3d& X_WD,
                            double from_angle, double to_angle);

/// m, how far from the kidnap's target the search for a free pose goes.
inline constexpr double kKidnapSearchRadius = 1.0;

/// What a scan fault did to one scan.
enum class ScanFault { kNone, kEmpty, kPartial };

/// The fault that `faults` sets for scan `index`.
ScanFault ScanFaultOf(const FaultParams& faults, std::uint64_t index);

/// Applies `fault` to `scan` (and its truth, when not null): the lost cells become no-returns
/// (range 0, position, intensity and colour zero; row, column and timestamp kept), and their
/// truth says a surface was hit but nothing reported (kTruthDropped). Returns the cells lost.
std::size_t ApplyScanFault(ScanFault fault, double partial_fraction, interfaces::TlsScan& scan,
                           sim::TlsTruth* truth);

/// The wheel motion `delta` (base frame, from one odometry reading to the next) as a slipping
/// wheel reports it: translation and rotation times `factor`.
Pose2 SlippedMotion(const Pose2& delta, double factor);

/// The kidnap's end pose: `from` moved `distance` along `direction` (rad, world), heading kept;
/// else, among the poses on rings around that target (5 cm apart, 72 directions) up to
/// kKidnapSearchRadius, the nearest one with `free` true on it and every 2 cm of the straight
/// slide to it. False when there is none.
bool KidnapTarget(const Pose2& from, double direction, double distance,
                  const std::function<bool(const Pose2&)>& free, Pose2* to);

}  // namespace mopad::mission
