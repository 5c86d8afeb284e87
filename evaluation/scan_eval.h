#pragma once
// Per-scan figures against the truth: the registration error of each
// scan's estimated pose, and the truth of the SM1 per-point labels with their accuracy.
//
// SM1 labels (the robot side uses the same numbers; they are written as `scalar_label`):
//   0 = none (no return / not labelled), 1 = inlier, 2 = outlier, 3 = clutter.
// Truth of a return, for room R:
//   inlier  - the surface hit is a wall, floor, ceiling or column element of R;
//   outlier - the echo came through glass (TruthFlags kTruthTransmitted), or the true surface
//             point lies outside R's polygon in plan view by more than `outside_margin`;
//   clutter - anything else (furniture, door leaves and frames, windows, BSCs, other rooms'
//             surfaces inside the polygon).
// The true surface point is the measured direction scaled to TlsPointTruth::true_range, mapped to
// the world with TlsTruth::X_WS. Frames: W world, M the robot's map, S scanner. Metres, degrees
// only in `_deg` names.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "interfaces/tls_scan.h"
#include "scenes/ground_truth.h"
#include "sim/tls_truth.h"

namespace mopad::evaluation {

/// Pose error of one scan.
struct PoseError {
  double translation = 0.0;   ///< m, |t_est - t_true|
  double rotation_deg = 0.0;  ///< deg, angle of R_est^T R_true, [0, 180]
};

/// Error of an estimated scanner pose X_MS_est against the true one.
PoseError RegistrationError(const Pose3& X_MS_estimated, const Pose3& X_MS_true);
/// The true scanner pose in the map frame: X_MW * X_WS (X_WS from the scan's truth).
Pose3 TrueScannerPoseInMap(const Pose3& X_WM, const sim::TlsTruth& truth);
/// RegistrationError(X_MS_estimated, TrueScannerPoseInMap(X_WM, truth)).
PoseError ScanRegistrationError(const Pose3& X_MS_estimated, const Pose3& X_WM,
                                const sim::TlsTruth& truth);

enum class Sm1Label : std::uint8_t { kNone = 0, kInlier = 1, kOutlier = 2, kClutter = 3 };
std::string_view ToString(Sm1Label label);

struct LabelTruthParams {
  double outside_margin = 0.02;  ///< m, a point must be this far outside the polygon, [0, 1]
  template <class V>
  void Visit(V& v) {
    v("outside_margin", outside_margin, Bounds{0.0, 1.0});
  }
};

/// Truth label of every cell of the scan grid (rows * columns, row-major like TlsScan);
/// kNone where the scan has no return. InputError when scan and truth grids differ or the room
/// is unknown.
std::vector<Sm1Label> TruthLabels(const interfaces::TlsScan& scan, const sim::TlsTruth& truth,
                                  const scenes::GroundTruth& ground_truth, const std::string& room,
                                  const LabelTruthParams& params = {});

/// The valid cells of a grid in the order scan PLYs list points (column by column, top row
/// first; io/scan_io.h): returns grid[i] for each valid cell.
std::vector<Sm1Label> InPlyOrder(const interfaces::TlsScan& scan,
                                 const std::vector<Sm1Label>& grid);

/// Agreement of estimated with true labels. Only points whose truth is not kNone count; an
/// estimated kNone for such a point counts as wrong (`unlabelled`).
struct LabelAccuracy {
  std::uint64_t points = 0;  ///< points with a truth label
  std::uint64_t correct = 0;
  std::uint64_t unlabelled = 0;  ///< truth labelled, estimate kNone
  /// confusion[t - 1][e - 1]: truth t, estimate e, for t, e in {inlier, outlier, clutter}.
  std::array<std::array<std::uint64_t, 3>, 3> confusion{};
  double Accuracy() const {
    return points ? static_cast<double>(correct) / static_cast<double>(points) : 0.0;
  }
  void Add(const LabelAccuracy& o);
};

/// Compares element-wise; InputError when the sizes differ or a value is not 0..3.
LabelAccuracy CompareLabels(std::span<const Sm1Label> truth,
                            std::span<const std::uint8_t> estimated);
LabelAccuracy CompareLabels(std::span<const Sm1Label> truth, std::span<const Sm1Label> estimated);

/// Deterministic JSON: {"points", "correct", "unlabelled", "accuracy", "confusion": 3x3 rows =
/// truth inlier/outlier/clutter, columns = estimate}.
std::string LabelAccuracyToJson(const LabelAccuracy& accuracy);

}  // namespace mopad::evaluation
