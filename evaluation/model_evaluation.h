#pragma once
// `mopad eval --model FILE --scene SCENE -o DIR`: scores a building model that another program
// made (or this program's own export) against the scene's truth with the metrics the robot's
// models get, plus the CV4AEC scan-to-BIM challenge's wall endpoints and room IoU
// (docs/evaluation.md, "Scoring other tools' models").
//
// What is read from the model:
//  - IFC 2x3 or IFC4 (.ifc): through the BIM import as it is (scenes::ImportBim with
//    BimImportParams::as_is): rooms are the storey's IfcSpace volumes, a wall is the face of an
//    IfcWall* that faces a room along the room's outline (the nearest such face within 30 cm of
//    it: a wall drawn off its space's outline is still scored, at its own place), floors and ceilings the slab and
//    covering faces at the room's floor and ceiling, columns IfcColumn, doors and windows their
//    hole in the room-side wall faces, service components the IfcOutlet, IfcSwitchingDevice, ...
//    hosted on a wall or ceiling. A model without IfcSpace is refused: its spaces are how a wall's
//    room face is told from its back. Door states come from the door's property set where the
//    model has one (MoPAD_Opening.State / OpeningAngle, this program's export); without one a
//    door has no state and is left out of the state figures. A component's class (and score alpha)
//    come from its MoPAD_Component set where present, else from its IFC class, type and names.
//  - This program's JSON model (.json, format mopad-sm3: a room's sm3.json), with the sm4.json
//    and sm5.json beside it when present; rooms are its floor polygons. The floor model
//    (floor/sm3.json: a wall between rooms on its axis, its faces inside) is refused: score its
//    export, export/model.ifc, which has the faces.
//
// The model's frame: `X_WE`, the pose of the model's frame in the world (default identity: a
// model drawn in the building's coordinates). With `fit` the model's main floor level (the floor
// height carrying the most area) is first put on the truth's, then the pose is refined by a
// 4-DoF point-to-plane alignment (x, y, z, yaw) of the model's structural surfaces to the
// truth's (it needs the model within about 0.3 m and a few degrees of its place in plan); the
// fitted pose and its residual are reported.
//
// Figures, floor-wide (every truth room of the scene, open-plan rooms merged as `mopad eval`
// merges them): walls, floors, ceilings (EvaluatePatches), columns as objects, ISPRS
// completeness/correctness, openings and door states (EvaluateOpenings), components
// (EvaluateComponents), the floorplan (room IoU, room corners) and the wall endpoints
// (EvaluateWallEndpoints). Writes DIR/evaluation.json (format "mopad-model-evaluation"),
// DIR/evaluation.md and DIR/eval.effective.yaml.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/frames.h"

namespace mopad::evaluation {

struct ModelEvalOptions {
  std::string model;               ///< .ifc (IFC 2x3 / IFC4) or a mopad-sm3 .json
  std::string scene;               ///< scene folder, scene file or spec .yaml
  std::vector<std::string> doors;  ///< door-angle overrides of the truth's world ("D1=90")
  std::string truth_file;          ///< overrides the scene's truth sidecar ("" = the scene's)
  std::string config;              ///< EvalParams YAML ("" = defaults)
  std::string out;                 ///< output folder
  std::string storey;              ///< IFC storey (Name, GlobalId); "" = lowest with spaces
  Pose3 X_WE = Pose3::Identity();  ///< the model's frame in the world
  bool fit = false;                ///< refine X_WE by aligning the surfaces
};

struct ModelEvaluation {
  std::string tables;              ///< what `mopad eval --model` prints
  nlohmann::ordered_json summary;  ///< evaluation.json's "summary"
};

/// Reads, scores and writes (see above). InputError on bad input (the model, the scene, the
/// options), before any file is written.
ModelEvaluation EvaluateModel(const ModelEvalOptions& options);

/// "x,y,z,yaw_deg" -> the pose (yaw about world z). InputError naming `what` otherwise.
Pose3 ParsePlanPose(const std::string& text, const std::string& what);

}  // namespace mopad::evaluation
