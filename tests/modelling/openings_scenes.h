#pragma once
// Small scenes for the SM4 tests, built in code from coloured oriented boxes and
// scanned by an analytic ray caster: a room x in [0, 5], y in [0, 4], z in [0, 2.7] whose south
// wall (y in [-0.2, 0]) holds the opening under test, a second room behind it (y down to -4) so
// that rays through an opening return (or nothing behind it: a door of a storey standing in
// nothing, whose rays through the opening return nothing), and whatever furniture a test adds.
// Glass boxes let rays pass with their transmission probability, keyed by ray index
// (deterministic). Range noise is
// +-2 mm uniform along the ray (counter-based, not std:: distributions). The robot-side code
// sees only the points, colours and scanner centres, as from a real scanner.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/rng.h"
#include "modelling/orthoimage.h"
#include "modelling/structural_model.h"

namespace mopad::modelling::testing {

using Rgb = std::array<std::uint8_t, 3>;
inline constexpr Rgb kWallRgb{219, 217, 204};
inline constexpr Rgb kFloorRgb{89, 84, 77};
inline constexpr Rgb kCeilingRgb{230, 230, 230};
inline constexpr Rgb kLeafRgb{115, 71, 38};
inline constexpr Rgb kCasingRgb{64, 64, 69};
inline constexpr Rgb kCabinetRgb{128, 133, 140};
inline constexpr Rgb kGlassRgb{204, 230, 242};
inline constexpr double kPi = 3.14159265358979323846;

struct Box {
  Eigen::Vector3d centre;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  ///< columns: box axes in the map frame
  Eigen::Vector3d half;
  Rgb rgb{0, 0, 0};
  double transmission = 0.0;
};

inline Box AxisBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgb rgb, double tr = 0.0) {
  Box b;
  b.centre = 0.5 * (lo + hi);
  b.half = 0.5 * (hi - lo);
  b.rgb = rgb;
  b.transmission = tr;
  return b;
}

struct Scene {
  std::vector<Box> boxes;
};

/// Entry distance of the ray o + t d into box b (t > 1e-6), or +inf.
inline double HitBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const Eigen::Vector3d ol = b.axes.transpose() * (o - b.centre);
  const Eigen::Vector3d dl = b.axes.transpose() * d;
  double t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dl[a]) < 1e-12) {
      if (std::abs(ol[a]) > b.half[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (-b.half[a] - ol[a]) / dl[a], tb = (b.half[a] - ol[a]) / dl[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  if (t0 > t1 || t1 < 1e-6) return std::numeric_limits<double>::infinity();
  return t0 > 1e-6 ? t0 : std::numeric_limits<double>::infinity();  // from inside: no hit
}

struct Cloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Rgb> colours;
  std::vector<std::uint16_t> scan_index;
  std::vector<Vec3> origins;
  std::vector<Eigen::Vector3f> no_return_dirs;  ///< rays that met nothing, unit
  std::vector<std::uint16_t> no_return_scan;
  std::vector<double> steps;  ///< rad, each scan's angular step
  OrthoPoints View() const {
    OrthoPoints v;
    v.points = &points, v.colours = &colours, v.scan_index = &scan_index, v.scan_origins = origins;
    v.no_return_dirs = no_return_dirs, v.no_return_scan = no_return_scan;
    v.scan_steps = steps;
    return v;
  }
};

/// One scan from `origin`: azimuth [az0, az1], elevation [-55, 60] deg, both at `step` rad.
inline void Scan(const Scene& s, const Eigen::Vector3d& origin, double az0, double az1, double step,
                 Cloud& out, std::uint64_t seed = 7) {
  const auto k = static_cast<std::uint16_t>(out.origins.size());
  out.origins.push_back(origin);
  out.steps.push_back(step);
  std::uint64_t ray = 0;
  for (double el = -55.0 * kPi / 180; el <= 60.0 * kPi / 180; el += step)
    for (double az = az0; az <= az1; az += step, ++ray) {
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      std::vector<std::pair<double, int>> hits;
      for (int i = 0; i < static_cast<int>(s.boxes.size()); ++i) {
        const double t = HitBox(s.boxes[i], origin, d);
        if (std::isfinite(t) && t < 60.0) hits.push_back({t, i});
      }
      std::sort(hits.begin(), hits.end());
      CounterRng rng(seed, "ray", ray * 64 + k);
      bool returned = false;
      for (const auto& [t, i] : hits) {
        const Box& b = s.boxes[i];
        if (b.transmission > 0.0 && rng.Uniform() < b.transmission) continue;
        const double r = t + (rng.Uniform() - 0.5) * 0.004;
        out.points.push_back((origin + r * d).cast<float>());
        out.colours.push_back(b.rgb);
        out.scan_index.push_back(k);
        returned = true;
        break;
      }
      if (!returned) {
        out.no_return_dirs.push_back(d.cast<float>());
        out.no_return_scan.push_back(k);
      }
    }
}

/// What sits in the south wall's hole [x0, x1] x [z0, z1].
struct HoleSpec {
  double x0 = 2.0, x1 = 2.9, z0 = 0.0, z1 = 2.1;
  bool casing = true;
  Rgb casing_rgb = kCasingRgb;
  // Door leaf (z0 == 0): none when !leaf.
  bool leaf = true;
  Rgb leaf_rgb = kLeafRgb;
  bool swing_into_room = true;  ///< else into the room behind (seen through the hole)
  double lambda_deg = 0.0;
  bool flush_leaf = false;  ///< a leaf filling the hole at y in [-0.04, 0] (no hinge, closed)
  // Window: glass pane in the middle of the wall.
  bool glass = false;
  /// No room behind the wall: nothing there returns a ray (no floor, walls or ceiling beyond).
  bool nothing_behind = false;
};

/// The room, the wall with its hole (if x1 > x0), the room behind and the hole's contents.
inline Scene RoomScene(const HoleSpec& h, bool with_hole = true) {
  Scene s;
  using V = Eigen::Vector3d;
  const double H = 2.7, t = 0.2;
  const double y0 = h.nothing_behind ? -t : -4.3;  // the south end of floor, ceiling and walls
  s.boxes.push_back(AxisBox(V(-0.3, y0, -0.1), V(5.3, 4.3, 0.0), kFloorRgb));           // floor
  s.boxes.push_back(AxisBox(V(-0.3, y0, H), V(5.3, 4.3, H + 0.1), kCeilingRgb));        // ceiling
  s.boxes.push_back(AxisBox(V(-0.2, std::max(y0, -4.2), 0), V(0, 4.2, H), kWallRgb));   // west
  s.boxes.push_back(AxisBox(V(5.0, std::max(y0, -4.2), 0), V(5.2, 4.2, H), kWallRgb));  // east
  s.boxes.push_back(AxisBox(V(-0.2, 4.0, 0), V(5.2, 4.2, H), kWallRgb));                // north
  if (!h.nothing_behind)
    s.boxes.push_back(AxisBox(V(-0.2, -4.2, 0), V(5.2, -4.0, H), Rgb{180, 200, 170}));  // far
  if (!with_hole) {
    s.boxes.push_back(AxisBox(V(0, -t, 0), V(5, 0, H), kWallRgb));
    return s;
  }
  // South wall around the hole.
  s.boxes.push_back(AxisBox(V(0, -t, 0), V(h.x0, 0, H), kWallRgb));
  s.boxes.push_back(AxisBox(V(h.x1, -t, 0), V(5, 0, H), kWallRgb));
  s.boxes.push_back(AxisBox(V(h.x0, -t, h.z1), V(h.x1, 0, H), kWallRgb));
  if (h.z0 > 0) s.boxes.push_back(AxisBox(V(h.x0, -t, 0), V(h.x1, 0, h.z0), kWallRgb));
  if (h.casing) {
    const double w = 0.08, p = 0.02;
    for (double y0 : {0.0, -t - p}) {
      const double y1 = y0 + p;
      s.boxes.push_back(
          AxisBox(V(h.x0 - w, y0, h.z0 > 0 ? h.z0 - w : 0), V(h.x0, y1, h.z1), h.casing_rgb));
      s.boxes.push_back(
          AxisBox(V(h.x1, y0, h.z0 > 0 ? h.z0 - w : 0), V(h.x1 + w, y1, h.z1), h.casing_rgb));
      s.boxes.push_back(AxisBox(V(h.x0 - w, y0, h.z1), V(h.x1 + w, y1, h.z1 + w), h.casing_rgb));
      if (h.z0 > 0)
        s.boxes.push_back(AxisBox(V(h.x0 - w, y0, h.z0 - w), V(h.x1 + w, y1, h.z0), h.casing_rgb));
    }
  }
  if (h.glass)
    s.boxes.push_back(AxisBox(V(h.x0, -0.11, h.z0), V(h.x1, -0.09, h.z1), kGlassRgb, 0.9));
  if (h.z0 == 0.0 && h.leaf) {
    if (h.flush_leaf) {
      s.boxes.push_back(
          AxisBox(V(h.x0 + 0.003, -0.04, 0.01), V(h.x1 - 0.003, 0, h.z1 - 0.003), h.leaf_rgb));
    } else {
      const double lam = h.lambda_deg * kPi / 180, lt = 0.04, lw = h.x1 - h.x0 - 0.006;
      const double yh = h.swing_into_room ? 0.021 : -t - 0.021;
      const V n = h.swing_into_room ? V(0, 1, 0) : V(0, -1, 0);
      const V dd(1, 0, 0);
      const V dl = std::cos(lam) * dd + std::sin(lam) * n;
      const V nl = std::cos(lam) * n - std::sin(lam) * dd;
      Box b;
      b.axes.col(0) = dl, b.axes.col(1) = nl, b.axes.col(2) = V::UnitZ();
      b.half = V(lw / 2, lt / 2, (h.z1 - 0.013) / 2);
      b.centre =
          V(h.x0 + 0.003, yh, 0.01) + dl * lw / 2 - nl * lt / 2 + V(0, 0, (h.z1 - 0.013) / 2);
      b.rgb = h.leaf_rgb;
      s.boxes.push_back(b);
    }
  }
  return s;
}

/// Two scans from the room (and none from behind the wall), 0.003 rad.
inline Cloud ScanRoom(const Scene& s) {
  Cloud c;
  Scan(s, {2.2, 2.3, 1.3}, -kPi, kPi, 0.003, c);
  Scan(s, {3.6, 1.6, 1.3}, -kPi, kPi, 0.003, c);
  return c;
}

/// SM3 of the room as the robot would model it (exact planes): the south wall is "wall_1".
inline StructuralModel RoomSm3() {
  StructuralModel m;
  m.room = "R";
  m.floor_z = 0.0, m.ceiling_z = 2.7;
  auto wall = [&](const std::string& id, Vec3 n, double d, std::vector<Vec3> poly) {
    StructuralPatch p;
    p.id = id;
    p.patch_class = PatchClass::kWall;
    p.plane.n = n, p.plane.d = d;
    p.polygon = std::move(poly);
    p.fitted = true;
    m.patches.push_back(p);
  };
  const double H = 2.7;
  wall("wall_1", {0, 1, 0}, 0.0, {{5, 0, 0}, {0, 0, 0}, {0, 0, H}, {5, 0, H}});
  wall("wall_2", {-1, 0, 0}, 5.0, {{5, 4, 0}, {5, 0, 0}, {5, 0, H}, {5, 4, H}});
  wall("wall_3", {0, -1, 0}, 4.0, {{0, 4, 0}, {5, 4, 0}, {5, 4, H}, {0, 4, H}});
  wall("wall_4", {1, 0, 0}, 0.0, {{0, 0, 0}, {0, 4, 0}, {0, 4, H}, {0, 0, H}});
  return m;
}

}  // namespace mopad::modelling::testing
