#include "exports/las_export.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/error.h"
#include "io/las_writer.h"
#include "io/scan_io.h"

namespace mopad::exports {
namespace {

using Vec3 = Eigen::Vector3d;
using modelling::PatchClass;

// An SM3 patch for the nearest-patch test: its plane and its polygon's extent in the plane.
struct PatchBox {
  Vec3 n, u, v;
  double d = 0.0;
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;  // m, polygon extent along u and v, widened by the band
  LasCode code = LasCode::kWall;
};

std::vector<PatchBox> PatchBoxes(const modelling::StructuralModel& sm3, double band) {
  std::vector<PatchBox> out;
  for (const auto& p : sm3.patches) {
    PatchBox b;
    b.n = p.plane.n.normalized();
    b.d = p.plane.d / p.plane.n.norm();
    b.u = (std::abs(b.n.z()) < 0.9 ? Vec3::UnitZ().cross(b.n) : Vec3::UnitX().cross(b.n))
              .normalized();
    b.v = b.n.cross(b.u);
    b.u0 = b.v0 = std::numeric_limits<double>::infinity();
    b.u1 = b.v1 = -b.u0;
    for (const auto& q : p.polygon) {
      b.u0 = std::min(b.u0, q.dot(b.u) - band), b.u1 = std::max(b.u1, q.dot(b.u) + band);
      b.v0 = std::min(b.v0, q.dot(b.v) - band), b.v1 = std::max(b.v1, q.dot(b.v) + band);
    }
    b.code = p.patch_class == PatchClass::kWall      ? LasCode::kWall
             : p.patch_class == PatchClass::kFloor   ? LasCode::kFloor
             : p.patch_class == PatchClass::kCeiling ? LasCode::kCeiling
                                                     : LasCode::kColumn;
    out.push_back(b);
  }
  return out;
}

LasCode Classify(int label, const Vec3& p_M, const std::vector<PatchBox>& boxes, double band) {
  switch (label) {
    case 1: {  // inlier: the nearest patch within the band
      LasCode best = LasCode::kInlier;
      double best_d = band;
      for (const auto& b : boxes) {
        const double dist = std::abs(b.n.dot(p_M) + b.d);
        if (dist > best_d) continue;
        const double u = p_M.dot(b.u), v = p_M.dot(b.v);
        if (u < b.u0 || u > b.u1 || v < b.v0 || v > b.v1) continue;
        best_d = dist;
        best = b.code;
      }
      return best;
    }
    case 2:
      return LasCode::kOutlier;
    case 3:
      return LasCode::kClutter;
    default:
      return LasCode::kUnlabelled;
  }
}

const io::ScalarField& NeedField(const io::PointCloud& cloud, const char* name,
                                 const std::string& path) {
  const io::ScalarField* f = cloud.Field(name);
  if (!f) throw InputError(path, std::string("missing vertex property ") + name);
  return *f;
}

// Expected bounds of the export: every room's SM3 polygons in E, widened by a scanner's reach.
void ExpectedBounds(const RunFolder& run, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const auto& room : run.rooms)
    for (const auto& p : room.sm3.patches)
      for (const auto& q : p.polygon) {
        lo = lo.cwiseMin(room.X_EM * q);
        hi = hi.cwiseMax(room.X_EM * q);
      }
  if (!lo.allFinite()) lo = hi = Vec3::Zero();
  lo -= Vec3::Constant(100.0);
  hi += Vec3::Constant(100.0);
}

std::uint16_t Unit16(double v) {
  return static_cast<std::uint16_t>(std::lround(std::clamp(v, 0.0, 1.0) * 65535.0));
}

void WriteRoom(const ModelSet& room, int ordinal, const LasExportParams& params,
               io::LasWriter& writer, LasExportSummary& summary) {
  const io::PointCloud cloud = io::ReadPly(room.sm1_path);
  const auto& label = NeedField(cloud, "scalar_label", room.sm1_path);
  const auto& scan = NeedField(cloud, "scalar_scan", room.sm1_path);
  const io::ScalarField* intensity = cloud.Field("scalar_intensity");
  const std::vector<PatchBox> boxes = PatchBoxes(room.sm3, params.patch_band);
  constexpr std::size_t kChunk = 1 << 20;
  std::vector<io::LasPoint> chunk;
  chunk.reserve(std::min(kChunk, cloud.points.size()));
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    io::LasPoint q;
    const Vec3 p_M = cloud.points[i].cast<double>();
    q.p = room.X_EM * p_M;
    if (!cloud.colors.empty())
      for (int c = 0; c < 3; ++c) q.rgb[c] = static_cast<std::uint16_t>(cloud.colors[i][c] * 257);
    if (intensity) q.intensity = Unit16(intensity->values[i]);
    const auto s = static_cast<std::size_t>(std::max(0.0, scan.values[i]));
    q.point_source_id = static_cast<std::uint16_t>(std::min<std::size_t>(s, 65535));
    q.gps_time = s < room.scan_times.size() ? room.scan_times[s] : static_cast<double>(s);
    q.classification = static_cast<std::uint8_t>(
        Classify(static_cast<int>(label.values[i]), p_M, boxes, params.patch_band));
    q.user_data = static_cast<std::uint8_t>(std::min(ordinal, 255));
    ++summary.histogram[q.classification];
    summary.min = summary.min.cwiseMin(q.p);
    summary.max = summary.max.cwiseMax(q.p);
    chunk.push_back(q);
    if (chunk.size() == kChunk) {
      writer.Append(chunk);
      chunk.clear();
    }
  }
  writer.Append(chunk);
  summary.points += cloud.points.size();
  ++summary.rooms;
}

}  // namespace

const char* ToString(LasCode code) {
  switch (code) {
    case LasCode::kUnlabelled:
      return "unlabelled";
    case LasCode::kOutlier:
      return "outlier";
    case LasCode::kClutter:
      return "clutter";
    case LasCode::kInlier:
      return "inlier";
    case LasCode::kWall:
      return "wall";
    case LasCode::kFloor:
      return "floor";
    case LasCode::kCeiling:
      return "ceiling";
    case LasCode::kColumn:
      return "column";
  }
  return "?";
}

LasExportSummary WriteSm1Las(const RunFolder& run, const std::string& path,
                             const LasExportParams& params) {
  bool any = false;
  for (const auto& room : run.rooms) any = any || !room.sm1_path.empty();
  if (!any) throw InputError(run.dir, "no sm1.ply in any room: nothing to write to " + path);
  io::LasFileInfo info;
  info.generating_software = "OpenMoPAD exports";
  ExpectedBounds(run, info.min, info.max);
  io::LasWriter writer(path, info);
  LasExportSummary summary;
  summary.min = Vec3::Constant(std::numeric_limits<double>::infinity());
  summary.max = -summary.min;
  for (std::size_t r = 0; r < run.rooms.size(); ++r)
    if (!run.rooms[r].sm1_path.empty())
      WriteRoom(run.rooms[r], static_cast<int>(r), params, writer, summary);
  writer.Close();
  if (summary.points == 0) summary.min = summary.max = Vec3::Zero();
  return summary;
}

}  // namespace mopad::exports
