#pragma once
// The TLS ground-truth sidecar: per pulse, what the beam really hit. Only the evaluator reads
// it; it is a separate type from interfaces::TlsScan on purpose (the robot never sees truth).

#include <cstdint>
#include <string>
#include <vector>

#include "common/frames.h"
#include "interfaces/tls_scan.h"
#include "io/scan_io.h"

namespace mopad::sim {

/// Bits of TlsPointTruth::flags.
enum TruthFlags : std::uint8_t {
  kTruthTransmitted = 1,  ///< the reported echo came through glass (an outlier behind a window)
  kTruthMixed = 2,        ///< the reported echo merged sub-rays from different surfaces
  kTruthDropped = 4,      ///< a surface was hit but the scanner reported nothing (dropout)
  kTruthTooClose = 8,     ///< the first surface was closer than range_min
};

/// Truth of one pulse (16 bytes).
struct TlsPointTruth {
  float true_range = 0.0f;         ///< m, noise-free distance to the reported surface (dominant
                                   ///< sub-ray); 0 = nothing reported and nothing hit
  std::int32_t element = -1;       ///< index into TlsTruth::element_ids, -1 = none / no hit
  std::int32_t part = -1;          ///< index into Scene::parts, -1 = no hit
  std::int16_t door = -1;          ///< index into EmbreeWorld::DoorIds(), -1 = not a door leaf
  std::uint8_t element_class = 0;  ///< scenes::ElementClass value (0 = unknown / no hit)
  std::uint8_t flags = 0;          ///< TruthFlags
};
static_assert(sizeof(TlsPointTruth) == 16);

struct TlsTruth {
  std::uint64_t scan_id = 0;
  std::uint32_t rows = 0, columns = 0;
  Pose3 X_WB = Pose3::Identity();  ///< true base pose
  Pose3 X_WS = Pose3::Identity();  ///< true scanner pose (with the drawn tilt)
  double range_bias = 0.0;         ///< m, this scan's systematic range error (incl. offset)
  double tilt_roll = 0.0, tilt_pitch = 0.0;  ///< rad, drawn levelling error
  std::vector<std::string> element_ids;      ///< EmbreeWorld::ElementIds()
  bool movers = false;  ///< the world had movers (people): the classes listed include kPerson
  std::vector<TlsPointTruth> points;         ///< rows * columns, row-major like TlsScan
  const TlsPointTruth& at(std::uint32_t r, std::uint32_t c) const {
    return points[static_cast<std::size_t>(r) * columns + c];
  }
};

/// Writes the truth of the *valid* points of `scan`, in the order WriteTlsScanPly uses
/// (column by column), as binary PLY: x y z (scanner frame, measured, as in the scan),
/// scalar_label (uchar ElementClass), scalar_element (int), scalar_part (int), scalar_door
/// (short), scalar_true_range (float), scalar_flags (uchar), scalar_row, scalar_column (uint).
/// Header comments carry the element table (`mopad_element <index> <id>`), the class names
/// (`mopad_class <value> <name>`) and the true poses. InputError on I/O failure.
void WriteTlsTruthPly(const std::string& path, const interfaces::TlsScan& scan,
                      const TlsTruth& truth);

/// Streaming writer of the same file (used by `mopad scan`).
class TlsTruthPlyStreamWriter {
 public:
  TlsTruthPlyStreamWriter(const std::string& path, const TlsTruth& meta,
                          std::uint64_t expected_points = 0);
  /// Encodes the truth of the valid points among `n` cells (pure; call from workers); returns
  /// the count.
  static std::uint64_t Encode(const interfaces::TlsPoint* points, const TlsPointTruth* truth,
                              std::size_t n, std::string& out);
  void Append(const std::string& bytes, std::uint64_t count) { ply_.Append(bytes, count); }
  void Close() { ply_.Close(); }

 private:
  io::PlyStreamWriter ply_;
};

}  // namespace mopad::sim
