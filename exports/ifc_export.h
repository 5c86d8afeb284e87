#pragma once
// IFC4 (ISO 16739-1:2018) text of a BuildingModel (docs/exports.md): IfcProject -> IfcSite ->
// IfcBuilding -> IfcBuildingStorey (IfcRelAggregates), one IfcSpace per room aggregated by the
// storey; walls (IfcWall), floors (IfcSlab .FLOOR.), ceilings (IfcCovering .CEILING.), columns
// (IfcColumn), doors and windows (IfcDoor / IfcWindow filling an IfcOpeningElement that voids
// the host wall) contained in the storey; service components (ComponentIfcClass) contained in
// their room's space. Every product has a swept-solid body (IfcExtrudedAreaSolid of an
// IfcArbitraryClosedProfileDef): a wall seen from both rooms (floor/ model) its axis polygon
// extruded by its measured thickness to both sides, a wall seen from one side its SM3 polygon
// extruded away from the room by the assumed wall thickness, a slab its floor polygon extruded
// down, a covering its ceiling polygon extruded up, a column its plan hull from bottom to top, an
// opening its hole through the wall, a door or window a leaf or pane in the hole, a component its
// box (size, or a default when unknown). Property sets MoPAD_Element (every product: id, room,
// class), MoPAD_Opening (state, opening angle, clear width, confidence, host) and MoPAD_Component
// (class, alpha, found_by, host). SI units (metre, square metre, cubic metre, radian); no owner
// history (optional in IFC4). GlobalIds: io::IfcGlobalId(content key + element id): the same run
// gives the same bytes.

#include <string>

#include "common/params.h"
#include "exports/building_model.h"

namespace mopad::exports {

/// Thicknesses the model files do not carry.
struct IfcExportParams {
  /// m, walls with one face seen (no measured thickness) extruded away from the room, (0, 2]
  double wall_thickness = 0.10;
  double slab_thickness = 0.20;      ///< m, floors extruded down, (0, 2]
  double covering_thickness = 0.02;  ///< m, ceilings extruded up, (0, 1]
  double leaf_thickness = 0.04;      ///< m, door leaves (modelled closed in the hole), (0, 0.5]
  double pane_thickness = 0.02;      ///< m, window panes, (0, 0.5]
  /// m, an opening's void reaches this far past both faces, [0, 1]
  double opening_margin = 0.05;
  double default_component_size = 0.10;   ///< m, width and height when sm5 gives none, (0, 2]
  double default_component_depth = 0.02;  ///< m, depth when sm5 gives none, (0, 1]

  template <class V>
  void Visit(V& v) {
    v("wall_thickness", wall_thickness, Bounds{1e-6, 2.0});
    v("slab_thickness", slab_thickness, Bounds{1e-6, 2.0});
    v("covering_thickness", covering_thickness, Bounds{1e-6, 1.0});
    v("leaf_thickness", leaf_thickness, Bounds{1e-6, 0.5});
    v("pane_thickness", pane_thickness, Bounds{1e-6, 0.5});
    v("opening_margin", opening_margin, Bounds{0.0, 1.0});
    v("default_component_size", default_component_size, Bounds{1e-6, 2.0});
    v("default_component_depth", default_component_depth, Bounds{1e-6, 1.0});
  }
};

/// Per-class counts of what IfcText wrote (the oracle tests compare them with a reader's).
struct IfcCounts {
  int spaces = 0, walls = 0, slabs = 0, coverings = 0, columns = 0, openings = 0, doors = 0,
      windows = 0;
  std::vector<std::pair<std::string, int>> components;  ///< IFC entity -> count, sorted
};

/// The whole .ifc file. `counts`, when not null, receives the per-class counts.
std::string IfcText(const BuildingModel& model, const IfcExportParams& params = {},
                    IfcCounts* counts = nullptr);

}  // namespace mopad::exports
