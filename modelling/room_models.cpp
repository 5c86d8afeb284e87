#include "modelling/room_models.h"

#include <chrono>
#include <utility>

namespace mopad::modelling {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool HasClosedDoor(const Sm4Model& sm4) {
  for (const auto& o : sm4.openings)
    if (o.type == OpeningType::kDoor && o.state == DoorState::kClosed) return true;
  return false;
}

}  // namespace

RoomModels BuildRoomModels(const RoomModel& model, OrthoPoints no_return, const Sm3Params& sm3,
                           const OpeningParams& sm4, const ComponentParams& sm5,
                           const std::string& room,
                           std::vector<std::pair<std::string, Orthoimage>>* images,
                           const ComponentRecogniser* recogniser,
                           const std::vector<Sm4Model>& neighbours) {
  RoomModels out;
  out.sm3 = BuildRoomSm3(model, sm3, room);
  OrthoPoints ortho = std::move(no_return);
  ortho.points = &model.Points();
  ortho.colours = &model.Colours();
  ortho.scan_index = &model.ScanIndices();
  ortho.scan_origins.clear();
  for (const Pose3& X : model.ScanPoses()) ortho.scan_origins.push_back(X.translation());
  ortho.scan_steps = model.ScanAngularSteps();
  const auto t0 = Clock::now();
  DropNoReturnRaysThroughSeenSurfaces(ortho, sm4.orthoimage);
  out.sm4 = DetectOpenings(out.sm3, ortho, sm4, images, neighbours);
  if (HasClosedDoor(out.sm4)) {
    const std::vector<std::uint8_t> mask =
        ClosedDoorPointMask(model.Points(), out.sm3.patches, out.sm4.openings);
    out.sm3 = BuildRoomSm3(model, sm3, room, &mask);
    if (images) images->clear();
    out.sm4 = DetectOpenings(out.sm3, ortho, sm4, images, neighbours);
  }
  out.sm4_seconds = Since(t0);
  out.sm5.room = room;
  if (recogniser) {
    const auto t1 = Clock::now();
    out.sm5 = DetectComponents(out.sm3, out.sm4, ortho, *recogniser, sm5);
    out.sm5_seconds = Since(t1);
  }
  out.dsm3 = model.Voxels();
  MarkOpeningVoxels(out.sm4.openings, out.dsm3);
  out.ortho = std::move(ortho);
  return out;
}

}  // namespace mopad::modelling
