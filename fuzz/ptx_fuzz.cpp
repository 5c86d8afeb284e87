// PTX TLS scans (io/scan_io.h, ReadTlsScanPtx): per-scan grid, pose and points as text.
#include "fuzz/fuzz_input.h"
#include "io/scan_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mopad::fuzz::AsFile(data, size, "scan.ptx");
  return mopad::fuzz::Run([&] { (void)mopad::io::ReadTlsScanPtx(path); });
}
