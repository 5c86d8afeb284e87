// PNG, JPEG and PGM through libpng and libjpeg-turbo (io/image_codec.h), against OpenCV's
// imgcodecs as the oracle: the same PNG bytes as cv::imencode, the same pixels as cv::imread.
#include "io/image_codec.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/rng.h"

namespace mopad::io {
namespace {

namespace fs = std::filesystem;

fs::path TempDir() {
  const fs::path d =
      fs::temp_directory_path() / ("mopad_image_codec_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// An image with smooth areas and noise (both kinds of what the encoders see).
cv::Mat Pattern(int rows, int cols, int type, std::uint64_t seed) {
  cv::Mat m(rows, cols, type);
  CounterRng rng(seed, "test/pattern");
  const int n = cols * m.channels();
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < n; ++k) {
      const double v =
          (r * 3 + k) % 97 < 60 ? (r + k / m.channels()) * 0.7 : rng.Uniform(0, 1) * 1e6;
      if (m.depth() == CV_16U)
        m.ptr<std::uint16_t>(r)[k] = static_cast<std::uint16_t>(static_cast<long>(v * 37) % 65536);
      else
        m.ptr<std::uint8_t>(r)[k] = static_cast<std::uint8_t>(static_cast<long>(v) % 256);
    }
  return m;
}

ImageView ViewOf(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, m.channels(), m.depth() == CV_16U ? 16 : 8, m.step};
}

std::string Bytes(const std::vector<unsigned char>& v) { return std::string(v.begin(), v.end()); }

void WriteFile(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

// Pixels of a read image equal to an OpenCV Mat of the same shape.
void ExpectSamePixels(const Image8& got, const cv::Mat& want, const std::string& what) {
  ASSERT_FALSE(want.empty()) << what;
  ASSERT_EQ(got.width, want.cols) << what;
  ASSERT_EQ(got.height, want.rows) << what;
  ASSERT_EQ(got.channels, want.channels()) << what;
  for (int r = 0; r < want.rows; ++r)
    ASSERT_EQ(0, std::memcmp(
                     got.pixels.data() + static_cast<std::size_t>(r) * want.cols * want.channels(),
                     want.ptr(r), static_cast<std::size_t>(want.cols) * want.channels()))
        << what << ", row " << r;
}

TEST(ImageCodec, PngBytesAreOpenCvs) {
  // Grey, B-G-R and B-G-R-A of 8 bits, grey of 16 (the orthoimages' depth), and a view into a
  // larger image (a stride beyond the row).
  const cv::Mat big = Pattern(70, 90, CV_8UC3, 5);
  const std::vector<cv::Mat> images = {
      Pattern(61, 83, CV_8UC1, 1),  Pattern(64, 64, CV_8UC3, 2),
      Pattern(17, 300, CV_8UC4, 3), Pattern(45, 77, CV_16UC1, 4),
      big(cv::Rect(5, 7, 40, 50)),  cv::Mat(1, 1, CV_8UC3, cv::Scalar(9, 8, 7))};
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::vector<unsigned char> oracle;
    ASSERT_TRUE(cv::imencode(".png", images[i], oracle));
    EXPECT_EQ(EncodePng(ViewOf(images[i])), Bytes(oracle)) << "image " << i;
  }
}

TEST(ImageCodec, ReadsWhatOpenCvReads) {
  const fs::path dir = TempDir();
  struct Case {
    std::string name;
    cv::Mat image;
  };
  const std::vector<Case> cases = {
      {"grey.png", Pattern(33, 41, CV_8UC1, 11)},  {"colour.png", Pattern(29, 52, CV_8UC3, 12)},
      {"alpha.png", Pattern(20, 20, CV_8UC4, 13)}, {"deep.png", Pattern(25, 31, CV_16UC1, 14)},
      {"deep3.png", Pattern(12, 9, CV_16UC3, 15)}, {"map.pgm", Pattern(23, 37, CV_8UC1, 16)}};
  for (const Case& c : cases) {
    const fs::path p = dir / c.name;
    ASSERT_TRUE(cv::imwrite(p.string(), c.image)) << c.name;
    ExpectSamePixels(ReadImage8(p.string(), 1), cv::imread(p.string(), cv::IMREAD_GRAYSCALE),
                     c.name + " as grey");
    ExpectSamePixels(ReadImage8(p.string(), 3), cv::imread(p.string(), cv::IMREAD_COLOR),
                     c.name + " as colour");
  }
}

TEST(ImageCodec, ASixteenBitPgmIsScaledByItsMaxval) {
  // v * 255 / maxval, rounded (OpenCV keeps the high byte instead: 1000 -> 3, not 4).
  const fs::path p = TempDir() / "deep.pgm";
  WriteFile(p, std::string("P5\n5 1\n65535\n") +
                   std::string("\x00\x00\x00\xff\x03\xe8\x9c\x40\xff\xff", 10));
  EXPECT_EQ(ReadImage8(p.string(), 1).pixels, (std::vector<std::uint8_t>{0, 1, 4, 156, 255}));
  const fs::path q = TempDir() / "ten_bit.pgm";
  WriteFile(q, "P2\n3 1\n1023\n0 512 1023");  // no newline at the end
  EXPECT_EQ(ReadImage8(q.string(), 1).pixels, (std::vector<std::uint8_t>{0, 128, 255}));
}

TEST(ImageCodec, ReadsAnAsciiPgmWithComments) {
  // map_server's maps are PGM; an ASCII one with a comment in its header, maxval 255.
  const fs::path p = TempDir() / "ascii.pgm";
  WriteFile(p, "P2\n# a hand-written map\n3 2\n255\n0 254 205\n100 7 255\n");
  const Image8 img = ReadImage8(p.string(), 1);
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.pixels, (std::vector<std::uint8_t>{0, 254, 205, 100, 7, 255}));
}

TEST(ImageCodec, BadFilesReadAsEmptyImages) {
  const fs::path dir = TempDir();
  std::vector<unsigned char> png;
  ASSERT_TRUE(cv::imencode(".png", Pattern(40, 40, CV_8UC3, 21), png));
  const std::string whole = Bytes(png);
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty.png", ""},
      {"text.png", "not an image at all"},
      {"cut.png", whole.substr(0, whole.size() / 2)},
      {"header_only.png", whole.substr(0, 33)},
      {"crc.png",
       [&] {
         std::string s = whole;
         s[40] = static_cast<char>(s[40] ^ 0x55);  // inside the first IDAT
         return s;
       }()},
      {"huge.pgm", "P5\n99999999 99999999\n255\n"},
      {"short.pgm", "P5\n4 4\n255\nabc"},
      {"nomax.pgm", "P2\n2 2\n"},
  };
  for (const auto& [name, bytes] : files) {
    WriteFile(dir / name, bytes);
    EXPECT_TRUE(ReadImage8((dir / name).string(), 3).empty()) << name;
  }
  EXPECT_TRUE(ReadImage8((dir / "missing.png").string(), 1).empty());
}

TEST(ImageCodec, JpegDecodesCloseToTheImage) {
  const cv::Mat smooth = [] {
    cv::Mat m(48, 64, CV_8UC3);
    for (int r = 0; r < m.rows; ++r)
      for (int c = 0; c < m.cols; ++c) m.at<cv::Vec3b>(r, c) = cv::Vec3b(r * 4, c * 3, 200 - r - c);
    return m;
  }();
  const std::string jpeg = EncodeJpeg(ViewOf(smooth), 90);
  ASSERT_GT(jpeg.size(), 100u);
  const cv::Mat back =
      cv::imdecode(cv::Mat(1, static_cast<int>(jpeg.size()), CV_8U, const_cast<char*>(jpeg.data())),
                   cv::IMREAD_COLOR);
  ASSERT_EQ(back.size(), smooth.size());
  EXPECT_GT(cv::PSNR(back, smooth), 35.0);  // colours in B, G, R order kept (a swap: ~10 dB)
  const cv::Mat grey = Pattern(16, 24, CV_8UC1, 31);
  EXPECT_FALSE(EncodeJpeg(ViewOf(grey), 75).empty());
}

TEST(ImageCodec, ViewsItCannotEncodeAreRefused) {
  const cv::Mat m = Pattern(4, 4, CV_8UC3, 41);
  ImageView v = ViewOf(m);
  v.channels = 2;
  EXPECT_THROW(EncodePng(v), std::invalid_argument);
  v = ViewOf(m);
  v.stride = 3;  // shorter than a row
  EXPECT_THROW(EncodePng(v), std::invalid_argument);
  v = ViewOf(m);
  v.data = nullptr;
  EXPECT_THROW(EncodePng(v), std::invalid_argument);
  EXPECT_THROW(EncodeJpeg(ViewOf(m), 0), std::invalid_argument);
  EXPECT_THROW(EncodeJpeg(ViewOf(Pattern(4, 4, CV_16UC1, 42)), 90), std::invalid_argument);
  EXPECT_THROW(ReadImage8("x.png", 2), std::invalid_argument);
}

}  // namespace
}  // namespace mopad::io
