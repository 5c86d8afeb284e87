#include "scenes/bsc_catalogue.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.h"

namespace mopad::scenes {
namespace {

const std::vector<std::string> kPaperClasses = {
    "electrical_panel",       "socket_x1",      "socket_x2",         "socket_x4",
    "built_in_socket",        "switch",         "fire_extinguisher", "radiator",
    "fire_alarm_switch",      "smoke_detector", "exit_light",        "extinguisher_sign",
    "fire_alarm_switch_sign", "fire_sign",      "exit_sign",         "electric_sign",
    "emergency_light",        "door_sign"};

constexpr double kMm = 1e-3;

TEST(BscCatalogue, HasExactlyThePapersEighteenClasses) {
  std::vector<std::string> names;
  for (const auto& s : BscCatalogue()) names.push_back(s.class_name);
  EXPECT_EQ(names, kPaperClasses);
}

TEST(BscCatalogue, SpecsHaveRealisticSizesAndMountHeights) {
  for (const auto& s : BscCatalogue()) {
    SCOPED_TRACE(s.class_name);
    EXPECT_GT(s.width, 0.0);
    EXPECT_GT(s.height, 0.0);
    EXPECT_GT(s.depth, 0.0);
    EXPECT_LE(std::max({s.width, s.height, s.depth}), 1.0);  // small components
    if (s.mounting == interfaces::Mounting::kWall) {
      EXPECT_GE(s.default_mount_height - s.height / 2, 0.0);  // not below the floor
      EXPECT_LE(s.default_mount_height + s.height / 2, 2.5);  // below a 2.5 m ceiling
    }
  }
  EXPECT_EQ(FindBsc("smoke_detector")->mounting, interfaces::Mounting::kCeiling);
  EXPECT_DOUBLE_EQ(FindBsc("socket_x1")->default_mount_height, 0.30);
  EXPECT_DOUBLE_EQ(FindBsc("switch")->default_mount_height, 1.05);
  EXPECT_DOUBLE_EQ(FindBsc("fire_extinguisher")->default_mount_height, 0.90);
  EXPECT_LT(FindBsc("built_in_socket")->depth, 0.005);  // flush: only a faceplate
}

TEST(BscCatalogue, UnknownClassIsNullOrInputError) {
  EXPECT_EQ(FindBsc("toaster"), nullptr);
  EXPECT_THROW(BuildBscModel("toaster"), InputError);
  EXPECT_THROW(MakeObjectModel("toaster"), InputError);
  EXPECT_THROW(MakeObjectModel("switch", 0.0), InputError);
  EXPECT_THROW(MakeObjectModel("switch", -1.0), InputError);
  EXPECT_THROW(MakeObjectModel("switch", std::nan("")), InputError);
}

TEST(BscModel, PartsAreLabelledServiceComponentsWithTexturedFront) {
  for (const auto& spec : BscCatalogue()) {
    SCOPED_TRACE(spec.class_name);
    const Scene m = BuildBscModel(spec.class_name);
    ASSERT_FALSE(m.parts.empty());
    ASSERT_EQ(m.textures.size(), 1u);
    const Texture& t = m.textures[0];
    EXPECT_GE(t.width, 16);
    EXPECT_GE(t.height, 16);
    EXPECT_EQ(t.rgba.size(), static_cast<std::size_t>(t.width) * t.height * 4);
    bool has_textured_part = false;
    for (const auto& p : m.parts) {
      EXPECT_EQ(p.element_class, ElementClass::kServiceComponent);
      EXPECT_EQ(p.subclass, spec.class_name);
      EXPECT_TRUE(p.element_id.empty());
      ASSERT_GE(p.material, 0);
      ASSERT_LT(p.material, static_cast<int>(m.materials.size()));
      EXPECT_TRUE(p.uvs.empty() || p.uvs.size() == p.positions.size());
      for (const auto& uv : p.uvs) {
        EXPECT_GE(uv.x(), -1e-6f);
        EXPECT_LE(uv.x(), 1 + 1e-6f);
        EXPECT_GE(uv.y(), -1e-6f);
        EXPECT_LE(uv.y(), 1 + 1e-6f);
      }
      for (const auto& tri : p.triangles)
        for (int k = 0; k < 3; ++k) {
          ASSERT_GE(tri[k], 0);
          ASSERT_LT(tri[k], static_cast<int>(p.positions.size()));
        }
      if (!p.uvs.empty() && m.materials[p.material].base_color_texture == 0)
        has_textured_part = true;
    }
    EXPECT_TRUE(has_textured_part);
  }
}

TEST(BscModel, BoundingBoxMatchesSpecWithBackOnTheSurface) {
  for (const auto& s : BscCatalogue()) {
    SCOPED_TRACE(s.class_name);
    const Eigen::AlignedBox3d b = BuildBscModel(s.class_name).Bounds();
    EXPECT_NEAR(b.min().x(), -s.width / 2, kMm);
    EXPECT_NEAR(b.max().x(), s.width / 2, kMm);
    EXPECT_NEAR(b.min().y(), -s.height / 2, kMm);
    EXPECT_NEAR(b.max().y(), s.height / 2, kMm);
    EXPECT_NEAR(b.min().z(), 0.0, 1e-6);
    EXPECT_NEAR(b.max().z(), s.depth, kMm);
  }
}

// Welds vertices across parts by position; a union of closed, consistently oriented meshes has
// every directed edge matched by its reverse, and a positive enclosed volume.
TEST(BscModel, MeshIsClosedAndFacesPointOutwards) {
  using Key = std::tuple<long, long, long>;
  auto key = [](const Eigen::Vector3f& p) {
    return Key{std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6)};
  };
  for (const auto& s : BscCatalogue()) {
    SCOPED_TRACE(s.class_name);
    const Scene m = BuildBscModel(s.class_name);
    std::map<std::pair<Key, Key>, int> edges;
    double volume = 0.0;
    for (const auto& p : m.parts) {
      for (const auto& t : p.triangles) {
        const Eigen::Vector3d a = p.positions[t[0]].cast<double>();
        const Eigen::Vector3d b = p.positions[t[1]].cast<double>();
        const Eigen::Vector3d c = p.positions[t[2]].cast<double>();
        EXPECT_GT((b - a).cross(c - a).norm(), 1e-12) << "degenerate triangle";
        volume += a.dot(b.cross(c)) / 6.0;
        for (int k = 0; k < 3; ++k)
          ++edges[{key(p.positions[t[k]]), key(p.positions[t[(k + 1) % 3]])}];
      }
    }
    int unmatched = 0;
    for (const auto& [e, n] : edges) {
      const auto it = edges.find({e.second, e.first});
      if (it == edges.end() || it->second != n) ++unmatched;
    }
    EXPECT_EQ(unmatched, 0);
    EXPECT_GT(volume, 0.0);
    EXPECT_LE(volume, s.width * s.height * s.depth * (1 + 1e-6));
  }
}

TEST(BscModel, IsDeterministic) {
  for (const auto& s : BscCatalogue()) {
    const Scene a = BuildBscModel(s.class_name), b = BuildBscModel(s.class_name);
    ASSERT_EQ(a.parts.size(), b.parts.size());
    for (std::size_t i = 0; i < a.parts.size(); ++i) {
      EXPECT_EQ(a.parts[i].positions, b.parts[i].positions);
      EXPECT_EQ(a.parts[i].triangles, b.parts[i].triangles);
    }
    EXPECT_EQ(a.textures[0].rgba, b.textures[0].rgba);
  }
}

TEST(ObjectModel, ImagesHaveExpectedSizeDepthAndPictogram) {
  constexpr double kPs = 0.002;
  for (const auto& s : BscCatalogue()) {
    SCOPED_TRACE(s.class_name);
    const interfaces::ObjectModel m = MakeObjectModel(s.class_name, kPs);
    EXPECT_EQ(m.class_name, s.class_name);
    EXPECT_EQ(m.mounting, s.mounting);
    EXPECT_EQ(m.width, s.width);
    EXPECT_EQ(m.height, s.height);
    EXPECT_EQ(m.depth, s.depth);
    EXPECT_EQ(m.pixel_size, kPs);
    EXPECT_EQ(m.image_width, static_cast<int>(std::ceil(s.width / kPs - 1e-9)));
    EXPECT_EQ(m.image_height, static_cast<int>(std::ceil(s.height / kPs - 1e-9)));
    const std::size_t n = static_cast<std::size_t>(m.image_width) * m.image_height;
    ASSERT_EQ(m.colour_rgb.size(), 3 * n);
    ASSERT_EQ(m.depth_m.size(), n);
    const auto [dmin, dmax] = std::minmax_element(m.depth_m.begin(), m.depth_m.end());
    EXPECT_GE(*dmin, 0.0f);
    EXPECT_NEAR(*dmax, s.depth, kPs);
    std::set<std::array<std::uint8_t, 3>> colours;
    for (std::size_t i = 0; i < n; ++i)
      colours.insert({m.colour_rgb[3 * i], m.colour_rgb[3 * i + 1], m.colour_rgb[3 * i + 2]});
    EXPECT_GE(colours.size(), 3u) << "colour image looks uniform";
  }
}

// Mean colour of the object model (pixels with geometry only).
std::array<double, 3> MeanColour(const interfaces::ObjectModel& m) {
  std::array<double, 3> sum{0, 0, 0};
  int count = 0;
  for (std::size_t i = 0; i < m.depth_m.size(); ++i) {
    if (m.depth_m[i] <= 0.0f) continue;
    for (int k = 0; k < 3; ++k) sum[k] += m.colour_rgb[3 * i + k];
    ++count;
  }
  for (auto& v : sum) v /= std::max(count, 1);
  return sum;
}

TEST(ObjectModel, PictogramColoursFollowTheSafetyColourCode) {
  const auto red = MeanColour(MakeObjectModel("fire_sign"));
  EXPECT_GT(red[0], red[1] + 60);
  const auto green = MeanColour(MakeObjectModel("exit_sign"));
  EXPECT_GT(green[1], green[0] + 50);
  const auto yellow = MeanColour(MakeObjectModel("electric_sign"));
  EXPECT_GT(yellow[0], yellow[2] + 60);
  EXPECT_GT(yellow[1], yellow[2] + 40);
  const auto white = MeanColour(MakeObjectModel("socket_x1"));
  EXPECT_GT(std::min({white[0], white[1], white[2]}), 200);
}

TEST(ObjectModel, DepthFollowsTheProtrudingGeometry) {
  constexpr double kPs = 0.002;
  // Sign plates: flat at their thickness everywhere.
  const auto sign = MakeObjectModel("exit_sign", kPs);
  for (float d : sign.depth_m) EXPECT_NEAR(d, 0.003, 1e-6);
  // Triangular plate: empty corners.
  const auto tri = MakeObjectModel("electric_sign", kPs);
  EXPECT_EQ(tri.depth_m.front(), 0.0f);               // top-left corner
  EXPECT_EQ(tri.depth_m[tri.image_width - 1], 0.0f);  // top-right corner
  EXPECT_NEAR(tri.depth_m.back(), 0.002, 1e-6);       // bottom edge is full width
  EXPECT_NEAR(tri.depth_m[5 * tri.image_width + tri.image_width / 2], 0.002, 1e-6);  // apex
  // Extinguisher: cylinder front at the centre, bracket-only side regions do not exist.
  const auto ext = MakeObjectModel("fire_extinguisher", kPs);
  const int cx = ext.image_width / 2, cy = ext.image_height / 2;
  EXPECT_NEAR(ext.depth_m[static_cast<std::size_t>(cy) * ext.image_width + cx], 0.19, kPs);
  EXPECT_LT(ext.depth_m[static_cast<std::size_t>(cy) * ext.image_width], 0.13);  // side edge
  // Switch: rocker stands 4 mm proud of the plate.
  const auto sw = MakeObjectModel("switch", kPs);
  EXPECT_NEAR(sw.depth_m[static_cast<std::size_t>(20) * 40 + 20], 0.012, 1e-6);
  EXPECT_NEAR(sw.depth_m[static_cast<std::size_t>(1) * 40 + 1], 0.008, 1e-6);
}

// The location signs the generators hang above equipment (`placement: above`) say so in the
// catalogue the robot carries; no other class marks anything.
TEST(ObjectModelCatalogue, LocationSignsMarkTheEquipmentBelowThem) {
  const interfaces::ObjectModelCatalogue cat = MakeObjectModelCatalogue(0.004);
  for (const auto& m : cat.models) {
    SCOPED_TRACE(m.class_name);
    if (m.class_name == "extinguisher_sign") {
      EXPECT_EQ(m.marks, "fire_extinguisher");
    } else if (m.class_name == "fire_alarm_switch_sign") {
      EXPECT_EQ(m.marks, "fire_alarm_switch");
    } else {
      EXPECT_EQ(m.marks, "");
    }
    if (!m.marks.empty()) {
      EXPECT_NE(cat.Find(m.marks), nullptr);
    }
  }
}

TEST(ObjectModelCatalogue, CoversAllClassesAndRoundTripsThroughFiles) {
  const interfaces::ObjectModelCatalogue cat = MakeObjectModelCatalogue(0.004);
  ASSERT_EQ(cat.models.size(), kPaperClasses.size());
  for (const auto& name : kPaperClasses) ASSERT_NE(cat.Find(name), nullptr) << name;
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("mopad_bsc_catalogue_test_" + std::to_string(static_cast<long>(::getpid())));
  std::filesystem::remove_all(dir);
  interfaces::WriteCatalogue(cat, dir.string());
  const interfaces::ObjectModelCatalogue back = interfaces::ReadCatalogue(dir.string());
  std::filesystem::remove_all(dir);
  ASSERT_EQ(back.models.size(), cat.models.size());
  for (std::size_t i = 0; i < cat.models.size(); ++i) {
    SCOPED_TRACE(cat.models[i].class_name);
    EXPECT_EQ(back.models[i].class_name, cat.models[i].class_name);
    EXPECT_EQ(back.models[i].mounting, cat.models[i].mounting);
    EXPECT_EQ(back.models[i].width, cat.models[i].width);
    EXPECT_EQ(back.models[i].depth, cat.models[i].depth);
    EXPECT_EQ(back.models[i].marks, cat.models[i].marks);
    EXPECT_EQ(back.models[i].colour_rgb, cat.models[i].colour_rgb);
    EXPECT_EQ(back.models[i].depth_m, cat.models[i].depth_m);
  }
}

}  // namespace
}  // namespace mopad::scenes
