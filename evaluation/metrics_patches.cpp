#include "evaluation/metrics_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "evaluation/hungarian.h"

namespace mopad::evaluation {

double ClassDetection::Recall() const {
  return n_truth > 0 ? static_cast<double>(tp) / n_truth : std::numeric_limits<double>::quiet_NaN();
}
double ClassDetection::Precision() const {
  return n_model > 0 ? static_cast<double>(tp) / n_model : std::numeric_limits<double>::quiet_NaN();
}

double NormalAngleDeg(const Vec3& a, const Vec3& b, bool oriented) {
  const Vec3 na = a.normalized(), nb = b.normalized();
  double ang = RadToDeg(std::atan2(na.cross(nb).norm(), na.dot(nb)));
  if (!oriented) ang = std::min(ang, 180.0 - ang);
  return ang;
}

namespace {

struct Edge {
  Vec3 mid;
  double length;
};

// Vertical and horizontal edges of a simplified polygon.
void ClassifyEdges(const Patch& p, const PatchMatchParams& params, std::vector<Edge>* vertical,
                   std::vector<Edge>* horizontal) {
  const std::vector<Vec3> poly =
      SimplifyPolygon3d(p.polygon, DegToRad(params.collinear_tolerance_deg));
  const double tol = DegToRad(params.edge_angle_tolerance_deg);
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3 a = poly[i], b = poly[(i + 1) % poly.size()];
    const Vec3 d = b - a;
    const double len = d.norm();
    if (len <= 0.0) continue;
    const double elevation = std::asin(std::min(1.0, std::abs(d.z()) / len));  // from horizontal
    const Edge e{0.5 * (a + b), len};
    if (elevation >= 0.5 * kPi - tol) {
      vertical->push_back(e);
    } else if (elevation <= tol) {
      horizontal->push_back(e);
    }
  }
}

// Pairs edges by midpoint distance; adds |len difference| per pair; returns unpaired count.
int PairEdges(const std::vector<Edge>& m, const std::vector<Edge>& t, ErrorStats* stats) {
  Eigen::MatrixXd cost(m.size(), t.size());
  for (size_t i = 0; i < m.size(); ++i) {
    for (size_t j = 0; j < t.size(); ++j) cost(i, j) = (m[i].mid - t[j].mid).norm();
  }
  const std::vector<int> a = SolveAssignment(cost);
  int paired = 0;
  for (size_t i = 0; i < m.size(); ++i) {
    if (a[i] < 0) continue;
    stats->Add(std::abs(m[i].length - t[a[i]].length));
    ++paired;
  }
  return static_cast<int>(m.size() + t.size()) - 2 * paired;
}

}  // namespace

PatchEvaluation EvaluatePatches(const std::vector<Patch>& model, const std::vector<Patch>& truth,
                                const PatchMatchParams& params) {
  ValidateParams(params, "patch_match.");
  for (size_t i = 0; i < model.size(); ++i) {
    ValidatePatch(model[i], params.validation, NameOf("model patch", i, model[i].id));
  }
  for (size_t i = 0; i < truth.size(); ++i) {
    ValidatePatch(truth[i], params.validation, NameOf("truth patch", i, truth[i].id));
  }
  PatchEvaluation out;
  std::vector<char> model_used(model.size(), 0), truth_used(truth.size(), 0);

  for (SurfaceClass cls : AllSurfaceClasses()) {
    const int ci = static_cast<int>(cls);
    std::vector<int> mi, ti;
    for (size_t i = 0; i < model.size(); ++i)
      if (model[i].cls == cls) mi.push_back(static_cast<int>(i));
    for (size_t i = 0; i < truth.size(); ++i)
      if (truth[i].cls == cls) ti.push_back(static_cast<int>(i));
    ClassDetection& det = out.detection[ci];
    det.n_model = static_cast<int>(mi.size());
    det.n_truth = static_cast<int>(ti.size());

    // Candidate tests and cost (1 - IoU), rows = truth, cols = model.
    Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(ti.size(), mi.size(), kForbiddenCost);
    Eigen::MatrixXd iou = Eigen::MatrixXd::Zero(ti.size(), mi.size());
    Eigen::MatrixXd plane_dist = Eigen::MatrixXd::Zero(ti.size(), mi.size());
    for (size_t r = 0; r < ti.size(); ++r) {
      const Patch& t = truth[ti[r]];
      const PlaneFrame ft = PlaneFrame::Of(t);
      std::vector<Vec2> t2;
      for (const Vec3& p : t.polygon) t2.push_back(ft.To2d(p));
      for (size_t c = 0; c < mi.size(); ++c) {
        const Patch& m = model[mi[c]];
        if (NormalAngleDeg(m.normal, t.normal, params.oriented_normals) >
            params.max_normal_angle_deg) {
          continue;
        }
        const double dist = std::abs(ft.SignedDistance(PlaneFrame::Of(m).origin));
        if (dist > params.max_plane_distance) continue;
        std::vector<Vec2> m2;
        for (const Vec3& p : m.polygon) m2.push_back(ft.To2d(p));
        const double v = PolygonIoU(m2, t2);
        if (v < params.min_overlap_iou) continue;
        cost(r, c) = 1.0 - v;
        iou(r, c) = v;
        plane_dist(r, c) = dist;
      }
    }
    const std::vector<int> assign = SolveAssignment(cost);
    for (size_t r = 0; r < ti.size(); ++r) {
      if (assign[r] < 0) continue;
      const int c = assign[r];
      const Patch& t = truth[ti[r]];
      const Patch& m = model[mi[c]];
      PatchPair pp;
      pp.model_index = mi[c];
      pp.truth_index = ti[r];
      pp.model_id = m.id;
      pp.truth_id = t.id;
      pp.cls = cls;
      pp.iou = iou(r, c);
      pp.plane_distance = plane_dist(r, c);
      pp.phi_deg = NormalAngleDeg(m.normal, t.normal, params.oriented_normals);
      std::vector<Edge> mv, mh, tv, th;
      ClassifyEdges(m, params, &mv, &mh);
      ClassifyEdges(t, params, &tv, &th);
      pp.unpaired_edges = PairEdges(mv, tv, &pp.d_v) + PairEdges(mh, th, &pp.d_h);
      model_used[mi[c]] = truth_used[ti[r]] = 1;
      ++det.tp;
      out.pairs.push_back(pp);
    }
    det.fp = det.n_model - det.tp;
    det.fn = det.n_truth - det.tp;
  }

  // Aggregates over edge pairs: merging the per-patch stats gives mean = total sum / count.
  for (const PatchPair& pp : out.pairs) {
    ClassAccuracy& acc = out.accuracy[static_cast<int>(pp.cls)];
    acc.d_v.Merge(pp.d_v);
    acc.d_h.Merge(pp.d_h);
    acc.phi_deg.Add(pp.phi_deg);
    out.phi_deg.Add(pp.phi_deg);
    if (pp.cls == SurfaceClass::kWall || pp.cls == SurfaceClass::kColumn) {
      out.d_v.Merge(pp.d_v);
      out.d_h.Merge(pp.d_h);
    }
  }
  for (size_t i = 0; i < model.size(); ++i) {
    if (!model_used[i]) {
      out.unmatched_model.push_back(static_cast<int>(i));
      out.unmatched_model_ids.push_back(model[i].id);
    }
  }
  for (size_t i = 0; i < truth.size(); ++i) {
    if (!truth_used[i]) {
      out.unmatched_truth.push_back(static_cast<int>(i));
      out.unmatched_truth_ids.push_back(truth[i].id);
    }
  }
  return out;
}

}  // namespace mopad::evaluation
