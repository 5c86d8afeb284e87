#pragma once
// ASPRS LAS 1.4 (R15) writer, point data record format 7, uncompressed, no VLRs: a 375-byte
// public header block, then 36-byte records (x, y, z as int32 counts of the scale around the
// offset, intensity, return 1 of 1, classification, user data, scan angle 0, point source id,
// GPS time, 16-bit red, green, blue). Global encoding: WKT bit set (required for formats 6-10;
// no CRS is written, the frame is local), GPS time as "GPS week time" (our times are simulation
// seconds).
// Streaming: the expected bounds given up front choose the scale and offset; Close() writes the
// true bounds of the written points and the point counts (legacy counts 0, as LAS 1.4 asks for
// formats above 5).
// Deterministic: no wall clock (the creation day and year are fields of LasFileInfo).
// Errors: InputError naming the file (cannot write, a point the scale and offset cannot hold).
// Not thread-safe: one writer per file, Append in file order.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

#include "common/atomic_file.h"

namespace mopad::io {

/// One PF7 point.
struct LasPoint {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< m, the file's frame
  std::uint16_t intensity = 0;                  ///< [0, 65535]
  std::array<std::uint16_t, 3> rgb{0, 0, 0};    ///< 16-bit red, green, blue
  double gps_time = 0.0;                        ///< s
  std::uint8_t classification = 0;              ///< ASPRS 0-63 standard, 64-255 user defined
  std::uint8_t user_data = 0;                   ///< free for the producer
  std::uint16_t point_source_id = 0;
};

/// Header fields that are not derived from the points.
struct LasFileInfo {
  std::string system_identifier = "OpenMoPAD";    ///< at most 32 characters
  std::string generating_software = "OpenMoPAD";  ///< at most 32 characters
  std::uint16_t file_source_id = 0;
  std::uint16_t creation_day = 0;   ///< day of year, 0 = unknown
  std::uint16_t creation_year = 0;  ///< 0 = unknown
  /// m, the expected bounds of the points: they choose the offset (their centre) and the scale.
  /// Points outside are written as long as the int32 counts hold them.
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();  ///< m
};

inline constexpr int kLasHeaderSize = 375;
inline constexpr int kLasPf7RecordSize = 36;

/// Scale (one value for x, y and z) for points within [min, max] around `offset`: 0.1 mm when
/// half the int32 range holds them, else the first of 1 mm, 1 cm, 1 dm, 1 m (then 10 m) that does.
double LasScaleFor(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                   const Eigen::Vector3d& offset);
/// Offset: the bounds' centre rounded to whole metres.
Eigen::Vector3d LasOffsetFor(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

class LasWriter {
 public:
  /// Opens `path` and writes a provisional header. InputError for non-finite or inverted
  /// bounds and when the file cannot be created.
  LasWriter(const std::string& path, const LasFileInfo& info);
  ~LasWriter();
  LasWriter(const LasWriter&) = delete;
  LasWriter& operator=(const LasWriter&) = delete;
  /// Appends records. InputError for a non-finite point or one beyond the int32 counts.
  void Append(std::span<const LasPoint> points);
  /// Rewrites the header with the counts and true bounds, closes and moves the file to its path
  /// (without Close(), no file appears). InputError on I/O failure.
  void Close();
  std::uint64_t points_written() const { return count_; }
  double scale() const { return scale_; }
  const Eigen::Vector3d& offset() const { return offset_; }

 private:
  std::string HeaderBytes() const;

  std::string path_;
  AtomicFile out_;  ///< the file appears at `path_` when Close() succeeds, never a part of it
  LasFileInfo info_;
  std::FILE* file_ = nullptr;
  double scale_ = 1e-4;
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d lo_, hi_;  // true bounds of the written points
  std::uint64_t count_ = 0;
};

}  // namespace mopad::io
