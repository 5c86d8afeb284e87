// Round trip: the generated office written as .glb and read back through scenes::LoadScene has
// the same triangles per element id, the same per-triangle classes and the same positions
// (the Z-up -> Y-up root rotation undone by the loader).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <tuple>

#include "scenes/generator.h"
#include "scenes/gltf_writer.h"
#include "scenes/scene_check.h"
#include "scenes/scene_loader.h"

namespace mopad::scenes {
namespace {

namespace fs = std::filesystem;

struct Stats {
  std::size_t triangles = 0;
  ElementClass cls = ElementClass::kUnknown;
  std::string subclass, room;
  Eigen::AlignedBox3d box;
};

std::map<std::string, Stats> PerElement(const Scene& s) {
  std::map<std::string, Stats> out;
  for (const MeshPart& p : s.parts) {
    Stats& st = out[p.element_id + "|" + std::string(ToString(p.element_class))];
    st.triangles += p.triangles.size();
    st.cls = p.element_class;
    st.subclass = p.subclass;
    st.room = p.room;
    for (const auto& t : p.triangles)
      for (int k = 0; k < 3; ++k) st.box.extend(p.positions[t[k]].cast<double>());
  }
  return out;
}

TEST(RoundTrip, GeneratedGlbLoadsBackWithTheSameLabelledTriangles) {
  const GeneratedScene g =
      Generate(LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/office_5rooms.yaml"));
  const fs::path dir =
      fs::temp_directory_path() / ("mopad_roundtrip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "scene.glb").string();
  WriteGlb(g.scene, path);
  LoadOptions options;
  options.drop_degenerate_triangles = false;
  const Scene loaded = LoadScene(path, options);
  EXPECT_EQ(loaded.TriangleCount(), g.scene.TriangleCount());
  const auto a = PerElement(g.scene), b = PerElement(loaded);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [key, sa] : a) {
    const auto it = b.find(key);
    ASSERT_NE(it, b.end()) << key;
    const Stats& sb = it->second;
    EXPECT_EQ(sa.triangles, sb.triangles) << key;
    EXPECT_EQ(sa.cls, sb.cls) << key;
    EXPECT_EQ(sa.subclass, sb.subclass) << key;
    EXPECT_EQ(sa.room, sb.room) << key;
    EXPECT_TRUE(sa.box.min().isApprox(sb.box.min(), 1e-5) ||
                (sa.box.min() - sb.box.min()).norm() < 1e-5)
        << key << " moved: Z-up conversion";
    EXPECT_LT((sa.box.max() - sb.box.max()).norm(), 1e-5) << key;
  }
  EXPECT_GE(loaded.materials.size(), g.scene.materials.size());
  // What `mopad scene validate DIR` does: the loaded file (default options) checks clean.
  const CheckReport r = CheckScene(LoadScene(path), g.truth);
  EXPECT_TRUE(r.ok()) << r.Summary();
  EXPECT_EQ(loaded.textures.size(), g.scene.textures.size());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mopad::scenes
