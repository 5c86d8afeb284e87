#include "sim/tls_truth.h"

#include <charconv>
#include <cstring>

#include "common/error.h"
#include "common/format.h"
#include "scenes/element_class.h"

namespace mopad::sim {

namespace {

std::vector<std::string> TruthComments(const TlsTruth& t) {
  std::vector<std::string> c = {
      "mopad_tls_truth 1",
      "mopad_scan_id " + std::to_string(t.scan_id),
      "mopad_grid " + std::to_string(t.rows) + " " + std::to_string(t.columns),
      "mopad_X_WB" + io::PoseWords(t.X_WB),
      "mopad_X_WS" + io::PoseWords(t.X_WS),
      "mopad_range_bias " + FormatShortest(t.range_bias),
      "mopad_tilt " + FormatShortest(t.tilt_roll) + " " + FormatShortest(t.tilt_pitch),
      "mopad_flags 1=transmitted 2=mixed 4=dropped 8=too_close"};
  const auto last = t.movers ? scenes::ElementClass::kPerson : scenes::ElementClass::kOther;
  for (int v = 0; v <= static_cast<int>(last); ++v) {
    c.push_back("mopad_class " + std::to_string(v) + " " +
                std::string(scenes::ToString(static_cast<scenes::ElementClass>(v))));
  }
  for (std::size_t i = 0; i < t.element_ids.size(); ++i) {
    std::string id = t.element_ids[i];
    for (char& ch : id)
      if (ch == '\n' || ch == '\r') ch = ' ';
    c.push_back("mopad_element " + std::to_string(i) + " " + id);
  }
  return c;
}

const std::vector<std::pair<std::string, io::PlyType>>& TruthProperties() {
  using io::PlyType;
  static const std::vector<std::pair<std::string, PlyType>> props = {
      {"x", PlyType::kFloat32},
      {"y", PlyType::kFloat32},
      {"z", PlyType::kFloat32},
      {"scalar_label", PlyType::kUInt8},
      {"scalar_element", PlyType::kInt32},
      {"scalar_part", PlyType::kInt32},
      {"scalar_door", PlyType::kInt16},
      {"scalar_true_range", PlyType::kFloat32},
      {"scalar_flags", PlyType::kUInt8},
      {"scalar_row", PlyType::kUInt32},
      {"scalar_column", PlyType::kUInt32}};
  return props;
}

constexpr std::size_t kRecord = 12 + 1 + 4 + 4 + 2 + 4 + 1 + 4 + 4;

}  // namespace

TlsTruthPlyStreamWriter::TlsTruthPlyStreamWriter(const std::string& path, const TlsTruth& meta,
                                                 std::uint64_t expected_points)
    : ply_(path, TruthComments(meta), TruthProperties(), expected_points) {}

std::uint64_t TlsTruthPlyStreamWriter::Encode(const interfaces::TlsPoint* points,
                                              const TlsPointTruth* truth, std::size_t n,
                                              std::string& out) {
  const std::size_t start = out.size();
  out.resize(start + n * kRecord);
  char* p = out.data() + start;
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const interfaces::TlsPoint& q = points[i];
    if (!q.valid()) continue;
    const TlsPointTruth& t = truth[i];
    std::memcpy(p, &q.x, 4);
    std::memcpy(p + 4, &q.y, 4);
    std::memcpy(p + 8, &q.z, 4);
    p[12] = static_cast<char>(t.element_class);
    std::memcpy(p + 13, &t.element, 4);
    std::memcpy(p + 17, &t.part, 4);
    std::memcpy(p + 21, &t.door, 2);
    std::memcpy(p + 23, &t.true_range, 4);
    p[27] = static_cast<char>(t.flags);
    std::memcpy(p + 28, &q.row, 4);
    std::memcpy(p + 32, &q.column, 4);
    p += kRecord;
    ++count;
  }
  out.resize(start + count * kRecord);
  return count;
}

void WriteTlsTruthPly(const std::string& path, const interfaces::TlsScan& scan,
                      const TlsTruth& truth) {
  if (truth.points.size() != scan.points.size() || truth.rows != scan.rows ||
      truth.columns != scan.columns) {
    throw InputError(path, "truth grid does not match the scan");
  }
  TlsTruthPlyStreamWriter writer(path, truth);
  std::vector<interfaces::TlsPoint> col_points(scan.rows);
  std::vector<TlsPointTruth> col_truth(scan.rows);
  std::string bytes;
  for (std::uint32_t c = 0; c < scan.columns; ++c) {
    for (std::uint32_t r = 0; r < scan.rows; ++r) {
      col_points[r] = scan.at(r, c);
      col_truth[r] = truth.at(r, c);
    }
    bytes.clear();
    const auto n =
        TlsTruthPlyStreamWriter::Encode(col_points.data(), col_truth.data(), scan.rows, bytes);
    writer.Append(bytes, n);
  }
  writer.Close();
}

}  // namespace mopad::sim
