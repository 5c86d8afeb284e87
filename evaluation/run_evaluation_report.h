#pragma once
// What EvaluateRun's two halves share (internal to the evaluation library): its parameters, one
// room's scores, the figures pooled over the rooms (evaluation/run_evaluation.cpp makes them)
// and the writers of its outputs (evaluation/run_evaluation_report.cpp): evaluation.json,
// evaluation.md, each room's isprs_<room>.svg and dsm3_truth_<room>.ply, and the tables `mopad
// eval` prints. Every figure is described in docs/evaluation.md; lengths are metres, angles
// degrees, the frame the world's unless noted.

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/params.h"
#include "evaluation/metrics_components.h"
#include "evaluation/metrics_floor.h"
#include "evaluation/metrics_floorplan.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_openings.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"
#include "evaluation/model_files.h"
#include "evaluation/truth_models.h"
#include "scenes/ground_truth.h"

namespace mopad::evaluation {

/// `mopad eval --config`: one field per metric family (eval.effective.yaml is this struct).
struct EvalParams {
  PatchMatchParams patches;
  ColumnMatchParams columns;
  IsprsParams isprs;
  FloorplanParams floorplan;
  TruthDsm3Params dsm3;
  OpeningMatchParams openings;
  ComponentMatchParams components;
  FloorEvalParams floor;
  double report_buffer = 0.05;  ///< m, ISPRS buffer of the summary and tables, [0, 1]
  template <class V>
  void Visit(V& v) {
    v("patches", patches);
    v("columns", columns);
    v("isprs", isprs);
    v("floorplan", floorplan);
    v("dsm3", dsm3);
    v("openings", openings);
    v("components", components);
    v("floor", floor);
    v("report_buffer", report_buffer, Bounds{0.0, 1.0});
  }
};

/// One room's models against its truth.
struct RoomResult {
  RunInfo run;
  std::string model_room;                      ///< the robot's name of the room (sm3.json "room")
  const scenes::GroundTruth* truth = nullptr;  ///< open-plan rooms merged (MergeOpenPlanRooms)
  std::string truth_room;                      ///< run.room's room in *truth
  std::vector<std::string> joined;             ///< the sidecar rooms it stands for, when merged
  std::size_t model_patches = 0;
  /// Walls, floors, ceilings patch by patch; the column row of `detection` counts the column
  /// objects of `columns`.
  PatchEvaluation patches;
  /// The same patches against the as-built truth (scenes::AsBuiltTruth), when the scene's
  /// truth records an as-built field; none otherwise.
  std::optional<PatchEvaluation> patches_as_built;
  ColumnEvaluation columns;
  IsprsResult isprs;
  std::optional<Room> floor;  ///< the largest SM3 floor in the world plan; none: no floor
  bool has_dsm3 = false;      ///< false: the run wrote no dsm3.ply, the DSM3 fields are empty
  std::vector<std::uint8_t> dsm3_truth, dsm3_pred;  ///< one label per voxel of dsm3_voxels
  Dsm3Voxels dsm3_voxels;                           ///< the robot's grid and voxel list
  ConfusionMatrix dsm3;
  std::size_t scanners = 0;                       ///< scanner positions of the truth DSM3
  std::optional<nlohmann::ordered_json> mission;  ///< the run's own evaluation.json
  std::optional<OpeningEvaluation> openings;      ///< SM4, when the run wrote sm4.json
  std::optional<ComponentEvaluation> components;  ///< SM5, when the run wrote sm5.json
};

/// A scene built off its design (scenes/as_built.h): the models scored against the as-built
/// surfaces, and how far the truth's surfaces depart from their design planes.
struct AsBuiltFigures {
  PatchEvaluation patches;  ///< walls, floors, ceilings against the as-built truth
  struct Deviation {
    int elements = 0;
    double rms_mm = 0.0;         ///< mm, mean over the elements of each one's rms normal offset
    double max_mm = 0.0;         ///< mm, largest normal offset of any element
    double tilt_mean_deg = 0.0;  ///< deg, best-fit plane against the design plane
    double tilt_max_deg = 0.0;
  };
  Deviation wall, floor, ceiling;  ///< over the truth's elements of the scored rooms
};

/// The missions' own figures (per-pulse truth during the run) pooled over the rooms; NaN where
/// no room reported one.
struct MissionFigures {
  double coverage_min = NAN;       ///< smallest coverage of the observable area, [0, 1]
  double translation_max_m = NAN;  ///< largest registration translation error, m
  double rotation_max_deg = NAN;   ///< largest registration rotation error, deg
  double sm1_points = 0;           ///< SM1 points with a truth label
  double sm1_correct = 0;          ///< of those, labelled correctly
};

/// The figures of all rooms together.
struct PooledFigures {
  /// Walls, floors, ceilings; the column row of `detection` counts column objects.
  PatchEvaluation patches;
  ColumnEvaluation columns;
  bool any_dsm3 = false;  ///< false: no room has a DSM3, `dsm3` is empty
  ConfusionMatrix dsm3;
  /// The "all" ISPRS curve at EvalParams::report_buffer, area-weighted over the rooms.
  double isprs_completeness = NAN, isprs_correctness = NAN;
  FloorplanResult floorplan;             ///< every room's SM3 floor against the truth rooms
  std::optional<FloorEvaluation> floor;  ///< the floor model (RUN_DIR/floor/); none: absent
  MissionFigures mission;
  std::optional<OpeningEvaluation> openings;      ///< none: no room has SM4
  std::optional<ComponentEvaluation> components;  ///< none: no room has SM5
  std::optional<AsBuiltFigures> as_built;         ///< none: the scene is its design
};

/// `mission`[key] (or [key][sub]) as a number; NaN when absent or not a number.
double MissionNumber(const std::optional<nlohmann::ordered_json>& mission, const char* key,
                     const char* sub = nullptr);

/// evaluation.json: format, the run, "summary" (the pooled figures), per room, floorplan, DSM3
/// of all rooms and the floor model. `truth_file` "" means each scene's own sidecar.
nlohmann::ordered_json EvaluationJson(const std::string& run_dir, const std::string& truth_file,
                                      const EvalParams& params,
                                      const std::vector<RoomResult>& rooms,
                                      const PooledFigures& pooled,
                                      const std::vector<std::string>& truth_notes);

/// evaluation.md: a table of every room and all, then the pooled and per-room sections.
std::string EvaluationMarkdown(const std::string& run_dir, const EvalParams& params,
                               const std::vector<RoomResult>& rooms, const PooledFigures& pooled,
                               const std::vector<std::string>& truth_notes);

/// Writes per room `dir`/isprs_<room>.svg and, with a DSM3, `dir`/dsm3_truth_<room>.ply (the
/// truth DSM3 in dsm3.ply's format). InputError when a PLY cannot be written.
void WriteRoomFiles(const std::string& dir, const std::vector<RoomResult>& rooms);

/// The tables `mopad eval` prints: one line per room and all, then the columns, floorplan and
/// floor model lines, and where the files went (`dir`).
std::string PrintedTables(const EvalParams& params, const std::vector<RoomResult>& rooms,
                          const PooledFigures& pooled, const std::string& dir);

}  // namespace mopad::evaluation
