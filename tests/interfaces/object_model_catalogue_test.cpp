#include "interfaces/object_model_catalogue.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.h"

namespace mopad::interfaces {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test under the system temp dir.
class CatalogueDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mopad_catalogue_test_" + std::string(info->name()) + "_" +
                                        std::to_string(static_cast<long>(::getpid())));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Dir() const { return dir_.string(); }
  std::string Yaml() const { return (dir_ / "catalogue.yaml").string(); }
  fs::path dir_;
};

ObjectModel MakeModel(const std::string& name, int w, int h, Mounting mounting) {
  ObjectModel m;
  m.class_name = name;
  m.mounting = mounting;
  m.width = w * 0.002 - 0.0007;  // not a multiple of the pixel size: tests exact doubles
  m.height = h * 0.002 - 0.0003;
  m.depth = 0.1 / 3.0;
  m.pixel_size = 0.002;
  m.image_width = w;
  m.image_height = h;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      // Asymmetric in rows and columns so that a flipped image cannot pass.
      m.colour_rgb.push_back(static_cast<std::uint8_t>(i * 7 + j));
      m.colour_rgb.push_back(static_cast<std::uint8_t>(j * 13));
      m.colour_rgb.push_back(static_cast<std::uint8_t>((i * j) & 0xFF));
      m.depth_m.push_back(static_cast<float>(0.001 * i + 0.0001 * j * j + 1e-7));
    }
  }
  return m;
}

ObjectModelCatalogue SampleCatalogue() {
  ObjectModelCatalogue c;
  c.models.push_back(MakeModel("socket_x2", 5, 3, Mounting::kWall));
  c.models.push_back(MakeModel("smoke_detector", 4, 4, Mounting::kCeiling));
  c.models.push_back(MakeModel("floor_box", 1, 2, Mounting::kFloor));
  c.models.back().marks = "socket_x2";
  return c;
}

std::string ReadText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
}

void ReplaceInFile(const std::string& path, const std::string& from, const std::string& to) {
  std::string s = ReadText(path);
  const auto pos = s.find(from);
  ASSERT_NE(pos, std::string::npos) << from;
  s.replace(pos, from.size(), to);
  WriteText(path, s);
}

// Expects ReadCatalogue(dir) to throw InputError whose message contains all of `parts`.
void ExpectInputError(const std::string& dir, std::initializer_list<std::string> parts) {
  try {
    ReadCatalogue(dir);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << msg << " / " << p;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST(ObjectModelCatalogue, FindReturnsModelOrNull) {
  const ObjectModelCatalogue c = SampleCatalogue();
  ASSERT_NE(c.Find("smoke_detector"), nullptr);
  EXPECT_EQ(c.Find("smoke_detector")->mounting, Mounting::kCeiling);
  EXPECT_EQ(c.Find("no_such_class"), nullptr);
}

TEST_F(CatalogueDir, WriteThenReadIsIdentical) {
  const ObjectModelCatalogue c = SampleCatalogue();
  WriteCatalogue(c, Dir());
  const ObjectModelCatalogue r = ReadCatalogue(Dir());
  ASSERT_EQ(r.models.size(), c.models.size());
  for (std::size_t k = 0; k < c.models.size(); ++k) {
    const ObjectModel& a = c.models[k];
    const ObjectModel& b = r.models[k];
    EXPECT_EQ(a.class_name, b.class_name);
    EXPECT_EQ(a.mounting, b.mounting);
    EXPECT_EQ(a.width, b.width);  // exact: 17 significant digits
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.marks, b.marks);
    EXPECT_EQ(a.pixel_size, b.pixel_size);
    EXPECT_EQ(a.image_width, b.image_width);
    EXPECT_EQ(a.image_height, b.image_height);
    EXPECT_EQ(a.colour_rgb, b.colour_rgb);
    EXPECT_EQ(a.depth_m, b.depth_m);
  }
  // Writing what was read gives the same bytes.
  const std::string yaml1 = ReadText(Yaml());
  const std::string ppm1 = ReadText((dir_ / "socket_x2_colour.ppm").string());
  const std::string pfm1 = ReadText((dir_ / "socket_x2_depth.pfm").string());
  WriteCatalogue(r, Dir());
  EXPECT_EQ(ReadText(Yaml()), yaml1);
  EXPECT_EQ(ReadText((dir_ / "socket_x2_colour.ppm").string()), ppm1);
  EXPECT_EQ(ReadText((dir_ / "socket_x2_depth.pfm").string()), pfm1);
}

TEST_F(CatalogueDir, FilesAreStandardPpmAndLittleEndianPfmBottomRowFirst) {
  WriteCatalogue(SampleCatalogue(), Dir());
  const std::string ppm = ReadText((dir_ / "socket_x2_colour.ppm").string());
  EXPECT_EQ(ppm.substr(0, 11), "P6\n5 3\n255\n");
  EXPECT_EQ(ppm.size(), 11u + 5 * 3 * 3);
  const std::string pfm = ReadText((dir_ / "socket_x2_depth.pfm").string());
  ASSERT_EQ(pfm.substr(0, 10), "Pf\n5 3\n-1\n");
  ASSERT_EQ(pfm.size(), 10u + 5 * 3 * 4);
  // First stored float = bottom-left pixel (row 2, col 0).
  float v = 0.0f;
  std::memcpy(&v, pfm.data() + 10, 4);  // the test machine is little-endian (x86-64/arm64)
  EXPECT_EQ(v, static_cast<float>(0.0001 * 4 + 1e-7));
}

TEST_F(CatalogueDir, EmptyCatalogueRoundTrips) {
  WriteCatalogue(ObjectModelCatalogue{}, Dir());
  EXPECT_TRUE(ReadCatalogue(Dir()).models.empty());
}

TEST_F(CatalogueDir, MissingDirectoryNamesThePath) { ExpectInputError(Dir(), {Yaml()}); }

TEST_F(CatalogueDir, MalformedYamlGivesFileAndLine) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "models:\n", "models: [\n");
  ExpectInputError(Dir(), {Yaml() + ":", "error:"});
}

TEST_F(CatalogueDir, UnknownKeyIsRejectedWithLine) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "    mounting: ceiling\n", "    mounting: ceiling\n    colour: red\n");
  ExpectInputError(Dir(), {Yaml() + ":", "unknown key", "colour"});
}

TEST_F(CatalogueDir, UnknownTopLevelKeyIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "version: 1\n", "version: 1\nauthor: me\n");
  ExpectInputError(Dir(), {Yaml() + ":", "unknown key 'author'"});
}

TEST_F(CatalogueDir, MissingKeyIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "    depth_file: floor_box_depth.pfm\n", "");
  ExpectInputError(Dir(), {Yaml() + ":", "missing key 'depth_file'"});
}

TEST_F(CatalogueDir, BadValuesAreRejected) {
  const std::pair<std::string, std::string> cases[] = {
      {"mounting: wall", "mounting: roof"},
      {"version: 1", "version: 2"},
      {"format: mopad-object-model-catalogue", "format: something-else"},
      {"image_width: 5", "image_width: -5"},
      {"image_width: 5", "image_width: five"},
      {"pixel_size: 0.002", "pixel_size: 0"},
      {"colour_file: socket_x2_colour.ppm", "colour_file: ../socket_x2_colour.ppm"},
      {"marks: socket_x2", "marks: ../socket_x2"},
  };
  for (const auto& [from, to] : cases) {
    SCOPED_TRACE(to);
    WriteCatalogue(SampleCatalogue(), Dir());
    ReplaceInFile(Yaml(), from, to);
    ExpectInputError(Dir(), {Yaml() + ":", "error:"});
  }
}

TEST_F(CatalogueDir, DuplicateClassIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "class_name: floor_box", "class_name: socket_x2");
  ExpectInputError(Dir(), {Yaml() + ":", "duplicate"});
}

TEST_F(CatalogueDir, MissingImageFileIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  fs::remove(dir_ / "smoke_detector_depth.pfm");
  ExpectInputError(Dir(), {Yaml() + ":", "missing image file", "smoke_detector_depth.pfm"});
}

TEST_F(CatalogueDir, SizeMismatchWithYamlIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  ReplaceInFile(Yaml(), "image_height: 3", "image_height: 4");
  ExpectInputError(Dir(), {"socket_x2_colour.ppm", "does not match", "5x3", "5x4"});
}

TEST_F(CatalogueDir, BadMagicIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  const std::string ppm = (dir_ / "socket_x2_colour.ppm").string();
  ReplaceInFile(ppm, "P6", "P3");
  ExpectInputError(Dir(), {ppm, "bad PPM magic"});
  WriteCatalogue(SampleCatalogue(), Dir());
  const std::string pfm = (dir_ / "socket_x2_depth.pfm").string();
  ReplaceInFile(pfm, "Pf", "PF");
  ExpectInputError(Dir(), {pfm, "bad PFM magic"});
}

TEST_F(CatalogueDir, TruncatedAndOverlongDataIsRejected) {
  WriteCatalogue(SampleCatalogue(), Dir());
  const std::string pfm = (dir_ / "socket_x2_depth.pfm").string();
  std::string s = ReadText(pfm);
  WriteText(pfm, s.substr(0, s.size() - 1));
  ExpectInputError(Dir(), {pfm, "data size mismatch"});
  WriteCatalogue(SampleCatalogue(), Dir());
  const std::string ppm = (dir_ / "floor_box_colour.ppm").string();
  WriteText(ppm, ReadText(ppm) + "x");
  ExpectInputError(Dir(), {ppm, "data size mismatch"});
  WriteCatalogue(SampleCatalogue(), Dir());
  WriteText(ppm, "P6\n1 2\n");
  ExpectInputError(Dir(), {ppm, "truncated header"});
}

TEST_F(CatalogueDir, NonFiniteDepthIsRejected) {
  ObjectModelCatalogue c = SampleCatalogue();
  WriteCatalogue(c, Dir());
  const std::string pfm = (dir_ / "floor_box_depth.pfm").string();
  std::string s = ReadText(pfm);
  const char nan_le[4] = {0x00, 0x00, static_cast<char>(0xC0), 0x7F};
  s.replace(s.size() - 4, 4, nan_le, 4);
  WriteText(pfm, s);
  ExpectInputError(Dir(), {pfm, "non-finite"});
}

TEST_F(CatalogueDir, WriteRejectsInconsistentModels) {
  ObjectModelCatalogue c = SampleCatalogue();
  c.models[0].depth_m.pop_back();
  EXPECT_THROW(WriteCatalogue(c, Dir()), InputError);
  c = SampleCatalogue();
  c.models[1].class_name = "../evil";
  EXPECT_THROW(WriteCatalogue(c, Dir()), InputError);
  c = SampleCatalogue();
  c.models[2].class_name = "socket_x2";
  EXPECT_THROW(WriteCatalogue(c, Dir()), InputError);
}

}  // namespace
}  // namespace mopad::interfaces
