#include "evaluation/metrics_voxels.h"

#include <cmath>
#include <limits>

#include "common/error.h"

namespace mopad::evaluation {

const std::vector<std::string>& Dsm3LabelNames() {
  static const std::vector<std::string> k = {"opening", "structure", "occluded_structure",
                                             "clutter", "empty",     "unseen"};
  return k;
}

ConfusionMatrix ComputeConfusion(const std::vector<std::uint8_t>& truth,
                                 const std::vector<std::uint8_t>& predicted,
                                 const std::vector<std::string>& labels, int ignore_label) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (labels.empty() || labels.size() > 256) {
    throw InputError("", "confusion label set size out of range", std::to_string(labels.size()),
                     "1..256");
  }
  if (truth.size() != predicted.size()) {
    throw InputError("", "label arrays differ in length",
                     std::to_string(truth.size()) + " vs " + std::to_string(predicted.size()),
                     "equal lengths");
  }
  const size_t k = labels.size();
  ConfusionMatrix m;
  m.labels = labels;
  m.counts.assign(k * k, 0);
  for (size_t i = 0; i < truth.size(); ++i) {
    const int t = truth[i], p = predicted[i];
    if (t == ignore_label || p == ignore_label) continue;
    if (static_cast<size_t>(t) >= k || static_cast<size_t>(p) >= k) {
      throw InputError("", "label out of range at element " + std::to_string(i),
                       std::to_string(static_cast<size_t>(t) >= k ? t : p),
                       "< " + std::to_string(k));
    }
    ++m.counts[static_cast<size_t>(t) * k + static_cast<size_t>(p)];
    ++m.total;
  }
  std::int64_t trace = 0;
  double iou_sum = 0.0;
  int iou_n = 0;
  for (size_t c = 0; c < k; ++c) {
    std::int64_t row = 0, col = 0;
    for (size_t j = 0; j < k; ++j) {
      row += m.counts[c * k + j];
      col += m.counts[j * k + c];
    }
    const std::int64_t tp = m.counts[c * k + c];
    trace += tp;
    const std::int64_t uni = row + col - tp;
    m.iou.push_back(uni > 0 ? static_cast<double>(tp) / uni : nan);
    m.precision.push_back(col > 0 ? static_cast<double>(tp) / col : nan);
    m.recall.push_back(row > 0 ? static_cast<double>(tp) / row : nan);
    if (uni > 0) {
      iou_sum += m.iou.back();
      ++iou_n;
    }
  }
  m.accuracy = m.total > 0 ? static_cast<double>(trace) / m.total : nan;
  m.mean_iou = iou_n > 0 ? iou_sum / iou_n : nan;
  return m;
}

ConfusionMatrix ComputeDsm3Confusion(const std::vector<std::uint8_t>& truth,
                                     const std::vector<std::uint8_t>& predicted, int ignore_label) {
  return ComputeConfusion(truth, predicted, Dsm3LabelNames(), ignore_label);
}

}  // namespace mopad::evaluation
