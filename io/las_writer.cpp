#include "io/las_writer.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "common/error.h"

namespace mopad::io {
namespace {

template <class T>
void Put(std::string& out, std::size_t at, T v) {
  std::memcpy(out.data() + at, &v, sizeof v);  // little-endian hosts only (x86-64, arm64)
}

void PutText(std::string& out, std::size_t at, const std::string& s, std::size_t width) {
  std::memcpy(out.data() + at, s.data(), std::min(s.size(), width));
}

std::int32_t Count(double v, double offset, double scale) {
  return static_cast<std::int32_t>(std::llround((v - offset) / scale));
}

}  // namespace

Eigen::Vector3d LasOffsetFor(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return (0.5 * (min + max)).array().round().matrix();
}

double LasScaleFor(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                   const Eigen::Vector3d& offset) {
  const double reach =
      std::max((max - offset).cwiseAbs().maxCoeff(), (min - offset).cwiseAbs().maxCoeff());
  for (double scale : {1e-4, 1e-3, 1e-2, 1e-1, 1.0})
    if (reach / scale < 0.5 * std::numeric_limits<std::int32_t>::max()) return scale;
  return 10.0;
}

LasWriter::LasWriter(const std::string& path, const LasFileInfo& info)
    : path_(path), out_(path), info_(info) {
  if (!info.min.allFinite() || !info.max.allFinite() || (info.max - info.min).minCoeff() < 0)
    throw InputError(path, "LAS bounds are not finite or min > max");
  offset_ = LasOffsetFor(info.min, info.max);
  scale_ = LasScaleFor(info.min, info.max, offset_);
  lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  file_ = std::fopen(out_.TempPath().c_str(), "wb");
  if (!file_) throw InputError(path, "cannot write the file");
  const std::string header = HeaderBytes();
  std::fwrite(header.data(), 1, header.size(), file_);
}

LasWriter::~LasWriter() {
  if (file_) std::fclose(file_);
}

std::string LasWriter::HeaderBytes() const {
  std::string h(kLasHeaderSize, '\0');
  PutText(h, 0, "LASF", 4);
  Put<std::uint16_t>(h, 4, info_.file_source_id);
  Put<std::uint16_t>(h, 6, 0x10);  // WKT bit; GPS week time
  h[24] = 1, h[25] = 4;            // version 1.4
  PutText(h, 26, info_.system_identifier, 32);
  PutText(h, 58, info_.generating_software, 32);
  Put<std::uint16_t>(h, 90, info_.creation_day);
  Put<std::uint16_t>(h, 92, info_.creation_year);
  Put<std::uint16_t>(h, 94, kLasHeaderSize);
  Put<std::uint32_t>(h, 96, kLasHeaderSize);  // offset to point data (no VLRs)
  Put<std::uint32_t>(h, 100, 0);              // number of VLRs
  h[104] = 7;                                 // point data record format
  Put<std::uint16_t>(h, 105, kLasPf7RecordSize);
  // 107: legacy point count and 111: legacy counts by return stay 0 (format > 5).
  for (int a = 0; a < 3; ++a) Put<double>(h, 131 + 8 * a, scale_);
  for (int a = 0; a < 3; ++a) Put<double>(h, 155 + 8 * a, offset_[a]);
  const bool any = count_ > 0;
  for (int a = 0; a < 3; ++a) {  // max x, min x, max y, min y, max z, min z
    Put<double>(h, 179 + 16 * a, any ? hi_[a] : 0.0);
    Put<double>(h, 187 + 16 * a, any ? lo_[a] : 0.0);
  }
  // 227: waveform start, 235: first EVLR, 243: EVLR count stay 0.
  Put<std::uint64_t>(h, 247, count_);
  Put<std::uint64_t>(h, 255, count_);  // every point is return 1 of 1
  return h;
}

void LasWriter::Append(std::span<const LasPoint> points) {
  if (!file_) throw InputError(path_, "LAS writer already closed");
  const double reach = scale_ * std::numeric_limits<std::int32_t>::max();
  std::string rec(points.size() * kLasPf7RecordSize, '\0');
  for (std::size_t i = 0; i < points.size(); ++i) {
    const LasPoint& q = points[i];
    if (!q.p.allFinite() || (q.p - offset_).cwiseAbs().maxCoeff() >= reach)
      throw InputError(
          path_, "point beyond what the LAS scale and offset hold",
          std::to_string(q.p.x()) + " " + std::to_string(q.p.y()) + " " + std::to_string(q.p.z()));
    const std::size_t at = i * kLasPf7RecordSize;
    for (int a = 0; a < 3; ++a)
      Put<std::int32_t>(rec, at + 4 * a, Count(q.p[a], offset_[a], scale_));
    Put<std::uint16_t>(rec, at + 12, q.intensity);
    rec[at + 14] = 0x11;  // return 1 of 1
    rec[at + 15] = 0;     // flags, channel, scan direction, edge of flight line
    rec[at + 16] = static_cast<char>(q.classification);
    rec[at + 17] = static_cast<char>(q.user_data);
    // 18: scan angle stays 0.
    Put<std::uint16_t>(rec, at + 20, q.point_source_id);
    Put<double>(rec, at + 22, q.gps_time);
    for (int c = 0; c < 3; ++c) Put<std::uint16_t>(rec, at + 30 + 2 * c, q.rgb[c]);
    // The header bounds are those of the stored (quantised) coordinates.
    for (int a = 0; a < 3; ++a) {
      const double stored = offset_[a] + scale_ * Count(q.p[a], offset_[a], scale_);
      lo_[a] = std::min(lo_[a], stored);
      hi_[a] = std::max(hi_[a], stored);
    }
  }
  count_ += points.size();
  if (std::fwrite(rec.data(), 1, rec.size(), file_) != rec.size())
    throw InputError(path_, "write failed");
}

void LasWriter::Close() {
  if (!file_) return;
  const std::string header = HeaderBytes();
  const bool ok = std::fseek(file_, 0, SEEK_SET) == 0 &&
                  std::fwrite(header.data(), 1, header.size(), file_) == header.size();
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) throw InputError(path_, "write failed");
  out_.Commit();
}

}  // namespace mopad::io
