#pragma once
// Self-calibration of a TLS scan's range offset from the floor and ceiling it sees.
//
// A scanner's ranges share an additive error b within one scan: the part of the data sheet's
// accuracy that its precision does not cover (docs/sensors.md; the simulator draws it once per
// scan, 4 mm 1 sigma for the VZ-400). A return at true range R along the unit direction u is
// reported at (R + b) u, so a horizontal plane at height h in the scanner frame is seen at
//   z = h + b u_z:
// a steep ray (u_z = -0.64 at -40 deg elevation) moves by 0.64 b, a grazing one hardly. The
// floor's and ceiling's points therefore tell b apart from the planes' heights. The estimate
// is the least-squares fit of
//   z_i = h_plane(i) + b u_z,i + s_x x_i + s_y y_i
// over the points of the lowest strong z peak below the scanner (the floor) and the highest
// above it (the ceiling); s_x and s_y take the levelling error's slopes so that a tilted
// scanner does not read as a bias. Residuals are trimmed twice. A wall seen with b bends by
// b cos(incidence): left in, a room scanned from several positions comes out warped by
// millimetres to a centimetre (docs/room-scanning.md, "Range offset").
//
// Frames: scanner S (levelled up to the small tilt above; z up). Consumes the scan only.
// Deterministic (sums in grid order, one thread).

#include <cstddef>
#include <string>

#include "common/params.h"
#include "interfaces/tls_scan.h"

namespace mopad::perception {

struct RangeBiasParams {
  bool estimate = true;  ///< false: scans are used as the scanner reports them
  /// m, floor candidates lie this far below the scanner centre, ceiling candidates this far
  /// above it, (0, 10]
  double min_height = 0.5;
  double band = 0.03;        ///< m, half-width of the band about a plane's z peak, (0, 0.5]
  int min_points = 5000;     ///< plane points the fit needs, [10, 1e9]
  double max_sigma = 0.001;  ///< m, an estimate less certain than this is not applied, (0, 1]
  /// m, a larger |b| is not applied: no range offset of a working scanner, (0, 1]
  double max_bias = 0.05;

  template <class V>
  void Visit(V& v) {
    v("estimate", estimate);
    v("min_height", min_height, Bounds{1e-3, 10.0});
    v("band", band, Bounds{1e-3, 0.5});
    v("min_points", min_points, Bounds{10, 1000000000});
    v("max_sigma", max_sigma, Bounds{1e-6, 1.0});
    v("max_bias", max_bias, Bounds{1e-6, 1.0});
  }
};

struct RangeBiasEstimate {
  bool ok = false;     ///< the estimate is certain and plausible: apply it
  double bias = 0.0;   ///< m, b (reported range minus true range)
  double sigma = 0.0;  ///< m, standard deviation of b from the fit
  double rms = 0.0;    ///< m, RMS residual of the plane points
  std::size_t floor_points = 0, ceiling_points = 0;
  std::string message;  ///< one line: the outcome with its figures
};

/// Estimates the scan's range offset (see the file comment). Never throws for scan content:
/// a scan without enough floor or ceiling gives ok = false and says why. InputError for bad
/// params.
RangeBiasEstimate EstimateRangeBias(const interfaces::TlsScan& scan, const RangeBiasParams& params);

/// Subtracts `bias` from every valid range of `scan` and moves its points along their rays.
void RemoveRangeBias(interfaces::TlsScan& scan, double bias);

}  // namespace mopad::perception
