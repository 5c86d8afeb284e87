#include "evaluation/metrics.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/polygon.h"

namespace mopad::evaluation {

const char* SurfaceClassName(SurfaceClass c) {
  switch (c) {
    case SurfaceClass::kWall:
      return "wall";
    case SurfaceClass::kFloor:
      return "floor";
    case SurfaceClass::kCeiling:
      return "ceiling";
    case SurfaceClass::kColumn:
      return "column";
  }
  return "unknown";
}

const std::array<SurfaceClass, kNumSurfaceClasses>& AllSurfaceClasses() {
  static const std::array<SurfaceClass, kNumSurfaceClasses> k = {
      SurfaceClass::kWall, SurfaceClass::kFloor, SurfaceClass::kCeiling, SurfaceClass::kColumn};
  return k;
}

std::string NameOf(const std::string& kind, std::size_t index, const std::string& id) {
  std::string s = kind;
  s.append(" ").append(std::to_string(index)).append(" '").append(id).append("'");
  return s;
}

void ErrorStats::Add(double x) {
  ++n;
  sum += x;
  mean = sum / n;
  max = std::max(max, x);
}

void ErrorStats::Merge(const ErrorStats& o) {
  if (o.n == 0) return;
  n += o.n;
  sum += o.sum;
  mean = sum / n;
  max = std::max(max, o.max);
}

// ---------------------------------------------------------------------------------------------
PlaneFrame PlaneFrame::Of(const Patch& patch) {
  PlaneFrame f;
  f.n = patch.normal.normalized();
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : patch.polygon) c += p;
  f.origin = c / static_cast<double>(std::max<size_t>(1, patch.polygon.size()));
  if (std::abs(f.n.z()) < 0.9) {
    f.u = Vec3::UnitZ().cross(f.n).normalized();
  } else {
    f.u = Vec3::UnitY().cross(f.n).normalized();
  }
  f.v = f.n.cross(f.u);
  return f;
}

Patch Transformed(const Patch& patch, const Pose3& X) {
  Patch out = patch;
  for (Vec3& v : out.polygon) v = X * v;
  out.normal = X.linear() * patch.normal;
  return out;
}

void ValidatePatch(const Patch& patch, const PatchValidationParams& params,
                   const std::string& what) {
  const size_t nv = patch.polygon.size();
  if (nv < 3) {
    throw InputError("", what + ": polygon has too few vertices", std::to_string(nv), ">= 3");
  }
  for (size_t i = 0; i < nv; ++i) {
    if (!patch.polygon[i].allFinite()) {
      throw InputError("", what + ": vertex " + std::to_string(i) + " is not finite", "NaN/Inf",
                       "finite coordinates");
    }
  }
  if (!patch.normal.allFinite() || patch.normal.norm() < 1e-12) {
    throw InputError("", what + ": normal is not finite or zero", "", "a non-zero finite vector");
  }
  if (static_cast<int>(patch.cls) >= kNumSurfaceClasses) {
    throw InputError("", what + ": unknown surface class",
                     std::to_string(static_cast<int>(patch.cls)), "wall/floor/ceiling/column");
  }
  const PlaneFrame f = PlaneFrame::Of(patch);
  double off = 0.0;
  for (const Vec3& p : patch.polygon) off = std::max(off, std::abs(f.SignedDistance(p)));
  if (off > params.planarity_tolerance) {
    throw InputError("", what + ": polygon is not planar (vertex off its plane)",
                     std::to_string(off) + " m",
                     "<= " + std::to_string(params.planarity_tolerance) + " m");
  }
  std::vector<Vec2> q;
  q.reserve(nv);
  for (const Vec3& p : patch.polygon) q.push_back(f.To2d(p));
  const double a = SignedArea(q);
  if (std::abs(a) < params.min_area) {
    throw InputError("", what + ": polygon area too small", std::to_string(std::abs(a)) + " m^2",
                     ">= " + std::to_string(params.min_area) + " m^2");
  }
  if (a < 0.0) {
    throw InputError("", what + ": polygon is clockwise seen from its normal", "clockwise",
                     "counter-clockwise");
  }
}

// ---------------------------------------------------------------------------------------------

namespace {

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Clips a convex polygon `subject` (CCW) by the CCW triangle `clip`; returns the area.
double ClippedArea(const std::array<Vec2, 3>& subject, const std::array<Vec2, 3>& clip) {
  std::vector<Vec2> out(subject.begin(), subject.end());
  for (int e = 0; e < 3 && !out.empty(); ++e) {
    const Vec2& a = clip[e];
    const Vec2& b = clip[(e + 1) % 3];
    const Vec2 d = b - a;
    std::vector<Vec2> in;
    in.swap(out);
    const size_t n = in.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec2& p = in[i];
      const Vec2& q = in[(i + 1) % n];
      const double sp = Cross(d, p - a);
      const double sq = Cross(d, q - a);
      if (sp >= 0.0) out.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) {
        const double t = sp / (sp - sq);
        out.push_back(p + t * (q - p));
      }
    }
  }
  return out.size() < 3 ? 0.0 : std::max(0.0, SignedArea(out));
}

bool InTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  // Closed test (points on the edges count), so ears never swallow a reflex vertex.
  return Cross(b - a, p - a) >= 0.0 && Cross(c - b, p - b) >= 0.0 && Cross(a - c, p - c) >= 0.0;
}

}  // namespace

std::vector<Vec2> SimplifyPolygon(const std::vector<Vec2>& in, double angle_tol) {
  std::vector<Vec2> p;
  for (const Vec2& q : in) {
    if (p.empty() || (q - p.back()).norm() > 1e-12) p.push_back(q);
  }
  while (p.size() > 1 && (p.front() - p.back()).norm() <= 1e-12) p.pop_back();
  bool changed = true;
  while (changed && p.size() > 3) {
    changed = false;
    for (size_t i = 0; i < p.size() && p.size() > 3; ++i) {
      const Vec2& a = p[(i + p.size() - 1) % p.size()];
      const Vec2& b = p[i];
      const Vec2& c = p[(i + 1) % p.size()];
      const Vec2 d1 = (b - a).normalized(), d2 = (c - b).normalized();
      const double turn = std::atan2(std::abs(Cross(d1, d2)), d1.dot(d2));
      if (turn < angle_tol) {
        p.erase(p.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  return p;
}

std::vector<Vec3> SimplifyPolygon3d(const std::vector<Vec3>& in, double angle_tol) {
  std::vector<Vec3> p;
  for (const Vec3& q : in) {
    if (p.empty() || (q - p.back()).norm() > 1e-12) p.push_back(q);
  }
  while (p.size() > 1 && (p.front() - p.back()).norm() <= 1e-12) p.pop_back();
  bool changed = true;
  while (changed && p.size() > 3) {
    changed = false;
    for (size_t i = 0; i < p.size() && p.size() > 3; ++i) {
      const Vec3& a = p[(i + p.size() - 1) % p.size()];
      const Vec3& b = p[i];
      const Vec3& c = p[(i + 1) % p.size()];
      const Vec3 d1 = (b - a).normalized(), d2 = (c - b).normalized();
      const double turn = std::atan2(d1.cross(d2).norm(), d1.dot(d2));
      if (turn < angle_tol) {
        p.erase(p.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  return p;
}

std::vector<std::array<Vec2, 3>> Triangulate(const std::vector<Vec2>& polygon) {
  std::vector<Vec2> p = SimplifyPolygon(polygon, 1e-12);
  std::vector<std::array<Vec2, 3>> tris;
  if (p.size() < 3) return tris;
  if (SignedArea(p) < 0.0) std::reverse(p.begin(), p.end());
  std::vector<int> idx(p.size());
  for (size_t i = 0; i < p.size(); ++i) idx[i] = static_cast<int>(i);
  while (idx.size() > 3) {
    const size_t n = idx.size();
    bool clipped = false;
    for (size_t i = 0; i < n; ++i) {
      const Vec2& a = p[idx[(i + n - 1) % n]];
      const Vec2& b = p[idx[i]];
      const Vec2& c = p[idx[(i + 1) % n]];
      if (Cross(b - a, c - b) <= 0.0) continue;  // reflex or flat
      bool ear = true;
      for (size_t k = 0; k < n && ear; ++k) {
        if (k == i || k == (i + 1) % n || k == (i + n - 1) % n) continue;
        const Vec2& q = p[idx[k]];
        if ((q - a).norm() < 1e-12 || (q - b).norm() < 1e-12 || (q - c).norm() < 1e-12) continue;
        if (InTriangle(q, a, b, c)) ear = false;
      }
      if (!ear) continue;
      tris.push_back({a, b, c});
      idx.erase(idx.begin() + static_cast<long>(i));
      clipped = true;
      break;
    }
    if (!clipped) {
      // Degenerate input (self-touching or numerically flat): fan the rest; only convex-ish
      // remnants reach here in practice.
      for (size_t i = 1; i + 1 < idx.size(); ++i)
        tris.push_back({p[idx[0]], p[idx[i]], p[idx[i + 1]]});
      return tris;
    }
  }
  tris.push_back({p[idx[0]], p[idx[1]], p[idx[2]]});
  return tris;
}

double IntersectionArea(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const auto ta = Triangulate(a);
  const auto tb = Triangulate(b);
  double area = 0.0;
  for (const auto& s : ta) {
    Eigen::AlignedBox2d bs;
    for (const Vec2& q : s) bs.extend(q);
    for (const auto& c : tb) {
      Eigen::AlignedBox2d bc;
      for (const Vec2& q : c) bc.extend(q);
      if (!bs.intersects(bc)) continue;
      area += ClippedArea(s, c);
    }
  }
  return area;
}

double PolygonIoU(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const double inter = IntersectionArea(a, b);
  const double uni = std::abs(SignedArea(a)) + std::abs(SignedArea(b)) - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

}  // namespace mopad::evaluation
