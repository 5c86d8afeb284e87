#pragma once
// Label confusion metrics: DSM3 per-voxel confusion over the six labels of the paper's §3.2
// (opening, structure, occluded structure, clutter, empty, unseen) and, with any label set,
// SM1 per-point label accuracy.
//
// Rows are truth labels, columns predicted labels. Per class c:
//   IoU(c) = TP / (TP + FP + FN), precision = TP / (TP + FP), recall = TP / (TP + FN)
// (NaN when the denominator is 0, i.e. the class occurs on neither side); accuracy = trace /
// total. Elements whose truth or prediction equals `ignore_label` are skipped.

#include <cstdint>
#include <string>
#include <vector>

namespace mopad::evaluation {

/// DSM3 voxel labels (values are the uint8 codes of the label arrays).
enum class VoxelLabel : std::uint8_t {
  kOpening = 0,
  kStructure = 1,
  kOccludedStructure = 2,
  kClutter = 3,
  kEmpty = 4,
  kUnseen = 5,
};
/// {"opening", "structure", "occluded_structure", "clutter", "empty", "unseen"}.
const std::vector<std::string>& Dsm3LabelNames();

struct ConfusionMatrix {
  std::vector<std::string> labels;
  std::vector<std::int64_t> counts;  ///< row-major, labels.size()^2; row truth, column predicted
  std::int64_t total = 0;            ///< elements counted (ignored ones excluded)
  double accuracy = 0.0;             ///< trace / total (NaN if total = 0)
  std::vector<double> iou, precision, recall;  ///< per label
  double mean_iou = 0.0;                       ///< over labels with a finite IoU (NaN if none)
  std::int64_t At(int truth, int predicted) const {
    return counts[static_cast<size_t>(truth) * labels.size() + static_cast<size_t>(predicted)];
  }
};

/// Confusion of `predicted` against `truth` (same length; each value < labels.size() unless it
/// is `ignore_label`; -1 = none). InputError on length mismatch or an out-of-range label.
ConfusionMatrix ComputeConfusion(const std::vector<std::uint8_t>& truth,
                                 const std::vector<std::uint8_t>& predicted,
                                 const std::vector<std::string>& labels, int ignore_label = -1);

/// DSM3: ComputeConfusion with the six voxel labels.
ConfusionMatrix ComputeDsm3Confusion(const std::vector<std::uint8_t>& truth,
                                     const std::vector<std::uint8_t>& predicted,
                                     int ignore_label = -1);

}  // namespace mopad::evaluation
