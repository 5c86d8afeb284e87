#include "evaluation/metrics_isprs.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/polygon.h"
#include "common/statistics.h"

namespace mopad::evaluation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A surface exactly b away counts as within b despite rounding (1 nm).
constexpr double kTie = 1e-9;

// A polygon prepared for repeated distance queries.
struct Target {
  PlaneFrame frame;
  std::vector<Vec2> poly2;
  Eigen::AlignedBox3d box;
  SurfaceClass cls;
};

Target Prepare(const Patch& p) {
  Target t;
  t.frame = PlaneFrame::Of(p);
  t.cls = p.cls;
  for (const Vec3& q : p.polygon) {
    t.poly2.push_back(t.frame.To2d(q));
    t.box.extend(q);
  }
  return t;
}

double Distance(const Vec3& p, const Target& t) {
  const double h = t.frame.SignedDistance(p);
  const Vec2 q = t.frame.To2d(p);
  if (PointInPolygon(q, t.poly2)) return std::abs(h);
  const double e = DistanceToBoundary(q, t.poly2);
  return std::sqrt(h * h + e * e);
}

struct SampleSet {
  std::vector<Vec3> points;
  std::vector<double> weight;
  std::vector<int> patch;  // index into its patch vector
};

SampleSet SampleAll(const std::vector<Patch>& patches, double spacing) {
  SampleSet s;
  for (size_t i = 0; i < patches.size(); ++i) {
    double w = 0.0;
    const std::vector<Vec3> pts = SamplePatch(patches[i], spacing, &w);
    for (const Vec3& p : pts) {
      s.points.push_back(p);
      s.weight.push_back(w);
      s.patch.push_back(static_cast<int>(i));
    }
  }
  return s;
}

// Nearest distance from each sample to the targets (same class if asked), capped at `cap`
// (values above are +inf).
std::vector<double> NearestDistances(const SampleSet& s, const std::vector<Patch>& from,
                                     const std::vector<Target>& targets, bool same_class,
                                     double cap) {
  std::vector<double> d(s.points.size(), std::numeric_limits<double>::infinity());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, s.points.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        const Vec3& p = s.points[i];
                        const SurfaceClass cls = from[s.patch[i]].cls;
                        double best = cap;
                        bool found = false;
                        for (const Target& t : targets) {
                          if (same_class && t.cls != cls) continue;
                          if (t.box.exteriorDistance(p) > best) continue;
                          const double dist = Distance(p, t);
                          if (dist <= best) {
                            best = dist;
                            found = true;
                          }
                        }
                        if (found) d[i] = best;
                      }
                    });
  return d;
}

}  // namespace

int IsprsResult::BufferIndex(double b) const {
  int best = 0;
  for (size_t i = 0; i < buffers.size(); ++i) {
    if (std::abs(buffers[i] - b) < std::abs(buffers[best] - b)) best = static_cast<int>(i);
  }
  return best;
}

std::vector<Vec3> SamplePatch(const Patch& patch, double spacing, double* area_per_sample) {
  const PlaneFrame f = PlaneFrame::Of(patch);
  std::vector<Vec2> q;
  Eigen::AlignedBox2d box;
  for (const Vec3& p : patch.polygon) {
    q.push_back(f.To2d(p));
    box.extend(q.back());
  }
  std::vector<Vec3> out;
  const long nx = static_cast<long>(std::floor(box.sizes().x() / spacing)) + 1;
  const long ny = static_cast<long>(std::floor(box.sizes().y() / spacing)) + 1;
  for (long j = 0; j < ny; ++j) {
    for (long i = 0; i < nx; ++i) {
      const Vec2 c = box.min() + Vec2((i + 0.5) * spacing, (j + 0.5) * spacing);
      if (PointInPolygon(c, q)) out.push_back(f.To3d(c));
    }
  }
  if (out.empty()) out.push_back(f.origin);
  *area_per_sample = PolygonArea3d(patch.polygon) / static_cast<double>(out.size());
  return out;
}

IsprsResult EvaluateIsprs(const std::vector<Patch>& source, const std::vector<Patch>& reference,
                          const IsprsParams& params) {
  ValidateParams(params, "isprs.");
  for (size_t i = 0; i < source.size(); ++i) {
    ValidatePatch(source[i], params.validation, NameOf("source patch", i, source[i].id));
  }
  for (size_t i = 0; i < reference.size(); ++i) {
    ValidatePatch(reference[i], params.validation, NameOf("reference patch", i, reference[i].id));
  }
  IsprsResult res;
  res.cutoff = params.cutoff;
  const int nb = static_cast<int>(std::floor(params.buffer_max / params.buffer_step + 1e-9)) + 1;
  for (int k = 0; k < nb; ++k) res.buffers.push_back(k * params.buffer_step);
  const double cap = std::max(params.buffer_max, params.cutoff) * (1.0 + 1e-9) + 1e-12;

  std::vector<Target> src_t, ref_t;
  for (const Patch& p : source) src_t.push_back(Prepare(p));
  for (const Patch& p : reference) ref_t.push_back(Prepare(p));
  const SampleSet ref_s = SampleAll(reference, params.sample_spacing);
  const SampleSet src_s = SampleAll(source, params.sample_spacing);
  const std::vector<double> ref_d =
      NearestDistances(ref_s, reference, src_t, params.same_class_only, cap);
  const std::vector<double> src_d =
      NearestDistances(src_s, source, ref_t, params.same_class_only, cap);

  // Fixed-order accumulation: per class, all, per patch.
  std::array<std::vector<double>, kNumSurfaceClasses> ref_in, src_in;
  std::vector<double> all_ref_in(nb, 0.0), all_src_in(nb, 0.0);
  for (auto& v : ref_in) v.assign(nb, 0.0);
  for (auto& v : src_in) v.assign(nb, 0.0);
  std::vector<std::vector<double>> ref_patch_in(reference.size(), std::vector<double>(nb, 0.0));
  std::vector<std::vector<double>> src_patch_in(source.size(), std::vector<double>(nb, 0.0));
  std::vector<double> ref_patch_area(reference.size(), 0.0), src_patch_area(source.size(), 0.0);
  std::array<std::vector<double>, kNumSurfaceClasses> acc_d;
  std::vector<double> all_acc_d;

  for (size_t i = 0; i < ref_d.size(); ++i) {
    const int pi = ref_s.patch[i];
    const int ci = static_cast<int>(reference[pi].cls);
    const double w = ref_s.weight[i];
    res.per_class[ci].reference_area += w;
    res.all.reference_area += w;
    ref_patch_area[pi] += w;
    for (int k = 0; k < nb; ++k) {
      if (ref_d[i] <= res.buffers[k] + kTie) {
        ref_in[ci][k] += w;
        all_ref_in[k] += w;
        ref_patch_in[pi][k] += w;
      }
    }
  }
  for (size_t i = 0; i < src_d.size(); ++i) {
    const int pi = src_s.patch[i];
    const int ci = static_cast<int>(source[pi].cls);
    const double w = src_s.weight[i];
    res.per_class[ci].source_area += w;
    res.all.source_area += w;
    src_patch_area[pi] += w;
    for (int k = 0; k < nb; ++k) {
      if (src_d[i] <= res.buffers[k] + kTie) {
        src_in[ci][k] += w;
        all_src_in[k] += w;
        src_patch_in[pi][k] += w;
      }
    }
    if (src_d[i] <= params.cutoff + kTie) {
      acc_d[ci].push_back(src_d[i]);
      all_acc_d.push_back(src_d[i]);
    }
  }
  auto fill = [&](IsprsCurve* c, const std::vector<double>& rin, const std::vector<double>& sin,
                  const std::vector<double>& acc) {
    c->completeness.resize(nb);
    c->correctness.resize(nb);
    for (int k = 0; k < nb; ++k) {
      c->completeness[k] = c->reference_area > 0.0 ? rin[k] / c->reference_area : kNaN;
      c->correctness[k] = c->source_area > 0.0 ? sin[k] / c->source_area : kNaN;
    }
    c->accuracy = acc.empty() ? kNaN : Median(acc);
    c->accuracy_samples = static_cast<long>(acc.size());
  };
  for (int ci = 0; ci < kNumSurfaceClasses; ++ci) {
    fill(&res.per_class[ci], ref_in[ci], src_in[ci], acc_d[ci]);
  }
  fill(&res.all, all_ref_in, all_src_in, all_acc_d);
  for (size_t i = 0; i < reference.size(); ++i) {
    for (double& v : ref_patch_in[i]) v /= ref_patch_area[i];
  }
  for (size_t i = 0; i < source.size(); ++i) {
    for (double& v : src_patch_in[i]) v /= src_patch_area[i];
  }
  res.reference_patch_completeness = std::move(ref_patch_in);
  res.source_patch_correctness = std::move(src_patch_in);
  return res;
}

}  // namespace mopad::evaluation
