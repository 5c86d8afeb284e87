// The scene generator's run and result: the order of its steps, materials and labelled parts,
// the final truth (rooms, facades, unique ids), the helpers its steps share, and the public API
// (scenes/generator.h). The steps themselves live in the generator_*.cpp files named in
// scenes/generator_internal.h.
#include "scenes/generator.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "common/atomic_file.h"
#include "common/error.h"
#include "scenes/as_built.h"
#include "scenes/generator_internal.h"
#include "scenes/gltf_writer.h"

namespace mopad::scenes::gen {

Polygon2 OrientedRect(const Vector2d& c, double yaw, double w, double d) {
  const Vector2d ex(std::cos(yaw), std::sin(yaw)), ey(-std::sin(yaw), std::cos(yaw));
  return {c - 0.5 * w * ex - 0.5 * d * ey, c + 0.5 * w * ex - 0.5 * d * ey,
          c + 0.5 * w * ex + 0.5 * d * ey, c - 0.5 * w * ex + 0.5 * d * ey};
}

double DistanceToConvex(const Vector2d& p, const Polygon2& poly) {
  if (PointInPolygon(p, poly)) return 0.0;
  return DistanceToBoundary(p, poly);
}

std::size_t PickWeighted(CounterRng& rng, const std::vector<double>& w) {
  double total = 0.0;
  for (double x : w) total += x;
  double r = rng.Uniform() * total;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (r < w[i]) return i;
    r -= w[i];
  }
  return w.size() - 1;
}

GeneratedScene Generator::Run() {
  ValidateSceneSpec(spec_);
  out_.spec = spec_;
  out_.scene.source = "generated:" + spec_.name;
  out_.truth.scene_name = spec_.name;
  out_.truth.storeys.push_back({"storey_0", 0.0, spec_.storey_height});
  BuildRooms();
  ComputeAdjacency();
  ResolveDoors();
  ResolveWindows();
  CheckColumns();
  EmitWalls();
  EmitFacades();
  EmitFloorsAndCeilings();
  EmitColumns();
  EmitDoors();
  EmitWindows();
  PlaceBscs();
  PlaceFurniture();
  PlaceDetails();
  Finish();
  // The building as built: every vertex moved by one smooth field, the truth's design kept
  // and the field recorded beside it.
  ApplyAsBuilt(spec_.as_built, &out_.scene);
  out_.truth.as_built = spec_.as_built;
  return std::move(out_);
}

int Generator::Mat(const std::string& name, const MaterialSpec& m) {
  auto it = materials_.find(name);
  if (it != materials_.end()) return it->second;
  Material mat;
  mat.name = name;
  mat.base_color = Eigen::Vector4f(static_cast<float>(m.colour[0]), static_cast<float>(m.colour[1]),
                                   static_cast<float>(m.colour[2]), 1.0f);
  mat.roughness = static_cast<float>(m.roughness);
  mat.metallic = static_cast<float>(m.metallic);
  mat.transmission = static_cast<float>(m.transmission);
  mat.nir_reflectance = static_cast<float>(m.nir_reflectance);
  mat.double_sided = true;
  const int idx = static_cast<int>(out_.scene.materials.size());
  out_.scene.materials.push_back(mat);
  materials_[name] = idx;
  return idx;
}

MeshPart Generator::NewPart(const std::string& name, const std::string& id, ElementClass cls,
                            const std::string& subclass, const std::string& room, int material) {
  MeshPart p;
  p.name = name;
  p.element_id = id;
  p.element_class = cls;
  p.subclass = subclass;
  p.room = room;
  p.material = material;
  return p;
}

void Generator::Push(MeshPart&& p) {
  if (!p.triangles.empty()) out_.scene.parts.push_back(std::move(p));
}

void Generator::Finish() {
  // Facade elements go last so that walls, floors, ceilings and columns keep their order.
  for (auto& e : facades_) out_.truth.elements.push_back(std::move(e));
  std::set<std::string> ids;
  auto add = [&](const std::string& id) {
    if (!ids.insert(id).second)
      throw InputError(spec_.source, "generated id '" + id + "' is not unique", "",
                       "spec ids that do not clash with generated ones");
  };
  for (const auto& e : out_.truth.elements) add(e.id);
  for (const auto& o : out_.truth.openings) add(o.id);
  for (const auto& b : out_.truth.service_components) add(b.id);
  for (const auto& f : out_.truth.furniture) add(f.id);
  for (const auto& d : out_.truth.details) add(d.id);
  for (const RoomData& r : rooms_) {
    Room room;
    room.id = r.id;
    room.storey = "storey_0";
    room.polygon = r.poly;
    room.floor_z = r.z0;
    room.ceiling_z = r.z1;
    out_.truth.rooms.push_back(room);
  }
}

}  // namespace mopad::scenes::gen

namespace mopad::scenes {

GeneratedScene Generate(const SceneSpec& spec) { return gen::Generator(spec).Run(); }

void WriteGeneratedScene(const GeneratedScene& generated, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory", ec.message());
  const std::filesystem::path d(dir);
  WriteGlb(generated.scene, (d / "scene.glb").string());
  WriteGroundTruth(generated.truth, (d / "scene.truth.json").string());
  WriteWholeFile((d / "spec.effective.yaml").string(),
                 "# Effective scene spec (defaults filled in); regenerate with\n"
                 "#   mopad scene generate spec.effective.yaml -o DIR\n" +
                     SceneSpecToYaml(generated.spec));
}

}  // namespace mopad::scenes
