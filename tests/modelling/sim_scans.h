#pragma once
// Simulated input for the room-model and next-best-scan tests: scenes built in code or
// generated from scenes/*.yaml, TLS scans taken with sim::TlsScanner, and the truth labels the
// evaluator would give (tests only: the robot-side libraries never see these).

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "interfaces/tls_scan.h"
#include "scenes/generator.h"
#include "scenes/ground_truth.h"
#include "scenes/scene.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/tls_scanner.h"
#include "tests/sim/test_scenes.h"

namespace mopad::modelling::testing {

using V3 = Eigen::Vector3f;
using scenes::ElementClass;

/// Closed axis-aligned box [lo, hi] with outward faces (furniture, a column, ...).
inline void AddBox(scenes::Scene& s, const V3& lo, const V3& hi, ElementClass cls,
                   const std::string& id, const std::string& room = "") {
  const float x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  using sim::testing::AddQuad;
  const std::size_t first = s.parts.size();
  AddQuad(s, V3(x0, y0, z1), V3(x1, y0, z1), V3(x1, y1, z1), V3(x0, y1, z1), cls, id);  // top
  AddQuad(s, V3(x0, y0, z0), V3(x0, y1, z0), V3(x1, y1, z0), V3(x1, y0, z0), cls, id);  // bottom
  AddQuad(s, V3(x0, y0, z0), V3(x1, y0, z0), V3(x1, y0, z1), V3(x0, y0, z1), cls, id);  // -y
  AddQuad(s, V3(x1, y0, z0), V3(x1, y1, z0), V3(x1, y1, z1), V3(x1, y0, z1), cls, id);  // +x
  AddQuad(s, V3(x1, y1, z0), V3(x0, y1, z0), V3(x0, y1, z1), V3(x1, y1, z1), cls, id);  // +y
  AddQuad(s, V3(x0, y1, z0), V3(x0, y0, z0), V3(x0, y0, z1), V3(x0, y1, z1), cls, id);  // -x
  for (std::size_t i = first; i < s.parts.size(); ++i) s.parts[i].room = room;
}

/// A room [0,W]x[0,D]x[0,H] (parts of room "R") whose east wall (x = W) has a door opening
/// y in [oy0, oy1], z in [0, door_h], inside a larger hall (room "out") so that beams through
/// the door hit something: a desk-sized box in the room, a cabinet in the hall. The hall's
/// ceiling is at `hall_h` (default: the room's); it reaches `hall_depth` m beyond the room.
inline scenes::Scene RoomWithDoorScene(float W = 6, float D = 4, float H = 2.7f, float oy0 = 1.5f,
                                       float oy1 = 2.4f, float door_h = 2.1f, float hall_h = -1.0f,
                                       float hall_depth = 5.0f) {
  scenes::Scene s;
  sim::testing::AddRoomWithOpening(s, W, D, H, oy0, oy1, 0.0f, door_h);
  const std::string room_id = "R";
  for (auto& p : s.parts) p.room = room_id;
  const std::size_t hall = s.parts.size();
  // 1 mm below the floor and above the ceiling: the room's own floor and ceiling win inside it.
  sim::testing::AddRoomBox(s, V3(-0.2f, -3.0f, -0.001f),
                           V3(W + hall_depth, D + 3.0f, hall_h > 0.0f ? hall_h : H + 0.001f), -1,
                           "hall_");
  for (std::size_t i = hall; i < s.parts.size(); ++i) s.parts[i].room = "out";
  // The room's walls are 0.2 m thick: outer faces of the south, north and east walls.
  // (1 mm clear of the room's faces, so that those are what the scanner hits from inside.)
  const float e = 0.001f;
  AddBox(s, V3(0.0f, -0.2f, 0.0f), V3(W + 0.2f, -e, H), ElementClass::kOther, "wall_s_outer",
         "out");
  AddBox(s, V3(0.0f, D + e, 0.0f), V3(W + 0.2f, D + 0.2f, H), ElementClass::kOther, "wall_n_outer",
         "out");
  AddBox(s, V3(W + e, 0.0f, door_h + e), V3(W + 0.2f, D, H), ElementClass::kOther, "lintel", "out");
  AddBox(s, V3(W + e, 0.0f, 0.0f), V3(W + 0.2f, oy0 - e, door_h), ElementClass::kOther, "wall_e_a",
         "out");
  AddBox(s, V3(W + e, oy1 + e, 0.0f), V3(W + 0.2f, D, door_h), ElementClass::kOther, "wall_e_b",
         "out");
  AddBox(s, V3(2.4f, 3.1f, 0.0f), V3(3.6f, 3.7f, 0.75f), ElementClass::kFurniture, "desk", "R");
  AddBox(s, V3(W + 2.0f, 1.0f, 0.0f), V3(W + 3.0f, 3.0f, 1.8f), ElementClass::kFurniture, "cabinet",
         "out");
  return s;
}

/// L-shaped room: leg A x in [0,10], y in [0,3]; leg B x in [7,10], y in [0,10]; height H.
inline scenes::Scene LRoomScene(float H = 2.7f) {
  scenes::Scene s;
  using sim::testing::AddQuad;
  const ElementClass W = ElementClass::kWall;
  // Floor and ceiling: two rectangles each.
  AddQuad(s, V3(0, 0, 0), V3(7, 0, 0), V3(7, 3, 0), V3(0, 3, 0), ElementClass::kFloor, "floor");
  AddQuad(s, V3(7, 0, 0), V3(10, 0, 0), V3(10, 10, 0), V3(7, 10, 0), ElementClass::kFloor, "floor");
  AddQuad(s, V3(0, 0, H), V3(0, 3, H), V3(7, 3, H), V3(7, 0, H), ElementClass::kCeiling, "ceiling");
  AddQuad(s, V3(7, 0, H), V3(7, 10, H), V3(10, 10, H), V3(10, 0, H), ElementClass::kCeiling,
          "ceiling");
  // Walls around the outline (0,0) (10,0) (10,10) (7,10) (7,3) (0,3).
  const std::vector<Eigen::Vector2f> o = {{0, 0}, {10, 0}, {10, 10}, {7, 10}, {7, 3}, {0, 3}};
  for (std::size_t i = 0; i < o.size(); ++i) {
    const auto& a = o[i];
    const auto& b = o[(i + 1) % o.size()];
    AddQuad(s, V3(a.x(), a.y(), 0), V3(b.x(), b.y(), 0), V3(b.x(), b.y(), H), V3(a.x(), a.y(), H),
            W, "wall_" + std::to_string(i));
  }
  for (auto& p : s.parts) p.room = "L";
  return s;
}

/// Default scanner profile with a coarser step (fast tests); noise on.
inline sim::TlsParams TestTls(double step_deg = 0.4) {
  sim::TlsParams p = sim::TlsProfile("riegl_vz400");
  p.step_deg = step_deg;
  return p;
}

struct SimScan {
  interfaces::TlsScan scan;
  sim::TlsTruth truth;
  Pose3 X_MS = Pose3::Identity();  ///< true scanner pose (map = world in these tests)
};

inline SimScan TakeScan(const sim::EmbreeWorld& world, const sim::TlsParams& params, double x,
                        double y, std::uint64_t scan_id, std::uint64_t seed = 5) {
  sim::TlsScanner scanner(world, params);
  sim::ScanRequest req;
  req.seed = seed;
  req.scan_id = scan_id;
  req.X_WB = Pose3::Identity();
  req.X_WB.translation() = Eigen::Vector3d(x, y, 0.0);
  SimScan out;
  out.scan = scanner.Scan(req, &out.truth);
  out.X_MS = out.truth.X_WS;
  return out;
}

/// Truth label of every valid point of `s` for room `room` (plan polygon `polygon`), the
/// evaluator's rule: structural surface of this room -> inlier; seen through glass or outside
/// the room polygon -> outlier; anything else -> clutter. Values as modelling::PointLabel.
inline std::vector<std::uint8_t> TruthLabels(const SimScan& s, const scenes::Scene& scene,
                                             const std::string& room,
                                             const std::vector<Eigen::Vector2d>& polygon) {
  std::vector<std::uint8_t> out;
  for (std::uint32_t c = 0; c < s.scan.columns; ++c) {
    for (std::uint32_t r = 0; r < s.scan.rows; ++r) {
      const auto& p = s.scan.at(r, c);
      if (!p.valid()) continue;
      const auto& t = s.truth.at(r, c);
      const Eigen::Vector3d q = s.X_MS * Eigen::Vector3d(p.x, p.y, p.z);
      std::uint8_t label = 3;
      const scenes::MeshPart* part = t.part >= 0 ? &scene.parts[t.part] : nullptr;
      const bool structural = part && (part->element_class == ElementClass::kWall ||
                                       part->element_class == ElementClass::kFloor ||
                                       part->element_class == ElementClass::kCeiling ||
                                       part->element_class == ElementClass::kColumn);
      if (t.flags & sim::kTruthTransmitted) {
        label = 2;
      } else if (structural && part->room == room) {
        label = 1;
      } else {
        // Outside the polygon by more than the evaluator's margin (2 cm).
        bool inside = false;
        const std::size_t n = polygon.size();
        double dmin = 1e300;
        for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
          const Eigen::Vector2d& a = polygon[i];
          const Eigen::Vector2d& b = polygon[j];
          if ((a.y() > q.y()) != (b.y() > q.y()) &&
              q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x()) {
            inside = !inside;
          }
          const Eigen::Vector2d ab = b - a;
          const double u = std::clamp((q.head<2>() - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
          dmin = std::min(dmin, (q.head<2>() - (a + u * ab)).norm());
        }
        label = (!inside && dmin > 0.02) ? 2 : 3;  // evaluation/scan_eval.h outside_margin
      }
      out.push_back(label);
    }
  }
  return out;
}

}  // namespace mopad::modelling::testing
