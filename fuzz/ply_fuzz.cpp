// PLY point clouds (io/scan_io.h): the generic reader and the TLS-scan reader that `mopad eval`
// and `mopad export` use on a run folder's scans and SM1 cloud.
#include "fuzz/fuzz_input.h"
#include "io/scan_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mopad::fuzz::AsFile(data, size, "cloud.ply");
  mopad::fuzz::Run([&] { (void)mopad::io::ReadPly(path); });
  return mopad::fuzz::Run([&] { (void)mopad::io::ReadTlsScanPly(path); });
}
