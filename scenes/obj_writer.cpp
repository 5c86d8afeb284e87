#include "scenes/obj_writer.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/frames.h"

namespace mopad::scenes {
namespace {

// OBJ names may not contain white space.
std::string ObjName(std::string s) {
  for (char& c : s)
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
  return s.empty() ? std::string("unnamed") : s;
}

}  // namespace

void WriteObj(const Scene& scene, const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  AtomicFile obj_file(path), mtl_file(mtl_path.string());
  std::ofstream obj(obj_file.TempPath()), mtl(mtl_file.TempPath());
  if (!obj) throw InputError(path, "cannot write file");
  if (!mtl) throw InputError(mtl_path.string(), "cannot write file");

  char buf[160];
  mtl << "# OpenMoPAD material export (base colours only)\n";
  mtl << "newmtl mopad_default\nKd 0.8 0.8 0.8\n";
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const auto& m = scene.materials[i];
    std::snprintf(buf, sizeof buf, "newmtl m%zu_%s\nKd %.6f %.6f %.6f\nd %.6f\n", i,
                  ObjName(m.name).c_str(), m.base_color.x(), m.base_color.y(), m.base_color.z(),
                  m.base_color.w());
    mtl << buf;
  }

  obj << "# OpenMoPAD scene export: Y-up, metres (world is Z-up: y_obj = z, z_obj = -y)\n";
  obj << "mtllib " << mtl_path.filename().string() << "\n";
  const Eigen::Matrix3f yup = YupFromZup().cast<float>();
  std::size_t base_v = 1, base_vt = 1;
  for (const auto& part : scene.parts) {
    const std::string name = std::string(ToString(part.element_class)) + ":" +
                             ObjName(part.element_id.empty() ? part.name : part.element_id);
    obj << "o " << name << "\n";
    for (const auto& p : part.positions) {
      const Eigen::Vector3f q = yup * p;
      std::snprintf(buf, sizeof buf, "v %.7g %.7g %.7g\n", q.x(), q.y(), q.z());
      obj << buf;
    }
    const bool has_uv = part.uvs.size() == part.positions.size() && !part.uvs.empty();
    if (has_uv) {
      for (const auto& t : part.uvs) {
        // OBJ's v runs up from the bottom of the image; glTF's runs down from the top.
        std::snprintf(buf, sizeof buf, "vt %.7g %.7g\n", t.x(), 1.0f - t.y());
        obj << buf;
      }
    }
    if (part.material >= 0 && part.material < static_cast<int>(scene.materials.size()))
      obj << "usemtl m" << part.material << "_" << ObjName(scene.materials[part.material].name)
          << "\n";
    else
      obj << "usemtl mopad_default\n";
    for (const auto& t : part.triangles) {
      if (has_uv)
        std::snprintf(buf, sizeof buf, "f %zu/%zu %zu/%zu %zu/%zu\n", base_v + t[0], base_vt + t[0],
                      base_v + t[1], base_vt + t[1], base_v + t[2], base_vt + t[2]);
      else
        std::snprintf(buf, sizeof buf, "f %zu %zu %zu\n", base_v + t[0], base_v + t[1],
                      base_v + t[2]);
      obj << buf;
    }
    base_v += part.positions.size();
    if (has_uv) base_vt += part.uvs.size();
  }
  obj.close();
  mtl.close();
  if (!obj || !mtl) throw InputError(path, "write failed");
  mtl_file.Commit();
  obj_file.Commit();
}

}  // namespace mopad::scenes
