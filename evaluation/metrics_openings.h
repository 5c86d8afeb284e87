#pragma once
// SM4 openings against the truth (paper §4, Figure 15b, equations (2)-(3)).
//
// Matching: a recognised opening and a truth opening can match when their planes agree (normals
// within max_normal_angle_deg, the recognised rectangle's centroid within max_plane_distance of
// the truth's plane) and their rectangles overlap in the truth's plane (exact polygon
// intersection, metrics.h). Pairs are matched one-to-one, largest overlap first (ties: truth
// order, then model order).
// Areas (m^2): a matched pair gives tp = overlap, fp = recognised area - tp, fn = truth area -
// tp; a missed truth opening fn = its area; a false opening fp = its area.
// Totals: Precision = sum tp / (sum tp + sum fp) (1 when nothing was recognised), Recall = sum tp
// / (sum tp + sum fn) (1 when the truth has none). Per opening (one row per matched pair, missed
// truth and false opening): e_abs = fp + fn; e_r = (fp + fn) / (tp + fn) for rows with a truth
// opening (NaN for false openings). Reported: e_abs and e_r mean and max, fn max, fp max.
// Doors: the state confusion matrix (rows truth closed/semi_open/open, columns recognised
// closed/semi_open/open/missed — missed also when the truth door was recognised as a window),
// and the angle error |lambda - lambda_truth| (deg) of matched doors whose angle was measured:
// mean, median, max.
//
// World frame, metres; angles in degrees at this edge (`_deg`). Bad input throws InputError.

#include <array>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/door_state.h"
#include "common/frames.h"
#include "common/params.h"
#include "evaluation/metrics.h"
#include "modelling/openings.h"
#include "scenes/ground_truth.h"

namespace mopad::evaluation {

/// One opening rectangle, recognised or true: 4 corners, CCW seen from the room (from `normal`).
struct OpeningRecord {
  std::string id;
  std::string type = "door";    ///< "door" | "window"
  std::string host;             ///< wall id (reports only)
  std::vector<Vec3> corners;    ///< world frame, m, 4 corners on the wall plane
  Vec3 normal = Vec3::UnitX();  ///< into the room (need not be unit)
  std::string state;            ///< doors: "closed" | "semi_open" | "open"; "" otherwise
  double angle_deg = std::numeric_limits<double>::quiet_NaN();  ///< doors: lambda; NaN unknown
};

struct OpeningMatchParams {
  double max_plane_distance = 0.30;    ///< m, recognised centroid to truth plane, (0, 5]
  double max_normal_angle_deg = 15.0;  ///< deg, between the normals, (0, 90]
  template <class V>
  void Visit(V& v) {
    v("max_plane_distance", max_plane_distance, Bounds{1e-6, 5.0});
    v("max_normal_angle_deg", max_normal_angle_deg, Bounds{1e-6, 90.0});
  }
};

/// One row of the per-opening table.
struct OpeningRow {
  std::string truth_id, model_id;                                 ///< "" when missing on that side
  std::string truth_type, model_type;                             ///< "door" | "window" | ""
  double truth_area = 0, model_area = 0, tp = 0, fp = 0, fn = 0;  ///< m^2
  double e_abs = 0;                                               ///< m^2, fp + fn
  double e_r = std::numeric_limits<double>::quiet_NaN();          ///< (fp + fn) / (tp + fn)
  std::string truth_state, model_state;                           ///< doors only
  double truth_angle_deg = std::numeric_limits<double>::quiet_NaN();
  double model_angle_deg = std::numeric_limits<double>::quiet_NaN();
  double angle_error_deg = std::numeric_limits<double>::quiet_NaN();
};

using mopad::kDoorStateNames;  // common/door_state.h

struct OpeningEvaluation {
  std::vector<OpeningRow> rows;  ///< truth order (matched or missed), then false openings
  int truth_count = 0, model_count = 0, matched = 0, missed = 0, false_openings = 0;
  int type_right = 0;             ///< matched pairs of the same type
  double tp = 0, fp = 0, fn = 0;  ///< m^2, sums
  double precision = 1.0, recall = 1.0;
  ErrorStats e_abs;               ///< m^2, over every row
  ErrorStats e_r;                 ///< over rows with a truth opening
  double fn_max = 0, fp_max = 0;  ///< m^2
  /// [truth state][recognised closed, semi_open, open, missed] counts of truth doors.
  std::array<std::array<int, 4>, 3> state_confusion{};
  int doors = 0, door_state_right = 0;
  ErrorStats angle_error;         ///< deg
  double angle_error_median = 0;  ///< deg (0 when no angle was compared)
};

/// Matches and scores (see the file comment). InputError for a record without 4 finite corners,
/// an unknown type or state, or bad params.
OpeningEvaluation EvaluateOpenings(const std::vector<OpeningRecord>& model,
                                   const std::vector<OpeningRecord>& truth,
                                   const OpeningMatchParams& params = {});

/// Pools rooms (or seeds): rows concatenated, counts, areas, confusion and angle errors summed,
/// Precision/Recall/e_abs/e_r/fn max/fp max/median recomputed over the pooled rows.
OpeningEvaluation PoolOpenings(const std::vector<OpeningEvaluation>& parts);

/// The truth openings of `room`: every door and window hosted by one of the room's walls, its
/// rectangle in that wall's plane (clipped to the wall), normal into the room, state and lambda
/// for doors. InputError for an unknown room.
std::vector<OpeningRecord> TruthOpenings(const scenes::GroundTruth& truth, const std::string& room);

/// The robot's openings (sm4.json, map frame) in the world: corners mapped by X_WM, normal from
/// the corners' winding.
std::vector<OpeningRecord> ModelOpenings(const modelling::Sm4Model& sm4, const Pose3& X_WM);

/// JSON of the evaluation (keys in docs/evaluation.md, "openings (SM4)"); NaN becomes null.
nlohmann::json ToJson(const OpeningEvaluation& e);
/// Markdown: the summary (Precision, Recall, e_abs, e_r, fn/fp max, states, angle errors), the
/// door-state confusion matrix and the per-opening table.
std::string MarkdownOpeningsTable(const OpeningEvaluation& e);

}  // namespace mopad::evaluation
