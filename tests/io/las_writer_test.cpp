#include "io/las_writer.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "common/error.h"

namespace mopad::io {
namespace {

// A reader written from the LAS 1.4 R15 tables (not from the writer).
template <class T>
T Get(const std::string& b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(testing::TempDir()) / name).string();
}

std::vector<LasPoint> ThreePoints() {
  std::vector<LasPoint> ps(3);
  ps[0].p = {1.23456, -4.5, 0.0};
  ps[1].p = {12.0, 3.0001, 2.8};
  ps[2].p = {-3.25, 0.0, -0.5};
  for (int i = 0; i < 3; ++i) {
    ps[i].intensity = static_cast<std::uint16_t>(1000 * (i + 1));
    ps[i].rgb = {static_cast<std::uint16_t>(257 * 10 * i), 65535, 0};
    ps[i].gps_time = 12.5 + i;
    ps[i].classification = static_cast<std::uint8_t>(64 + i);
    ps[i].point_source_id = static_cast<std::uint16_t>(i);
    ps[i].user_data = static_cast<std::uint8_t>(7 * i);
  }
  return ps;
}

TEST(LasWriter, HeaderFieldsAndRecordsReadBack) {
  const std::string path = TempPath("mopad_three.las");
  LasFileInfo info;
  info.min = {-4, -5, -1};
  info.max = {13, 4, 3};
  LasWriter w(path, info);
  const auto ps = ThreePoints();
  w.Append(ps);
  w.Close();
  const std::string b = ReadBytes(path);
  ASSERT_EQ(b.size(), 375u + 3 * 36u);
  EXPECT_EQ(b.substr(0, 4), "LASF");
  EXPECT_EQ(Get<std::uint16_t>(b, 6) & 0x10, 0x10);  // WKT bit (formats 6-10)
  EXPECT_EQ(b[24], 1);
  EXPECT_EQ(b[25], 4);
  EXPECT_EQ(b.substr(26, 9), "OpenMoPAD");
  EXPECT_EQ(Get<std::uint16_t>(b, 94), 375);
  EXPECT_EQ(Get<std::uint32_t>(b, 96), 375u);
  EXPECT_EQ(Get<std::uint32_t>(b, 100), 0u);
  EXPECT_EQ(static_cast<int>(b[104]), 7);
  EXPECT_EQ(Get<std::uint16_t>(b, 105), 36);
  EXPECT_EQ(Get<std::uint32_t>(b, 107), 0u);  // legacy count: 0 for format 7
  EXPECT_EQ(Get<std::uint64_t>(b, 247), 3u);
  EXPECT_EQ(Get<std::uint64_t>(b, 255), 3u);  // all return 1
  EXPECT_EQ(Get<std::uint64_t>(b, 263), 0u);
  const double scale = Get<double>(b, 131);
  EXPECT_DOUBLE_EQ(scale, 1e-4);
  EXPECT_DOUBLE_EQ(Get<double>(b, 155), 5.0);    // offset: bounds centre rounded to metres
  EXPECT_DOUBLE_EQ(Get<double>(b, 179), 12.0);   // max x
  EXPECT_DOUBLE_EQ(Get<double>(b, 187), -3.25);  // min x
  EXPECT_NEAR(Get<double>(b, 195), 3.0001, 1e-9);
  EXPECT_DOUBLE_EQ(Get<double>(b, 203), -4.5);
  EXPECT_NEAR(Get<double>(b, 211), 2.8, 1e-9);
  EXPECT_DOUBLE_EQ(Get<double>(b, 219), -0.5);
  for (int i = 0; i < 3; ++i) {
    const std::size_t at = 375 + 36 * i;
    for (int a = 0; a < 3; ++a) {
      const double v = Get<std::int32_t>(b, at + 4 * a) * scale + Get<double>(b, 155 + 8 * a);
      EXPECT_NEAR(v, ps[i].p[a], 0.5e-4 + 1e-12) << i << " " << a;
    }
    EXPECT_EQ(Get<std::uint16_t>(b, at + 12), ps[i].intensity);
    EXPECT_EQ(static_cast<std::uint8_t>(b[at + 14]), 0x11);  // return 1 of 1
    EXPECT_EQ(static_cast<std::uint8_t>(b[at + 16]), ps[i].classification);
    EXPECT_EQ(static_cast<std::uint8_t>(b[at + 17]), ps[i].user_data);
    EXPECT_EQ(Get<std::uint16_t>(b, at + 20), ps[i].point_source_id);
    EXPECT_EQ(Get<double>(b, at + 22), ps[i].gps_time);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(Get<std::uint16_t>(b, at + 30 + 2 * c), ps[i].rgb[c]);
  }
  // Same points, same bytes.
  const std::string again = TempPath("mopad_three_again.las");
  LasWriter w2(again, info);
  w2.Append(ps);
  w2.Close();
  EXPECT_EQ(ReadBytes(again), b);
}

// The file appears whole at Close() or not at all: a writer given up half way (an exception
// between Append and Close) leaves neither the file nor its temporary (common/atomic_file.h).
TEST(LasWriter, TheFileAppearsOnlyWhenClosed) {
  const std::string path = TempPath("mopad_unclosed.las");
  std::filesystem::remove(path);
  LasFileInfo info;
  info.min = {-4, -5, -1};
  info.max = {13, 4, 3};
  {
    LasWriter w(path, info);
    w.Append(ThreePoints());
    EXPECT_FALSE(std::filesystem::exists(path)) << "a part of the file is visible before Close()";
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  LasWriter w(path, info);
  w.Append(ThreePoints());
  w.Close();
  EXPECT_EQ(ReadBytes(path).size(), 375u + 3 * 36u);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(LasWriter, ScaleCoarsensOnlyWhenTheInt32CountsWouldOverflow) {
  const Eigen::Vector3d lo(0, 0, 0);
  EXPECT_DOUBLE_EQ(LasScaleFor(lo, {100, 50, 3}, LasOffsetFor(lo, {100, 50, 3})), 1e-4);
  EXPECT_DOUBLE_EQ(LasScaleFor(lo, {1e6, 1, 1}, LasOffsetFor(lo, {1e6, 1, 1})), 1e-3);
  EXPECT_DOUBLE_EQ(LasScaleFor(lo, {1e7, 1, 1}, LasOffsetFor(lo, {1e7, 1, 1})), 1e-2);
  EXPECT_EQ(LasOffsetFor({-4, -5, -1}, {13, 4, 3}),
            Eigen::Vector3d(5, -1, 1));  // halves away from 0
}

TEST(LasWriter, BadBoundsAndUnrepresentablePointsAreInputErrors) {
  LasFileInfo info;
  info.min = {1, 0, 0};
  info.max = {0, 1, 1};
  EXPECT_THROW(LasWriter(TempPath("mopad_bad.las"), info), InputError);
  info.min = {0, 0, 0};
  LasWriter w(TempPath("mopad_far.las"), info);
  std::vector<LasPoint> far(1);
  far[0].p = {1e6, 0, 0};  // 1000 km at 0.1 mm does not fit an int32
  EXPECT_THROW(w.Append(far), InputError);
  far[0].p = {std::nan(""), 0, 0};
  EXPECT_THROW(w.Append(far), InputError);
  EXPECT_THROW(LasWriter("/nonexistent-dir/x.las", LasFileInfo{}), InputError);
}

}  // namespace
}  // namespace mopad::io
