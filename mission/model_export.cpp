#include "mission/model_export.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "scenes/geometry.h"
#include "scenes/gltf_writer.h"
#include "scenes/scene.h"

namespace mopad::mission {

void WriteRunJson(const std::string& dir, const sim::SceneWorld& mw, const std::string& room,
                  std::uint64_t seed, const Pose3& X_WM) {
  nlohmann::ordered_json j;
  j["format"] = "mopad-room-run";
  j["version"] = 1;
  j["scene"] = mw.source;
  j["doors"] = mw.door_overrides;
  j["room"] = room;
  j["seed"] = seed;
  nlohmann::ordered_json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r)
    m.push_back(
        {X_WM.matrix()(r, 0), X_WM.matrix()(r, 1), X_WM.matrix()(r, 2), X_WM.matrix()(r, 3)});
  j["X_WM"] = m;
  j["files"] = {{"sm1", "sm1.ply"},
                {"sm2", "sm2.json"},
                {"sm3", "sm3.json"},
                {"sm4", "sm4.json"},
                {"dsm3", "dsm3.ply"}};
  const std::string path = (std::filesystem::path(dir) / "run.json").string();
  std::ofstream f(path);
  if (!f) throw InputError(path, "cannot write the file");
  f << j.dump(2) << "\n";
}

void WriteModelsGlb(const modelling::StructuralModel& sm3, const std::string& room,
                    const std::string& path) {
  scenes::Scene scene;
  scene.source = "robot model of room " +
                 room;  // the glTF scene name: not the output path (same run, same bytes)
  struct ClassStyle {
    modelling::PatchClass cls;
    scenes::ElementClass element;
    const char* name;
    Eigen::Vector4f colour;
  };
  const ClassStyle styles[] = {{modelling::PatchClass::kWall,
                                scenes::ElementClass::kWall,
                                "wall",
                                {0.85f, 0.80f, 0.70f, 1.f}},
                               {modelling::PatchClass::kFloor,
                                scenes::ElementClass::kFloor,
                                "floor",
                                {0.45f, 0.50f, 0.55f, 1.f}},
                               {modelling::PatchClass::kCeiling,
                                scenes::ElementClass::kCeiling,
                                "ceiling",
                                {0.95f, 0.95f, 0.95f, 1.f}},
                               {modelling::PatchClass::kColumn,
                                scenes::ElementClass::kColumn,
                                "column",
                                {0.70f, 0.35f, 0.30f, 1.f}}};
  for (const auto& s : styles) {
    scenes::Material m;
    m.name = s.name;
    m.base_color = s.colour;
    scene.materials.push_back(m);
  }
  for (const auto& p : sm3.patches) {
    if (p.polygon.size() < 3) continue;
    int style = 0;
    for (int k = 0; k < 4; ++k)
      if (styles[k].cls == p.patch_class) style = k;
    // Triangulate in the patch's plane (u, v with u x v = n: CCW stays CCW).
    const Eigen::Vector3d n = p.plane.n.normalized();
    const Eigen::Vector3d u = (std::abs(n.z()) < 0.9 ? Eigen::Vector3d::UnitZ().cross(n)
                                                     : Eigen::Vector3d::UnitX().cross(n))
                                  .normalized();
    const Eigen::Vector3d v = n.cross(u);
    scenes::Polygon2 poly;
    for (const auto& q : p.polygon) poly.emplace_back(q.dot(u), q.dot(v));
    if (scenes::SignedArea(poly) < 0) continue;  // not CCW seen from the room: skip, never flip
    scenes::MeshPart part;
    part.name = room + "/" + p.id;
    part.element_id = room + "/" + p.id;
    part.element_class = styles[style].element;
    part.room = room;
    part.material = style;
    for (const auto& q : p.polygon) part.positions.push_back(q.cast<float>());
    part.triangles = scenes::TriangulatePolygon(poly);
    if (part.triangles.empty()) continue;
    scene.parts.push_back(std::move(part));
  }
  if (scene.parts.empty())
    throw InputError(path, "no patch of the structural model could be triangulated");
  scenes::WriteGlb(scene, path);
}

}  // namespace mopad::mission
