#pragma once
// Coverage of a room's structural surfaces by the robot's points: a cell
// (evaluation/truth_surfaces.h) is *sensed* when some robot point, mapped to the world with
// X_WM, lies within `distance_tolerance` of the cell's plane and its projection falls in the
// cell's square. Reported as the sensed share of the observable area
// (evaluation/observability.h) and of the total structural area, for the room, per class and per
// element. A partial cell (cut by an opening) counts as sensed when a point lands anywhere in its
// square. Metres, m^2; shares in [0, 1] (0 when the denominator is 0).
//
// Both shares count only cells that are sensed *and* observable: points of thin things standing
// within the tolerance of a wall (door and window casings, shelf backs, flush BSCs) fall on the
// wall cells they hide, and those cells cannot have been seen. `sensed_area` keeps the raw
// figure (about 1.5 % above sensed_observable_area in office_5rooms' R1).

#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "evaluation/truth_surfaces.h"

namespace mopad::evaluation {

struct CoverageParams {
  double distance_tolerance = 0.03;  ///< m, point-to-plane distance that counts, [0, 1]
  template <class V>
  void Visit(V& v) {
    v("distance_tolerance", distance_tolerance, Bounds{0.0, 1.0});
  }
};

/// Areas of one group of cells (the room, a class or an element), m^2.
struct CoverageFigures {
  std::string name;  ///< "room" id, class name ("wall") or element id
  double total_area = 0.0;
  double observable_area = 0.0;
  double sensed_area = 0.0;             ///< sensed cells, observable or not (raw)
  double sensed_observable_area = 0.0;  ///< sensed cells that are observable
  double ShareOfObservable() const {
    return observable_area > 0 ? sensed_observable_area / observable_area : 0.0;
  }
  double ShareOfTotal() const { return total_area > 0 ? sensed_observable_area / total_area : 0.0; }
};

struct CoverageReport {
  CoverageFigures room;
  std::vector<CoverageFigures> per_class;    ///< wall, floor, ceiling, column (classes present)
  std::vector<CoverageFigures> per_element;  ///< StructuralSurfaces::elements order
  std::uint64_t points = 0;                  ///< points given
  std::uint64_t points_on_cells = 0;         ///< points that fell on some cell
};

/// One flag per cell: 1 when a point p_M (robot map frame) maps into it. Parallel,
/// deterministic.
std::vector<std::uint8_t> SensedCells(const StructuralSurfaces& surfaces,
                                      std::span<const Eigen::Vector3f> p_M, const Pose3& X_WM,
                                      const CoverageParams& params = {},
                                      std::uint64_t* points_on_cells = nullptr);

/// Area figures from per-cell flags (`observable` as from ComputeObservability; empty = all
/// cells observable). InputError when a flag vector has the wrong size.
CoverageReport SummariseCoverage(const StructuralSurfaces& surfaces,
                                 const std::vector<std::uint8_t>& observable,
                                 const std::vector<std::uint8_t>& sensed);

/// SensedCells + SummariseCoverage.
CoverageReport ComputeCoverage(const StructuralSurfaces& surfaces,
                               const std::vector<std::uint8_t>& observable,
                               std::span<const Eigen::Vector3f> p_M, const Pose3& X_WM,
                               const CoverageParams& params = {});

/// Reads the points of a PLY (io::ReadPly: x y z in the map frame) and computes coverage.
CoverageReport ComputeCoverageFromPly(const StructuralSurfaces& surfaces,
                                      const std::vector<std::uint8_t>& observable,
                                      const std::string& ply_path, const Pose3& X_WM,
                                      const CoverageParams& params = {});

/// Deterministic pretty JSON: {"room": {...}, "per_class": [...], "per_element": [...],
/// "points": n, "points_on_cells": n}; each figure has name, total_area_m2, observable_area_m2,
/// sensed_area_m2, sensed_observable_area_m2, share_of_observable, share_of_total.
nlohmann::ordered_json CoverageJson(const CoverageReport& report);
/// CoverageJson's text (2-space indent, a final newline).
std::string CoverageToJson(const CoverageReport& report);

}  // namespace mopad::evaluation
