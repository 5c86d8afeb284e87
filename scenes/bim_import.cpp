// The BIM import's entry points and its result: the public API (parameters, door angles, the
// import, the writer), the order of the import's steps, and the assembly of scene and truth from
// the buckets of pieces the steps filled. The steps themselves live in the bim_*.cpp files
// named in scenes/bim_import_internal.h.
#include "scenes/bim_import.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "scenes/bim_import_internal.h"
#include "scenes/gltf_writer.h"

namespace mopad::scenes::bim {

std::string Fmt(double v, int precision) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -precision)) v = 0.0;  // no "-0.000"
  return FormatFixed(v, precision);
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

Bucket& Output::Get(const std::string& id, ElementClass cls, const std::string& subclass,
                    const std::string& room, int material, const std::string& name) {
  const std::string key = id + "\x1f" + std::to_string(static_cast<int>(cls)) + "\x1f" + subclass +
                          "\x1f" + room + "\x1f" + std::to_string(material);
  auto it = index_.find(key);
  if (it == index_.end()) {
    it = index_.emplace(key, buckets_.size()).first;
    Bucket b;
    b.id = id;
    b.cls = cls;
    b.subclass = subclass;
    b.room = room;
    b.material = material;
    b.name = (name.empty() ? id : name) + "/" + std::to_string(buckets_.size());
    buckets_.push_back(std::move(b));
  }
  return buckets_[it->second];
}

std::vector<MeshPart> Output::Parts() const {
  std::vector<MeshPart> parts;
  for (const Bucket& b : buckets_) {
    if (b.pieces.empty()) continue;
    MeshPart& p = parts.emplace_back();
    p.name = b.name;
    p.element_id = b.id;
    p.element_class = b.cls;
    p.subclass = b.subclass;
    p.room = b.room;
    p.material = b.material;
    std::map<std::array<float, 3>, int> vertex;
    auto v = [&](const Vector3d& x) {
      const std::array<float, 3> key{static_cast<float>(x.x()), static_cast<float>(x.y()),
                                     static_cast<float>(x.z())};
      auto [it, fresh] = vertex.emplace(key, static_cast<int>(p.positions.size()));
      if (fresh) p.positions.emplace_back(key[0], key[1], key[2]);
      return it->second;
    };
    for (const Poly3& poly : b.pieces)
      for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
        const Eigen::Vector3i t(v(poly[0]), v(poly[i]), v(poly[i + 1]));
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) p.triangles.push_back(t);
      }
    if (p.triangles.empty()) parts.pop_back();
  }
  return parts;
}

BimImport Importer::Run() {
  p_.Validate();
  Load();
  SelectStorey();
  MakeRooms();
  ResolveHeights();
  Shift();
  MakeFaces();
  FindWallPlanes();
  DistributeStructure();
  FinishFaces();
  FloorsAndCeilings();
  SlopedCeilings();
  Columns();
  Openings();
  Doorways();
  Passages();
  Components();
  Finish();
  if (!needed_.empty()) {
    std::vector<std::string> lines;
    std::set<std::string> options;
    for (const auto& [line, option] : needed_) {
      lines.push_back(line + " (" + option + ")");
      if (option != "--repair") options.insert(option);
    }
    std::string flags;
    for (const std::string& o : options) flags += (flags.empty() ? "" : ", ") + o;
    if (!flags.empty()) flags += " ";
    const std::string what = FormatError(
        path_,
        "the file needs " + std::to_string(lines.size()) + " repair(s); the first: " +
            needed_.front().first.substr(needed_.front().first.find(' ') + 1),
        "", flags + "or --repair, which applies them all");
    throw BimRepairsNeeded(what, std::move(lines));
  }
  return std::move(out_);
}

void Importer::Repair(const std::string& what, const std::string& where, const std::string& from,
                      const std::string& to, bool allowed, const std::string& option) {
  const std::string line = "repair: " + what + " " + where + ": " + from + " -> " + to;
  if (allowed)
    out_.repairs.push_back(line);
  else if (p_.as_is)
    out_.report.push_back("as it is: " + what + " " + where + ": " + from + " (not repaired)");
  else
    needed_.emplace_back(line, option);
}

void Importer::Finish() {
  for (const auto& [key, deg] : p_.door_angles_deg)
    if (!used_door_keys_.count(key))
      throw InputError(path_, "--doors names no door of this storey", "'" + key + "'",
                       "a door id (D1), IFC GlobalId or IFC Name");
  out_.truth.scene_name = CleanUtf8(std::filesystem::path(path_).stem().string());
  for (const RoomData& r : rooms_) out_.truth.rooms.push_back(r.room);
  for (const auto& w : walls_) out_.truth.elements.push_back(w);
  for (const auto& f : floors_) out_.truth.elements.push_back(f);
  for (const auto& c : ceilings_)
    if (!c.polygons.empty()) out_.truth.elements.push_back(c);
  for (const auto& c : sloped_ceilings_) out_.truth.elements.push_back(c);
  for (const auto& c : columns_) out_.truth.elements.push_back(c);
  std::set<std::string> emitted;
  for (const Bucket& b : out_bucket_.buckets()) {
    if (b.cls != ElementClass::kOther || b.pieces.empty() || !emitted.insert(b.id).second) continue;
    StructuralElement s;
    s.id = b.id;
    s.element_class = ElementClass::kOther;
    out_.truth.elements.push_back(s);
  }
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    bool contained = false;
    for (std::size_t pi : elements_[i].parts) contained = contained || storey_parts_.count(pi);
    if (contained && !elements_[i].merged) ++out_.storey_elements[elements_[i].ifc];
  }
  out_.walls_with_room_faces = static_cast<int>(walls_with_faces_.size());
  std::string counts;
  for (const auto& [cls, n] : out_.storey_elements)
    counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + cls;
  out_.report.push_back("IFC elements with geometry on the storey: " + counts);
  out_.report.push_back(std::to_string(out_.walls_with_room_faces) +
                        " IFC wall(s) give the room-side wall faces");
  out_.scene.source = path_;
  // Only the materials (and their textures) the parts use, in order of first use.
  out_.scene.parts = out_bucket_.Parts();
  std::map<int, int> material_index, texture_index;
  for (MeshPart& part : out_.scene.parts) {
    if (part.material < 0) continue;
    auto [it, fresh] =
        material_index.emplace(part.material, static_cast<int>(out_.scene.materials.size()));
    if (fresh) {
      Material m = scene_.materials[static_cast<std::size_t>(part.material)];
      // The format's materials are all double-sided; BIM solids' winding varies.
      m.double_sided = true;
      if (m.base_color_texture >= 0) {
        auto [t, new_texture] = texture_index.emplace(m.base_color_texture,
                                                      static_cast<int>(out_.scene.textures.size()));
        if (new_texture)
          out_.scene.textures.push_back(
              scene_.textures[static_cast<std::size_t>(m.base_color_texture)]);
        m.base_color_texture = t->second;
      }
      out_.scene.materials.push_back(m);
    }
    part.material = it->second;
  }
  // Every truth id once across elements, openings, components and furniture (two IFC elements
  // sharing a GlobalId would clash).
  std::set<std::string> ids;
  std::vector<std::string> all;
  for (const auto& e : out_.truth.elements) all.push_back(e.id);
  for (const auto& o : out_.truth.openings) all.push_back(o.id);
  for (const auto& c : out_.truth.service_components) all.push_back(c.id);
  for (const auto& f : out_.truth.furniture) all.push_back(f.id);
  for (const std::string& id : all)
    if (!ids.insert(id).second)
      throw InputError(path_, "two elements have the same id", "'" + id + "'",
                       "unique IFC GlobalIds");
}

}  // namespace mopad::scenes::bim

namespace mopad::scenes {

void BimImportParams::Validate() const {
  auto range = [](const std::string& field, double v, double lo, double hi, bool open_lo) {
    if (!std::isfinite(v) || v > hi || (open_lo ? v <= lo : v < lo))
      throw InputError(
          "", "import parameter " + field + " out of range", bim::Fmt(v, 4),
          std::string(open_lo ? "(" : "[") + bim::Fmt(lo, 3) + ", " + bim::Fmt(hi, 3) + "]");
  };
  range("door_angle_deg", door_angle_deg, 0.0, 180.0, false);
  for (const auto& [id, deg] : door_angles_deg) range("doors " + id, deg, 0.0, 180.0, false);
  range("leaf_thickness", leaf_thickness, 0.0, 0.2, true);
  range("plane_tolerance", plane_tolerance, 0.0, 0.05, true);
  range("component_snap", component_snap, 0.0, 0.5, false);
  range("min_face_area", min_face_area, 0.0, 1e3, true);
  range("wall_search", wall_search, 0.0, 1.0, false);
}

BimImport ImportBim(const std::string& path, const BimImportParams& params) {
  return bim::Importer(path, params).Run();
}

void WriteBimImport(const BimImport& imported, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory", ec.message());
  const std::filesystem::path d(dir);
  WriteGlb(imported.scene, (d / "scene.glb").string());
  WriteGroundTruth(imported.truth, (d / "scene.truth.json").string());
}

}  // namespace mopad::scenes
