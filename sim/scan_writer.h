#pragma once
// Streaming file output of a TLS scan: binary PLY (the robot's data), optional PTX and optional
// truth PLY (the evaluator's), encoded in parallel by the scanner's workers and written in
// column order, so a scan of any size needs only a few blocks of memory. The bytes are the same
// as WriteTlsScanPly / WriteTlsScanPtx / WriteTlsTruthPly of the in-memory scan.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "io/scan_io.h"
#include "sim/tls_scanner.h"

namespace mopad::sim {

struct ScanOutputPaths {
  std::string ply;    ///< required
  std::string ptx;    ///< "" = none
  std::string truth;  ///< "" = none (truth PLY)
};

class ScanFileSink final : public ScanSink {
 public:
  /// Opens the files (InputError if they cannot be created). `header`/`truth_header` from
  /// TlsScanner::MakeHeader / MakeTruthHeader; `expected_points` preallocates (0 = no).
  ScanFileSink(const ScanOutputPaths& paths, const interfaces::TlsScan& header,
               const TlsTruth& truth_header, std::uint64_t expected_points);
  ~ScanFileSink() override;
  void Process(ScanBlock& block) override;
  void Consume(ScanBlock& block) override;
  /// Closes every file (patches PLY counts). Throws on I/O failure.
  void Close();
  std::uint64_t points_written() const { return points_; }
  std::uint64_t columns_done() const { return columns_; }
  /// Called from Consume with the number of columns written so far (e.g. a progress bar).
  std::function<void(std::uint64_t)> on_progress;

 private:
  std::unique_ptr<io::TlsPlyStreamWriter> ply_;
  std::unique_ptr<io::TlsPtxStreamWriter> ptx_;
  std::unique_ptr<TlsTruthPlyStreamWriter> truth_;
  bool wide_row_ = false, wide_col_ = false;
  std::uint64_t points_ = 0, columns_ = 0;
};

}  // namespace mopad::sim
