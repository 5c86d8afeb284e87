#pragma once
// The scanning stopping rule of one room (paper §3.1 step (6), Figure 5): stop when the sensed
// structural area reaches epsilon1 of the estimated observable structure (the estimated total
// less what no reachable position can see, CoverageFigures::observable_ratio; the paper's
// total while nothing is estimated hidden), or when the last scan added less than epsilon2 of
// the total. The decision carries a one-line reason with the figures for the log.

#include <string>

#include "common/params.h"
#include "modelling/room_model.h"

namespace mopad::modelling {

struct StoppingParams {
  /// Minimum sensed share of the observable structure (CoverageFigures::observable_ratio), (0, 1].
  /// The paper's 0.90 was a share of the whole RoI; 0.95 of what can be seen is the mission's
  /// promise (docs/room-scanning.md, Stopping).
  double epsilon1 = 0.95;
  double epsilon2 = 0.01;  ///< minimum increment of that share per scan, [0, 1]
  /// Safety net beyond the paper: stop after this many scans of one room (0 = no limit). [0, 1000]
  int max_scans = 0;

  template <class V>
  void Visit(V& v) {
    v("epsilon1", epsilon1, Bounds{1e-9, 1.0});
    v("epsilon2", epsilon2, Bounds{0.0, 1.0});
    v("max_scans", max_scans, Bounds{0, 1000});
  }
  void Validate() const { ValidateParams(*this, "stopping."); }
};

enum class StopReason { kContinue = 0, kCoverageReached, kIncrementTooSmall, kMaxScans };

struct StopDecision {
  bool stop = false;
  StopReason reason = StopReason::kContinue;
  std::string
      message;  ///< e.g. "stop: coverage 0.934 >= epsilon1 0.900 (sensed 112.3 m2 of 120.2 m2)"
};

/// Applies the rule to the figures after the latest scan. The increment criterion needs at
/// least two scans (the first scan's increment is its whole coverage). Throws InputError for
/// invalid params.
StopDecision CheckStopping(const CoverageFigures& figures, const StoppingParams& params);

}  // namespace mopad::modelling
