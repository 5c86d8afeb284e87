#include "evaluation/metrics_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "common/error.h"
#include "common/polygon.h"
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

// ---- Columns as objects ----

Vec2 ColumnObject::Centre() const {
  // Area centroid of a simple polygon (shoelace); vertex mean when degenerate.
  double a = 0.0;
  Vec2 c = Vec2::Zero();
  for (std::size_t i = 0; i < footprint.size(); ++i) {
    const Vec2& p = footprint[i];
    const Vec2& q = footprint[(i + 1) % footprint.size()];
    const double w = p.x() * q.y() - q.x() * p.y();
    a += w;
    c += w * (p + q);
  }
  if (std::abs(a) < 1e-15) {
    Vec2 m = Vec2::Zero();
    for (const Vec2& p : footprint) m += p;
    return footprint.empty() ? m : Vec2(m / static_cast<double>(footprint.size()));
  }
  return c / (3.0 * a);
}

double ColumnObject::Area() const { return std::abs(SignedArea(footprint)); }

ColumnObject MakeColumnObject(const std::string& id, const std::vector<Patch>& faces) {
  if (faces.empty()) throw InputError("column '" + id + "'", "no faces");
  ColumnObject c;
  c.id = id;
  c.faces = faces;
  std::vector<Vec2> plan;
  c.z_min = std::numeric_limits<double>::infinity();
  c.z_max = -std::numeric_limits<double>::infinity();
  for (const Patch& f : faces)
    for (const Vec3& v : f.polygon) {
      plan.emplace_back(v.x(), v.y());
      c.z_min = std::min(c.z_min, v.z());
      c.z_max = std::max(c.z_max, v.z());
    }
  c.footprint = ConvexHull(plan);
  if (c.footprint.size() < 3 || !(c.Area() > 1e-9))
    throw InputError("column '" + id + "'", "footprint has no area");
  return c;
}

std::vector<ColumnObject> GroupModelColumns(const std::vector<Patch>& model) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<Patch>> groups;
  for (const Patch& p : model) {
    if (p.cls != SurfaceClass::kColumn) continue;
    std::string key = p.id;
    const auto first = p.id.find('_');
    if (first != std::string::npos) {
      const auto second = p.id.find('_', first + 1);
      if (second != std::string::npos) key = p.id.substr(0, second);
    }
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(p);
  }
  std::vector<ColumnObject> out;
  for (const auto& key : order) out.push_back(MakeColumnObject(key, groups[key]));
  return out;
}

ColumnEvaluation EvaluateColumns(const std::vector<ColumnObject>& model,
                                 const std::vector<ColumnObject>& truth,
                                 const ColumnMatchParams& params, const PatchMatchParams& faces) {
  ValidateParams(params, "column_match.");
  ColumnEvaluation out;
  out.detection.n_model = static_cast<int>(model.size());
  out.detection.n_truth = static_cast<int>(truth.size());
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(truth.size(), model.size(), kForbiddenCost);
  Eigen::MatrixXd iou = Eigen::MatrixXd::Zero(truth.size(), model.size());
  for (std::size_t r = 0; r < truth.size(); ++r)
    for (std::size_t c = 0; c < model.size(); ++c) {
      const double v = PolygonIoU(model[c].footprint, truth[r].footprint);
      iou(r, c) = v;
      if (v > params.min_plan_iou) cost(r, c) = 1.0 - v;
    }
  const std::vector<int> assign = SolveAssignment(cost);
  std::vector<char> model_used(model.size(), 0), truth_used(truth.size(), 0);
  for (std::size_t r = 0; r < truth.size(); ++r) {
    if (assign[r] < 0) continue;
    const ColumnObject& t = truth[r];
    const ColumnObject& m = model[assign[r]];
    ColumnPair p;
    p.model_index = assign[r];
    p.truth_index = static_cast<int>(r);
    p.model_id = m.id;
    p.truth_id = t.id;
    p.plan_iou = iou(r, assign[r]);
    p.centre_error = (m.Centre() - t.Centre()).norm();
    p.area_error = std::abs(m.Area() - t.Area());
    p.diameter_error = std::abs(2.0 * std::sqrt(m.Area() / kPi) - 2.0 * std::sqrt(t.Area() / kPi));
    p.height_error = std::abs((m.z_max - m.z_min) - (t.z_max - t.z_min));
    if (static_cast<int>(t.faces.size()) <= params.max_polygonal_faces) {
      p.faces_compared = true;
      p.faces = EvaluatePatches(m.faces, t.faces, faces);
      const auto& d = p.faces.detection[static_cast<int>(SurfaceClass::kColumn)];
      auto& fd = out.face_detection;
      fd.n_truth += d.n_truth, fd.n_model += d.n_model, fd.tp += d.tp, fd.fp += d.fp, fd.fn += d.fn;
      const auto& a = p.faces.accuracy[static_cast<int>(SurfaceClass::kColumn)];
      out.face_accuracy.d_v.Merge(a.d_v);
      out.face_accuracy.d_h.Merge(a.d_h);
      out.face_accuracy.phi_deg.Merge(a.phi_deg);
    }
    out.plan_iou.Add(p.plan_iou);
    out.centre_error.Add(p.centre_error);
    out.area_error.Add(p.area_error);
    out.diameter_error.Add(p.diameter_error);
    out.height_error.Add(p.height_error);
    model_used[assign[r]] = truth_used[r] = 1;
    ++out.detection.tp;
    out.pairs.push_back(std::move(p));
  }
  out.detection.fp = out.detection.n_model - out.detection.tp;
  out.detection.fn = out.detection.n_truth - out.detection.tp;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (!model_used[i]) out.unmatched_model_ids.push_back(model[i].id);
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (!truth_used[i]) out.unmatched_truth_ids.push_back(truth[i].id);
  return out;
}

}  // namespace mopad::evaluation
