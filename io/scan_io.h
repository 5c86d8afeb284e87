#pragma once
// Point-cloud files: binary little-endian PLY (any labelled cloud, and TLS scans) and PTX
// (one organised TLS scan per file). In io/ (file formats without truth) so the robot's
// libraries can write clouds too.
//
// PLY field names follow what Debian's CloudCompare 2.11 and Open3D both read: x y z (float),
// red green blue (uchar), and every other field named `scalar_*` (CloudCompare keeps only the
// first non-standard property otherwise).
//
// A TLS scan PLY holds the *valid* returns only, in acquisition order (column by column, top
// row first inside a column), with fields
//   x y z            float   m, scanner frame
//   red green blue   uchar   sRGB
//   scalar_intensity float   [0, 1]
//   scalar_range     float   m
//   scalar_row       ushort  (uint when rows > 65535)
//   scalar_column    ushort  (uint when columns > 65535)
//   scalar_timestamp double  s, simulation time
// and the grid geometry and poses in `comment mopad_*` header lines, so ReadTlsScanPly can
// rebuild the organised grid. The vertex count in the header is padded with spaces to a fixed
// width so a streaming writer can fill it in after the last point (PLY readers tokenise on
// whitespace).
//
// PTX (Leica's ASCII structured format, read by CloudCompare): columns, rows, scanner position
// and axes (X_MS_estimate), the same pose as a 4x4 matrix, then `x y z intensity r g b` per cell,
// column by column; cells without a return are written as `0 0 0 0 0 0 0`.
//
// Errors: every reader/writer throws mopad::InputError naming the file.
// Thread-safety: free functions are reentrant; a stream writer belongs to one thread.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/atomic_file.h"
#include "interfaces/tls_scan.h"

namespace mopad::io {

using interfaces::TlsPoint;
using interfaces::TlsScan;

/// PLY scalar types (the classic names are written: char uchar short ushort int uint float
/// double).
enum class PlyType : std::uint8_t {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kFloat32,
  kFloat64
};

/// One extra per-point field of a cloud (stored as double, written as `type`).
struct ScalarField {
  std::string name;  ///< written as-is; use the `scalar_` prefix for CloudCompare
  PlyType type = PlyType::kFloat32;
  std::vector<double> values;  ///< one per point
};

/// A generic (e.g. labelled) point cloud.
struct PointCloud {
  std::vector<Eigen::Vector3f> points;              ///< m, frame given by the producer
  std::vector<std::array<std::uint8_t, 3>> colors;  ///< empty or one per point (sRGB)
  std::vector<ScalarField> fields;                  ///< each with one value per point
  std::vector<std::string> comments;                ///< header comments (no newlines)

  const ScalarField* Field(const std::string& name) const;
};

/// A 3x4 pose as the twelve numbers of its rows (shortest round-trip text, each preceded by a
/// space): the `comment mopad_X_*` header lines of PLY files.
std::string PoseWords(const Eigen::Isometry3d& X);

/// Writes binary little-endian PLY. Throws InputError if field sizes disagree or the file cannot
/// be written.
void WritePly(const std::string& path, const PointCloud& cloud);
/// Reads a binary little-endian PLY vertex element (x y z required; red green blue optional;
/// every other vertex property becomes a ScalarField). Other elements must come after vertex
/// and are ignored. Throws InputError on anything malformed.
PointCloud ReadPly(const std::string& path);

/// Writes the valid points of `scan` (see the file comment for the layout).
void WriteTlsScanPly(const std::string& path, const TlsScan& scan);
/// Rebuilds the organised scan written by WriteTlsScanPly (cells absent from the file get
/// range 0 and their row/column).
TlsScan ReadTlsScanPly(const std::string& path);

/// Writes `scan` as PTX.
void WriteTlsScanPtx(const std::string& path, const TlsScan& scan);
/// Reads a single-scan PTX file written by WriteTlsScanPtx (or by other tools: unknown fields
/// such as row/column come from the grid position, timestamps are 0). Only x y z i [r g b].
TlsScan ReadTlsScanPtx(const std::string& path);

/// Binary little-endian PLY with one vertex element whose count is known only at the end:
/// the header reserves a fixed-width count that Close() fills in. Append records in file order.
class PlyStreamWriter {
 public:
  /// `properties` in record order; `expected_points` (0 = unknown) preallocates the file.
  PlyStreamWriter(const std::string& path, const std::vector<std::string>& comments,
                  const std::vector<std::pair<std::string, PlyType>>& properties,
                  std::uint64_t expected_points = 0);
  ~PlyStreamWriter();
  PlyStreamWriter(const PlyStreamWriter&) = delete;
  PlyStreamWriter& operator=(const PlyStreamWriter&) = delete;
  /// Bytes per record.
  int record_size() const { return record_size_; }
  /// Appends already encoded records holding `count` points.
  void Append(const std::string& bytes, std::uint64_t count);
  /// Patches the vertex count, trims preallocated space, closes and moves the file to its path
  /// (without Close(), no file appears). Throws on I/O failure.
  void Close();
  std::uint64_t points_written() const { return count_; }

 private:
  std::string path_;
  AtomicFile out_;  ///< the file appears at `path_` when Close() succeeds, never a part of it
  std::FILE* file_ = nullptr;
  long count_offset_ = 0;
  std::uint64_t count_ = 0;
  std::uint64_t bytes_ = 0;
  int record_size_ = 0;
};

/// Streaming writer of a TLS-scan PLY: write the header for a scan's metadata, append encoded
/// points in order, Close() patches the vertex count. `EncodePoints` is a pure function
/// (call it from worker threads), `Append` must be called in file order.
class TlsPlyStreamWriter {
 public:
  /// `meta` supplies grid geometry, poses and ids; its points are ignored. `expected_points` is
  /// an upper bound used to preallocate the file (0 = none).
  TlsPlyStreamWriter(const std::string& path, const TlsScan& meta,
                     std::uint64_t expected_points = 0);

  /// Appends the binary records of the valid points among `points` to `out`; returns how many.
  static std::uint64_t EncodePoints(std::span<const TlsPoint> points, bool wide_row, bool wide_col,
                                    std::string& out);
  bool wide_row() const { return wide_row_; }
  bool wide_col() const { return wide_col_; }
  void Append(const std::string& bytes, std::uint64_t count) { ply_.Append(bytes, count); }
  void Close() { ply_.Close(); }
  std::uint64_t points_written() const { return ply_.points_written(); }

 private:
  bool wide_row_ = false, wide_col_ = false;
  PlyStreamWriter ply_;
};

/// Streaming PTX writer: header on construction, then columns in order.
class TlsPtxStreamWriter {
 public:
  TlsPtxStreamWriter(const std::string& path, const TlsScan& meta);
  ~TlsPtxStreamWriter();
  TlsPtxStreamWriter(const TlsPtxStreamWriter&) = delete;
  TlsPtxStreamWriter& operator=(const TlsPtxStreamWriter&) = delete;
  /// Appends the ASCII lines of `cells` (whole columns, top row first) to `out`. Pure.
  static void EncodeCells(std::span<const TlsPoint> cells, std::string& out);
  void Append(const std::string& text);
  void Close();

 private:
  std::string path_;
  AtomicFile out_;  ///< the file appears at `path_` when Close() succeeds, never a part of it
  std::FILE* file_ = nullptr;
};

}  // namespace mopad::io
