#pragma once
// One-call truth-side figures of a room: its structural surface cells, the robot's
// reachable positions and the observable cells, plus the parameters of every truth-side
// evaluator in one YAML-loadable struct. See truth_surfaces.h, observability.h, coverage.h and
// scan_eval.h for the definitions.

#include <string>

#include "common/params.h"
#include "evaluation/coverage.h"
#include "evaluation/observability.h"
#include "evaluation/scan_eval.h"
#include "evaluation/truth_surfaces.h"
#include "scenes/ground_truth.h"
#include "sim/embree_world.h"

namespace mopad::evaluation {

struct TruthEvalParams {
  SurfaceSamplingParams surfaces;
  ObservabilityParams observability;
  CoverageParams coverage;
  LabelTruthParams labels;
  template <class V>
  void Visit(V& v) {
    v("surfaces", surfaces);
    v("observability", observability);
    v("coverage", coverage);
    v("labels", labels);
  }
};

struct RoomTruth {
  StructuralSurfaces surfaces;
  ReachableArea reachable;
  Observability observability;
};

/// Samples `room`'s surfaces, its reachable positions and observable cells in `world`'s scene
/// (build `world` with WorldOptions::robust for exact figures; observability.h).
RoomTruth ComputeRoomTruth(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                           const std::string& room, const TruthEvalParams& params = {});

}  // namespace mopad::evaluation
