#pragma once
// The floor model (floor/sm3.json, floor/sm4.json; modelling/floor_model.h) against the truth
// (docs/evaluation.md "floor model").
//
// Truth walls are the sidecar's wall elements: one planar interior face of one room each (the
// paper's wall_1A), so office_5rooms has 24 wall faces; a physical wall between two rooms is
// two of them. Two truth faces of different rooms are one physical wall when they are
// antiparallel (within 1 deg), back to back at most max_truth_thickness apart and overlap
// along the wall (truth pairs).
//
// Figures:
//  - faces: every floor wall's faces (map frame, mapped to the world by X_WM) matched to the
//    truth wall faces of the rooms evaluated (EvaluatePatches, oriented normals, so the two
//    faces of a wall never swap): detection TP/FP/FN, d_v, d_h, Phi per face;
//  - pairs: a model face pair (two faces the floor model joined) is correct when its faces
//    match the two faces of a truth pair; its thickness error |t_model - t_truth| is the
//    room-to-room alignment error across the wall (a shift of one room's model against the
//    other's along the wall's normal changes it one for one; a shift of the whole map does not);
//  - rooms: each room's offset against the truth, the 2D translation t (world x, y) that best
//    explains the signed distances of its matched wall faces' centroids to their truth planes
//    (least squares over n_truth . t = n_truth . (c_model - p_truth); needs faces in two
//    directions). The room-to-room alignment error of two rooms that share a wall (a correct
//    pair) is |t_a - t_b|: how far one room's model sits from where the other's puts it, in
//    any direction, each face's SM3 plane error included; a shift of the whole map cancels;
//  - doors: truth doors between two evaluated rooms; a floor door matches the truth door whose
//    centre is nearest in plan within max_door_distance; a door seen from both rooms (two
//    sides) is merged correctly when its rooms are the truth door's two rooms. For each correct
//    merge, the along-wall offset between the two sides' door centres (the same hole seen from
//    each room) is a room-to-room alignment error along the wall, SM4's edge errors included.
// World frame, metres. Deterministic.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "evaluation/metrics.h"
#include "evaluation/metrics_patches.h"
#include "modelling/floor_model.h"
#include "scenes/ground_truth.h"

namespace mopad::evaluation {

struct FloorEvalParams {
  PatchMatchParams faces;  ///< matching of the floor walls' faces to the truth wall faces
  /// m, truth faces back to back at most this far apart are the two faces of one wall, (0, 2]
  double max_truth_thickness = 0.5;
  /// m, plan distance between a floor door's centre and a truth door's centre to match, (0, 5]
  double max_door_distance = 0.3;
  template <class V>
  void Visit(V& v) {
    v("faces", faces);
    v("max_truth_thickness", max_truth_thickness, Bounds{1e-3, 2.0});
    v("max_door_distance", max_door_distance, Bounds{1e-3, 5.0});
  }
};

/// The truth the floor model is scored against: the wall faces of the evaluated rooms (ids
/// "<room>/<element>") and the doors between two of them. World frame.
struct FloorTruth {
  std::vector<Patch> faces;
  std::vector<std::string> face_rooms;  ///< the truth room of each face
  struct Door {
    std::string id;
    std::vector<std::string> rooms;  ///< the two rooms, sorted
    Vec3 centre = Vec3::Zero();
  };
  std::vector<Door> doors;
};
/// InputError for an unknown room.
FloorTruth MakeFloorTruth(const scenes::GroundTruth& truth, const std::vector<std::string>& rooms);

struct FloorPairResult {
  std::string wall;              ///< floor wall id
  std::string face_a, face_b;    ///< "<robot room>/<patch>"
  std::string truth_a, truth_b;  ///< matched truth faces ("" unmatched)
  double thickness = 0.0;        ///< m, the model's
  double truth_thickness = 0.0;  ///< m, NaN when not a truth pair
  bool correct = false;
};

struct FloorDoorResult {
  std::string opening;             ///< floor opening id
  std::vector<std::string> rooms;  ///< the truth rooms of its sides
  std::string truth;               ///< matched truth door ("" none)
  double side_offset = 0.0;        ///< m, along the wall between the sides' centres (2 sides)
  bool merged = false, correct = false;
};

struct FloorRoomOffset {
  std::string room, truth_room;
  Vec2 offset = Vec2::Zero();  ///< m, world x, y
  int faces = 0;               ///< matched wall faces used
  bool solved = false;         ///< false: too few directions
};

struct FloorEvaluation {
  int walls = 0, two_sided_walls = 0;  ///< of the floor model
  PatchEvaluation faces;               ///< the floor walls' faces vs the truth wall faces
  int truth_pairs = 0;                 ///< truth faces pairs that are one physical wall
  int model_pairs = 0, correct_pairs = 0;
  int truth_pairs_found = 0;                  ///< truth pairs some correct model pair matches
  ErrorStats thickness_error;                 ///< m, over correct pairs: the alignment across walls
  std::vector<FloorRoomOffset> room_offsets;  ///< in the model's room order
  ErrorStats room_alignment;                  ///< m, |t_a - t_b| over room pairs sharing a wall
  int truth_doors = 0;                        ///< doors between two evaluated rooms
  int merged_doors = 0, merged_correct = 0;
  int one_sided_doors = 0;  ///< truth doors between two evaluated rooms found from one side only
  ErrorStats door_side_offset;  ///< m, over correct merges: the alignment along walls
  std::vector<FloorPairResult> pairs;
  std::vector<FloorDoorResult> doors;
};

/// Scores `model` (map frame; X_WM maps it into the world) against `truth`. `truth_room` maps
/// each robot room name of the model to its truth room (a room missing from it: InputError).
FloorEvaluation EvaluateFloor(const modelling::FloorModel& model, const Pose3& X_WM,
                              const std::map<std::string, std::string>& truth_room,
                              const FloorTruth& truth, const FloorEvalParams& params = {});

nlohmann::ordered_json ToJson(const FloorEvaluation& e);
std::string MarkdownFloorTable(const FloorEvaluation& e);

}  // namespace mopad::evaluation
