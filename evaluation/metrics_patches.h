#pragma once
// SM3 structural-element metrics of the MoPAD paper (§4, Figure 15a): detection TP/FP/FN per
// class, edge-length errors d_v and d_h, orientation error Phi.
//
// Matching. A model patch m and a truth patch t are candidates when they have the same class,
// the angle between their normals is <= max_normal_angle_deg (oriented normals unless
// `oriented_normals` is false), the model's vertex centroid lies within max_plane_distance of
// the truth plane, and the IoU of the two polygons in the truth plane (model projected
// orthogonally onto it) is >= min_overlap_iou. Per class, a Hungarian assignment minimises the
// sum of (1 - IoU) over candidates; assigned pairs are TP, the other model patches FP, the other
// truth patches FN.
//
// d_v, d_h (per matched pair). Both polygons are simplified (collinear vertices within
// collinear_tolerance_deg dropped, so a wall cut into collinear pieces has one edge per side).
// An edge is vertical when its direction is within edge_angle_tolerance_deg of world z,
// horizontal when within that angle of the horizontal plane; slanted edges are ignored. Edges of
// one category are paired model <-> truth by a Hungarian assignment on the distance between edge
// midpoints (for rectangles: left-left, right-right, bottom-bottom, top-top); each pair gives the
// error |length_model - length_truth|; edges left unpaired (different edge counts) are counted in
// `unpaired_edges` and give no error. A patch's d_v (d_h) is the mean over its vertical
// (horizontal) pairs. Floors and ceilings have only horizontal edges: their d_h is reported per
// class but, as in the paper (Figure 15a shows walls), the overall d_v/d_h figures aggregate
// walls and columns only. Aggregates: mean and max over all edge pairs. `mopad eval` passes
// walls, floors and ceilings only and scores columns as objects (EvaluateColumns below), so its
// figures are the walls' (docs/evaluation.md).
//
// Phi (per matched pair): angle between the normals in degrees, computed with atan2 for
// precision at small angles (unoriented: the smaller of a and 180 - a). Aggregates over all
// classes and per class.

#include <array>
#include <string>
#include <vector>

#include "evaluation/metrics.h"

namespace mopad::evaluation {

struct PatchMatchParams {
  double max_normal_angle_deg = 10.0;      ///< deg, candidate pairs' normal angle, (0, 90]
  double max_plane_distance = 0.20;        ///< m, model centroid to truth plane, (0, 10]
  double min_overlap_iou = 0.20;           ///< IoU in the truth plane needed to match, (0, 1]
  bool oriented_normals = true;            ///< false: a normal and its opposite are the same plane
  double edge_angle_tolerance_deg = 10.0;  ///< deg, vertical/horizontal edge test, (0, 45)
  double collinear_tolerance_deg = 1.0;    ///< deg, merge of collinear edges, [0, 10]
  PatchValidationParams validation;

  template <class V>
  void Visit(V& v) {
    v("max_normal_angle_deg", max_normal_angle_deg, Bounds{1e-6, 90.0});
    v("max_plane_distance", max_plane_distance, Bounds{1e-6, 10.0});
    v("min_overlap_iou", min_overlap_iou, Bounds{1e-6, 1.0});
    v("oriented_normals", oriented_normals);
    v("edge_angle_tolerance_deg", edge_angle_tolerance_deg, Bounds{1e-6, 45.0 - 1e-6});
    v("collinear_tolerance_deg", collinear_tolerance_deg, Bounds{0.0, 10.0});
    v("validation", validation);
  }
};

/// One matched model/truth patch pair (a true positive) and its accuracy.
struct PatchPair {
  int model_index = -1;  ///< into the model patch vector
  int truth_index = -1;  ///< into the truth patch vector
  std::string model_id, truth_id;
  SurfaceClass cls = SurfaceClass::kWall;
  double iou = 0.0;             ///< overlap in the truth plane
  double plane_distance = 0.0;  ///< m, model centroid to truth plane
  double phi_deg = 0.0;         ///< orientation error
  ErrorStats d_v;               ///< over this patch's vertical edge pairs, m
  ErrorStats d_h;               ///< over this patch's horizontal edge pairs, m
  int unpaired_edges = 0;       ///< vertical/horizontal edges without a partner (both sides)
};

struct ClassDetection {
  int n_truth = 0, n_model = 0;
  int tp = 0, fp = 0, fn = 0;
  double Recall() const;     ///< tp / n_truth (the paper's recognition rate); NaN if no truth
  double Precision() const;  ///< tp / n_model; NaN if no model patch
};

struct ClassAccuracy {
  ErrorStats d_v, d_h, phi_deg;  ///< d_v, d_h over edge pairs (m); Phi over pairs (deg)
};

struct PatchEvaluation {
  std::vector<PatchPair> pairs;                              ///< by class, then truth index
  std::vector<int> unmatched_model;                          ///< FP model patch indices, ascending
  std::vector<int> unmatched_truth;                          ///< FN truth patch indices, ascending
  std::array<ClassDetection, kNumSurfaceClasses> detection;  ///< indexed by SurfaceClass
  std::array<ClassAccuracy, kNumSurfaceClasses> accuracy;
  ErrorStats d_v, d_h;  ///< paper figures: walls and columns, over edge pairs, m
  ErrorStats phi_deg;   ///< all classes, over matched pairs
  std::vector<std::string> unmatched_model_ids, unmatched_truth_ids;
};

/// Matches `model` against `truth` and computes the SM3 metrics. Validates every patch first
/// (InputError on bad input, naming the patch). Deterministic; O(N^2) candidate tests per class.
PatchEvaluation EvaluatePatches(const std::vector<Patch>& model, const std::vector<Patch>& truth,
                                const PatchMatchParams& params = {});

/// Orientation error in degrees between two normals (not necessarily unit).
double NormalAngleDeg(const Vec3& a, const Vec3& b, bool oriented);

// ---- Columns as objects (as BIM scores columns) ----
//
// A column is one object, not a set of faces: a round column's truth has 16 narrow facets that a
// model need not reproduce one by one. A column object is its vertical faces, its plan footprint
// (the convex hull of every face vertex projected on x-y; columns are convex prisms) and its
// height range. Model columns are the model patches of class column grouped by the id prefix
// `column_N_` (SM3 names them column_N_face_k); truth columns come from the sidecar
// (TruthColumns in truth_models.h).
//
// Matching: a model and a truth column are candidates when their footprints' plan IoU is
// > min_plan_iou (0.5); a Hungarian assignment on 1 - IoU pairs them one-to-one: TP pairs, the
// other model columns FP, the other truth columns FN. Per TP pair: plan IoU, centre error (plan
// distance between the footprints' area centroids), footprint area error |A_m - A_t| and
// equivalent-diameter error |2 sqrt(A_m/pi) - 2 sqrt(A_t/pi)|, height error |h_m - h_t| with
// h = z_max - z_min. Face accuracy (d_v, d_h, Phi by EvaluatePatches with `faces` params) is
// computed only for pairs whose truth column is polygonal (at most max_polygonal_faces faces,
// e.g. a square column's 4), where a face-to-face pairing is meaningful; round columns get none.

struct ColumnMatchParams {
  double min_plan_iou = 0.5;  ///< footprint IoU a match needs (strictly more), [0, 1)
  int max_polygonal_faces =
      8;  ///< truth columns with more faces are round (no face pairing), [3, 1000]
  template <class V>
  void Visit(V& v) {
    v("min_plan_iou", min_plan_iou, Bounds{0.0, 1.0 - 1e-9});
    v("max_polygonal_faces", max_polygonal_faces, Bounds{3, 1000});
  }
};

/// One column (model or truth) as an object. World frame, metres.
struct ColumnObject {
  std::string id;               ///< "column_1" (model) or the truth element id ("C1")
  std::vector<Patch> faces;     ///< vertical faces, class column, normals pointing away from it
  std::vector<Vec2> footprint;  ///< plan convex hull of the face vertices, CCW
  double z_min = 0.0, z_max = 0.0;
  Vec2 Centre() const;  ///< area centroid of the footprint
  double Area() const;  ///< m^2, footprint area
};

/// A column object from its faces (footprint = convex hull, heights = vertex z range).
/// InputError when there are no faces or the footprint has no area.
ColumnObject MakeColumnObject(const std::string& id, const std::vector<Patch>& faces);

/// The model's columns: patches of class column grouped by the id prefix up to and including
/// the second '_' (`column_3_face_2` -> `column_3`), in order of first appearance. A column
/// patch whose id has no such prefix is a column of its own.
std::vector<ColumnObject> GroupModelColumns(const std::vector<Patch>& model);

/// One matched model/truth column (a true positive).
struct ColumnPair {
  int model_index = -1, truth_index = -1;
  std::string model_id, truth_id;
  double plan_iou = 0.0;
  double centre_error = 0.0;    ///< m, plan distance between footprint centroids
  double area_error = 0.0;      ///< m^2, |A_m - A_t|
  double diameter_error = 0.0;  ///< m, error of the equivalent-circle diameter
  double height_error = 0.0;    ///< m
  bool faces_compared = false;  ///< polygonal truth column: `faces` holds the face metrics
  PatchEvaluation faces;        ///< face-to-face d_v, d_h, Phi (only when faces_compared)
};

struct ColumnEvaluation {
  ClassDetection detection;       ///< objects: n_truth, n_model, tp, fp, fn
  std::vector<ColumnPair> pairs;  ///< by truth index
  std::vector<std::string> unmatched_model_ids, unmatched_truth_ids;
  ErrorStats plan_iou;  ///< over TP pairs (mean/max of the IoU itself)
  ErrorStats centre_error, area_error, diameter_error, height_error;  ///< over TP pairs
  /// Face metrics pooled over the polygonal TP pairs: detection counts faces, d_v/d_h over
  /// edge pairs, Phi over face pairs (column class).
  ClassDetection face_detection;
  ClassAccuracy face_accuracy;
};

/// Scores model columns against truth columns (see above). `faces` are the parameters of the
/// face matching inside polygonal pairs. Deterministic.
ColumnEvaluation EvaluateColumns(const std::vector<ColumnObject>& model,
                                 const std::vector<ColumnObject>& truth,
                                 const ColumnMatchParams& params = {},
                                 const PatchMatchParams& faces = {});

}  // namespace mopad::evaluation
