#pragma once
// The floor mission's floor-level models: the robot's per-room SM3/SM4 of the rooms it
// modelled, joined by modelling::BuildFloorModel, written to DIR/floor/sm3.json and
// DIR/floor/sm4.json (docs/models.md, map frame). Reads nothing of the truth.

#include <functional>
#include <string>

#include "autonomy/floor_scan.h"
#include "modelling/floor_model.h"

namespace mopad::mission {

/// Builds the floor model of `mission`'s rooms modelled without error (visit order) and writes
/// `dir`/floor/. Then one door, one state, on both faces (modelling::ShareDoors): a door seen
/// from two rooms takes the better-observed side's state in both rooms' SM4 in `mission`, a
/// door one room found goes to the room on its wall's other face. The rooms' own model files
/// are written after this (runfolder::WriteRoomModelFiles), once.
/// Returns false, having told `progress` why, when no room was modelled, the rooms' models
/// cannot be joined (a malformed model) or the folder cannot be written: the rooms' own files
/// stand, and the mission's other files are still written.
bool WriteFloorModel(autonomy::FloorScanResult& mission, const modelling::FloorModelParams& params,
                     const std::string& dir,
                     const std::function<void(const std::string&)>& progress = {});

}  // namespace mopad::mission
