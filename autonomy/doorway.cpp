#include "autonomy/doorway.h"

#include <algorithm>
#include <cmath>

namespace mopad::autonomy {

double DoorwayClearWidth(const perception::OccupancyGrid& map, const Vec2& a, const Vec2& b,
                         const Vec2& inward, const DoorwayParams& params) {
  const double width = (b - a).norm();
  if (!(width > 0.0)) return 0.0;
  const Vec2 t = (b - a) / width;
  const double step = 0.5 * map.Resolution();
  const int stations = std::max(1, static_cast<int>(std::ceil(width / step)));
  const double du = width / stations;
  const int depths =
      1 + static_cast<int>(std::ceil((params.depth_front + params.depth_beyond) / step));
  const double dv = (params.depth_front + params.depth_beyond) / std::max(1, depths - 1);
  int run = 0, best = 0;
  for (int k = 0; k < stations; ++k) {
    const Vec2 on_plane = a + (k + 0.5) * du * t;
    bool blocked = false;
    for (int m = 0; m < depths && !blocked; ++m) {
      const Vec2 p = on_plane + (params.depth_front - m * dv) * inward;
      const perception::Cell c = map.CellOf(p);
      blocked = map.Contains(c) && map.State(c) == perception::CellState::kOccupied;
    }
    run = blocked ? 0 : run + 1;
    best = std::max(best, run);
  }
  return best * du;
}

}  // namespace mopad::autonomy
