// The room model's outputs: SM1 (the labelled coloured cloud, as a cloud and as binary PLY) and
// the figures of the mission log (JSON).
#include <Eigen/Geometry>
#include <cstdio>
#include <string>

#include "modelling/room_model.h"

namespace mopad::modelling {

io::PointCloud RoomModel::Sm1Cloud() const {
  io::PointCloud cloud;
  cloud.points = points_;
  cloud.colors = colours_;
  io::ScalarField inten{"scalar_intensity", io::PlyType::kFloat32, {}};
  io::ScalarField label{"scalar_label", io::PlyType::kUInt8, {}};
  io::ScalarField scan{"scalar_scan", io::PlyType::kUInt16, {}};
  inten.values.assign(intensity_.begin(), intensity_.end());
  label.values.resize(labels_.size());
  for (std::size_t i = 0; i < labels_.size(); ++i)
    label.values[i] = static_cast<double>(labels_[i]);
  scan.values.assign(scan_index_.begin(), scan_index_.end());
  cloud.fields = {std::move(inten), std::move(label), std::move(scan)};
  char buf[256];
  cloud.comments.push_back("mopad_sm1 labels 0=none 1=inlier 2=outlier 3=clutter");
  std::snprintf(buf, sizeof(buf), "mopad_heights floor_z %.4f ceiling_z %.4f", roi_.floor_z,
                roi_.ceiling_z);
  cloud.comments.push_back(buf);
  for (std::size_t s = 0; s < scan_poses_.size(); ++s) {
    const Eigen::Quaterniond q(scan_poses_[s].linear());
    const Vec3 t = scan_poses_[s].translation();
    std::snprintf(buf, sizeof(buf), "mopad_scan_pose %zu %.6f %.6f %.6f %.9f %.9f %.9f %.9f", s,
                  t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
    cloud.comments.push_back(buf);
  }
  return cloud;
}

void RoomModel::WriteSm1(const std::string& path) const { io::WritePly(path, Sm1Cloud()); }

std::string RoomModel::FiguresJson() const {
  std::string s = "{";
  char buf[256];
  auto num = [&](const char* key, double v, bool comma = true) {
    std::snprintf(buf, sizeof(buf), "\"%s\": %.6g%s", key, v, comma ? ", " : "");
    s += buf;
  };
  num("scans", ScanCount());
  num("floor_z", roi_.floor_z);
  num("ceiling_z", roi_.ceiling_z);
  s += "\"perimeter\": [";
  for (std::size_t i = 0; i < roi_.perimeter.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%s[%.4f, %.4f]", i ? ", " : "", roi_.perimeter[i].x(),
                  roi_.perimeter[i].y());
    s += buf;
  }
  s += "], \"columns\": [";
  for (std::size_t k = 0; k < roi_.columns.size(); ++k) {
    s += k ? ", [" : "[";
    for (std::size_t i = 0; i < roi_.columns[k].size(); ++i) {
      std::snprintf(buf, sizeof(buf), "%s[%.4f, %.4f]", i ? ", " : "", roi_.columns[k][i].x(),
                    roi_.columns[k][i].y());
      s += buf;
    }
    s += "]";
  }
  s += "], \"faces\": [";
  for (std::size_t i = 0; i < roi_.faces.size(); ++i) {
    const RoiFace& f = roi_.faces[i];
    std::snprintf(buf, sizeof(buf),
                  "%s{\"kind\": \"%s\", \"element\": %d, \"area\": %.4f, \"structural\": %s, "
                  "\"sensed_share\": %.4f}",
                  i ? ", " : "", ToString(f.kind), f.element, f.area,
                  f.structural ? "true" : "false", f.sensed_share);
    s += buf;
  }
  s += "], \"voxels\": {";
  const auto counts = voxels_.LabelCounts();
  for (int l = 0; l < kVoxelLabelCount; ++l) {
    std::snprintf(buf, sizeof(buf), "%s\"%s\": %lld", l ? ", " : "",
                  ToString(static_cast<VoxelLabel>(l)), static_cast<long long>(counts[l]));
    s += buf;
  }
  std::snprintf(buf, sizeof(buf), ", \"size\": %.3f}, ", voxels_.Size());
  s += buf;
  const LabelCounts lc = CountLabels();
  std::snprintf(
      buf, sizeof(buf),
      "\"labels\": {\"none\": %lld, \"inlier\": %lld, \"outlier\": %lld, \"clutter\": %lld}, ",
      static_cast<long long>(lc.none), static_cast<long long>(lc.inlier),
      static_cast<long long>(lc.outlier), static_cast<long long>(lc.clutter));
  s += buf;
  s += "\"coverage\": [";
  for (std::size_t i = 0; i < coverage_.size(); ++i) {
    const CoverageFigures& c = coverage_[i];
    std::snprintf(
        buf, sizeof(buf),
        "%s{\"scans\": %d, \"sensed_area\": %.4f, \"total_area\": %.4f, \"opening_area\": %.4f, "
        "\"ratio\": %.5f, \"increment\": %.5f}",
        i ? ", " : "", c.scans, c.sensed_area, c.total_area, c.opening_area, c.ratio, c.increment);
    s += buf;
  }
  s += "]}";
  return s;
}

}  // namespace mopad::modelling
