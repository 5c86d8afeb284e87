// Building details (scenes/details_params.h): placed where a builder would put them — skirting
// along the walls but never across a doorway, posters and ducts clear of openings and
// components, pipes in corners outside door swings — on the committed office and on random
// floors of every family; a glazed leaf that the base LRF still sees; a spec without details
// generated as if the step did not exist; the truth's `details` read back.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "common/error.h"
#include "scenes/generator.h"
#include "scenes/geometry.h"
#include "scenes/random_floor.h"
#include "scenes/scene_check.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

DetailsParams Lots(std::uint64_t seed) {
  DetailsParams d;
  d.skirting_height = 0.08;
  d.ceiling_trim_height = 0.05;
  d.ducts_per_room = 1.0;
  d.pipes_per_room = 1.0;
  d.posters_per_room = 4.0;
  d.frames_in_wall_colour = 0.6;
  d.glazed_doors = 0.5;
  d.seed = seed;
  return d;
}

SceneSpec Office() {
  return LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml");
}

std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The along-wall interval [lo, hi] and the across-wall offset of a detail box on the line of a
// wall through `a` with unit direction `dir`.
struct OnLine {
  double lo, hi, across;
};
OnLine Project(const FurnitureItem& d, const Vector2d& a, const Vector2d& dir) {
  const Vector2d c = d.centre.head<2>() - a;
  const double along = c.dot(dir),
               half = 0.5 * d.size.x() * std::abs(std::cos(d.yaw - std::atan2(dir.y(), dir.x())));
  return {along - half, along + half, std::abs(dir.x() * c.y() - dir.y() * c.x())};
}

// Checks one generated scene's details against its truth; returns the counts per type.
std::map<std::string, int> CheckDetails(const GeneratedScene& g, const std::string& what) {
  const CheckReport report = CheckScene(g.scene, g.truth);
  EXPECT_TRUE(report.ok()) << what << "\n" << report.Summary();
  std::map<std::string, int> count;
  for (const FurnitureItem& d : g.truth.details) {
    ++count[d.type];
    const Room* room = g.truth.FindRoom(d.room);
    EXPECT_NE(room, nullptr) << what << " " << d.id;
    if (!room) continue;
    // Inside its room (the box's centre within the room's polygon, up to the box's depth).
    EXPECT_TRUE(PointInPolygon(d.centre.head<2>(), room->polygon) ||
                DistanceToBoundary(d.centre.head<2>(), room->polygon) < 0.01)
        << what << " " << d.id;
    EXPECT_GE(d.centre.z() - 0.5 * d.size.z(), room->floor_z - 1e-9) << what << " " << d.id;
    EXPECT_LE(d.centre.z() + 0.5 * d.size.z(), room->ceiling_z + 1e-9) << what << " " << d.id;
    // Nothing on a wall lies across a door or window of that wall.
    for (const Opening& o : g.truth.openings) {
      const Vector2d a = o.corners[0].head<2>(), b = o.corners[3].head<2>();
      const Vector2d dir = (b - a).normalized();
      const OnLine p = Project(d, a, dir);
      if (d.type == "pipe" || p.across > 0.3) continue;
      const double z0 = d.centre.z() - 0.5 * d.size.z(), z1 = d.centre.z() + 0.5 * d.size.z();
      const bool beside = p.hi <= 1e-6 || p.lo >= (b - a).norm() - 1e-6;
      const bool above_or_below = z1 <= o.corners[0].z() + 1e-6 || z0 >= o.corners[1].z() - 1e-6;
      EXPECT_TRUE(beside || above_or_below) << what << " " << d.id << " across " << o.id;
    }
    // Posters, pictures and whiteboards keep clear of the service components on their wall.
    if (d.type == "poster" || d.type == "picture" || d.type == "whiteboard")
      for (const ServiceComponent& s : g.truth.service_components) {
        const Vector3d off = s.centre - d.centre;
        const bool same_wall = std::abs(off.head<2>().dot(s.normal.head<2>())) < 0.05;
        const bool apart = std::abs(off.z()) > 0.5 * (d.size.z() + s.size.y()) ||
                           std::abs(off.x() * std::cos(d.yaw) + off.y() * std::sin(d.yaw)) >
                               0.5 * (d.size.x() + s.size.x());
        EXPECT_TRUE(!same_wall || apart) << what << " " << d.id << " over " << s.id;
      }
  }
  return count;
}

TEST(Details, TheOfficeGetsEveryKindOfDetailWhereABuilderWouldPutIt) {
  SceneSpec spec = Office();
  spec.details = Lots(3);
  const GeneratedScene g = Generate(spec);
  const auto count = CheckDetails(g, "office_5rooms");
  const int rooms = static_cast<int>(g.truth.rooms.size());
  EXPECT_GE(count.at("skirting"), 2 * rooms);  // every room, broken at its doors
  EXPECT_GE(count.at("ceiling_trim"), rooms);
  EXPECT_GE(count.at("duct"), rooms - 1);  // mean 1 per room; a room may lack a free stretch
  EXPECT_GE(count.at("pipe"), 1);
  EXPECT_EQ(count.at("poster") + count.at("picture") + count.at("whiteboard"), 4 * rooms);
  // Doors: some frames in the wall's paint, some leaves glazed, each with a pane that lets rays
  // through and a bottom rail up to 0.3 m that the base LRF (0.25 m) still sees.
  int wall_frames = 0, glazed = 0;
  for (const Material& m : g.scene.materials)
    if (m.name.rfind("door_frame_wall", 0) == 0) ++wall_frames;
  for (const MeshPart& p : g.scene.parts) {
    if (p.element_class != ElementClass::kDoorLeaf || p.name.find("/glass") == std::string::npos)
      continue;
    ++glazed;
    EXPECT_GT(g.scene.materials[p.material].transmission, 0.5f);
    float pane_z0 = 1e9f;
    for (const auto& v : p.positions) pane_z0 = std::min(pane_z0, v.z());
    EXPECT_NEAR(pane_z0, 0.3f, 1e-4f);
    const std::string leaf = p.element_id + "/leaf";
    const auto it = std::find_if(g.scene.parts.begin(), g.scene.parts.end(),
                                 [&](const MeshPart& q) { return q.name == leaf; });
    ASSERT_NE(it, g.scene.parts.end());
    float leaf_z0 = 1e9f;
    for (const auto& v : it->positions) leaf_z0 = std::min(leaf_z0, v.z());
    EXPECT_LT(leaf_z0, 0.02f);
  }
  EXPECT_GE(wall_frames, 1);
  EXPECT_GE(glazed, 2);
  EXPECT_LT(glazed, static_cast<int>(spec.doors.size()));
}

TEST(Details, RandomFloorsOfEveryFamilyGetTheirDetailsClearOfOpenings) {
  const FloorFamily families[] = {FloorFamily::kOffice, FloorFamily::kCorridor,
                                  FloorFamily::kJunction, FloorFamily::kHall};
  int posters = 0;
  for (std::uint64_t seed = 201; seed < 209; ++seed) {
    const FloorFamily family = families[seed % 4];
    SceneSpec spec = RandomFloorSpec(seed, 4 + static_cast<int>(seed % 4), family);
    spec.details = Lots(seed);
    const GeneratedScene g = Generate(spec);
    const auto count = CheckDetails(g, FloorFamilyName(family) + " " + std::to_string(seed));
    EXPECT_GE(count.count("skirting") ? count.at("skirting") : 0,
              static_cast<int>(g.truth.rooms.size()));
    for (const char* t : {"poster", "picture", "whiteboard"})
      posters += count.count(t) ? count.at(t) : 0;
  }
  EXPECT_GT(posters, 40);
}

TEST(Details, ASpecWithoutDetailsIsGeneratedAsBeforeAndTheDetailsAreSeeded) {
  const SceneSpec spec = Office();
  ASSERT_FALSE(spec.details.Enabled());
  SceneSpec with = spec, again = spec, other = spec;
  with.details = again.details = Lots(3);
  other.details = Lots(4);
  const auto dir =
      std::filesystem::temp_directory_path() / ("mopad_details_" + std::to_string(::getpid()));
  WriteGeneratedScene(Generate(spec), (dir / "plain").string());
  WriteGeneratedScene(Generate(with), (dir / "with").string());
  WriteGeneratedScene(Generate(again), (dir / "again").string());
  WriteGeneratedScene(Generate(other), (dir / "other").string());
  // No details: no `details` in the truth or the spec, and nothing else moved by them.
  EXPECT_EQ(ReadFile(dir / "plain/scene.truth.json").find("\"details\""), std::string::npos);
  EXPECT_EQ(ReadFile(dir / "plain/spec.effective.yaml").find("details"), std::string::npos);
  // The same seed, the same bytes; another seed, another building.
  EXPECT_EQ(ReadFile(dir / "with/scene.glb"), ReadFile(dir / "again/scene.glb"));
  EXPECT_NE(ReadFile(dir / "with/scene.glb"), ReadFile(dir / "other/scene.glb"));
  // The structure, openings, components and furniture are the design's whatever the details.
  const GroundTruth plain = ReadGroundTruth((dir / "plain/scene.truth.json").string());
  const GroundTruth detailed = ReadGroundTruth((dir / "with/scene.truth.json").string());
  ASSERT_EQ(plain.elements.size(), detailed.elements.size());
  for (std::size_t i = 0; i < plain.elements.size(); ++i)
    EXPECT_EQ(plain.elements[i].polygons, detailed.elements[i].polygons);
  ASSERT_EQ(plain.service_components.size(), detailed.service_components.size());
  for (std::size_t i = 0; i < plain.service_components.size(); ++i)
    EXPECT_EQ(plain.service_components[i].centre, detailed.service_components[i].centre);
  EXPECT_EQ(plain.furniture.size(), detailed.furniture.size());
  EXPECT_TRUE(plain.details.empty());
  // The details read back from the truth and the spec.
  const GeneratedScene g = Generate(with);
  ASSERT_EQ(detailed.details.size(), g.truth.details.size());
  for (std::size_t i = 0; i < g.truth.details.size(); ++i) {
    EXPECT_EQ(detailed.details[i].id, g.truth.details[i].id);
    EXPECT_EQ(detailed.details[i].type, g.truth.details[i].type);
    EXPECT_LT((detailed.details[i].centre - g.truth.details[i].centre).norm(), 1e-9);
  }
  const SceneSpec back = LoadSceneSpec((dir / "with/spec.effective.yaml").string());
  EXPECT_DOUBLE_EQ(back.details.posters_per_room, 4.0);
  EXPECT_EQ(back.details.seed, 3u);
  std::filesystem::remove_all(dir);
  EXPECT_THROW(ParseSceneSpec("name: x\ndetails: {glazed_doors: 2}\nrooms: []\n", "x.yaml"),
               InputError);
}

TEST(Details, AGeneratedIdThatClashesWithASpecIdIsRefused) {
  SceneSpec spec = Office();
  ASSERT_FALSE(spec.columns.empty());
  spec.columns[0].id = "skirting_1";
  EXPECT_NO_THROW(Generate(spec));  // no details, no clash
  spec.details = Lots(3);
  try {
    Generate(spec);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("generated id 'skirting_1' is not unique"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mopad::scenes
