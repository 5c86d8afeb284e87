// A generated scene exported to OBJ and read back through assimp gives the same triangles
// (the glTF and assimp paths agree on the same geometry).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>

#include "scenes/generator.h"
#include "scenes/obj_writer.h"
#include "scenes/scene_loader.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {
namespace {

using Tri = std::array<std::int64_t, 9>;

// Each triangle as its three vertices quantised to 0.1 mm, rotated so the smallest vertex comes
// first (winding kept): equal triangles compare equal whatever the vertex order in the file.
std::vector<Tri> Triangles(const Scene& s) {
  std::vector<Tri> out;
  for (const auto& p : s.parts) {
    for (const auto& t : p.triangles) {
      std::array<std::array<std::int64_t, 3>, 3> v;
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d)
          v[k][d] = std::llround(static_cast<double>(p.positions[t[k]][d]) * 1e4);
      const int first = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
      Tri tri;
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) tri[k * 3 + d] = v[(first + k) % 3][d];
      out.push_back(tri);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::map<std::string, std::size_t> TrianglesPerClass(const Scene& s, bool from_obj_names) {
  std::map<std::string, std::size_t> n;
  for (const auto& p : s.parts) {
    std::string cls(ToString(p.element_class));
    if (from_obj_names) {  // assimp names nodes "<file>/<object>"
      const std::string obj = p.name.substr(p.name.rfind('/') + 1);
      cls = obj.substr(0, obj.find(':'));
    }
    n[cls] += p.triangles.size();
  }
  return n;
}

TEST(ObjRoundTrip, GeneratedSceneReadThroughAssimpGivesTheSameTriangles) {
  const std::string spec = std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml";
  const GeneratedScene g = Generate(LoadSceneSpec(spec));
  const std::string dir = testing::TempDir() + "/obj_roundtrip";
  std::filesystem::create_directories(dir);
  WriteObj(g.scene, dir + "/scene.obj");
  ASSERT_TRUE(std::filesystem::exists(dir + "/scene.mtl"));

  const Scene back = LoadScene(dir + "/scene.obj");
  EXPECT_EQ(back.TriangleCount(), g.scene.TriangleCount());
  const auto a = Triangles(g.scene), b = Triangles(back);
  ASSERT_EQ(a.size(), b.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += a[i] != b[i];
  EXPECT_EQ(differing, 0u) << "of " << a.size() << " triangles";
  // Object names carry the class, so per-class triangle counts survive the trip as well.
  EXPECT_EQ(TrianglesPerClass(back, true), TrianglesPerClass(g.scene, false));
}

}  // namespace
}  // namespace mopad::scenes
