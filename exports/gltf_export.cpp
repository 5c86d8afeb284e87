#include "exports/gltf_export.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include "common/error.h"
#include "common/polygon.h"
#include "common/rng.h"

namespace mopad::exports {
namespace {

using Vec3 = Eigen::Vector3d;
using Json = nlohmann::ordered_json;

constexpr double kOpeningOffset = 0.005;  // m, door and window quads in front of their wall

// Appends the triangles of a planar polygon (CCW seen from the tip of `n`); false when it
// cannot be triangulated (not simple, or clockwise).
bool AddPolygon(const std::vector<Vec3>& poly, const Vec3& n, io::GlbMesh& mesh) {
  if (poly.size() < 3) return false;
  const Vec3 u =
      (std::abs(n.z()) < 0.9 ? Vec3::UnitZ().cross(n) : Vec3::UnitX().cross(n)).normalized();
  const Vec3 v = n.cross(u);
  std::vector<Eigen::Vector2d> plane;
  double area2 = 0.0;
  for (const auto& q : poly) plane.emplace_back(q.dot(u), q.dot(v));
  for (std::size_t k = 0; k < plane.size(); ++k) {
    const auto& a = plane[k];
    const auto& b = plane[(k + 1) % plane.size()];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  if (area2 <= 0) return false;
  std::vector<Eigen::Vector3i> tris;
  try {
    tris = TriangulatePolygon(plane);
  } catch (const std::invalid_argument&) {
    return false;
  }
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (const auto& q : poly) mesh.positions.push_back(q.cast<float>());
  for (const auto& t : tris)
    mesh.triangles.push_back({base + static_cast<std::uint32_t>(t[0]),
                              base + static_cast<std::uint32_t>(t[1]),
                              base + static_cast<std::uint32_t>(t[2])});
  return !tris.empty();
}

// A prism over a plan footprint (CCW seen from above) from z0 to z1.
bool AddPrism(const std::vector<Vec3>& footprint, double z0, double z1, io::GlbMesh& mesh) {
  const std::size_t n = footprint.size();
  if (n < 3 || z1 <= z0) return false;
  auto at = [&](std::size_t k, double z) { return Vec3(footprint[k].x(), footprint[k].y(), z); };
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = (k + 1) % n;
    const Vec3 side_n = (at(j, z0) - at(k, z0)).cross(Vec3::UnitZ()).normalized();
    AddPolygon({at(k, z0), at(j, z0), at(j, z1), at(k, z1)}, side_n, mesh);
  }
  std::vector<Vec3> top, bottom;
  for (std::size_t k = 0; k < n; ++k) top.push_back(at(k, z1)), bottom.push_back(at(n - 1 - k, z0));
  const bool a = AddPolygon(top, Vec3::UnitZ(), mesh);
  const bool b = AddPolygon(bottom, -Vec3::UnitZ(), mesh);
  return a && b;
}

// A box centred at c with axes x (width w), y (height h), z (depth d).
void AddBox(const Vec3& c, const Vec3& x, const Vec3& y, const Vec3& z, double w, double h,
            double d, io::GlbMesh& mesh) {
  const Vec3 hx = 0.5 * w * x, hy = 0.5 * h * y, hz = 0.5 * d * z;
  const Vec3 axes[3] = {x, y, z};
  const Vec3 half[3] = {hx, hy, hz};
  for (int a = 0; a < 3; ++a) {
    const Vec3 &p = half[(a + 1) % 3], &q = half[(a + 2) % 3];
    for (int s : {1, -1}) {
      const Vec3 f = c + s * half[a];
      const Vec3 n = s * axes[a];
      std::vector<Vec3> quad = {f - p - q, f + p - q, f + p + q, f - p + q};
      if ((p.cross(q)).dot(n) < 0) std::swap(quad[1], quad[3]);
      AddPolygon(quad, n, mesh);
    }
  }
}

std::array<float, 4> ClassColour(const std::string& cls) {
  static const std::map<std::string, std::array<float, 4>> kFixed = {
      {"wall", {0.85f, 0.80f, 0.70f, 1.f}},    {"floor", {0.45f, 0.50f, 0.55f, 1.f}},
      {"ceiling", {0.95f, 0.95f, 0.95f, 1.f}}, {"column", {0.70f, 0.35f, 0.30f, 1.f}},
      {"door", {0.55f, 0.35f, 0.20f, 1.f}},    {"window", {0.55f, 0.75f, 0.95f, 0.6f}}};
  const auto it = kFixed.find(cls);
  if (it != kFixed.end()) return it->second;
  CounterRng rng(HashName(cls));  // a stable colour per component class
  return {static_cast<float>(rng.Uniform(0.2, 1.0)), static_cast<float>(rng.Uniform(0.2, 1.0)),
          static_cast<float>(rng.Uniform(0.2, 1.0)), 1.f};
}

std::string IfcClassName(const Element& e) {
  switch (e.kind) {
    case ElementKind::kWall:
      return "IfcWall";
    case ElementKind::kFloor:
      return "IfcSlab";
    case ElementKind::kCeiling:
      return "IfcCovering";
    case ElementKind::kColumn:
      return "IfcColumn";
    case ElementKind::kDoor:
      return "IfcDoor";
    case ElementKind::kWindow:
      return "IfcWindow";
    case ElementKind::kComponent:
      return ComponentIfcClass(e.class_name).entity;
  }
  return "";
}

bool AddGeometry(const Element& e, io::GlbMesh& mesh) {
  switch (e.kind) {
    case ElementKind::kColumn:
      return AddPrism(e.polygon, e.z0, e.z1, mesh);
    case ElementKind::kDoor:
    case ElementKind::kWindow: {
      std::vector<Vec3> quad;
      for (const auto& c : e.polygon) quad.push_back(c + kOpeningOffset * e.normal);
      return AddPolygon(quad, e.normal, mesh);
    }
    case ElementKind::kComponent: {
      const Vec3 z = e.normal;
      const Vec3 x0 = Vec3::UnitZ().cross(z);
      const Vec3 x = x0.norm() > 1e-6 ? x0.normalized() : Vec3::UnitX();
      const double w = e.size.x() > 0 ? e.size.x() : 0.1, h = e.size.y() > 0 ? e.size.y() : 0.1;
      const double d = e.size.z() > 0 ? e.size.z() : 0.02;
      // On its host: the back face centred at `centre` (on the host plane), depth out along z.
      AddBox(e.centre + 0.5 * d * z, x, z.cross(x), z, w, h, d, mesh);
      return true;
    }
    default:
      return AddPolygon(e.polygon, e.normal, mesh);
  }
}

}  // namespace

io::GlbScene SemanticScene(const BuildingModel& model) {
  io::GlbScene scene;
  scene.name = model.name + " (semantic)";
  std::map<std::string, int> material_of;
  // Materials of the classes present only (the validator reports unused objects).
  std::map<std::string, bool> present;
  for (const auto& e : model.elements) present[e.class_name] = e.kind == ElementKind::kComponent;
  std::vector<std::string> order;
  for (const char* cls : {"wall", "floor", "ceiling", "column", "door", "window"})
    if (present.count(cls)) order.push_back(cls);
  for (const auto& [cls, component] : present)
    if (component) order.push_back(cls);
  for (const auto& cls : order) {
    material_of[cls] = static_cast<int>(scene.materials.size());
    scene.materials.push_back({cls, ClassColour(cls)});
  }
  for (const auto& e : model.elements) {
    io::GlbMesh mesh;
    mesh.name = e.id;
    mesh.material = material_of.at(e.class_name);
    if (!AddGeometry(e, mesh) || mesh.triangles.empty()) continue;
    Json m{{"id", e.id},
           {"class", e.class_name},
           {"kind", ToString(e.kind)},
           {"room", e.room},
           {"ifc_class", IfcClassName(e)},
           {"host", e.host >= 0 ? Json(model.elements[e.host].id) : Json(nullptr)},
           {"properties", e.properties}};
    mesh.extras = {{"mopad", std::move(m)}};
    scene.meshes.push_back(std::move(mesh));
  }
  return scene;
}

int WriteSemanticGlb(const BuildingModel& model, const std::string& path) {
  const io::GlbScene scene = SemanticScene(model);
  if (scene.meshes.empty()) throw InputError(path, "no model element could be triangulated");
  io::WriteGlb(scene, path);
  return static_cast<int>(scene.meshes.size());
}

}  // namespace mopad::exports
