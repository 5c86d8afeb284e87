#pragma once
// The parameters of a building's as-built geometry (scenes/as_built.h has the model): kept in
// a scene spec (`as_built:`), in a run's realism profile (`realism.geometry`) and in the truth
// sidecar, so every reader can rebuild the same field.

#include <cstdint>

#include "common/params.h"

namespace mopad::scenes {

struct AsBuiltParams {
  /// mm, 1 sigma of each component of the smooth displacement (flatness, level), [0, 50]
  double flatness_mm = 0.0;
  /// deg, 1 sigma of the local lean of vertical surfaces off plumb, [0, 2]
  double lean_sigma_deg = 0.0;
  double wavelength = 2.0;     ///< m, shortest wavelength of the flatness terms, [0.5, 100]
  double mesh_spacing = 0.25;  ///< m, longest triangle edge after subdivision, [0.02, 5]
  std::uint64_t seed = 1;      ///< the field's draw (a run sets its own seed)

  bool Enabled() const { return flatness_mm > 0.0 || lean_sigma_deg > 0.0; }

  template <class V>
  void Visit(V& v) {
    v("flatness_mm", flatness_mm, Bounds{0, 50});
    v("lean_sigma_deg", lean_sigma_deg, Bounds{0, 2});
    v("wavelength", wavelength, Bounds{0.5, 100});
    v("mesh_spacing", mesh_spacing, Bounds{0.02, 5});
    v("seed", seed);
  }
};

}  // namespace mopad::scenes
