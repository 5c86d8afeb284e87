#include "scenes/ifc4_loader.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

// IfcPlusPlus (2019 snapshot) and carve: warnings of their headers are theirs.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <ifcpp/IFC4/include/IfcAnnotation.h>
#include <ifcpp/IFC4/include/IfcFeatureElementSubtraction.h>
#include <ifcpp/IFC4/include/IfcProject.h>
#include <ifcpp/IFC4/include/IfcRelAggregates.h>
#include <ifcpp/IFC4/include/IfcRelContainedInSpatialStructure.h>
#include <ifcpp/IFC4/include/IfcSpace.h>
#include <ifcpp/IFC4/include/IfcSpatialElement.h>
#include <ifcpp/geometry/Carve/GeometryConverter.h>
#include <ifcpp/model/BuildingModel.h>
#include <ifcpp/reader/ReaderSTEP.h>

#include <carve/triangulator.hpp>
#pragma GCC diagnostic pop

#include "common/error.h"
#include "scenes/assimp_loader.h"
#include "scenes/bim_import_internal.h"
#include "scenes/child_reader.h"
#include "scenes/mesh_validation.h"

namespace mopad::scenes {
namespace {

// --- IfcPlusPlus's model and geometry to parts (runs in the child) ---

class Ifc4SceneBuilder {
 public:
  Ifc4SceneBuilder(shared_ptr<BuildingModel> model, GeometryConverter* conv,
                   const bim::StepIndex& step, double scale, bool spaces)
      : model_(std::move(model)), conv_(*conv), step_(step), scale_(scale), spaces_(spaces) {}

  Scene Build() {
    // Roots: what the project aggregates (the site, or a building without a site), as assimp
    // starts at the project's first spatial element.
    const auto& entities = model_->getMapIfcEntities();
    for (const auto& [id, entity] : entities) {
      const auto project = dynamic_pointer_cast<IfcProject>(entity);
      if (!project) continue;
      for (const auto& rel_weak : project->m_IsDecomposedBy_inverse) {
        const shared_ptr<IfcRelAggregates> rel = rel_weak.lock();
        if (!rel) continue;
        for (const auto& child : rel->m_RelatedObjects) Visit(child, "");
      }
    }
    return std::move(scene_);
  }

 private:
  // `<IfcClass>_<Name without white space>_<GlobalId>`, the strings decoded from the STEP text
  // as the IFC 2x3 path's STEP readers decode them ("Unnamed" when Name is unset, as assimp).
  std::string NodeName(const IfcObjectDefinition& od) const {
    const auto body = step_.bodies.find(static_cast<unsigned long>(od.m_entity_id));
    const std::vector<std::string> a =
        body == step_.bodies.end() ? std::vector<std::string>{} : bim::Attributes(body->second);
    const std::string name = a.size() > 2 && a[2] != "$" ? bim::StepString(a[2]) : "Unnamed";
    const std::string guid = a.empty() ? "" : bim::StepString(a[0]);
    return std::string(od.className()) + "_" + bim::NoSpaces(name) + "_" + guid;
  }

  void Visit(const shared_ptr<IfcObjectDefinition>& od, const std::string& parent) {
    if (!od || !visited_.insert(od->m_entity_id).second) return;
    if (dynamic_pointer_cast<IfcFeatureElementSubtraction>(od)) return;  // cut from the host
    if (dynamic_pointer_cast<IfcAnnotation>(od)) return;                 // 2D drawing
    const std::string name = NodeName(*od);
    const std::string path = parent.empty() ? name : parent + "/" + name;
    AddGeometry(*od, path, name);
    // Elements contained in a spatial element hang directly below it.
    if (const auto spatial = dynamic_pointer_cast<IfcSpatialElement>(od)) {
      for (const auto& rel_weak : spatial->m_ContainsElements_inverse) {
        const shared_ptr<IfcRelContainedInSpatialStructure> rel = rel_weak.lock();
        if (!rel) continue;
        for (const auto& e : rel->m_RelatedElements) Visit(e, path);
      }
    }
    // Aggregated parts (storeys of a building, spaces of a storey, parts of a stair).
    for (const auto& rel_weak : od->m_IsDecomposedBy_inverse) {
      const shared_ptr<IfcRelAggregates> rel = rel_weak.lock();
      if (!rel) continue;
      for (const auto& child : rel->m_RelatedObjects) Visit(child, path + "/$RelAggregates");
    }
  }

  static bool IsBody(const std::wstring& id) { return id == L"Body"; }
  static bool IsNotGeometry(const std::wstring& id) {
    static const std::set<std::wstring> kOther = {
        L"Axis",     L"FootPrint", L"Box", L"Annotation", L"Profile", L"Clearance",
        L"Lighting", L"Reference", L"CoG", L"Plan",       L"Survey",  L"Surface"};
    return kOther.count(id) > 0;
  }

  void AddGeometry(const IfcObjectDefinition& od, const std::string& path,
                   const std::string& node) {
    if (!spaces_ && dynamic_cast<const IfcSpace*>(&od) != nullptr) return;
    const auto it = conv_.getShapeInputData().find(od.m_entity_id);
    if (it == conv_.getShapeInputData().end() || !it->second) return;
    ProductShapeData& shape = *it->second;
    bool has_body = false;
    for (const auto& rep : shape.m_vec_representations)
      has_body = has_body || (rep && IsBody(rep->m_representation_identifier));
    const carve::math::Matrix t = shape.getTransform();
    const std::string cls = od.className();
    for (const auto& rep : shape.m_vec_representations) {
      if (!rep) continue;
      const std::wstring& id = rep->m_representation_identifier;
      if (has_body ? !IsBody(id) : IsNotGeometry(id)) continue;
      for (const auto& item : rep->m_vec_item_data) {
        if (!item) continue;
        MeshPart part;
        part.name = path;
        part.element_id = node;
        part.subclass = cls;
        part.element_class = FromIfcClass(cls);
        part.material = MaterialOf(*item, *rep, shape);
        for (const auto* sets : {&item->m_meshsets, &item->m_meshsets_open})
          for (const auto& ms : *sets)
            if (ms) AddMeshSet(*ms, t, &part);
        if (!part.triangles.empty()) scene_.parts.push_back(std::move(part));
      }
    }
  }

  void AddMeshSet(const carve::mesh::MeshSet<3>& ms, const carve::math::Matrix& t, MeshPart* part) {
    std::map<const carve::mesh::Vertex<3>*, int> index;
    auto vertex = [&](const carve::mesh::Vertex<3>* v) {
      const auto [it, fresh] = index.emplace(v, static_cast<int>(part->positions.size()));
      if (fresh) {
        const carve::geom::vector<3> p = t * v->v;
        part->positions.emplace_back(static_cast<float>(p.x * scale_),
                                     static_cast<float>(p.y * scale_),
                                     static_cast<float>(p.z * scale_));
      }
      return it->second;
    };
    for (const carve::mesh::Mesh<3>* mesh : ms.meshes) {
      for (const carve::mesh::Face<3>* face : mesh->faces) {
        const std::size_t n = face->nVertices();
        if (n < 3) continue;
        std::vector<const carve::mesh::Vertex<3>*> verts;
        const carve::mesh::Edge<3>* e = face->edge;
        for (std::size_t k = 0; k < n; ++k, e = e->next) verts.push_back(e->vert);
        std::vector<carve::triangulate::tri_idx> tris;
        if (n == 3) {
          tris.emplace_back(0, 1, 2);
        } else {
          // Faces after CSG can be concave: ear-clip in the face's plane.
          std::vector<carve::geom2d::P2> flat;
          face->getProjectedVertices(flat);
          try {
            carve::triangulate::triangulate(flat, tris);
          } catch (...) {
            tris.clear();
          }
          if (tris.empty())
            for (std::size_t k = 1; k + 1 < n; ++k) tris.emplace_back(0, k, k + 1);
        }
        // Keep the face's own orientation (outward for closed shells).
        const carve::geom::vector<3> normal = face->plane.N;
        for (const auto& tri : tris) {
          const carve::geom::vector<3> a = verts[tri.a]->v, b = verts[tri.b]->v,
                                       c = verts[tri.c]->v;
          const bool flip = carve::geom::dot(carve::geom::cross(b - a, c - a), normal) < 0.0;
          Eigen::Vector3i out(vertex(verts[tri.a]), vertex(verts[tri.b]), vertex(verts[tri.c]));
          if (flip) std::swap(out[1], out[2]);
          part->triangles.push_back(out);
        }
      }
    }
  }

  // The surface style of an item (else of its representation, else of the product).
  int MaterialOf(const ItemShapeData& item, const RepresentationData& rep,
                 ProductShapeData& shape) {
    const AppearanceData* style = nullptr;
    auto pick = [&](const std::vector<shared_ptr<AppearanceData>>& list) {
      for (const auto& a : list)
        if (!style && a && a->m_apply_to_geometry_type != AppearanceData::GEOM_TYPE_TEXT &&
            a->m_apply_to_geometry_type != AppearanceData::GEOM_TYPE_CURVE)
          style = a.get();
    };
    pick(item.m_vec_item_appearances);
    pick(rep.m_vec_representation_appearances);
    pick(shape.getAppearances());
    const int key = style ? style->m_step_style_id : -1;
    if (const auto it = materials_.find(key); it != materials_.end()) return it->second;
    Material m;
    if (style) {
      // IfcSurfaceStyle(Name, Side, Styles).
      const auto body = step_.bodies.find(static_cast<unsigned long>(style->m_step_style_id));
      if (body != step_.bodies.end()) {
        const std::vector<std::string> a = bim::Attributes(body->second);
        if (!a.empty()) m.name = bim::StepString(a[0]);
      }
      const vec4& c = style->m_color_diffuse;
      m.base_color = Eigen::Vector4f(static_cast<float>(c.r()), static_cast<float>(c.g()),
                                     static_cast<float>(c.b()), static_cast<float>(c.a()))
                         .cwiseMax(0.0f)
                         .cwiseMin(1.0f);
      if (m.base_color[3] < 1.0f) m.transmission = 1.0f - m.base_color[3];  // glass
    } else {
      m.name = "<IFCDefault>";
      m.base_color = Eigen::Vector4f(0.6f, 0.6f, 0.6f, 1.0f);
    }
    scene_.materials.push_back(m);
    const int index = static_cast<int>(scene_.materials.size()) - 1;
    materials_[key] = index;
    return index;
  }

  shared_ptr<BuildingModel> model_;
  GeometryConverter& conv_;
  const bim::StepIndex& step_;
  const double scale_;
  const bool spaces_;
  Scene scene_;
  std::set<int> visited_;
  std::map<int, int> materials_;  // style entity id (-1 = none) -> material
};

// Reads the file and builds the scene; throws std::exception with a one-line reason.
Scene ReadWithIfcPlusPlus(const std::string& path, const std::string& text,
                          const LoadOptions& options) {
  shared_ptr<BuildingModel> model(new BuildingModel());
  shared_ptr<ReaderSTEP> reader(new ReaderSTEP());
  std::string content = text;
  reader->loadModelFromString(content, model);
  if (model->getMapIfcEntities().empty()) throw std::runtime_error("IfcPlusPlus read no entities");
  GeometryConverter conv(model);
  conv.convertGeometry();
  // The unit the STEP text assigns is authoritative; IfcPlusPlus applies its own reading.
  const bim::StepIndex index = bim::IndexStep(text);
  const double file_scale = bim::FullLengthScale(text, index, path);
  const double ifcpp_scale = model->getUnitConverter()->getLengthInMeterFactor();
  const double scale = ifcpp_scale > 0.0 ? file_scale / ifcpp_scale : 1.0;
  Ifc4SceneBuilder builder(model, &conv, index, scale, options.import_ifc_spaces);
  return builder.Build();
}

}  // namespace

Scene LoadIfc4(const std::string& path, const LoadOptions& options) {
  const std::string text = bim::ReadText(path);
  const std::string reader = "the IFC4 reader (IfcPlusPlus)";
  Scene scene = ReadSceneInChild(path, reader, "an IFC4 file it can read", [&] {
    try {
      return ReadWithIfcPlusPlus(path, text, options);
    } catch (const std::exception& e) {
      throw InputError(path, reader + " cannot read the file", e.what(), "a valid IFC4 file");
    }
  });
  for (MeshPart& p : scene.parts) p.element_class = FromIfcClass(p.subclass);
  if (scene.parts.empty())
    throw InputError(path, "the IFC4 reader (IfcPlusPlus) made no geometry", "0 mesh parts",
                     "products with a Body representation");
  scene.source = path;
  ValidateScene(&scene, options.drop_degenerate_triangles);
  return scene;
}

}  // namespace mopad::scenes
