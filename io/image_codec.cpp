#include "io/image_codec.h"

#include <jpeglib.h>
#include <png.h>
#include <zlib.h>

#include <cctype>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace mopad::io {
namespace {

// Larger images than these are refused when read (a corrupt or hostile header).
constexpr png_uint_32 kMaxSide = 1u << 16;               // pixels
constexpr std::size_t kMaxBytes = std::size_t{1} << 31;  // decoded bytes

void CheckView(const ImageView& v, bool jpeg) {
  const bool channels_ok = jpeg ? (v.channels == 1 || v.channels == 3)
                                : (v.channels == 1 || v.channels == 3 || v.channels == 4);
  const bool bits_ok = jpeg ? v.bits == 8 : (v.bits == 8 || v.bits == 16);
  if (!v.data || v.width <= 0 || v.height <= 0 || !channels_ok || !bits_ok ||
      v.stride < static_cast<std::size_t>(v.width) * v.channels * (v.bits / 8))
    throw std::invalid_argument(std::string("cannot encode ") + (jpeg ? "JPEG" : "PNG") + ": " +
                                std::to_string(v.width) + " x " + std::to_string(v.height) +
                                " pixels, " + std::to_string(v.channels) + " channels of " +
                                std::to_string(v.bits) + " bits");
}

void AppendToString(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), size);
}
void FlushNothing(png_structp) {}

// Everything between setjmp and its longjmp is libpng calls and plain data, so the jump skips
// no destructor. False when libpng reported an error.
bool WritePng(png_structp png, png_infop info, const ImageView& v, png_bytepp rows,
              std::string* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, AppendToString, FlushNothing);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  const int type = v.channels == 1   ? PNG_COLOR_TYPE_GRAY
                   : v.channels == 3 ? PNG_COLOR_TYPE_RGB
                                     : PNG_COLOR_TYPE_RGBA;
  png_set_IHDR(png, info, static_cast<png_uint_32>(v.width), static_cast<png_uint_32>(v.height),
               v.bits, type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  if (v.bits == 16) png_set_swap(png);  // PNG stores big-endian samples; x86 and ARM are little
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

struct PngRead {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, colour = 0;
};

bool ReadPng(png_structp png, png_infop info, std::FILE* f, int channels, PngRead* head,
             std::vector<std::uint8_t>* pixels, std::vector<png_bytep>* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, f);
  png_set_user_limits(png, kMaxSide, kMaxSide);
  png_read_info(png, info);
  png_get_IHDR(png, info, &head->width, &head->height, &head->bit_depth, &head->colour, nullptr,
               nullptr, nullptr);
  if (head->bit_depth == 16) png_set_strip_16(png);
  png_set_strip_alpha(png);
  if (head->colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((head->colour & PNG_COLOR_MASK_COLOR) == 0 && head->bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  if ((head->colour & PNG_COLOR_MASK_COLOR) && channels == 3)
    png_set_bgr(png);
  else if (channels == 3)
    png_set_gray_to_rgb(png);
  else
    png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  if (row_bytes != static_cast<std::size_t>(head->width) * channels ||
      row_bytes * head->height > kMaxBytes)
    return false;
  pixels->resize(row_bytes * head->height);
  rows->resize(head->height);
  for (png_uint_32 y = 0; y < head->height; ++y) (*rows)[y] = pixels->data() + y * row_bytes;
  png_read_image(png, rows->data());
  png_read_end(png, nullptr);
  return true;
}

Image8 ReadPngFile(const std::string& path, int channels) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!f) return {};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return {};
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return {};
  }
  PngRead head;
  Image8 out;
  std::vector<png_bytep> rows;
  const bool ok = ReadPng(png, info, f.get(), channels, &head, &out.pixels, &rows);
  png_destroy_read_struct(&png, &info, nullptr);
  if (!ok) return {};
  out.width = static_cast<int>(head.width);
  out.height = static_cast<int>(head.height);
  out.channels = channels;
  return out;
}

// The next header token of a PGM (whitespace and # comments skipped); -1 when malformed.
long PgmNumber(std::istream& in) {
  int c = in.get();
  while (c == '#' || std::isspace(c)) {
    if (c == '#')
      while (c != '\n' && c != EOF) c = in.get();
    c = in.get();
  }
  if (!std::isdigit(c)) return -1;
  long v = 0;
  while (std::isdigit(c)) {
    v = v * 10 + (c - '0');
    if (v > 1L << 20) return -1;
    c = in.get();
  }
  return std::isspace(c) || c == EOF ? v : -1;  // one whitespace ends a token (and the header)
}

Image8 ReadPgmFile(const std::string& path, int channels) {
  std::ifstream in(path, std::ios::binary);
  char magic[2] = {};
  if (!in.read(magic, 2) || magic[0] != 'P' || (magic[1] != '5' && magic[1] != '2')) return {};
  const long w = PgmNumber(in), h = PgmNumber(in), maxval = PgmNumber(in);
  if (w <= 0 || h <= 0 || w > long{kMaxSide} || h > long{kMaxSide} || maxval <= 0 || maxval > 65535)
    return {};
  Image8 out;
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  out.channels = channels;
  out.pixels.resize(static_cast<std::size_t>(w) * h * channels);
  auto to8 = [&](long v) -> std::uint8_t {
    if (v > maxval) v = maxval;
    return static_cast<std::uint8_t>(maxval <= 255 ? v : (v * 255 + maxval / 2) / maxval);
  };
  for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i) {
    long v = 0;
    if (magic[1] == '2') {
      v = PgmNumber(in);
      if (v < 0) return {};
    } else if (maxval <= 255) {
      const int c = in.get();
      if (c == EOF) return {};
      v = c;
    } else {
      const int hi = in.get(), lo = in.get();
      if (lo == EOF) return {};
      v = hi * 256 + lo;
    }
    for (int k = 0; k < channels; ++k) out.pixels[i * channels + k] = to8(v);
  }
  return out;
}

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
};
void JpegErrorExit(j_common_ptr cinfo) {
  std::longjmp(reinterpret_cast<JpegError*>(cinfo->err)->jump, 1);
}

bool WriteJpeg(jpeg_compress_struct* c, JpegError* err, const ImageView& v, int quality,
               unsigned char** buf, unsigned long* size) {
  if (setjmp(err->jump)) return false;
  jpeg_create_compress(c);
  jpeg_mem_dest(c, buf, size);
  c->image_width = static_cast<JDIMENSION>(v.width);
  c->image_height = static_cast<JDIMENSION>(v.height);
  c->input_components = v.channels;
  c->in_color_space = v.channels == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_set_defaults(c);
  jpeg_set_quality(c, quality, TRUE);
  jpeg_start_compress(c, TRUE);
  while (c->next_scanline < c->image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(static_cast<const JSAMPLE*>(v.data) +
                                        static_cast<std::size_t>(c->next_scanline) * v.stride);
    jpeg_write_scanlines(c, &row, 1);
  }
  jpeg_finish_compress(c);
  return true;
}

}  // namespace

std::string EncodePng(const ImageView& image) {
  CheckView(image, false);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) throw std::runtime_error("libpng: cannot create a writer");
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y)
    rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(
        static_cast<const png_byte*>(image.data) + static_cast<std::size_t>(y) * image.stride);
  std::string out;
  const bool ok = info && WritePng(png, info, image, rows.data(), &out);
  png_destroy_write_struct(&png, info ? &info : nullptr);
  if (!ok) throw std::runtime_error("libpng: cannot encode the image");
  return out;
}

std::string EncodeJpeg(const ImageView& image, int quality) {
  CheckView(image, true);
  if (quality < 1 || quality > 100)
    throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " not in 1-100");
  jpeg_compress_struct c;
  JpegError err;
  c.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = JpegErrorExit;
  unsigned char* buf = nullptr;
  unsigned long size = 0;
  const bool ok = WriteJpeg(&c, &err, image, quality, &buf, &size);
  std::string out = ok ? std::string(reinterpret_cast<const char*>(buf), size) : std::string();
  jpeg_destroy_compress(&c);
  std::free(buf);
  if (!ok) throw std::runtime_error("libjpeg: cannot encode the image");
  return out;
}

Image8 ReadImage8(const std::string& path, int channels) {
  if (channels != 1 && channels != 3)
    throw std::invalid_argument("ReadImage8: channels must be 1 or 3");
  std::ifstream in(path, std::ios::binary);
  unsigned char sig[8] = {};
  if (!in.read(reinterpret_cast<char*>(sig), 8)) return {};
  in.close();
  if (png_sig_cmp(sig, 0, 8) == 0) return ReadPngFile(path, channels);
  if (sig[0] == 'P' && (sig[1] == '5' || sig[1] == '2')) return ReadPgmFile(path, channels);
  return {};
}

}  // namespace mopad::io
