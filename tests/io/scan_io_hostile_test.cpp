// The PLY and PTX readers (io/scan_io.h) on hostile headers that the fuzz targets pointed to
// (docs/reliability.md): a count that claims more than the file holds is InputError before
// anything is allocated, never std::length_error, std::bad_alloc or an out-of-memory kill.
#include <gtest/gtest.h>

#include <string>

#include "common/error.h"
#include "io/scan_io.h"

namespace mopad::io {
namespace {

std::string Data(const std::string& name) {
  return std::string(MOPAD_SOURCE_DIR) + "/tests/io/data/" + name;
}

// "element vertex 1537228672809129302" of 12-byte records: the byte count n * 12 wraps around
// to 8, which the 8 data bytes then seemed to hold.
TEST(ScanIoHostile, APlyVertexCountWhoseByteCountWrapsIsATruncatedFile) {
  try {
    (void)ReadPly(Data("ply_vertex_count_wraps.ply"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file truncated; got 141 bytes, expected "
                                         "1537228672809129302 vertices of 12 bytes"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)ReadTlsScanPly(Data("ply_vertex_count_wraps.ply")), InputError);
}

// A 100000 x 100000 grid (10^10 cells, ~500 GB of points) in an 84-byte file.
TEST(ScanIoHostile, APtxHeaderClaimingMoreCellsThanTheFileHoldsIsRefusedBeforeAllocating) {
  try {
    (void)ReadTlsScanPtx(Data("ptx_header_claims_more_cells_than_the_file.ptx"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":1: error: PTX header claims more cells than the file "
                                         "holds; got 100000 x 100000, expected at most 10 cells "
                                         "in 84 bytes"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mopad::io
