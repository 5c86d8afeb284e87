#pragma once
// Thread-count control for the simulator's parallel work (TBB stays private to sim/).

#include <functional>

namespace mopad::sim {

/// Runs `fn` so that the parallel work inside it uses at most `threads` threads (0 = all
/// hardware threads). Results of the simulator never depend on this number.
void RunWithThreads(int threads, const std::function<void()>& fn);

/// Hardware threads available to the process.
int AvailableThreads();

}  // namespace mopad::sim
