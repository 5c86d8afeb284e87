#pragma once
// What the exports read from a run folder (`mopad run -o DIR`, docs/exports.md): per room
// DIR/rooms/<ID>/ the model files (sm3.json, and when present sm4.json, sm5.json, sm1.ply,
// scans.json, run.json) and, when a floor mission wrote it, DIR/floor/ with floor-level models in
// the same formats. A folder of one room (`mopad room -o DIR`: sm3.json beside run.json) is read
// as a run of that room.
//
// Frames: every model file is in its room's map frame M. The export frame E is the map frame of
// the first room (by id). Rooms that share one map frame (the floor mission) are exported as they
// are; a room with its own map frame is placed into E with the run.json poses X_WM
// (X_EM = X_WM(first)^-1 X_WM(room)) — the harness's record of where each room's map sits, not
// something the robot estimated (RunFolder::placed_by_run_json says when this happened).
//
// Errors: InputError naming the file for a missing folder, no room with an sm3.json, a malformed
// file. A missing optional file (sm4, sm5, sm1, scans.json) only leaves its part out.

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "modelling/openings.h"
#include "modelling/structural_model.h"

namespace mopad::exports {

/// One service component of sm5.json (SM5; docs/models.md): map frame, metres.
struct ServiceComponent {
  std::string id;          ///< "component_1", unique in its room
  std::string class_name;  ///< catalogue class ("socket_x2", "smoke_detector", ...)
  std::string host;        ///< SM3 patch id it is mounted on ("" unknown)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();   ///< m
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, out of the host surface
  Eigen::Vector3d size = Eigen::Vector3d::Zero();     ///< m: width, height, depth (0 = unknown)
  double alpha = 0.0;                                 ///< detection score alpha, [0, 1]
  std::string found_by;                               ///< detection path ("image", "geometry", ...)
};

struct Sm5Model {
  std::string room;
  std::vector<ServiceComponent> components;
};

/// Parses sm5.json ({"format": "mopad-sm5", "version": 1, "room", "components": [{"id",
/// "class", "host", "centre", "normal", "size", "alpha", "found_by"}]}); `size` may hold 2 or 3
/// numbers, `host` and `found_by` may be absent. InputError naming the field otherwise.
Sm5Model ParseSm5(const std::string& text, const std::string& where);

/// The models of one room (or of the floor) in the export frame.
struct ModelSet {
  std::string id;                                          ///< room id ("R1"), or "floor"
  std::string dir;                                         ///< folder holding the files
  Eigen::Isometry3d X_EM = Eigen::Isometry3d::Identity();  ///< this set's map frame -> export
  modelling::StructuralModel sm3;
  std::optional<modelling::Sm4Model> sm4;
  std::optional<Sm5Model> sm5;
  std::string sm1_path;            ///< "" when absent
  std::vector<double> scan_times;  ///< s, sim time of scan i (scans.json); empty when absent
  /// floor/sm3.json: measured thickness (m) of each two-sided floor wall, by patch id; a wall
  /// not listed has one face (its other side unknown)
  std::map<std::string, double> wall_thickness;
};

struct RunFolder {
  std::string dir;
  std::vector<ModelSet> rooms;      ///< sorted by id
  std::optional<ModelSet> floor;    ///< DIR/floor/sm3.json present: the elements come from here
  bool placed_by_run_json = false;  ///< some room was placed with X_WM (see the file comment)
  /// The export frame in the world: the first room's run.json X_WM (absent without one). Only
  /// for drawing the truth beside the model (the report); the exports never use it.
  std::optional<Eigen::Isometry3d> X_WE;
  std::string content_key;  ///< hash of every model file's bytes: seeds the IFC GlobalIds
};

/// Reads the run folder `dir` (see the file comment).
RunFolder ReadRunFolder(const std::string& dir);

}  // namespace mopad::exports
