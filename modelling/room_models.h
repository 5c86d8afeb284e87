#pragma once
// The room-model pipeline (paper §3.2-3.4): SM3, SM4 and SM5 of a scanned room in one call, as
// the room loop and the floor mission both build them.
//
//   SM3: the structural model of the RoomModel's points (walls, floor, ceiling, columns);
//   SM4: the openings in its walls from their colour + depth orthoimages (the accepted scans'
//        points and the rays that returned nothing); when a closed door is found, SM3 and SM4
//        once more without its leaf and casing (a closed door is not its wall);
//   SM5: with a recogniser (trained from the robot's catalogue of object models), the service
//        components on its walls and ceiling;
//   DSM3: the room's voxels with the voxels of SM4's openings marked.
// Robot side: reads only the robot's own data. Deterministic (timings aside).

#include <string>
#include <utility>
#include <vector>

#include "modelling/components.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/room_model.h"
#include "modelling/structural_model.h"
#include "modelling/voxel_space.h"

namespace mopad::modelling {

struct RoomModels {
  StructuralModel sm3;
  Sm4Model sm4;
  Sm5Model sm5;              ///< empty (its room set) without a recogniser
  VoxelSpace dsm3;           ///< the RoomModel's voxels, SM4's openings marked
  double sm4_seconds = 0.0;  ///< s of wall time of SM4 (reporting only)
  double sm5_seconds = 0.0;  ///< s of wall time of SM5 (reporting only)
  /// SM4's input and SM5's: the RoomModel's points, colours and scan indices (pointers, valid
  /// while it lives), its scans' origins and the rays without a return SM4 kept
  OrthoPoints ortho;
};

/// The models of `model`'s room named `room`. `no_return`: the accepted scans' rays without a
/// return (its points, colours and scan indices are taken from `model`). `images` receives each
/// wall's orthoimage when given. `neighbours`: SM4 of rooms modelled before (their doors on this
/// room's walls are hints). Without a recogniser, SM5 can follow later from the result's sm3,
/// sm4 and ortho (DetectComponents), as long as `model` lives.
RoomModels BuildRoomModels(const RoomModel& model, OrthoPoints no_return, const Sm3Params& sm3,
                           const OpeningParams& sm4, const ComponentParams& sm5,
                           const std::string& room,
                           std::vector<std::pair<std::string, Orthoimage>>* images,
                           const ComponentRecogniser* recogniser = nullptr,
                           const std::vector<Sm4Model>& neighbours = {});

}  // namespace mopad::modelling
