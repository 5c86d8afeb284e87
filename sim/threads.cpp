#include "sim/threads.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

namespace mopad::sim {

void RunWithThreads(int threads, const std::function<void()>& fn) {
  if (threads <= 0) {
    fn();
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute(fn);
}

int AvailableThreads() { return tbb::info::default_concurrency(); }

}  // namespace mopad::sim
