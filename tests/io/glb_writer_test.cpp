#include "io/glb_writer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/error.h"

namespace mopad::io {
namespace {

std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::uint32_t U32(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

GlbScene Quad() {
  GlbScene s;
  s.name = "test";
  s.materials.push_back({"wall", {0.8f, 0.7f, 0.6f, 1.0f}});
  GlbMesh m;
  m.name = "R1/wall_1";
  m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 0, 3}, {0, 0, 3}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.extras = {{"mopad", {{"id", "R1/wall_1"}, {"class", "wall"}}}};
  s.meshes.push_back(m);
  return s;
}

TEST(Glb, HeaderChunksAccessorsAndExtrasAreThoseOfTheScene) {
  const std::string path = (std::filesystem::path(testing::TempDir()) / "mopad_quad.glb").string();
  WriteGlb(Quad(), path);
  const auto b = ReadBytes(path);
  ASSERT_GE(b.size(), 28u);
  EXPECT_EQ(U32(b, 0), 0x46546C67u);  // glTF
  EXPECT_EQ(U32(b, 4), 2u);
  EXPECT_EQ(U32(b, 8), b.size());
  const std::uint32_t json_len = U32(b, 12);
  EXPECT_EQ(json_len % 4, 0u);
  EXPECT_EQ(U32(b, 16), 0x4E4F534Au);  // JSON
  const auto j = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + json_len);
  EXPECT_EQ(U32(b, 20 + json_len + 4), 0x004E4942u);  // BIN
  // 4 positions (48 bytes) + 6 indices (24 bytes).
  EXPECT_EQ(U32(b, 20 + json_len), 72u);
  EXPECT_EQ(j["nodes"][0]["children"], nlohmann::json::array({1}));
  EXPECT_EQ(j["nodes"][1]["extras"]["mopad"]["class"], "wall");
  EXPECT_EQ(j["accessors"][0]["count"], 4);
  EXPECT_EQ(j["accessors"][0]["max"], nlohmann::json::array({2.0, 0.0, 3.0}));
  EXPECT_EQ(j["accessors"][1]["count"], 6);
  EXPECT_EQ(j["scenes"][0]["name"], "test");
  // Same scene, same bytes.
  const std::string again =
      (std::filesystem::path(testing::TempDir()) / "mopad_quad2.glb").string();
  WriteGlb(Quad(), again);
  EXPECT_EQ(ReadBytes(again), b);
}

TEST(Glb, BadMeshesAreOneLineErrors) {
  const std::string path = (std::filesystem::path(testing::TempDir()) / "mopad_bad.glb").string();
  GlbScene s = Quad();
  s.meshes[0].triangles[0][2] = 7;
  EXPECT_THROW(WriteGlb(s, path), InputError);
  s = Quad();
  s.meshes[0].positions[1].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(WriteGlb(s, path), InputError);
  s = Quad();
  s.meshes[0].material = 3;
  EXPECT_THROW(WriteGlb(s, path), InputError);
  s = Quad();
  s.meshes[0].triangles.clear();
  EXPECT_THROW(WriteGlb(s, path), InputError);
}

}  // namespace
}  // namespace mopad::io
