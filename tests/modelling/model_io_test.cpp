// sm3.json read back: every field of every patch survives Sm3Json -> ParseSm3, and bad files
// are one-line InputErrors naming the field.
#include "modelling/model_io.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"

namespace mopad::modelling {
namespace {

StructuralModel TwoPatches() {
  StructuralModel m;
  m.room = "R7";
  m.floor_z = -0.01;
  m.ceiling_z = 2.75;
  StructuralPatch w;
  w.id = "wall_1";
  w.patch_class = PatchClass::kWall;
  w.plane.n = {0, 1, 0};
  w.plane.d = 1.5;
  w.polygon = {{0, -1.5, 0}, {4, -1.5, 0}, {4, -1.5, 2.75}, {0, -1.5, 2.75}};
  w.support = 1234;
  w.rms = 0.0021;
  w.fitted = true;
  StructuralPatch c = w;
  c.id = "column_1_face_2";
  c.patch_class = PatchClass::kColumn;
  c.plane.n = {-1, 0, 0};
  c.plane.d = 2.25;
  c.polygon = {{2.25, 0, 0}, {2.25, 0.5, 0}, {2.25, 0.5, 2.75}};
  c.support = 7;
  c.rms = 0.125;
  c.fitted = false;
  m.patches = {w, c};
  m.adjacency = {{0, 1}};
  return m;
}

TEST(Sm3File, EveryFieldReadsBack) {
  const StructuralModel a = TwoPatches();
  const StructuralModel b = ParseSm3(Sm3Json(a), "sm3.json");
  EXPECT_EQ(b.room, "R7");
  EXPECT_DOUBLE_EQ(b.floor_z, -0.01);
  EXPECT_DOUBLE_EQ(b.ceiling_z, 2.75);
  ASSERT_EQ(b.patches.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto &p = a.patches[i], &q = b.patches[i];
    EXPECT_EQ(q.id, p.id);
    EXPECT_EQ(q.patch_class, p.patch_class);
    EXPECT_TRUE(q.plane.n.isApprox(p.plane.n));
    EXPECT_DOUBLE_EQ(q.plane.d, p.plane.d);
    ASSERT_EQ(q.polygon.size(), p.polygon.size());
    for (std::size_t k = 0; k < p.polygon.size(); ++k)
      EXPECT_TRUE(q.polygon[k].isApprox(p.polygon[k], 1e-9)) << i << " " << k;
    EXPECT_EQ(q.support, p.support);
    EXPECT_DOUBLE_EQ(q.rms, p.rms);
    EXPECT_EQ(q.fitted, p.fitted);
  }
  ASSERT_EQ(b.adjacency.size(), 1u);
  EXPECT_EQ(b.adjacency[0], std::make_pair(0, 1));
}

TEST(Sm3File, BadFilesNameTheField) {
  const std::string good = Sm3Json(TwoPatches());
  auto message = [](const std::string& text) {
    try {
      ParseSm3(text, "sm3.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{").find("not valid JSON"), std::string::npos);
  std::string t = good;
  t.replace(t.find("mopad-sm3"), 9, "mopad-sm4");
  EXPECT_NE(message(t).find("format"), std::string::npos);
  t = good;
  t.replace(t.find("\"column\""), 8, "\"beam\"");
  EXPECT_NE(message(t).find("patches[1].class: unknown"), std::string::npos) << message(t);
  t = good;
  t.replace(t.find("\"support\""), 9, "\"suport\"");
  EXPECT_NE(message(t).find("patches[0].support: missing field"), std::string::npos) << message(t);
  EXPECT_THROW(ReadSm3("/nonexistent/sm3.json"), InputError);
}

// models.glb carries SM5: a switch on wall_1 is a box of its size standing on the wall (depth
// into the room), named and described in its extras.
TEST(ModelsGlb, AComponentIsABoxOnItsHostWithItsClassInTheExtras) {
  const StructuralModel sm3 = TwoPatches();
  Sm5Model sm5;
  sm5.room = "R7";
  DetectedComponent c;
  c.id = "bsc_1", c.class_name = "switch", c.host = "wall_1";
  c.centre = {2.0, -1.5, 1.2}, c.normal = {0, 1, 0}, c.size = {0.08, 0.12, 0.01};
  c.alpha = 0.95, c.found_by = FoundBy::kColour;
  sm5.components = {c};
  const std::string path =
      (std::filesystem::temp_directory_path() / "mopad_models_glb_sm5.glb").string();
  WriteModelsGlb(sm3, nullptr, "R7", path, &sm5);
  std::ifstream in(path, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint32_t len = 0;
  std::memcpy(&len, b.data() + 12, 4);
  const auto j = nlohmann::json::parse(b.substr(20, len));
  bool found = false;
  for (const auto& node : j["nodes"]) {
    if (node["name"] != "R7/bsc_1") continue;
    found = true;
    const auto& x = node["extras"]["mopad"];
    const auto& mesh = j["meshes"][node["mesh"].get<int>()];
    EXPECT_EQ(x["class"], "switch");
    EXPECT_EQ(x["host"], "wall_1");
    EXPECT_EQ(x["found_by"], "colour");
    EXPECT_DOUBLE_EQ(x["alpha"].get<double>(), 0.95);
    const auto& acc = j["accessors"][mesh["primitives"][0]["attributes"]["POSITION"].get<int>()];
    const double lo[3] = {1.96, -1.5, 1.14}, hi[3] = {2.04, -1.49, 1.26};
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(acc["min"][k].get<double>(), lo[k], 1e-6) << k;
      EXPECT_NEAR(acc["max"][k].get<double>(), hi[k], 1e-6) << k;
    }
    EXPECT_EQ(j["accessors"][mesh["primitives"][0]["indices"].get<int>()]["count"], 36);
  }
  EXPECT_TRUE(found);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace mopad::modelling
