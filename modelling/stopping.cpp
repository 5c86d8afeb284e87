#include "modelling/stopping.h"

#include <cstdio>

namespace mopad::modelling {

StopDecision CheckStopping(const CoverageFigures& f, const StoppingParams& params) {
  params.Validate();
  char figures[256];
  std::snprintf(figures, sizeof(figures),
                "scan %d: sensed %.2f m2 of %.2f m2, %.2f m2 hidden (coverage %.3f of the total, "
                "increment %.3f)",
                f.scans, f.sensed_area, f.total_area, f.hidden_area, f.ratio, f.increment);
  StopDecision d;
  char buf[400];
  if (f.observable_ratio >= params.epsilon1) {
    d.stop = true;
    d.reason = StopReason::kCoverageReached;
    std::snprintf(buf, sizeof(buf), "stop: coverage %.3f >= epsilon1 %.3f; %s", f.observable_ratio,
                  params.epsilon1, figures);
  } else if (f.scans >= 2 && f.increment < params.epsilon2) {
    d.stop = true;
    d.reason = StopReason::kIncrementTooSmall;
    std::snprintf(buf, sizeof(buf), "stop: increment %.3f < epsilon2 %.3f; %s", f.increment,
                  params.epsilon2, figures);
  } else if (params.max_scans > 0 && f.scans >= params.max_scans) {
    d.stop = true;
    d.reason = StopReason::kMaxScans;
    std::snprintf(buf, sizeof(buf), "stop: %d scans reached max_scans %d; %s", f.scans,
                  params.max_scans, figures);
  } else {
    std::snprintf(buf, sizeof(buf),
                  "continue: coverage %.3f < epsilon1 %.3f, increment %.3f >= epsilon2 %.3f; %s",
                  f.observable_ratio, params.epsilon1, f.increment, params.epsilon2, figures);
  }
  d.message = buf;
  return d;
}

}  // namespace mopad::modelling
