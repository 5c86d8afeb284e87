#pragma once
// The robot's floor mission (paper §2, Figures 3-5): one robot explores a building floor room
// by room from where it stands, building the Dynamic Traversal Tree (autonomy/traversal_tree.h)
// as it goes:
//
//   room loop (autonomy/room_scan.h) in the start room -> SM3, SM4 -> its doors into space no
//   visited room covers become children (passable) or leaves (closed, too narrow); so do the
//   gaps in its walls that the obstacle map saw through and SM4 did not model
//   loop: nearest unvisited child of the current node (route length in the robot's map)
//         -> drive in front of its door, scan (door scan 1) -> drive just beyond the door frame
//         -> room loop there (its first scan is door scan 2) -> SM3, SM4 -> children
//         none left: drive back through the entry door to the parent; at the root: done.
//
// Doors change while the robot works (someone shuts one): each door's doorway is measured in
// the obstacle map when the door is found (autonomy/doorway.h) and again after the door scan,
// when a drive through it fails, and when the way back fails. A doorway the map showed passable
// that is blocked now is a door closed since it was mapped: not entered, explained, and the
// robot goes on with the other doors; shut behind it, the robot is shut in and the mission ends
// there, explained.
//
// One navigator throughout (one map frame, no teleports). Every scan the mission uses is
// registered against all earlier ones (the floor's S(t-1)): the door scan in front of the frame
// as a scan of the room it stands in, the room's first scan beyond it as a door scan
// (RoomScanParams::entry_icp), so each room is tied to the rooms before it through the doors. A
// room whose modelling fails is recorded with its reason and the mission goes on.
//
// A room's SM5 runs beside the robot's next steps (autonomy/background_sm5.h): the robot
// decides nothing from it. It is in FloorScanResult::rooms when RunFloorScan returns, not yet
// in the RoomVisit handed to FloorScanHooks::room_done.
//
// Robot side only: it drives an autonomy::Navigator and sees nothing of the world.
// Deterministic: same platform behaviour + params -> same decisions and outputs.

#include <functional>
#include <string>
#include <vector>

#include "autonomy/background_sm5.h"
#include "autonomy/doorway.h"
#include "autonomy/navigator.h"
#include "autonomy/room_scan.h"
#include "autonomy/traversal_tree.h"
#include "autonomy/wall_gaps.h"
#include "common/params.h"
#include "modelling/room_models.h"

namespace mopad::autonomy {

struct FloorScanParams {
  /// m, base centre in front of a door's wall plane for the scan before the frame, [0.3, 5]
  double door_approach = 1.0;
  /// m, base centre beyond the door's wall plane (the wall's thickness included) for the scan
  /// after the frame: the new room's first scan, [0.3, 5]
  double door_exit = 1.3;
  /// m, door scan poses move at most this far from their nominal place to find clearance, [0, 3]
  double door_pose_search = 0.6;
  /// m, clearance of door scan poses to known obstacles (unknown counts as obstacle), [0, 3]
  double door_pose_clearance = 0.45;
  /// m, doors narrower than this (SM4 clear width, or the gap in the robot's map) are not
  /// entered: the base's width (0.5 m) plus the local controller's safety margins (2 x 0.03 m)
  /// plus 2 x 0.04 m for the width's measurement error, [0, 5]
  double min_clear_width = 0.64;
  /// m, a door leads to explored space when the point this far beyond its wall plane lies in
  /// a visited room's perimeter, [0.1, 5]
  double beyond_probe = 0.6;
  int max_rooms = 64;  ///< rooms visited at most (the mission ends there, explained), [1, 10000]
  /// A door through which at least this share of the rays that rose through it returned
  /// nothing (SM4's sky_share: no ceiling or walls above its far side) leads outside and is not
  /// entered, [0, 1]; indoors the share is near 0, outdoors near 1
  double outside_sky_share = 0.5;
  /// Doorways SM4 did not model: gaps in the room's walls its map saw through (wall_gaps.h)
  WallGapParams gaps;
  /// A doorway's clear width in the obstacle map (doorway.h): a door whose doorway the map
  /// showed at least min_clear_width wide when it was found, and narrower when the robot comes
  /// to pass it, was closed since it was mapped
  DoorwayParams doorway;

  template <class V>
  void Visit(V& v) {
    v("door_approach", door_approach, Bounds{0.3, 5.0});
    v("door_exit", door_exit, Bounds{0.3, 5.0});
    v("door_pose_search", door_pose_search, Bounds{0.0, 3.0});
    v("door_pose_clearance", door_pose_clearance, Bounds{0.0, 3.0});
    v("min_clear_width", min_clear_width, Bounds{0.0, 5.0});
    v("beyond_probe", beyond_probe, Bounds{0.1, 5.0});
    v("max_rooms", max_rooms, Bounds{1, 10000});
    v("outside_sky_share", outside_sky_share, Bounds{0.0, 1.0});
    v("gaps", gaps);
    v("doorway", doorway);
  }
};

/// One TLS scan of the mission that is not a room-loop scan of the room model.
struct DoorScan {
  int index = -1;         ///< the navigator's scan index
  double sim_time = 0.0;  ///< s
  Pose3 X_MS = Pose3::Identity();
  /// The room whose scans it is listed with: the room it led into, or the room that found the
  /// door when the robot could not pass it.
  std::string room;
};

/// A room as the floor mission saw it, handed to RoomDone before the room model is dropped.
struct RoomVisit {
  int node = -1;
  std::string room;           ///< the robot's name: "room_<visit order + 1>"
  DoorScan door_scan_before;  ///< index -1 for the start room
  RoomScanResult scan;        ///< the room loop's log (its first scan is door scan 2)
  const modelling::RoomModel* model = nullptr;
  modelling::RoomModels models;  ///< SM3, SM4, DSM3 (SM5 follows: FloorRoom::sm5)
  std::vector<std::pair<std::string, modelling::Orthoimage>> images;  ///< wall orthoimages
  std::string error;  ///< non-empty: modelling failed; the room has no models
};

/// What the mission's owner hears (all optional).
struct FloorScanHooks {
  /// Before the room loop of a room starts (the robot stands where its first scan is taken).
  std::function<void(const std::string& room)> room_started;
  /// Every scan the room model accepted (as autonomy::ScanHook).
  std::function<void(const std::string& room, int index, const interfaces::TlsScan& scan)> scan;
  /// A room finished (models built, or the error).
  std::function<void(const RoomVisit& visit)> room_done;
  /// The points of a finished room's model (RoomModel::Points(), same order and values), read
  /// back from where room_done stored them. When set, the mission keeps no room's points in
  /// memory (the end-of-mission door pass reads them back one room at a time).
  std::function<std::vector<Eigen::Vector3f>(const std::string& room)> room_points;
  /// One line of what the robot is doing, for a person.
  std::function<void(const std::string& line)> progress;
  /// Asked before each room: true ends the mission there, explained (an operator's stop).
  std::function<bool()> stop_requested;
};

/// A visited room, as kept after its visit.
struct FloorRoom {
  int node = -1;
  std::string room;
  int scans = 0;  ///< room-loop scans taken (door scan 2 included)
  std::string stop_reason;
  double coverage = 0.0;        ///< the robot's own estimate after the last scan
  std::vector<Vec2> perimeter;  ///< map frame plan polygon (empty when modelling failed)
  modelling::StructuralModel sm3;
  modelling::Sm4Model sm4;
  modelling::Sm5Model sm5;   ///< empty without a recogniser or when sm5_error is set
  double sm5_seconds = 0.0;  ///< s of wall time of SM5 (reporting only)
  std::string error;
  /// Non-empty: SM5 failed with this message (the room keeps SM3 and SM4 and its doors)
  std::string sm5_error;
  /// Doors added to sm4 at the mission's end from rooms modelled after this one
  /// (modelling::AddDoorsFromNeighbours).
  int doors_from_later_rooms = 0;
  /// SM1 points in the height band of door leaves and lintels (floor + leaf_v_low *
  /// door_min_height to floor + door_max_height + lintel_search), kept for that pass only
  /// (and only without FloorScanHooks::room_points; then read back for it).
  std::vector<Eigen::Vector3f> leaf_points;
  double leaf_z0 = 0.0, leaf_z1 = 0.0;  ///< m, map z: that band
};

struct FloorScanResult {
  TraversalTree tree;
  std::vector<FloorRoom> rooms;  ///< in visit order
  std::vector<DoorScan> door_scans;
  /// Drives that failed outside a room loop and doors found closed since they were mapped,
  /// one line each
  std::vector<std::string> events;
  std::string end_reason;  ///< why the mission ended
  int scans = 0;           ///< TLS scans of the whole mission
  double sim_time = 0.0, wall_time = 0.0;
};

/// `recogniser` (optional): SM5's, trained from the robot's catalogue of object models; asked
/// for when the first room's SM5 starts, on the thread that runs it.
FloorScanResult RunFloorScan(Navigator& navigator, const RoomScanParams& room_params,
                             const FloorScanParams& params, const FloorScanHooks& hooks = {},
                             const RecogniserSource& recogniser = {});

/// The door of `o` (a door of SM4) as the floor mission uses it.
DoorRecord DoorOf(const modelling::DetectedOpening& o, const std::string& room);

}  // namespace mopad::autonomy
