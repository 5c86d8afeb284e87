#pragma once
// SM5 service components against the truth (paper §4, Table 3; metrics.md "Service
// components (SM5)").
//
// Matching: a recognised component and a truth component match when they have the same class
// and their centres lie within max_centre_distance (m, 3D). Pairs are matched one-to-one,
// nearest first (ties: truth order, then model order). Per class: N (truth count), TP, FN
// (truth not matched), FP (recognised, not matched; a right place with a wrong class counts as
// one FN and one FP), as counts and as shares of N (the paper's Table 3: FP % = FP / N);
// among the TP the shares whose alpha > 0.9 and whose alpha = 0.5.
// Centre errors of the TP on the truth host plane: horizontal along the plane's horizontal axis
// (normal x z; on a ceiling the world x axis), vertical along the plane's upward axis (on a
// ceiling the world y axis); absolute values, mean, median, max.
//
// World frame, metres. Bad input throws InputError.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/frames.h"
#include "common/params.h"
#include "evaluation/metrics.h"
#include "modelling/components.h"
#include "scenes/ground_truth.h"

namespace mopad::evaluation {

struct ComponentRecord {
  std::string id, class_name, host;
  Vec3 centre = Vec3::Zero();   ///< world frame, m
  Vec3 normal = Vec3::UnitX();  ///< out of the host surface
  double alpha = 0.0;           ///< recognised only
  std::string found_by;         ///< recognised only
};

struct ComponentMatchParams {
  double max_centre_distance = 0.05;  ///< m, (0, 1]
  template <class V>
  void Visit(V& v) {
    v("max_centre_distance", max_centre_distance, Bounds{1e-6, 1.0});
  }
};

/// One line of Table 3.
struct ComponentClassRow {
  std::string class_name;  ///< "all" for the total
  int n = 0, tp = 0, fn = 0, fp = 0;
  int tp_alpha_high = 0;  ///< TP with alpha > 0.9
  int tp_alpha_half = 0;  ///< TP with alpha = 0.5
  double Share(int x) const { return n > 0 ? static_cast<double>(x) / n : 0.0; }
};

/// One matched pair, missed truth or false component.
struct ComponentPair {
  std::string truth_id, model_id, truth_class, model_class, found_by;
  double alpha = 0.0;
  double horizontal = 0.0, vertical = 0.0;  ///< m, |error| (matched pairs only)
};

struct ComponentEvaluation {
  std::vector<ComponentClassRow> classes;  ///< by class name
  ComponentClassRow total;
  std::vector<ComponentPair> pairs;          ///< matched (truth order), missed, then false
  std::vector<double> horizontal, vertical;  ///< m, |errors| of the TP (pair order)
  ErrorStats horizontal_stats, vertical_stats;
  double horizontal_median = 0.0, vertical_median = 0.0;  ///< m (0 when no pair matched)
};

/// Matches and scores (see the file comment). InputError for a non-finite centre or bad params.
ComponentEvaluation EvaluateComponents(const std::vector<ComponentRecord>& model,
                                       const std::vector<ComponentRecord>& truth,
                                       const ComponentMatchParams& params = {});
/// Pools rooms or seeds: rows and counts summed, errors concatenated, statistics recomputed.
ComponentEvaluation PoolComponents(const std::vector<ComponentEvaluation>& parts);

/// The truth components of `room` (world frame).
std::vector<ComponentRecord> TruthComponents(const scenes::GroundTruth& truth,
                                             const std::string& room);
/// The robot's components (sm5.json, map frame) in the world.
std::vector<ComponentRecord> ModelComponents(const modelling::Sm5Model& sm5, const Pose3& X_WM);

/// JSON (keys in docs/evaluation.md, "components (SM5)").
nlohmann::json ToJson(const ComponentEvaluation& e);
/// Table 3 as text cells (the one layout the Markdown and the run's HTML report share): class,
/// N, TP %, FN %, FP %, TP alpha > 0.9 %, TP alpha = 0.5 %, TP / FN / FP; one row per class,
/// then "all"; and the centre errors on the host plane as one line.
struct ComponentTableText {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  ///< classes, then "all" last
  std::string centre_errors;
};
ComponentTableText ComponentsTable(const ComponentEvaluation& e);
/// Markdown: Table 3 (per class and all, in bold) and the centre errors.
std::string MarkdownComponentsTable(const ComponentEvaluation& e);

}  // namespace mopad::evaluation
