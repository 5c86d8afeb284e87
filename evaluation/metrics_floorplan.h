#pragma once
// Floorplan metrics in the RoomFormer/HEAT protocol used by the CV4AEC Scan-to-BIM challenge
// (../shared/reference/metrics.md):
//   rooms   - per-room IoU of 2D polygons, computed exactly (ear-clipped triangles clipped
//             pairwise, no rasterisation error). Predicted and truth rooms are paired by a
//             Hungarian assignment on 1 - IoU; a pair is a true positive when IoU > 0.5 (the
//             one-to-one assignment stands for "no overlap with other predictions").
//   corners - room polygon vertices after dropping collinear vertices (collinear_tolerance_deg).
//             Within each TP room pair, corners are paired by a Hungarian assignment on their
//             distance; at threshold t a pair within t is a TP. Corners of unmatched rooms are
//             FP (predicted) or FN (truth). Precision = TP / #predicted corners, recall = TP /
//             #truth corners, F1 their harmonic mean; at t = 5, 10, 20 cm by default.
//   angles  - a corner pair within angle_corner_threshold whose interior angles differ by
//             <= angle_tolerance_deg is an angle TP (same precision/recall/F1 definitions).
// Plan frame: x-y of the world frame, metres.

#include <string>
#include <vector>

#include "evaluation/metrics.h"

namespace mopad::evaluation {

struct Room {
  std::string id;
  std::vector<Vec2> polygon;  ///< simple polygon, either winding, first vertex not repeated
};

struct FloorplanParams {
  double room_iou_threshold = 0.5;  ///< a room pair is a TP when IoU > this, [0, 1)
  std::vector<double> corner_thresholds = {0.05, 0.10, 0.20};  ///< m, each in (0, 10]
  double angle_corner_threshold = 0.10;  ///< m, corner pairs checked for angles, (0, 10]
  double angle_tolerance_deg = 5.0;      ///< deg, [0, 180]
  double collinear_tolerance_deg = 1.0;  ///< deg, vertices turning less are not corners, [0, 10]
  template <class V>
  void Visit(V& v) {
    v("room_iou_threshold", room_iou_threshold, Bounds{0.0, 1.0 - 1e-9});
    v("corner_thresholds", corner_thresholds, Bounds{1e-9, 10.0});
    v("angle_corner_threshold", angle_corner_threshold, Bounds{1e-9, 10.0});
    v("angle_tolerance_deg", angle_tolerance_deg, Bounds{0.0, 180.0});
    v("collinear_tolerance_deg", collinear_tolerance_deg, Bounds{0.0, 10.0});
  }
};

struct PrecisionRecall {
  int tp = 0, n_predicted = 0, n_truth = 0;
  double precision = 0.0, recall = 0.0, f1 = 0.0;  ///< 0 when a denominator is 0
  static PrecisionRecall From(int tp, int n_predicted, int n_truth);
};

struct RoomPair {
  int predicted = -1, truth = -1;
  std::string predicted_id, truth_id;
  double iou = 0.0;
  bool true_positive = false;  ///< iou > room_iou_threshold
};

struct CornerScore {
  double threshold = 0.0;  ///< m
  PrecisionRecall score;
};

struct FloorplanResult {
  std::vector<RoomPair> room_pairs;    ///< Hungarian pairs with IoU > 0, by truth index
  std::vector<double> truth_room_iou;  ///< per truth room, its pair's IoU (0 if unpaired)
  double mean_truth_iou = 0.0;         ///< mean of truth_room_iou (0 if no truth room)
  PrecisionRecall rooms;
  std::vector<CornerScore> corners;  ///< one per corner threshold
  PrecisionRecall angles;
};

/// Scores `predicted` rooms against `truth` rooms. InputError for a room with < 3 vertices,
/// non-finite coordinates or zero area.
FloorplanResult EvaluateFloorplan(const std::vector<Room>& predicted,
                                  const std::vector<Room>& truth,
                                  const FloorplanParams& params = {});

}  // namespace mopad::evaluation
