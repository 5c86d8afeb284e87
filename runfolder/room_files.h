#pragma once
// A room's files in a run folder (docs/models.md), written once each, in two calls:
//  - WriteRoomScanFiles when the room ends: what the robot sensed and did there (SM1, SM2,
//    DSM3, the orthoimages, the scan log, scan poses, trajectories, obstacle map, figures,
//    effective config, run.json and, when scored, evaluation.json). These are final when the
//    room ends and hold the bulk of its bytes, so a room's cloud can leave memory then.
//  - WriteRoomModelFiles once the room's semantic models are settled: sm3.json, sm4.json,
//    sm5.json and models.glb. In a floor mission that is after the floor model has shared each
//    door's state between the rooms that saw it (modelling::ShareDoors); a room mission calls
//    both at once (WriteRoomFiles).
// Truth-free: the truth side's documents (true trajectory, evaluation) arrive as text.

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "autonomy/room_scan.h"
#include "common/frames.h"
#include "modelling/components.h"
#include "modelling/openings.h"
#include "modelling/orthoimage.h"
#include "modelling/room_model.h"
#include "modelling/structural_model.h"
#include "modelling/voxel_space.h"
#include "perception/occupancy_grid.h"
#include "runfolder/run_record.h"

namespace mopad::runfolder {

/// The driving figures of summary.json (the simulator's truth figures, handed over as numbers).
struct DriveFigures {
  double path_length = 0.0;  ///< m, true distance travelled
  int contacts = 0;          ///< body contact episodes
  double loc_rms = 0.0;      ///< m, localisation error RMS
  double loc_max = 0.0;      ///< m, localisation error max
};

/// What a room's scans left (every pointer set).
struct RoomScanFiles {
  const modelling::RoomModel* model = nullptr;  ///< sm1.ply, sm2.json (its RoI), model.json
  std::string room;                             ///< the robot's room id (SM2's "room")
  const modelling::VoxelSpace* dsm3 = nullptr;  ///< dsm3.ply (openings marked)
  /// orthoimages/<patch id>_colour.png and _depth.png
  const std::vector<std::pair<std::string, modelling::Orthoimage>>* images = nullptr;
  const autonomy::RoomScanResult* log = nullptr;     ///< scans.json, scan_poses.tum
  std::vector<std::pair<double, Pose3>> door_scans;  ///< (sim time s, X_MS): first in scan_poses
  DriveFigures drive;
  std::string trajectory_estimated_tum, trajectory_true_tum;  ///< TUM text
  const perception::OccupancyGrid* map = nullptr;             ///< map.yaml + map.png
  std::string effective_config_yaml;                          ///< room.effective.yaml
  RunRecord run;                                              ///< run.json
  std::string evaluation_json;  ///< evaluation.json's text; "" writes none
};

/// The room's semantic models (every pointer set).
struct RoomModelFiles {
  std::string room;  ///< the name models.glb gives the room
  const modelling::StructuralModel* sm3 = nullptr;
  const modelling::Sm4Model* sm4 = nullptr;
  const modelling::Sm5Model* sm5 = nullptr;
};

/// Writes the scan files into `dir` (created when missing). InputError naming the file or the
/// folder that cannot be written.
void WriteRoomScanFiles(const std::string& dir, const RoomScanFiles& files);
/// Writes the truth side's scores of the room (evaluation.json, as RoomScanFiles's
/// evaluation_json) into `dir` (which must exist): for an owner that writes the scan files
/// while the scores are still being computed.
void WriteRoomEvaluation(const std::string& dir, const std::string& evaluation_json);
/// Writes sm3.json, sm4.json, sm5.json and models.glb into `dir` (which must exist).
void WriteRoomModelFiles(const std::string& dir, const RoomModelFiles& files);
/// Both, for a room whose models are final when it ends.
void WriteRoomFiles(const std::string& dir, const RoomScanFiles& scans,
                    const RoomModelFiles& models);

/// scans.json's document of a room's scan log (docs/models.md).
nlohmann::ordered_json ScanLogJson(const autonomy::RoomScanResult& log);

}  // namespace mopad::runfolder
