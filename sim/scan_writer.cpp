#include "sim/scan_writer.h"

namespace mopad::sim {

ScanFileSink::ScanFileSink(const ScanOutputPaths& paths, const interfaces::TlsScan& header,
                           const TlsTruth& truth_header, std::uint64_t expected_points) {
  ply_ = std::make_unique<io::TlsPlyStreamWriter>(paths.ply, header, expected_points);
  wide_row_ = ply_->wide_row();
  wide_col_ = ply_->wide_col();
  if (!paths.ptx.empty()) ptx_ = std::make_unique<io::TlsPtxStreamWriter>(paths.ptx, header);
  if (!paths.truth.empty()) {
    truth_ = std::make_unique<TlsTruthPlyStreamWriter>(paths.truth, truth_header, expected_points);
  }
}

ScanFileSink::~ScanFileSink() = default;

void ScanFileSink::Process(ScanBlock& b) {
  for (auto& e : b.encoded) e.clear();
  b.encoded_count = {};
  b.encoded_count[0] =
      io::TlsPlyStreamWriter::EncodePoints(b.points, wide_row_, wide_col_, b.encoded[0]);
  if (ptx_) io::TlsPtxStreamWriter::EncodeCells(b.points, b.encoded[1]);
  if (truth_) {
    b.encoded_count[2] = TlsTruthPlyStreamWriter::Encode(b.points.data(), b.truth.data(),
                                                         b.points.size(), b.encoded[2]);
  }
}

void ScanFileSink::Consume(ScanBlock& b) {
  ply_->Append(b.encoded[0], b.encoded_count[0]);
  if (ptx_) ptx_->Append(b.encoded[1]);
  if (truth_) truth_->Append(b.encoded[2], b.encoded_count[2]);
  points_ += b.encoded_count[0];
  columns_ += b.column_end - b.column_begin;
  if (on_progress) on_progress(columns_);
}

void ScanFileSink::Close() {
  ply_->Close();
  if (ptx_) ptx_->Close();
  if (truth_) truth_->Close();
}

}  // namespace mopad::sim
