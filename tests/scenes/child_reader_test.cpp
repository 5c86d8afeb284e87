// scenes/child_reader.h: a reader run in a child process gives back the whole Scene, its
// InputError as is, and a crash as one InputError naming the reader and the signal.
#include "scenes/child_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <functional>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "tests/input_error_of.h"

namespace mopad::scenes {
namespace {

using test_support::InputErrorOf;

Scene SampleScene() {
  Scene s;
  s.source = "model.ifc";
  s.textures.push_back({"t", 2, 1, {1, 2, 3, 4, 5, 6, 7, 8}, false});
  Material m;
  m.name = "glass";
  m.base_color = {0.1f, 0.2f, 0.3f, 0.4f};
  m.base_color_texture = 0;
  m.metallic = 0.5f;
  m.roughness = 0.25f;
  m.transmission = 0.6f;
  m.nir_reflectance = 0.7f;
  m.double_sided = false;
  s.materials.push_back(m);
  MeshPart p;
  p.name = "IfcWall_W_1";
  p.element_id = "1YvctVUKr0kugbFTf53O9L";
  p.element_class = ElementClass::kWall;
  p.subclass = "IfcWallStandardCase";
  p.room = "R1";
  p.material = 0;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f}};
  p.uvs = {{0, 0}, {1, 0}, {0, 1}};
  p.triangles = {{0, 1, 2}};
  s.parts.push_back(p);
  s.parts.push_back(MeshPart{});  // an empty part, every field at its default
  return s;
}

TEST(ChildReader, TheSceneComesBackWhole) {
  const Scene in = SampleScene();
  const Scene out = ReadSceneInChild("model.ifc", "the test reader", "a file", [&] { return in; });
  EXPECT_EQ(out.source, in.source);
  ASSERT_EQ(out.textures.size(), 1u);
  EXPECT_EQ(out.textures[0].name, "t");
  EXPECT_EQ(out.textures[0].width, 2);
  EXPECT_EQ(out.textures[0].rgba, in.textures[0].rgba);
  EXPECT_FALSE(out.textures[0].repeat);
  ASSERT_EQ(out.materials.size(), 1u);
  const Material& m = out.materials[0];
  EXPECT_EQ(m.name, "glass");
  EXPECT_EQ(m.base_color, in.materials[0].base_color);
  EXPECT_EQ(m.base_color_texture, 0);
  EXPECT_EQ(m.metallic, 0.5f);
  EXPECT_EQ(m.roughness, 0.25f);
  EXPECT_EQ(m.transmission, 0.6f);
  EXPECT_EQ(m.nir_reflectance, 0.7f);
  EXPECT_FALSE(m.double_sided);
  ASSERT_EQ(out.parts.size(), 2u);
  const MeshPart& p = out.parts[0];
  EXPECT_EQ(p.name, "IfcWall_W_1");
  EXPECT_EQ(p.element_id, "1YvctVUKr0kugbFTf53O9L");
  EXPECT_EQ(p.element_class, ElementClass::kWall);
  EXPECT_EQ(p.subclass, "IfcWallStandardCase");
  EXPECT_EQ(p.room, "R1");
  EXPECT_EQ(p.material, 0);
  EXPECT_EQ(p.positions, in.parts[0].positions);
  EXPECT_EQ(p.uvs, in.parts[0].uvs);
  EXPECT_EQ(p.triangles, in.parts[0].triangles);
  EXPECT_TRUE(out.parts[1].positions.empty());
  EXPECT_EQ(out.parts[1].material, -1);
}

// A third-party reader that crashes on a hostile file (assimp's IFC 2x3 reader did, found by
// fuzzing: docs/reliability.md) ends as one InputError; this process goes on.
TEST(ChildReader, ACrashIsAnInputErrorNamingTheReaderAndTheSignal) {
  const std::string m = InputErrorOf([] {
    ReadSceneInChild("bad.ifc", "the IFC 2x3 reader (assimp)", "an IFC 2x3 file it can read",
                     []() -> Scene {
                       std::raise(SIGSEGV);
                       return {};
                     });
  });
  EXPECT_EQ(m.rfind("bad.ifc: error: the IFC 2x3 reader (assimp) crashed on this file; got "
                    "signal 11",
                    0),
            0u)
      << m;
  EXPECT_NE(m.find(", expected an IFC 2x3 file it can read"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// A crash handler of this process, as AddressSanitizer and libFuzzer install one, is not the
// child's: the reader still dies of the signal. Were the handler kept, the child would exit by
// the handler's status (here 1) and the crash would read "cannot read the file; got exit
// status 1".
TEST(ChildReader, ACrashHandlerOfThisProcessDoesNotHideTheReadersSignal) {
  struct sigaction handler {};
  struct sigaction before {};
  handler.sa_handler = [](int) { _exit(1); };
  sigemptyset(&handler.sa_mask);
  ASSERT_EQ(sigaction(SIGSEGV, &handler, &before), 0);
  const std::string m = InputErrorOf([] {
    ReadSceneInChild("bad.ifc", "the reader", "a file", []() -> Scene {
      std::raise(SIGSEGV);
      return {};
    });
  });
  sigaction(SIGSEGV, &before, nullptr);
  EXPECT_NE(m.find("the reader crashed on this file; got signal 11"), std::string::npos) << m;
}

TEST(ChildReader, TheReadersInputErrorArrivesAsItIsAndOtherErrorsNameTheReader) {
  EXPECT_EQ(InputErrorOf([] {
              ReadSceneInChild("a.ifc", "the reader", "a file", []() -> Scene {
                throw InputError("a.ifc", "assimp cannot read the file", "\"x\"", "a valid ifc");
              });
            }),
            "a.ifc: error: assimp cannot read the file; got \"x\", expected a valid ifc");
  EXPECT_EQ(InputErrorOf([] {
              ReadSceneInChild("a.ifc", "the reader", "a file",
                               []() -> Scene { throw std::runtime_error("no entities"); });
            }),
            "a.ifc: error: the reader cannot read the file; got no entities, expected a file");
}

}  // namespace
}  // namespace mopad::scenes
