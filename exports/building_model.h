#pragma once
// The building the exports write, gathered from a run folder (RunFolder) in the export frame E
// (z up, metres): one Space per room and one Element per wall, floor, ceiling, column, opening
// (door or window) and service component. Both the IFC and the glTF export walk this list, so
// their element counts and ids agree. Ids are "<set>/<file id>" ("R1/wall_3", "R1/column_2",
// "floor/opening_4"). Elements come from DIR/floor/ when a floor model exists, else from the
// rooms; spaces always come from the rooms' SM3 floors. Order: the files' order, room by room.
// Deterministic; no I/O.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "exports/run_folder.h"

namespace mopad::exports {

enum class ElementKind { kWall, kFloor, kCeiling, kColumn, kDoor, kWindow, kComponent };
const char* ToString(ElementKind kind);

/// The IFC4 entity and predefined type a service-component class maps to (docs/exports.md):
/// sockets IfcOutlet, switch IfcSwitchingDevice, smoke_detector IfcSensor, fire_alarm_switch
/// IfcAlarm, fire_extinguisher IfcFireSuppressionTerminal, exit/emergency lights
/// IfcLightFixture, radiator IfcSpaceHeater, electrical_panel IfcElectricDistributionBoard,
/// anything else IfcBuildingElementProxy (USERDEFINED, the class name as ObjectType).
struct IfcClassOf {
  std::string entity;           ///< "IfcOutlet"
  std::string predefined_type;  ///< "POWEROUTLET"
};
IfcClassOf ComponentIfcClass(const std::string& class_name);

struct Element {
  std::string id;          ///< unique: "R1/wall_3"
  std::string room;        ///< room id, "floor" for floor-level elements
  std::string class_name;  ///< wall, floor, ceiling, column, door, window or the SM5 class
  ElementKind kind = ElementKind::kWall;
  /// Walls, floors, ceilings, openings: the surface polygon (CCW seen from the room). Columns:
  /// the footprint at z0 (CCW seen from above). Components: unused.
  std::vector<Eigen::Vector3d> polygon;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, into the room (off the host)
  double z0 = 0.0, z1 = 0.0;                          ///< m, columns: bottom and top
  int host = -1;  ///< openings, components: index of the host element (-1 none)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< components: m
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    ///< components: width, height, depth (m)
  double width = 0.0, height = 0.0;                  ///< openings: m
  nlohmann::ordered_json properties = nlohmann::ordered_json::object();  ///< file figures
};

struct Space {
  std::string room;
  std::vector<Eigen::Vector3d> footprint;  ///< the SM3 floor polygon (CCW seen from above)
  double z0 = 0.0, z1 = 0.0;               ///< m, floor and ceiling
};

struct BuildingModel {
  std::string name;         ///< "OpenMoPAD run" (no path: the same run gives the same bytes)
  std::string content_key;  ///< RunFolder::content_key
  std::string frame_note;   ///< one sentence on the export frame (docs/exports.md)
  std::vector<Space> spaces;
  std::vector<Element> elements;
};

/// Builds the model of `run`. Patches whose polygon is degenerate (area below 1e-6 m^2) are left
/// out; an opening or component whose host is not found keeps host -1.
BuildingModel BuildBuildingModel(const RunFolder& run);

}  // namespace mopad::exports
