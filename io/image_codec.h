#pragma once
// PNG and JPEG images, and the PGM maps of ROS map_server, through libpng and libjpeg-turbo.
//
// The project's images (orthoimages, map images, the report's wall pictures) are encoded here
// rather than through OpenCV's imgcodecs: that module links GDAL, GDCM, HDF5 and PROJ, whose
// loading made 0.05 s of every `mopad` process's start (docs/performance.md). The PNG settings
// are OpenCV's defaults (sub filter, zlib level 1, run-length strategy), so files written before
// keep their bytes; the decoders apply libpng's transforms as OpenCV's imread does.
//
// Pixels are interleaved in OpenCV's channel order (B, G, R[, A]), rows top first.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mopad::io {

/// Pixels owned elsewhere: `channels` 1 (grey), 3 (B, G, R) or 4 (B, G, R, A); samples of
/// `bits` 8 or 16 (host byte order); `stride` bytes from the start of a row to the next.
struct ImageView {
  const void* data = nullptr;
  int width = 0;
  int height = 0;
  int channels = 1;
  int bits = 8;
  std::size_t stride = 0;
};

/// An 8-bit image read from a file: `pixels` holds height rows of width * channels bytes.
struct Image8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> pixels;
  bool empty() const { return pixels.empty(); }
};

/// The PNG file of `image` (any channels and bits above). Throws std::invalid_argument for a
/// view it cannot encode (no pixels, other channels or bits).
std::string EncodePng(const ImageView& image);
/// The baseline JPEG file of an 8-bit grey or B, G, R `image` at `quality` (1-100, libjpeg's
/// scale; 4:2:0 chroma for colour). Throws std::invalid_argument as EncodePng.
std::string EncodeJpeg(const ImageView& image, int quality);
/// Reads the PNG (any colour type and depth: alpha dropped, 16-bit samples cut to 8, palettes
/// expanded) or PGM (binary P5 or ASCII P2, maxval up to 255 read as is, above it scaled to 8
/// bits) at `path` as `channels` 1 (grey: colour converted with libpng's 0.299/0.587/0.114
/// weights) or 3 (B, G, R: grey repeated). Empty when the file is missing, of another format
/// or malformed; never throws for a bad file.
Image8 ReadImage8(const std::string& path, int channels);

}  // namespace mopad::io
