#pragma once
// Wall-clock seconds, for reporting only: no algorithm reads the wall clock (simulation time
// drives every decision, so results never depend on how fast the machine is).

#include <chrono>

namespace mopad {

using WallClock = std::chrono::steady_clock;

/// s of wall time since `t0`.
inline double SecondsSince(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

}  // namespace mopad
