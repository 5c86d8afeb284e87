#pragma once
// What the robot's software can ask of its hardware: a clock, wheels, two LRFs and a terrestrial
// laser scanner. It is the robot boundary as one interface (a real robot's driver, or the
// simulated robot of mission/sim_robot.h): the brain (autonomy/navigator.h) drives a platform
// and sees nothing else. Nothing here carries ground truth: odometry drifts, sweeps and scans
// are in their sensor frames, and a scan comes back with an identity `X_MS_estimate` (the
// caller stamps its own pose estimate).

#include "interfaces/lrf_scan.h"
#include "interfaces/odometry.h"
#include "interfaces/tls_scan.h"

namespace mopad::interfaces {

class RobotPlatform {
 public:
  virtual ~RobotPlatform() = default;

  /// s, the platform's clock (simulation time in the simulator).
  virtual double Time() const = 0;
  /// s, the duration of one Step.
  virtual double ControlPeriod() const = 0;
  /// Applies `cmd` for one control period. Returns true when a new top-LRF sweep arrived
  /// during it (the base LRF may have swept too; BaseSweep() is always the latest).
  virtual bool Step(const VelocityCommand& cmd) = 0;
  /// The latest integrated wheel odometry (drifts; never the true pose).
  virtual const Odometry& WheelOdometry() const = 0;
  /// The latest sweeps of the base LRF (near the floor) and the top LRF (above the furniture).
  virtual const LrfScan& BaseSweep() const = 0;
  virtual const LrfScan& TopSweep() const = 0;
  /// One TLS scan at `step_deg` (deg, angular step) from where the base stands. `still_for`
  /// receives how long (s) the base must then stand still for the head to finish turning
  /// (0 where the platform takes the scan instantly); the caller steps with a zero command for
  /// that long. Before the first Step, the LRFs sweep once first, so that BaseSweep() and
  /// TopSweep() are valid with the first scan.
  virtual TlsScan Scan(double step_deg, double* still_for) = 0;
};

}  // namespace mopad::interfaces
