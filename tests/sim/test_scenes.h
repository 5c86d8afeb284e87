#pragma once
// Tiny scenes built in code with analytic answers, for the simulator tests.

#include <Eigen/Core>
#include <string>

#include "scenes/ground_truth.h"
#include "scenes/scene.h"

namespace mopad::sim::testing {

using scenes::ElementClass;

/// Adds a planar quad p0 p1 p2 p3 (CCW seen from the front) as one part; UVs (0,0) (1,0) (1,1)
/// (0,1) scaled by `uv_scale`. Returns the part index.
inline int AddQuad(scenes::Scene& s, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                   const Eigen::Vector3f& p2, const Eigen::Vector3f& p3, ElementClass cls,
                   const std::string& id, int material = -1, float uv_scale = 1.0f) {
  scenes::MeshPart p;
  p.name = id;
  p.element_id = id;
  p.element_class = cls;
  p.material = material;
  p.positions = {p0, p1, p2, p3};
  p.uvs = {Eigen::Vector2f(0, 0), Eigen::Vector2f(uv_scale, 0), Eigen::Vector2f(uv_scale, uv_scale),
           Eigen::Vector2f(0, uv_scale)};
  p.triangles = {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(0, 2, 3)};
  s.parts.push_back(std::move(p));
  return static_cast<int>(s.parts.size()) - 1;
}

/// Axis-aligned box with faces pointing inwards: floor, ceiling and four walls as six parts.
inline void AddRoomBox(scenes::Scene& s, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                       int material = -1, const std::string& prefix = "") {
  const float x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  using V = Eigen::Vector3f;
  AddQuad(s, V(x0, y0, z0), V(x1, y0, z0), V(x1, y1, z0), V(x0, y1, z0), ElementClass::kFloor,
          prefix + "floor", material);
  AddQuad(s, V(x0, y0, z1), V(x0, y1, z1), V(x1, y1, z1), V(x1, y0, z1), ElementClass::kCeiling,
          prefix + "ceiling", material);
  AddQuad(s, V(x0, y0, z0), V(x0, y0, z1), V(x1, y0, z1), V(x1, y0, z0), ElementClass::kWall,
          prefix + "wall_s", material);
  AddQuad(s, V(x1, y0, z0), V(x1, y0, z1), V(x1, y1, z1), V(x1, y1, z0), ElementClass::kWall,
          prefix + "wall_e", material);
  AddQuad(s, V(x1, y1, z0), V(x1, y1, z1), V(x0, y1, z1), V(x0, y1, z0), ElementClass::kWall,
          prefix + "wall_n", material);
  AddQuad(s, V(x0, y1, z0), V(x0, y1, z1), V(x0, y0, z1), V(x0, y0, z0), ElementClass::kWall,
          prefix + "wall_w", material);
}

/// Room [0,W]x[0,D]x[0,H] whose east wall (x = W) has a rectangular opening
/// y in [oy0, oy1], z in [oz0, oz1] (the wall is built from four quads around it).
inline void AddRoomWithOpening(scenes::Scene& s, float W, float D, float H, float oy0, float oy1,
                               float oz0, float oz1, int material = -1) {
  using V = Eigen::Vector3f;
  AddQuad(s, V(0, 0, 0), V(W, 0, 0), V(W, D, 0), V(0, D, 0), ElementClass::kFloor, "floor",
          material);
  AddQuad(s, V(0, 0, H), V(0, D, H), V(W, D, H), V(W, 0, H), ElementClass::kCeiling, "ceiling",
          material);
  AddQuad(s, V(0, 0, 0), V(0, 0, H), V(W, 0, H), V(W, 0, 0), ElementClass::kWall, "wall_s",
          material);
  AddQuad(s, V(W, D, 0), V(W, D, H), V(0, D, H), V(0, D, 0), ElementClass::kWall, "wall_n",
          material);
  AddQuad(s, V(0, D, 0), V(0, D, H), V(0, 0, H), V(0, 0, 0), ElementClass::kWall, "wall_w",
          material);
  // East wall pieces around the opening (all element "wall_e").
  AddQuad(s, V(W, 0, 0), V(W, 0, H), V(W, oy0, H), V(W, oy0, 0), ElementClass::kWall, "wall_e",
          material);
  AddQuad(s, V(W, oy1, 0), V(W, oy1, H), V(W, D, H), V(W, D, 0), ElementClass::kWall, "wall_e",
          material);
  AddQuad(s, V(W, oy0, 0), V(W, oy0, oz0), V(W, oy1, oz0), V(W, oy1, 0), ElementClass::kWall,
          "wall_e", material);
  AddQuad(s, V(W, oy0, oz1), V(W, oy0, H), V(W, oy1, H), V(W, oy1, oz1), ElementClass::kWall,
          "wall_e", material);
}

/// Distance from p along unit d to the inside of the box [lo, hi] (p inside).
inline double BoxExitDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                              const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double t = 1e300;
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 1e-15) t = std::min(t, (hi[a] - p[a]) / d[a]);
    if (d[a] < -1e-15) t = std::min(t, (lo[a] - p[a]) / d[a]);
  }
  return t;
}

/// A matte material with the given linear base colour (no texture).
inline int AddMaterial(scenes::Scene& s, const std::string& name, float r, float g, float b,
                       float metallic = 0.f, float roughness = 1.f, float transmission = 0.f,
                       float nir = -1.f) {
  scenes::Material m;
  m.name = name;
  m.base_color = Eigen::Vector4f(r, g, b, 1.f);
  m.metallic = metallic;
  m.roughness = roughness;
  m.transmission = transmission;
  m.nir_reflectance = nir;
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size()) - 1;
}

}  // namespace mopad::sim::testing
