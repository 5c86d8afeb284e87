#include "evaluation/truth_eval.h"

namespace mopad::evaluation {

RoomTruth ComputeRoomTruth(const sim::EmbreeWorld& world, const scenes::GroundTruth& truth,
                           const std::string& room, const TruthEvalParams& params) {
  RoomTruth out;
  out.surfaces = SampleStructuralSurfaces(world.scene(), truth, room, params.surfaces);
  out.reachable = ComputeReachable(world.scene(), truth, room, params.observability);
  out.observability =
      ComputeObservability(world, out.surfaces, out.reachable, params.observability);
  return out;
}

}  // namespace mopad::evaluation
