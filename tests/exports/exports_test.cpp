// The exports of a tiny synthetic run folder (one 4 m x 3 m room with a column, a door, a window
// and three service components, a 9-point SM1 cloud), checked against what the files say, and
// by the independent npm readers when node has them (web-ifc, copc, gltf-validator).
#include "exports/exports.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "common/error.h"
#include "io/scan_io.h"
#include "modelling/model_io.h"

namespace mopad::exports {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Vec3 = Eigen::Vector3d;

std::string ReadBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

modelling::StructuralPatch Patch(const std::string& id, modelling::PatchClass cls, Vec3 n,
                                 std::vector<Vec3> poly) {
  modelling::StructuralPatch p;
  p.id = id;
  p.patch_class = cls;
  p.plane.n = n;
  p.plane.d = -n.dot(poly.front());
  p.polygon = std::move(poly);
  p.support = 100;
  p.fitted = true;
  return p;
}

// A 4 x 3 x 2.5 m room (x in [0, 4], y in [0, 3]), a 0.4 m square column at (2, 1.5).
modelling::StructuralModel Room() {
  using modelling::PatchClass;
  modelling::StructuralModel m;
  m.room = "R1";
  m.ceiling_z = 2.5;
  const double h = 2.5;
  m.patches = {
      Patch("wall_1", PatchClass::kWall, {0, 1, 0}, {{4, 0, 0}, {0, 0, 0}, {0, 0, h}, {4, 0, h}}),
      Patch("wall_2", PatchClass::kWall, {-1, 0, 0}, {{4, 3, 0}, {4, 0, 0}, {4, 0, h}, {4, 3, h}}),
      Patch("wall_3", PatchClass::kWall, {0, -1, 0}, {{0, 3, 0}, {4, 3, 0}, {4, 3, h}, {0, 3, h}}),
      Patch("wall_4", PatchClass::kWall, {1, 0, 0}, {{0, 0, 0}, {0, 3, 0}, {0, 3, h}, {0, 0, h}}),
      Patch("floor", PatchClass::kFloor, {0, 0, 1}, {{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}),
      Patch("ceiling", PatchClass::kCeiling, {0, 0, -1},
            {{0, 0, h}, {0, 3, h}, {4, 3, h}, {4, 0, h}})};
  const double a = 1.8, b = 2.2, c = 1.3, d = 1.7;  // column footprint
  m.patches.push_back(Patch("column_1_face_1", PatchClass::kColumn, {0, -1, 0},
                            {{a, c, 0}, {b, c, 0}, {b, c, h}, {a, c, h}}));
  m.patches.push_back(Patch("column_1_face_2", PatchClass::kColumn, {1, 0, 0},
                            {{b, c, 0}, {b, d, 0}, {b, d, h}, {b, c, h}}));
  m.patches.push_back(Patch("column_1_face_3", PatchClass::kColumn, {0, 1, 0},
                            {{b, d, 0}, {a, d, 0}, {a, d, h}, {b, d, h}}));
  m.patches.push_back(Patch("column_1_face_4", PatchClass::kColumn, {-1, 0, 0},
                            {{a, d, 0}, {a, c, 0}, {a, c, h}, {a, d, h}}));
  return m;
}

modelling::Sm4Model Openings() {
  modelling::Sm4Model m;
  m.room = "R1";
  modelling::DetectedOpening door;
  door.id = "opening_1";
  door.host = "wall_1";
  door.corners = {Vec3(3, 0, 0), Vec3(2, 0, 0), Vec3(2, 0, 2), Vec3(3, 0, 2)};
  door.state = modelling::DoorState::kSemiOpen;
  door.opening_angle_deg = 37.5;
  door.clear_width_m = 0.2;
  door.confidence = 0.9;
  modelling::DetectedOpening window = door;
  window.id = "opening_2";
  window.type = modelling::OpeningType::kWindow;
  window.host = "wall_2";
  window.corners = {Vec3(4, 2, 1), Vec3(4, 1, 1), Vec3(4, 1, 2), Vec3(4, 2, 2)};  // CCW from inside
  window.confidence = 0.8;
  m.openings = {door, window};
  return m;
}

const char* kSm5 = R"({"format": "mopad-sm5", "version": 1, "room": "R1", "components": [
 {"id": "component_1", "class": "socket_x2", "host": "wall_3", "centre": [1, 2.98, 0.3],
  "normal": [0, -1, 0], "size": [0.15, 0.08, 0.04], "alpha": 0.91, "found_by": "image"},
 {"id": "component_2", "class": "smoke_detector", "host": "ceiling", "centre": [1, 1, 2.47],
  "normal": [0, 0, -1], "size": [0.11, 0.11, 0.05], "alpha": 0.75, "found_by": "geometry"},
 {"id": "component_3", "class": "exit_sign", "centre": [0.02, 1.5, 2.2],
  "normal": [1, 0, 0], "size": [0.3, 0.15], "alpha": 0.5}]})";

// Nine points: an inlier on wall_1, the floor, the ceiling, a column face and in mid-air
// (no patch near), an outlier, clutter, an unlabelled point; scans 0 and 1.
void WriteSm1(const fs::path& path) {
  io::PointCloud c;
  c.points = {{1, 0.01f, 1}, {1, 1, 0.0f}, {1, 1, 2.5f},       {1.8f, 1.5f, 1},    {1, 1.5f, 1.2f},
              {-3, 1, 1},    {3, 2, 0.5f}, {0.5f, 0.5f, 0.5f}, {3.95f, 2.9f, 2.4f}};
  const std::size_t n = c.points.size();
  for (std::size_t i = 0; i < n; ++i)
    c.colors.push_back(
        {static_cast<std::uint8_t>(10 * i), 200, static_cast<std::uint8_t>(255 - i)});
  c.fields = {
      {"scalar_intensity", io::PlyType::kFloat32, {0.5, 1, 0, 0.25, 0.5, 0.5, 0.5, 0.5, 0.5}},
      {"scalar_label", io::PlyType::kUInt8, {1, 1, 1, 1, 1, 2, 3, 0, 1}},
      {"scalar_scan", io::PlyType::kUInt16, {0, 0, 1, 1, 1, 0, 1, 0, 1}}};
  io::WritePly(path.string(), c);
}

// rooms/R1/ with every file the exports read; returns the run folder.
std::string MakeRun(const std::string& name, bool with_sm1 = true) {
  const fs::path dir = fs::path(testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "rooms" / "R1");
  const fs::path r = dir / "rooms" / "R1";
  WriteText(r / "sm3.json", modelling::Sm3Json(Room()));
  WriteText(r / "sm4.json", modelling::Sm4Json(Openings()));
  WriteText(r / "sm5.json", kSm5);
  WriteText(r / "scans.json",
            R"({"scans": [{"index": 0, "sim_time": 3.0}, {"index": 1, "sim_time": 36.5}]})");
  WriteText(r / "run.json", R"({"format": "mopad-room-run", "version": 1, "scene": "s",
    "room": "R1", "X_WM": [[1,0,0,3.15],[0,1,0,5.25],[0,0,1,0],[0,0,0,1]], "files": {}})");
  if (with_sm1) WriteSm1(r / "sm1.ply");
  return dir.string();
}

int CountEntities(const std::string& ifc, const std::string& entity) {
  int n = 0;
  for (std::size_t at = ifc.find("=" + entity + "("); at != std::string::npos;
       at = ifc.find("=" + entity + "(", at + 1))
    ++n;
  return n;
}

TEST(ExportsIfc, TinyRoomHasTheSpatialTreeOneProductPerElementAndResolvedReferences) {
  const std::string dir = MakeRun("exp_ifc");
  const ExportResult r = WriteExports(dir, {ExportKind::kIfc});
  const std::string ifc = ReadBytes(dir + "/export/model.ifc");
  ASSERT_FALSE(ifc.empty());
  EXPECT_NE(ifc.find("FILE_SCHEMA(('IFC4'));"), std::string::npos);
  const std::map<std::string, int> expected = {{"IFCPROJECT", 1},
                                               {"IFCSITE", 1},
                                               {"IFCBUILDING", 1},
                                               {"IFCBUILDINGSTOREY", 1},
                                               {"IFCSPACE", 1},
                                               {"IFCWALL", 4},
                                               {"IFCSLAB", 1},
                                               {"IFCCOVERING", 1},
                                               {"IFCCOLUMN", 1},
                                               {"IFCOPENINGELEMENT", 2},
                                               {"IFCDOOR", 1},
                                               {"IFCWINDOW", 1},
                                               {"IFCRELVOIDSELEMENT", 2},
                                               {"IFCRELFILLSELEMENT", 2},
                                               {"IFCOUTLET", 1},
                                               {"IFCSENSOR", 1},
                                               {"IFCBUILDINGELEMENTPROXY", 1}};
  for (const auto& [entity, n] : expected) EXPECT_EQ(CountEntities(ifc, entity), n) << entity;
  // Every product has a body: one IfcProductDefinitionShape each for the space, 4 walls, slab,
  // covering, column, 2 voids, door, window and 3 components.
  EXPECT_EQ(CountEntities(ifc, "IFCPRODUCTDEFINITIONSHAPE"), 15);
  EXPECT_NE(ifc.find(".CEILING."), std::string::npos);
  EXPECT_NE(ifc.find("'exit_sign'"), std::string::npos);  // the proxy's ObjectType
  EXPECT_NE(ifc.find("IFCPLANEANGLEMEASURE(0.6544984694978736)"), std::string::npos);  // 37.5 deg
  // Every #reference names a defined instance; GlobalIds are 22 characters and unique.
  std::set<int> defined;
  const std::regex def(R"(^#(\d+)=)", std::regex::multiline);
  for (auto it = std::sregex_iterator(ifc.begin(), ifc.end(), def); it != std::sregex_iterator();
       ++it)
    defined.insert(std::stoi((*it)[1]));
  const std::regex ref(R"([,(]#(\d+))");
  int refs = 0;
  for (auto it = std::sregex_iterator(ifc.begin(), ifc.end(), ref); it != std::sregex_iterator();
       ++it, ++refs)
    EXPECT_TRUE(defined.count(std::stoi((*it)[1]))) << (*it)[0];
  EXPECT_GT(refs, 100);
  std::set<std::string> ids;
  const std::regex gid(R"(=IFC[A-Z]+\('([0-9A-Za-z_$]{22})',)");
  int rooted = 0;
  for (auto it = std::sregex_iterator(ifc.begin(), ifc.end(), gid); it != std::sregex_iterator();
       ++it, ++rooted)
    EXPECT_TRUE(ids.insert((*it)[1]).second) << "duplicate GlobalId " << (*it)[1];
  EXPECT_GT(rooted, 40);
  EXPECT_NE(r.summary.find("4 walls"), std::string::npos) << r.summary;
}

TEST(ExportsIfc, SameRunGivesTheSameBytesInAnyFolder) {
  const std::string a = MakeRun("exp_same_a"), b = MakeRun("exp_same_b");
  WriteAllExports(a);
  WriteAllExports(b);
  for (const char* f : {"model.ifc", "model.glb", "sm1.las", "export.json"}) {
    const std::string fa = ReadBytes(a + "/export/" + f);
    EXPECT_FALSE(fa.empty()) << f;
    EXPECT_EQ(fa, ReadBytes(b + "/export/" + f)) << f;
  }
  // A changed model changes the GlobalIds (they hash the run's content).
  std::string sm4 = ReadBytes(b + "/rooms/R1/sm4.json");
  sm4.replace(sm4.find("0.9"), 3, "0.7");
  WriteText(fs::path(b) / "rooms/R1/sm4.json", sm4);
  WriteExports(b, {ExportKind::kIfc});
  const std::string ia = ReadBytes(a + "/export/model.ifc");
  const std::string ib = ReadBytes(b + "/export/model.ifc");
  EXPECT_NE(ia.substr(ia.find("IFCPROJECT("), 40), ib.substr(ib.find("IFCPROJECT("), 40));
}

Json GlbJson(const std::string& path) {
  const std::string b = ReadBytes(path);
  std::uint32_t len = 0;
  std::memcpy(&len, b.data() + 12, 4);
  return Json::parse(b.substr(20, len));
}

TEST(ExportsGltf, OneNodePerElementWithItsSemanticsInExtras) {
  const std::string dir = MakeRun("exp_glb");
  WriteExports(dir, {ExportKind::kGltf});
  const Json j = GlbJson(dir + "/export/model.glb");
  // 4 walls, floor, ceiling, 1 column, door, window, 3 components under the Z-up root.
  ASSERT_EQ(j["nodes"].size(), 13u);
  EXPECT_EQ(j["nodes"][0]["rotation"], Json::array({-0.7071068, 0.0, 0.0, 0.7071068}));
  std::map<std::string, Json> by_id;
  for (std::size_t k = 1; k < j["nodes"].size(); ++k)
    by_id[j["nodes"][k]["name"].get<std::string>()] = j["nodes"][k]["extras"]["mopad"];
  EXPECT_EQ(by_id.at("R1/column_1")["ifc_class"], "IfcColumn");
  EXPECT_EQ(by_id.at("R1/opening_1")["class"], "door");
  EXPECT_EQ(by_id.at("R1/opening_1")["host"], "R1/wall_1");
  EXPECT_EQ(by_id.at("R1/opening_1")["properties"]["state"], "semi_open");
  EXPECT_EQ(by_id.at("R1/component_1")["ifc_class"], "IfcOutlet");
  EXPECT_EQ(by_id.at("R1/component_1")["properties"]["alpha"], 0.91);
  EXPECT_EQ(by_id.at("R1/component_3")["ifc_class"], "IfcBuildingElementProxy");
  EXPECT_EQ(by_id.at("R1/wall_2")["room"], "R1");
  std::set<std::string> materials;
  for (const auto& m : j["materials"]) materials.insert(m["name"]);
  EXPECT_EQ(materials,
            (std::set<std::string>{"wall", "floor", "ceiling", "column", "door", "window",
                                   "exit_sign", "smoke_detector", "socket_x2"}));
}

template <class T>
T Get(const std::string& b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

TEST(ExportsLas, CodesTimesSourcesAndColoursComeFromSm1AndScans) {
  const std::string dir = MakeRun("exp_las");
  WriteExports(dir, {ExportKind::kLas});
  const std::string b = ReadBytes(dir + "/export/sm1.las");
  ASSERT_EQ(b.size(), 375u + 9 * 36u);
  EXPECT_EQ(Get<std::uint64_t>(b, 247), 9u);
  // wall, floor, ceiling, column, inlier without patch, outlier, clutter, unlabelled, and an
  // inlier in a corner (5 cm from wall_2, 10 cm from wall_3 and the ceiling): the nearest wins.
  const int codes[9] = {68, 69, 70, 71, 67, 65, 66, 64, 68};
  const double times[9] = {3, 3, 36.5, 36.5, 36.5, 3, 36.5, 3, 36.5};
  for (int i = 0; i < 9; ++i) {
    const std::size_t at = 375 + 36 * i;
    EXPECT_EQ(static_cast<int>(static_cast<std::uint8_t>(b[at + 16])), codes[i]) << i;
    EXPECT_EQ(Get<double>(b, at + 22), times[i]) << i;
    EXPECT_EQ(Get<std::uint16_t>(b, at + 20), i == 2 || i == 3 || i == 4 || i == 6 || i == 8) << i;
    EXPECT_EQ(Get<std::uint16_t>(b, at + 30), 257 * 10 * i) << i;  // 8-bit x 257
    EXPECT_EQ(Get<std::uint16_t>(b, at + 32), 257 * 200) << i;
  }
  EXPECT_EQ(Get<std::uint16_t>(b, 375 + 36 + 12), 65535);  // intensity 1
  // The map frame of the first room is the export frame: x of point 0 is 1 m, not 4.15.
  const double x0 = Get<std::int32_t>(b, 375) * Get<double>(b, 131) + Get<double>(b, 155);
  EXPECT_NEAR(x0, 1.0, 1e-4);
}

TEST(ExportsErrors, BadFoldersAndFilesAreOneLineInputErrors) {
  EXPECT_THROW(WriteAllExports("/nonexistent/run"), InputError);
  const fs::path empty = fs::path(testing::TempDir()) / "exp_empty";
  fs::create_directories(empty);
  EXPECT_THROW(WriteAllExports(empty.string()), InputError);
  const std::string dir = MakeRun("exp_bad", /*with_sm1=*/false);
  EXPECT_THROW(WriteExports(dir, {ExportKind::kLas}), InputError);  // LAS needs an sm1.ply
  const ExportResult all = WriteAllExports(dir);  // `all` leaves LAS out and says so
  EXPECT_NE(all.summary.find("sm1.las: not written"), std::string::npos);
  std::string sm5 = kSm5;
  sm5.replace(sm5.find("\"alpha\": 0.75"), 13, "\"alpha\": \"x\"");
  WriteText(fs::path(dir) / "rooms/R1/sm5.json", sm5);
  try {
    WriteAllExports(dir);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("components[1].alpha: wrong type"), std::string::npos)
        << e.what();
  }
}

TEST(ExportsFrames, ASecondRoomWithItsOwnMapIsPlacedByTheRunPoses) {
  const std::string dir = MakeRun("exp_two_rooms", /*with_sm1=*/false);
  const fs::path r2 = fs::path(dir) / "rooms" / "R2";
  fs::create_directories(r2);
  modelling::StructuralModel room2 = Room();
  room2.room = "R2";
  WriteText(r2 / "sm3.json", modelling::Sm3Json(room2));
  // R2's map sits 10 m further along x in the world than R1's.
  WriteText(r2 / "run.json", R"({"format": "mopad-room-run", "version": 1, "scene": "s",
    "room": "R2", "X_WM": [[1,0,0,13.15],[0,1,0,5.25],[0,0,1,0],[0,0,0,1]], "files": {}})");
  const RunFolder run = ReadRunFolder(dir);
  ASSERT_EQ(run.rooms.size(), 2u);
  EXPECT_TRUE(run.placed_by_run_json);
  const BuildingModel m = BuildBuildingModel(run);
  ASSERT_EQ(m.spaces.size(), 2u);
  double x_min = 1e9;
  for (const auto& p : m.spaces[1].footprint) x_min = std::min(x_min, p.x());
  EXPECT_NEAR(x_min, 10.0, 1e-9);  // R2's floor starts at x = 0 in its own map
  EXPECT_NE(m.frame_note.find("run.json X_WM"), std::string::npos) << m.frame_note;
}

TEST(ExportsFrames, AFloorModelReplacesTheRoomsElementsButNotTheirSpaces) {
  const std::string dir = MakeRun("exp_floor", /*with_sm1=*/false);
  fs::create_directories(fs::path(dir) / "floor");
  modelling::StructuralModel floor = Room();
  floor.room = "floor";
  floor.patches.resize(3);  // wall_1..wall_3 only
  WriteText(fs::path(dir) / "floor" / "sm3.json", modelling::Sm3Json(floor));
  WriteExports(dir, {ExportKind::kIfc});
  const std::string ifc = ReadBytes(dir + "/export/model.ifc");
  EXPECT_EQ(CountEntities(ifc, "IFCWALL"), 3);
  EXPECT_EQ(CountEntities(ifc, "IFCDOOR"), 0);    // no floor/sm4.json
  EXPECT_EQ(CountEntities(ifc, "IFCSPACE"), 1);   // from rooms/R1
  EXPECT_EQ(CountEntities(ifc, "IFCOUTLET"), 1);  // components stay with the rooms
  EXPECT_NE(ifc.find("'floor/wall_1'"), std::string::npos);
}

TEST(ExportsIfc, AWallSeenFromBothRoomsTakesItsMeasuredThicknessAboutItsAxisPlane) {
  const std::string dir = MakeRun("exp_floor_thickness", /*with_sm1=*/false);
  fs::create_directories(fs::path(dir) / "floor");
  modelling::StructuralModel floor = Room();
  floor.room = "floor";
  floor.patches.resize(3);
  nlohmann::json j = nlohmann::json::parse(modelling::Sm3Json(floor));
  j["patches"][0]["thickness_m"] = 0.24;     // wall_1: two faces, 0.24 m apart
  j["patches"][1]["thickness_m"] = nullptr;  // wall_2: one face
  WriteText(fs::path(dir) / "floor" / "sm3.json", j.dump());
  WriteExports(dir, {ExportKind::kIfc});
  const std::string ifc = ReadBytes(dir + "/export/model.ifc");
  const auto solids_of_depth = [&](const std::string& depth) {
    int n = 0;
    std::istringstream lines(ifc);
    for (std::string line; std::getline(lines, line);)
      if (line.find("IFCEXTRUDEDAREASOLID(") != std::string::npos &&
          line.find("," + depth + ");") != std::string::npos)
        ++n;
    return n;
  };
  EXPECT_EQ(solids_of_depth("0.24"), 1);  // wall_1
  EXPECT_EQ(solids_of_depth("0.1"), 2);   // wall_2, wall_3: the assumed thickness
  // wall_1 lies on y = 0, its normal +y: its body starts 0.12 m on the +y side of the axis
  // plane (at its first vertex, (4, 0, 0)) and is extruded 0.24 m toward -y.
  ASSERT_EQ(floor.patches[0].plane.n, Vec3(0, 1, 0));
  EXPECT_NE(ifc.find("IFCCARTESIANPOINT((4.,0.12,0.));"), std::string::npos);
}

// Runs `node tools/validators/<script> FILE MODULES`; nullopt when node or `package` is absent.
std::optional<std::string> Node(const std::string& script, const std::string& file,
                                const std::string& package, int* status) {
  const char* modules = std::getenv("NODE_PATH");
  if (!modules || std::system("node --version >/dev/null 2>&1") != 0 ||
      !fs::exists(fs::path(modules) / package / "package.json"))
    return std::nullopt;
  const std::string cmd = "node " + std::string(MOPAD_SOURCE_DIR) + "/tools/validators/" + script +
                          " " + file + " " + modules + " 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return std::nullopt;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), p)) out += buf.data();
  *status = pclose(p);
  return out;
}

TEST(ExportsOracles, WebIfcOpensTheIfcCountsEqualTheModelAndEveryElementHasAMesh) {
  const std::string dir = MakeRun("exp_oracle_ifc");
  WriteExports(dir, {ExportKind::kIfc});
  int status = 0;
  const auto out = Node("check_ifc.js", dir + "/export/model.ifc", "web-ifc", &status);
  if (!out) GTEST_SKIP() << "node or npm web-ifc absent (scripts/install-deps.sh --test)";
  ASSERT_EQ(status, 0) << *out;
  const Json j = Json::parse(*out);
  EXPECT_EQ(j["schema"], "IFC4");
  EXPECT_EQ(j["errors"], 0) << *out;
  const std::map<std::string, int> expected = {{"IFCSPACE", 1},
                                               {"IFCWALL", 4},
                                               {"IFCSLAB", 1},
                                               {"IFCCOVERING", 1},
                                               {"IFCCOLUMN", 1},
                                               {"IFCOPENINGELEMENT", 2},
                                               {"IFCDOOR", 1},
                                               {"IFCWINDOW", 1},
                                               {"IFCOUTLET", 1},
                                               {"IFCSENSOR", 1},
                                               {"IFCBUILDINGELEMENTPROXY", 1}};
  for (const auto& [entity, n] : expected) {
    EXPECT_EQ(j["counts"][entity], n) << entity << " " << *out;
    if (entity != "IFCOPENINGELEMENT" && entity != "IFCSPACE") {  // voids cut, spaces not drawn
      EXPECT_EQ(j["meshed"].value(entity, 0), n) << entity << " has no mesh: " << *out;
    }
  }
}

TEST(ExportsOracles, CopcReadsTheLasWithTheCloudsCountsBoundsClassesAndColours) {
  const std::string dir = MakeRun("exp_oracle_las");
  WriteExports(dir, {ExportKind::kLas});
  int status = 0;
  const auto out = Node("check_las.js", dir + "/export/sm1.las", "copc", &status);
  if (!out) GTEST_SKIP() << "node or npm copc absent (scripts/install-deps.sh --test)";
  ASSERT_EQ(status, 0) << *out;
  const Json j = Json::parse(*out);
  EXPECT_EQ(j["version"], "1.4");
  EXPECT_EQ(j["format"], 7);
  EXPECT_EQ(j["points"], 9);
  const io::PointCloud ply = io::ReadPly(dir + "/rooms/R1/sm1.ply");
  for (int a = 0; a < 3; ++a) {
    float lo = 1e9f, hi = -1e9f;
    for (const auto& p : ply.points) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
    EXPECT_NEAR(j["min"][a].get<double>(), lo, 1e-4) << a;
    EXPECT_NEAR(j["max"][a].get<double>(), hi, 1e-4) << a;
    EXPECT_NEAR(j["header_min"][a].get<double>(), lo, 1e-4) << a;
  }
  double red = 0;
  for (const auto& c : ply.colors) red += 257.0 * c[0];
  EXPECT_EQ(j["rgb_sum"][0].get<double>(), red);
  EXPECT_EQ(j["classification"]["68"], 2);
  EXPECT_EQ(j["classification"]["65"], 1);
}

TEST(ExportsOracles, KhronosValidatorFindsNoErrorInTheSemanticGlb) {
  const std::string dir = MakeRun("exp_oracle_glb");
  WriteExports(dir, {ExportKind::kGltf});
  int status = 0;
  const auto out = Node("validate_gltf.js", dir + "/export/model.glb", "gltf-validator", &status);
  if (!out) GTEST_SKIP() << "node or npm gltf-validator absent (scripts/install-deps.sh --test)";
  EXPECT_EQ(status, 0) << *out;
  EXPECT_NE(out->find("errors=0 "), std::string::npos) << *out;
}

TEST(ExportParams, EveryFieldIsInTheFieldList) {
  for (const auto& m : FieldsMissingFromVisit(ExportParams{}, "export.")) ADD_FAILURE() << m;
}

}  // namespace
}  // namespace mopad::exports
