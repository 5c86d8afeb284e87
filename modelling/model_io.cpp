#include "modelling/model_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "common/error.h"
#include "io/scan_io.h"

namespace mopad::modelling {
namespace {

using Json = nlohmann::ordered_json;

// Rounded to 0.1 mm / 1e-6 so that files are stable and readable.
double R(double v, double q = 1e-4) { return std::round(v / q) * q; }
Json V3(const Vec3& v) { return Json::array({R(v.x()), R(v.y()), R(v.z())}); }
Json N3(const Vec3& v) { return Json::array({R(v.x(), 1e-9), R(v.y(), 1e-9), R(v.z(), 1e-9)}); }

}  // namespace

std::string Sm2Json(const Roi& roi, const std::string& room) {
  Json j;
  j["format"] = "mopad-sm2";
  j["version"] = kModelFormatVersion;
  j["room"] = room;
  j["floor_z"] = R(roi.floor_z);
  j["ceiling_z"] = R(roi.ceiling_z);
  Json vs = Json::array();
  for (const auto& v : roi.vertices) vs.push_back(V3(v));
  j["vertices"] = std::move(vs);
  Json es = Json::array();
  for (const auto& e : roi.edges)
    es.push_back({{"v", {e.v0, e.v1}}, {"faces", {e.face0, e.face1}}});
  j["edges"] = std::move(es);
  Json fs = Json::array();
  for (const auto& f : roi.faces) {
    Json jf;
    jf["kind"] = ToString(f.kind);
    jf["loop"] = f.loop;
    jf["holes"] = f.holes;
    jf["normal"] = N3(f.normal);
    jf["area"] = R(f.area);
    jf["structural"] = f.structural;
    jf["sensed_share"] = R(f.sensed_share, 1e-6);
    fs.push_back(std::move(jf));
  }
  j["faces"] = std::move(fs);
  j["face_adjacency"] = roi.face_adjacency;
  return j.dump(1);
}

std::string Sm3Json(const StructuralModel& m) {
  Json j;
  j["format"] = "mopad-sm3";
  j["version"] = kModelFormatVersion;
  j["room"] = m.room;
  j["floor_z"] = R(m.floor_z);
  j["ceiling_z"] = R(m.ceiling_z);
  Json ps = Json::array();
  for (const auto& p : m.patches) {
    Json jp;
    jp["id"] = p.id;
    jp["class"] = ToString(p.patch_class);
    jp["plane"] = {{"n", N3(p.plane.n)}, {"d", R(p.plane.d, 1e-6)}};
    Json poly = Json::array();
    for (const auto& v : p.polygon) poly.push_back(V3(v));
    jp["polygon"] = std::move(poly);
    jp["support"] = p.support;
    jp["rms"] = R(p.rms, 1e-6);
    jp["fitted"] = p.fitted;
    ps.push_back(std::move(jp));
  }
  j["patches"] = std::move(ps);
  Json adj = Json::array();
  for (const auto& [a, b] : m.adjacency) adj.push_back({a, b});
  j["adjacency"] = std::move(adj);
  return j.dump(1);
}

void WriteDsm3Ply(const VoxelSpace& vs, const std::string& path) {
  io::PointCloud cloud;
  char buf[160];
  std::snprintf(buf, sizeof buf, "mopad_dsm3_voxel_size %.6f", vs.Size());
  cloud.comments.push_back(buf);
  std::snprintf(buf, sizeof buf, "mopad_dsm3_origin %.6f %.6f %.6f", vs.Origin().x(),
                vs.Origin().y(), vs.Origin().z());
  cloud.comments.push_back(buf);
  std::snprintf(buf, sizeof buf, "mopad_dsm3_dims %d %d %d", vs.Nx(), vs.Ny(), vs.Nz());
  cloud.comments.push_back(buf);
  for (int l = 0; l < kVoxelLabelCount; ++l)
    cloud.comments.push_back("mopad_dsm3_label " + std::to_string(l) + " " +
                             ToString(static_cast<VoxelLabel>(l)));
  io::ScalarField label{"scalar_label", io::PlyType::kUInt8, {}};
  io::ScalarField fi{"scalar_i", io::PlyType::kInt32, {}};
  io::ScalarField fj{"scalar_j", io::PlyType::kInt32, {}};
  io::ScalarField fk{"scalar_k", io::PlyType::kInt32, {}};
  for (int k = 0; k < vs.Nz(); ++k)
    for (int j = 0; j < vs.Ny(); ++j)
      for (int i = 0; i < vs.Nx(); ++i) {
        const std::size_t idx = vs.Index(i, j, k);
        const std::uint8_t fl = vs.Flags(idx);
        if (!(fl & (VoxelSpace::kInside | VoxelSpace::kStructural))) continue;
        cloud.points.push_back(vs.Centre(i, j, k).cast<float>());
        label.values.push_back(static_cast<double>(vs.Label(idx)));
        fi.values.push_back(i), fj.values.push_back(j), fk.values.push_back(k);
      }
  cloud.fields = {std::move(label), std::move(fi), std::move(fj), std::move(fk)};
  io::WritePly(path, cloud);
}

}  // namespace mopad::modelling
