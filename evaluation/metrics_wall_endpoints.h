#pragma once
// Wall endpoints in plan, the CV4AEC scan-to-BIM challenge's wall figure (docs/evaluation.md,
// "Scoring other tools' models"): every wall is a segment in plan, model walls are paired
// one-to-one with truth walls by a Hungarian assignment, and an endpoint of a pair counts at a
// threshold when it lies within that distance of its partner. Precision = endpoints within /
// (2 x model walls), recall = endpoints within / (2 x truth walls), F = their harmonic mean, at
// each threshold (5, 10 and 20 cm by default).
//
// The challenge draws walls as centre lines; the truth here records a wall as the interior faces
// of the rooms it bounds (the paper's wall_1A; a wall between two rooms is two faces), so the
// segments are the faces': a face's plan segment runs along the face (u = z x n, n the normal into
// the room) from its smallest to its largest u, at its vertices' mean offset along n. Its first
// endpoint is the one on the left seen from the room. A model face and a truth face are candidates
// when their normals agree within max_normal_angle_deg (oriented: the two faces of a wall never
// pair), the model segment's midpoint lies within max_plane_distance of the truth face's line and
// the two overlap along it; the assignment minimises the sum of the two endpoint distances.
// World frame, metres. Deterministic.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/params.h"
#include "evaluation/metrics.h"
#include "evaluation/metrics_floorplan.h"

namespace mopad::evaluation {

struct WallEndpointParams {
  std::vector<double> thresholds = {0.05, 0.10, 0.20};  ///< m, each in (0, 10]
  double max_normal_angle_deg = 10.0;                   ///< deg, candidate pairs, (0, 90]
  double max_plane_distance = 0.30;                     ///< m, model midpoint to truth line, (0, 10]
  template <class V>
  void Visit(V& v) {
    v("thresholds", thresholds, Bounds{1e-9, 10.0});
    v("max_normal_angle_deg", max_normal_angle_deg, Bounds{1e-6, 90.0});
    v("max_plane_distance", max_plane_distance, Bounds{1e-6, 10.0});
  }
};

/// A wall face in plan.
struct WallSegment {
  std::string id;
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();  ///< m, left and right end seen from the room
  Vec2 normal = Vec2::UnitX();              ///< unit, into the room
};

/// The plan segment of a wall patch (class wall; InputError for a polygon without horizontal
/// extent).
WallSegment WallSegmentOf(const Patch& wall);

struct WallEndpointPair {
  std::string model_id, truth_id;
  double error_a = 0.0, error_b = 0.0;  ///< m, endpoint distances
};

struct WallEndpointScore {
  double threshold = 0.0;  ///< m
  PrecisionRecall endpoints;
};

struct WallEndpointEvaluation {
  int model_walls = 0, truth_walls = 0;
  std::vector<WallEndpointPair> pairs;  ///< by truth index
  std::vector<WallEndpointScore> scores;  ///< one per threshold
  ErrorStats endpoint_error;  ///< m, over the endpoints of every pair
};

/// Scores the wall patches of `model` against those of `truth` (other classes are ignored).
WallEndpointEvaluation EvaluateWallEndpoints(const std::vector<Patch>& model,
                                             const std::vector<Patch>& truth,
                                             const WallEndpointParams& params = {});

nlohmann::ordered_json ToJson(const WallEndpointEvaluation& e);

}  // namespace mopad::evaluation
