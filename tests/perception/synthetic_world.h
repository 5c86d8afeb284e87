#pragma once
// Test-only synthetic worlds for the robot-side libraries: axis-aligned boxes (walls,
// furniture), the 3D points a scanner would return from them, and a 2D LRF simulated by exact
// ray casting against the test's own boxes. The robot's
// libraries never get a simulator; the tests bring their own (shared by tests/perception and
// tests/autonomy).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/frames.h"
#include "common/rng.h"
#include "interfaces/lrf_scan.h"
#include "perception/occupancy_grid.h"

namespace mopad::testing {

struct Box2 {
  Vec2 lo, hi;  ///< map frame, m
};

/// Two rooms side by side, 10 m x 6 m overall, 0.1 m walls, separated at x = 5 by a wall with
/// a 0.9 m door gap at y in [2.55, 3.45], with some furniture making it asymmetric.
inline std::vector<Box2> TwoRooms(bool door_closed = false) {
  std::vector<Box2> b = {
      {{-0.1, -0.1}, {10.1, 0.0}},  // south wall
      {{-0.1, 6.0}, {10.1, 6.1}},   // north wall
      {{-0.1, -0.1}, {0.0, 6.1}},   // west wall
      {{10.0, -0.1}, {10.1, 6.1}},  // east wall
      {{4.95, 0.0}, {5.05, 2.55}},  // partition, south of the door
      {{4.95, 3.45}, {5.05, 6.0}},  // partition, north of the door
      {{1.5, 0.6}, {2.5, 1.2}},     // table-like block, west room
      {{0.0, 4.6}, {0.8, 6.0}},     // cupboard in the north-west corner
      {{7.3, 4.0}, {7.7, 4.4}},     // pillar, east room
      {{9.0, 4.8}, {10.0, 6.0}},    // cabinet in the north-east corner
  };
  if (door_closed) b.push_back({{4.97, 2.55}, {5.03, 3.45}});
  return b;
}

/// Points a scanner would return: the vertical faces of every box, sampled every `step` m at a
/// few heights in the obstacle band, plus floor points on a grid over [lo, hi] outside boxes.
inline std::vector<Eigen::Vector3d> ScanPoints(const std::vector<Box2>& boxes, const Vec2& lo,
                                               const Vec2& hi, double step = 0.02) {
  std::vector<Eigen::Vector3d> pts;
  const double zs[] = {0.2, 0.7, 1.2, 1.7, 2.4 /* above the band: ignored */};
  for (const auto& b : boxes) {
    for (double z : zs) {
      for (double x = b.lo.x(); x <= b.hi.x() + 1e-9; x += step) {
        pts.emplace_back(x, b.lo.y(), z);
        pts.emplace_back(x, b.hi.y(), z);
      }
      for (double y = b.lo.y(); y <= b.hi.y() + 1e-9; y += step) {
        pts.emplace_back(b.lo.x(), y, z);
        pts.emplace_back(b.hi.x(), y, z);
      }
    }
  }
  for (double x = lo.x(); x <= hi.x(); x += 0.04) {
    for (double y = lo.y(); y <= hi.y(); y += 0.04) {
      bool inside = false;
      for (const auto& b : boxes) {
        inside |= x > b.lo.x() && x < b.hi.x() && y > b.lo.y() && y < b.hi.y();
      }
      if (!inside) pts.emplace_back(x, y, 0.0);
    }
  }
  return pts;
}

/// The obstacle map the robot would build from ScanPoints. The origin puts the boxes' faces
/// (multiples of 5 cm) exactly on cell boundaries: the worst case for a grid's half-cell
/// quantisation, which the maps' sub-cell return positions must absorb.
inline perception::OccupancyGrid BuildGrid(const std::vector<Box2>& boxes,
                                           perception::OccupancyGridParams params = {}) {
  const auto pts = ScanPoints(boxes, {0.0, 0.0}, {10.0, 6.0});
  const double r = params.resolution;
  const Vec2 origin(-0.5, -0.5);
  const int w = static_cast<int>(std::ceil(11.0 / r)), h = static_cast<int>(std::ceil(7.0 / r));
  perception::OccupancyGrid grid(params, origin, w, h);
  grid.InsertPoints(pts);
  return grid;
}

/// Distance (m) from `o` along unit direction `d` to the first box surface (slab test), or
/// `max_range` if none. Rays starting inside a box return 0.
inline double CastBoxes(const std::vector<Box2>& boxes, const Vec2& o, const Vec2& d,
                        double max_range) {
  double best = max_range;
  for (const auto& b : boxes) {
    double t0 = 0.0, t1 = max_range;
    bool miss = false;
    for (int a = 0; a < 2 && !miss; ++a) {
      if (std::abs(d[a]) < 1e-12) {
        miss = o[a] < b.lo[a] || o[a] > b.hi[a];
      } else {
        double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        miss = t0 > t1;
      }
    }
    if (!miss) best = std::min(best, t0);
  }
  return best;
}

/// A base LRF: 270 degrees, 0.5 degree steps, 20 m, mounted 0.1 m ahead of the axle.
inline interfaces::LrfScan EmptyBaseScan() {
  interfaces::LrfScan s;
  s.frame = "lrf_base";
  s.angle_min = DegToRad(-135.0);
  s.angle_increment = DegToRad(0.5);
  s.range_min = 0.05;
  s.range_max = 20.0;
  s.ranges.assign(541, 0.0f);
  s.X_BL = Eigen::Isometry3d::Identity();
  s.X_BL.translation() = Eigen::Vector3d(0.1, 0.0, 0.2);
  return s;
}

/// Simulates the base LRF at true pose `X_MB` against `world` (boxes the test owns, which may
/// include obstacles the robot's map lacks), with Gaussian range noise `sigma` keyed by
/// (seed, seq, beam).
inline interfaces::LrfScan SimulateScan(const std::vector<Box2>& world, const Pose2& X_MB,
                                        std::uint64_t seed, std::uint64_t seq,
                                        double sigma = 0.01) {
  interfaces::LrfScan s = EmptyBaseScan();
  s.seq = seq;
  const Eigen::Vector3d t = s.X_BL.translation();
  const double c = std::cos(X_MB.yaw), sn = std::sin(X_MB.yaw);
  const Vec2 o(X_MB.x + c * t.x() - sn * t.y(), X_MB.y + sn * t.x() + c * t.y());
  for (std::size_t k = 0; k < s.ranges.size(); ++k) {
    const double a = X_MB.yaw + s.angle_min + s.angle_increment * static_cast<double>(k);
    double r = CastBoxes(world, o, Vec2(std::cos(a), std::sin(a)), s.range_max);
    if (r < s.range_max) {
      CounterRng rng(DeriveKey(DeriveKey(seed, seq), k));
      r = std::clamp(r + sigma * rng.Normal(), static_cast<double>(s.range_min),
                     s.range_max - 1e-3);
    }
    s.ranges[k] = static_cast<float>(r);
  }
  return s;
}

}  // namespace mopad::testing
