// Truth models (evaluation/truth_models.h), model file readers (evaluation/model_files.h) and,
// with MOPAD_EVAL_CLI, the `mopad eval` command end to end.
#include "evaluation/truth_models.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/error.h"
#include "common/polygon.h"
#include "evaluation/metrics_isprs.h"
#include "evaluation/metrics_patches.h"
#include "evaluation/metrics_voxels.h"
#include "evaluation/model_files.h"
#include "scenes/as_built.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "tests/input_error_of.h"
#include "tests/sim/test_scenes.h"

namespace mopad::evaluation {
namespace {

namespace fs = std::filesystem;
using sim::testing::AddQuad;
using V3f = Eigen::Vector3f;

fs::path TempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("mopad_truth_models_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void WriteText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Every voxel of an nx x ny x nz grid, in (k, j, i) order.
std::vector<std::array<int, 3>> AllVoxels(int nx, int ny, int nz) {
  std::vector<std::array<int, 3>> v;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) v.push_back({i, j, k});
  return v;
}

#ifndef MOPAD_BINARY  // the library tests (the CLI binary runs EvalCli only)
Vec3 Centroid(const std::vector<Vec3>& poly) {
  Vec3 c = Vec3::Zero();
  for (const auto& v : poly) c += v;
  return c / static_cast<double>(poly.size());
}

// ---- Truth patches of a generated room ----

TEST(TruthModels, PatchesOfOneRoomMatchTheRoom) {
  const auto g = scenes::Generate(scenes::LoadSceneSpec(MOPAD_SOURCE_DIR "/scenes/one_room.yaml"));
  const scenes::Room& room = *g.truth.FindRoom("R1");
  const double H = room.ceiling_z - room.floor_z;
  EXPECT_NEAR(H, 2.7, 1e-9);
  const auto patches = TruthPatches(g.truth, "R1");
  int walls = 0, floors = 0, ceilings = 0;
  double wall_area = 0.0;
  const Vec3 centre(3.0, 2.0, room.floor_z + H / 2);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Patch& p = patches[i];
    EXPECT_NO_THROW(ValidatePatch(p, {}, p.id)) << p.id;  // planar, CCW seen from the normal
    EXPECT_GT(p.normal.normalized().dot(centre - Centroid(p.polygon)), 0.0)
        << p.id << " normal not into the room";
    if (p.cls == SurfaceClass::kWall) ++walls, wall_area += PolygonArea3d(p.polygon);
    if (p.cls == SurfaceClass::kFloor) {
      ++floors;
      EXPECT_NEAR(PolygonArea3d(p.polygon), 24.0, 1e-6);
      EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
    }
    if (p.cls == SurfaceClass::kCeiling) {
      ++ceilings;
      EXPECT_NEAR(PolygonArea3d(p.polygon), 24.0, 1e-6);
      EXPECT_NEAR(p.normal.z(), -1.0, 1e-12);
      EXPECT_NEAR(p.polygon[0].z(), room.ceiling_z, 1e-9);
    }
  }
  EXPECT_EQ(walls, 4);
  EXPECT_EQ(floors, 1);
  EXPECT_EQ(ceilings, 1);
  EXPECT_NEAR(wall_area, 2 * (6.0 + 4.0) * 2.7, 1e-6);  // whole walls: openings are not cut
  // The truth against itself: every patch a TP with zero error, ISPRS complete and correct.
  const PatchEvaluation e = EvaluatePatches(patches, patches);
  EXPECT_EQ(e.detection[0].tp, 4);
  EXPECT_EQ(e.unmatched_model.size() + e.unmatched_truth.size(), 0u);
  EXPECT_NEAR(e.d_v.max + e.d_h.max + e.phi_deg.max, 0.0, 1e-9);
  // Door D1 and window W1 give one opening patch each, on their wall's plane.
  const auto openings = TruthOpeningPatches(g.truth, "R1");
  ASSERT_EQ(openings.size(), 2u);
  for (const auto& o : openings) EXPECT_NO_THROW(ValidatePatch(o, {}, o.id));
  const auto rooms = TruthFloorplan(g.truth);
  ASSERT_EQ(rooms.size(), 1u);
  EXPECT_NEAR(std::abs(SignedArea(rooms[0].polygon)), 24.0, 1e-9);
  EXPECT_THROW(TruthPatches(g.truth, "R9"), InputError);
}

// ---- Open-plan rooms: spaces joined by open passages are scored as one room ----

scenes::StructuralElement TestWall(const std::string& id, const std::string& room, Vec3 origin,
                                   Vec3 u, double length, double height) {
  scenes::StructuralElement w;
  w.id = id;
  w.element_class = scenes::ElementClass::kWall;
  w.rooms = {room};
  w.origin = origin;
  w.u_axis = u;
  w.length = length;
  w.height = height;
  w.normal = Vec3::UnitZ().cross(u);  // left of u: into a CCW room
  w.polygons = {{origin, origin + length * u, origin + length * u + height * Vec3::UnitZ(),
                 origin + height * Vec3::UnitZ()}};
  return w;
}

// Two spaces A = [0,4]x[0,3] and B = [4,10]x[0,3] with no wall between them (a BIM model's
// hall and living area), and C = [0,10]x[3,6] behind a door from A.
scenes::GroundTruth OpenPlanTruth3() {
  scenes::GroundTruth t;
  t.format_version = scenes::kTruthFormatVersionPassages;
  auto room = [](const std::string& id, std::vector<Vec2> poly) {
    scenes::Room r;
    r.id = id;
    r.polygon = std::move(poly);
    r.ceiling_z = 2.5;
    return r;
  };
  t.rooms = {room("A", {{0, 0}, {4, 0}, {4, 3}, {0, 3}}),
             room("B", {{4, 0}, {10, 0}, {10, 3}, {4, 3}}),
             room("C", {{0, 3}, {10, 3}, {10, 6}, {0, 6}})};
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY();
  t.elements = {TestWall("wall_A_s", "A", {0, 0, 0}, x, 4, 2.5),
                TestWall("wall_B_s", "B", {4, 0, 0}, x, 6, 2.5),
                TestWall("wall_B_e", "B", {10, 0, 0}, y, 3, 2.5),
                TestWall("wall_B_n", "B", {10, 3, 0}, -x, 6, 2.5),
                TestWall("wall_A_n", "A", {4, 3, 0}, -x, 4, 2.5),
                TestWall("wall_A_w", "A", {0, 3, 0}, -y, 3, 2.5),
                TestWall("wall_C_s", "C", {0, 3, 0}, x, 10, 2.5)};
  for (const std::string r : {"A", "B", "C"})
    for (const auto cls : {scenes::ElementClass::kFloor, scenes::ElementClass::kCeiling}) {
      scenes::StructuralElement e;
      e.id = std::string(cls == scenes::ElementClass::kFloor ? "floor_" : "ceiling_") + r;
      e.element_class = cls;
      e.rooms = {r};
      t.elements.push_back(e);  // no polygon: the room's plan
    }
  scenes::Opening w;
  w.id = "W1";
  w.type = scenes::OpeningType::kWindow;
  w.host_walls = {"wall_B_s"};
  w.rooms = {"B"};
  w.u0 = 1, w.u1 = 2, w.v0 = 1, w.v1 = 2;
  w.corners = {{5, 0, 1}, {6, 0, 1}, {6, 0, 2}, {5, 0, 2}};
  t.openings.push_back(w);
  scenes::ServiceComponent c;
  c.id = "S1";
  c.bsc_class = "socket_x1";
  c.host = "wall_B_s";
  c.room = "B";
  c.centre = {8, 0, 0.3};
  c.normal = y;
  t.service_components.push_back(c);
  t.connections = {{"", "A", "B"}, {"D1", "A", "C"}};
  return t;
}

TEST(OpenPlanTruth, SpacesJoinedByAnOpenPassageAreOneRoomWithWholeWalls) {
  const OpenPlanTruth op = MergeOpenPlanRooms(OpenPlanTruth3());
  EXPECT_TRUE(op.notes.empty());
  EXPECT_EQ(op.room_of.at("A"), "A");
  EXPECT_EQ(op.room_of.at("B"), "A");
  EXPECT_EQ(op.room_of.at("C"), "C");
  ASSERT_EQ(op.members.count("A"), 1u);
  EXPECT_EQ(op.members.at("A"), (std::vector<std::string>{"A", "B"}));
  ASSERT_EQ(op.truth.rooms.size(), 2u);
  const scenes::Room& a = *op.truth.FindRoom("A");
  EXPECT_EQ(a.polygon.size(), 4u);
  EXPECT_NEAR(SignedArea(a.polygon), 30.0, 1e-9);
  EXPECT_EQ(op.truth.FindRoom("B"), nullptr);
  // The south and north walls run on across the boundary without a wall: one face each.
  const auto patches = TruthPatches(op.truth, "A");
  int walls = 0, floors = 0, ceilings = 0;
  for (const auto& p : patches) {
    EXPECT_NO_THROW(ValidatePatch(p, {}, p.id)) << p.id;
    if (p.cls == SurfaceClass::kWall) ++walls;
    if (p.cls == SurfaceClass::kFloor || p.cls == SurfaceClass::kCeiling) {
      (p.cls == SurfaceClass::kFloor ? floors : ceilings) += 1;
      EXPECT_NEAR(PolygonArea3d(p.polygon), 30.0, 1e-9) << p.id;
    }
  }
  EXPECT_EQ(walls, 4);
  EXPECT_EQ(floors, 1);
  EXPECT_EQ(ceilings, 1);
  const scenes::StructuralElement* south = op.truth.FindElement("wall_A_s");
  ASSERT_NE(south, nullptr);
  EXPECT_NEAR(south->length, 10.0, 1e-12);
  EXPECT_EQ(op.truth.FindElement("wall_B_s"), nullptr);
  const scenes::StructuralElement* north = op.truth.FindElement("wall_B_n");
  ASSERT_NE(north, nullptr);
  EXPECT_NEAR(north->length, 10.0, 1e-12);
  // The window and the socket move onto the joined wall, the window's u along it.
  const scenes::Opening& w = op.truth.openings[0];
  EXPECT_EQ(w.host_walls, (std::vector<std::string>{"wall_A_s"}));
  EXPECT_NEAR(w.u0, 5.0, 1e-12);
  EXPECT_NEAR(w.u1, 6.0, 1e-12);
  EXPECT_EQ(w.rooms, (std::vector<std::string>{"A"}));
  ASSERT_EQ(TruthOpeningPatches(op.truth, "A").size(), 1u);
  EXPECT_EQ(op.truth.service_components[0].host, "wall_A_s");
  EXPECT_EQ(op.truth.service_components[0].room, "A");
  // The passage inside the room is gone, the door to C stays.
  ASSERT_EQ(op.truth.connections.size(), 1u);
  EXPECT_EQ(op.truth.connections[0].door, "D1");
  // Room C is untouched.
  EXPECT_EQ(TruthPatches(op.truth, "C").size(), TruthPatches(OpenPlanTruth3(), "C").size());
  // Rooms only: every element keeps its id (the scene's element ids stay valid) and is A's.
  const OpenPlanTruth rooms_only = MergeOpenPlanRooms(OpenPlanTruth3(), /*join_faces=*/false);
  ASSERT_EQ(rooms_only.truth.elements.size(), OpenPlanTruth3().elements.size());
  EXPECT_EQ(rooms_only.truth.FindElement("wall_B_s")->rooms, (std::vector<std::string>{"A"}));
  EXPECT_NEAR(rooms_only.truth.FindElement("wall_B_s")->length, 6.0, 1e-12);
  EXPECT_EQ(rooms_only.truth.openings[0].host_walls, (std::vector<std::string>{"wall_B_s"}));
  EXPECT_NEAR(SignedArea(rooms_only.truth.FindRoom("A")->polygon), 30.0, 1e-9);
}

TEST(OpenPlanTruth, WithoutPassagesTheTruthIsUnchangedAndAnUnmergeableGroupStaysApart) {
  scenes::GroundTruth t = OpenPlanTruth3();
  t.connections = {{"D1", "A", "C"}};
  const OpenPlanTruth same = MergeOpenPlanRooms(t);
  EXPECT_TRUE(same.members.empty());
  EXPECT_EQ(same.truth.rooms.size(), 3u);
  EXPECT_EQ(same.truth.elements.size(), t.elements.size());
  // A "passage" between rooms whose plans only meet at a corner cannot be one outline.
  t = OpenPlanTruth3();
  t.rooms[1].polygon = {{4, 3.5}, {10, 3.5}, {10, 6}, {4, 6}};  // B moved off A (overlaps C)
  t.rooms[2].polygon = {{4, 3}, {8, 3}, {8, 3.2}, {4, 3.2}};
  const OpenPlanTruth apart = MergeOpenPlanRooms(t);
  EXPECT_TRUE(apart.members.empty());
  ASSERT_EQ(apart.notes.size(), 1u);
  EXPECT_NE(apart.notes[0].find("A, B"), std::string::npos) << apart.notes[0];
  EXPECT_EQ(apart.truth.rooms.size(), 3u);
  EXPECT_EQ(apart.room_of.at("B"), "B");
}

// ---- Truth columns of the office: round C1, C2 (16 facets, r 0.2) in R1, square C3 in R4 ----

TEST(TruthModels, ColumnsAreObjectsWithFootprintsFromTheSidecar) {
  const auto g =
      scenes::Generate(scenes::LoadSceneSpec(MOPAD_SOURCE_DIR "/scenes/office_5rooms.yaml"));
  const auto r1 = TruthColumns(g.truth, "R1");
  ASSERT_EQ(r1.size(), 2u);
  EXPECT_EQ(r1[0].id, "C1");
  EXPECT_EQ(r1[1].id, "C2");
  const scenes::Room& room = *g.truth.FindRoom("R1");
  for (const auto& c : r1) {
    EXPECT_EQ(c.faces.size(), 16u);
    EXPECT_EQ(c.footprint.size(), 16u);
    EXPECT_NEAR(c.Area(), 8 * 0.04 * std::sin(kPi / 8), 1e-9);  // 16-gon of vertex radius 0.2
    EXPECT_NEAR(c.z_max - c.z_min, room.ceiling_z - room.floor_z, 1e-9);
    for (const auto& f : c.faces) EXPECT_EQ(f.cls, SurfaceClass::kColumn);
  }
  EXPECT_NEAR((r1[1].Centre() - r1[0].Centre()).norm(), 5.0, 1e-9);  // 5.0 and 10.0 in the spec
  const auto r4 = TruthColumns(g.truth, "R4");
  ASSERT_EQ(r4.size(), 1u);
  EXPECT_EQ(r4[0].faces.size(), 4u);
  EXPECT_NEAR(r4[0].Area(), 0.16, 1e-9);
  EXPECT_TRUE(TruthColumns(g.truth, "R3").empty());
  EXPECT_THROW(TruthColumns(g.truth, "R9"), InputError);
  // The truth against itself: every column a TP with zero errors; only C3's faces are paired.
  const ColumnEvaluation e1 = EvaluateColumns(r1, r1);
  EXPECT_EQ(e1.detection.tp, 2);
  EXPECT_NEAR(e1.centre_error.max + e1.diameter_error.max + e1.height_error.max, 0.0, 1e-12);
  EXPECT_EQ(e1.face_detection.n_truth, 0);
  const ColumnEvaluation e4 = EvaluateColumns(r4, r4);
  EXPECT_EQ(e4.detection.tp, 1);
  EXPECT_EQ(e4.face_detection.tp, 4);
  EXPECT_NEAR(e4.face_accuracy.phi_deg.max, 0.0, 1e-9);
}

// ---- Truth DSM3 of a box room: 4 m x 3 m x 2.5 m, 0.1 m voxels ----

struct BoxRoom {
  scenes::Scene scene;
  scenes::GroundTruth truth;
};

scenes::StructuralElement Wall(const std::string& id, Vec3 origin, Vec3 u, double length,
                               Vec3 normal) {
  scenes::StructuralElement e;
  e.id = id;
  e.element_class = scenes::ElementClass::kWall;
  e.rooms = {"R1"};
  e.origin = origin;
  e.u_axis = u;
  e.length = length;
  e.height = 2.5;
  e.normal = normal;
  e.polygons = {{origin, origin + length * u, origin + length * u + Vec3(0, 0, 2.5),
                 origin + Vec3(0, 0, 2.5)}};
  return e;
}

// A window W1 (x in [1, 2], z in [1, 2]) in the north wall (y = 3); optionally a cabinet
// x [2.55, 3.15] x y [0.55, 0.95] x z [0, 0.95].
BoxRoom MakeBoxRoom(bool cabinet) {
  BoxRoom b;
  sim::testing::AddRoomBox(b.scene, V3f(0, 0, 0), V3f(4, 3, 2.5));
  if (cabinet) {
    const float x0 = 2.55f, x1 = 3.15f, y0 = 0.55f, y1 = 0.95f, z0 = 0.0f, z1 = 0.95f;
    using scenes::ElementClass;
    const auto F = ElementClass::kFurniture;
    AddQuad(b.scene, V3f(x0, y0, z1), V3f(x1, y0, z1), V3f(x1, y1, z1), V3f(x0, y1, z1), F,
            "cabinet_R1_1");
    AddQuad(b.scene, V3f(x0, y0, z0), V3f(x0, y1, z0), V3f(x1, y1, z0), V3f(x1, y0, z0), F,
            "cabinet_R1_1");
    AddQuad(b.scene, V3f(x0, y0, z0), V3f(x1, y0, z0), V3f(x1, y0, z1), V3f(x0, y0, z1), F,
            "cabinet_R1_1");
    AddQuad(b.scene, V3f(x1, y1, z0), V3f(x0, y1, z0), V3f(x0, y1, z1), V3f(x1, y1, z1), F,
            "cabinet_R1_1");
    AddQuad(b.scene, V3f(x0, y1, z0), V3f(x0, y0, z0), V3f(x0, y0, z1), V3f(x0, y1, z1), F,
            "cabinet_R1_1");
    AddQuad(b.scene, V3f(x1, y0, z0), V3f(x1, y1, z0), V3f(x1, y1, z1), V3f(x1, y0, z1), F,
            "cabinet_R1_1");
  }
  auto& t = b.truth;
  t.scene_name = "box";
  t.rooms.push_back({"R1", "", {{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0.0, 2.5});
  t.elements.push_back(Wall("wall_s", {0, 0, 0}, Vec3::UnitX(), 4.0, Vec3::UnitY()));
  t.elements.push_back(Wall("wall_e", {4, 0, 0}, Vec3::UnitY(), 3.0, -Vec3::UnitX()));
  t.elements.push_back(Wall("wall_n", {4, 3, 0}, -Vec3::UnitX(), 4.0, -Vec3::UnitY()));
  t.elements.push_back(Wall("wall_w", {0, 3, 0}, -Vec3::UnitY(), 3.0, Vec3::UnitX()));
  scenes::StructuralElement floor, ceiling;
  floor.id = "floor";
  floor.element_class = scenes::ElementClass::kFloor;
  floor.rooms = {"R1"};
  floor.polygons = {{{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}};
  ceiling = floor;
  ceiling.id = "ceiling";
  ceiling.element_class = scenes::ElementClass::kCeiling;
  ceiling.normal = -Vec3::UnitZ();
  ceiling.polygons = {{{0, 0, 2.5}, {0, 3, 2.5}, {4, 3, 2.5}, {4, 0, 2.5}}};
  t.elements.push_back(floor);
  t.elements.push_back(ceiling);
  scenes::Opening w;
  w.id = "W1";
  w.type = scenes::OpeningType::kWindow;
  w.host_walls = {"wall_n"};
  w.rooms = {"R1"};
  w.u0 = 2.0, w.u1 = 3.0, w.v0 = 1.0, w.v1 = 2.0;  // wall_n runs from x = 4 towards -x
  w.corners = {{2, 3, 1}, {1, 3, 1}, {1, 3, 2}, {2, 3, 2}};
  t.openings.push_back(w);
  return b;
}

TruthDsm3Params WideOpenScanner() {
  TruthDsm3Params p;
  p.elevation_min_deg = -90.0;
  p.elevation_max_deg = 90.0;
  p.range_min = 0.0;
  return p;
}

// Hand-computed: the shell of the 40 x 30 x 25 grid is 40*30*25 - 38*28*23 = 5528 voxels; the
// window covers 10 x 10 of them (x 1..2, z 1..2 at 0.1 m); the interior 38*28*23 = 24472 voxels
// are all seen from the centre of an empty room.
constexpr int kShell = 40 * 30 * 25 - 38 * 28 * 23;
constexpr int kInterior = 38 * 28 * 23;

// The box room's grid: 0.1 m voxels over its 4 x 3 x 2.5 m.
VoxelGrid BoxRoomGrid() {
  VoxelGrid grid;
  grid.voxel_size = 0.1;
  grid.dims = {40, 30, 25};
  return grid;
}

TEST(TruthDsm3, EmptyBoxRoomWithWindowFromOneScanner) {
  BoxRoom b = MakeBoxRoom(false);
  const sim::EmbreeWorld world(b.scene, nullptr);
  const VoxelGrid grid = BoxRoomGrid();
  const auto voxels = AllVoxels(40, 30, 25);
  const auto labels = TruthDsm3(world, b.truth, "R1", grid, voxels, Pose3::Identity(),
                                {Vec3(2.0, 1.5, 1.4)}, WideOpenScanner());
  const auto c = CountVoxelLabels(labels);
  EXPECT_EQ(c[int(VoxelLabel::kStructure)], kShell - 100);
  EXPECT_EQ(c[int(VoxelLabel::kOpening)], 100);
  EXPECT_EQ(c[int(VoxelLabel::kOccludedStructure)], 0);
  EXPECT_EQ(c[int(VoxelLabel::kClutter)], 0);
  EXPECT_EQ(c[int(VoxelLabel::kEmpty)], kInterior);
  EXPECT_EQ(c[int(VoxelLabel::kUnseen)], 0);
  // The window voxels are where expected: north wall layer j = 29, i and k in 10..19.
  for (std::size_t n = 0; n < voxels.size(); ++n)
    if (labels[n] == int(VoxelLabel::kOpening)) {
      EXPECT_EQ(voxels[n][1], 29);
      EXPECT_TRUE(voxels[n][0] >= 10 && voxels[n][0] <= 19 && voxels[n][2] >= 10 &&
                  voxels[n][2] <= 19);
    }
  // Without any scanner nothing is seen: all structure is occluded, the rest unseen.
  const auto dark = CountVoxelLabels(
      TruthDsm3(world, b.truth, "R1", grid, voxels, Pose3::Identity(), {}, WideOpenScanner()));
  EXPECT_EQ(dark[int(VoxelLabel::kOccludedStructure)], kShell - 100);
  EXPECT_EQ(dark[int(VoxelLabel::kUnseen)], kInterior);
}

TEST(TruthDsm3, CabinetIsClutterAndHidesTheFloorUnderIt) {
  BoxRoom b = MakeBoxRoom(true);
  const sim::EmbreeWorld world(b.scene, nullptr);
  const VoxelGrid grid = BoxRoomGrid();
  const auto voxels = AllVoxels(40, 30, 25);
  const std::vector<Vec3> scanners = {
      {2.0, 1.5, 1.4}, {0.5, 0.5, 1.4}, {3.5, 0.5, 1.4}, {0.5, 2.5, 1.4}, {3.5, 2.5, 1.4}};
  const auto labels =
      TruthDsm3(world, b.truth, "R1", grid, voxels, Pose3::Identity(), scanners, WideOpenScanner());
  const auto c = CountVoxelLabels(labels);
  // Cabinet voxels: i 25..31, j 5..9, k 0..9 (7 x 5 x 10); its surface touches the shell of that
  // block (350 - 5*3*8 interior = 230) less the floor layer k = 0 (35, structure): 195 clutter.
  EXPECT_EQ(c[int(VoxelLabel::kClutter)], 195);
  // Floor voxels entirely under the cabinet (i 26..30, j 6..8) are seen by no scanner.
  EXPECT_EQ(c[int(VoxelLabel::kOccludedStructure)], 15);
  EXPECT_EQ(c[int(VoxelLabel::kStructure)], kShell - 100 - 15);
  EXPECT_EQ(c[int(VoxelLabel::kOpening)], 100);
  // Inside the cabinet (5 x 3 x 8 voxels) is unseen; shadows behind it may add some.
  EXPECT_GE(c[int(VoxelLabel::kUnseen)], 120);
  EXPECT_EQ(c[int(VoxelLabel::kEmpty)] + c[int(VoxelLabel::kUnseen)], kInterior - 195);
  // Deterministic across thread counts.
  std::vector<std::uint8_t> one;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = TruthDsm3(world, b.truth, "R1", grid, voxels, Pose3::Identity(), scanners,
                    WideOpenScanner());
  }
  EXPECT_EQ(one, labels);
}

TEST(TruthDsm3, MapFrameRotatedAgainstTheWorldGivesTheSameCounts) {
  BoxRoom b = MakeBoxRoom(false);
  const sim::EmbreeWorld world(b.scene, nullptr);
  // Map frame: world = R_z(90 deg) * map + (4, 0, 0); the room is [0,3] x [0,4] in the map.
  Pose3 X_WM = Pose3::Identity();
  X_WM.linear() = Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix();
  X_WM.translation() = Vec3(4, 0, 0);
  VoxelGrid grid;
  grid.voxel_size = 0.1;
  grid.dims = {30, 40, 25};
  const auto labels = TruthDsm3(world, b.truth, "R1", grid, AllVoxels(30, 40, 25), X_WM,
                                {Vec3(2.0, 1.5, 1.4)}, WideOpenScanner());
  const auto c = CountVoxelLabels(labels);
  EXPECT_EQ(c[int(VoxelLabel::kStructure)], kShell - 100);
  EXPECT_EQ(c[int(VoxelLabel::kOpening)], 100);
  EXPECT_EQ(c[int(VoxelLabel::kEmpty)], kInterior);
}

// A full-size room of office_5rooms at 5 cm voxels (~0.5-1 M voxels): sane label counts, and the
// run time shows in the test log (the brief: "a room in seconds").
TEST(TruthDsm3, LargestOfficeRoomAtFiveCentimetres) {
  const auto g =
      scenes::Generate(scenes::LoadSceneSpec(MOPAD_SOURCE_DIR "/scenes/office_5rooms.yaml"));
  const scenes::Room* big = nullptr;
  for (const auto& r : g.truth.rooms)
    if (!big || std::abs(SignedArea(r.polygon)) > std::abs(SignedArea(big->polygon))) big = &r;
  Eigen::AlignedBox2d box;
  for (const auto& q : big->polygon) box.extend(q);
  VoxelGrid grid;
  grid.voxel_size = 0.05;
  grid.origin = Vec3(box.min().x() - 0.1, box.min().y() - 0.1, big->floor_z - 0.1);
  grid.dims = {int(std::ceil((box.sizes().x() + 0.2) / 0.05)),
               int(std::ceil((box.sizes().y() + 0.2) / 0.05)),
               int(std::ceil((big->ceiling_z - big->floor_z + 0.2) / 0.05))};
  const auto voxels = AllVoxels(grid.dims[0], grid.dims[1], grid.dims[2]);
  const Vec2 c = box.center();
  std::vector<Vec3> scanners;
  for (const Vec2& o : {Vec2(0, 0), Vec2(1, 0.5), Vec2(-1, -0.5), Vec2(0.5, -1), Vec2(-0.5, 1)})
    scanners.emplace_back(c.x() + o.x(), c.y() + o.y(), big->floor_z + 1.4);
  const sim::EmbreeWorld world(g.scene, &g.truth);
  const auto labels = TruthDsm3(world, g.truth, big->id, grid, voxels, Pose3::Identity(), scanners);
  const auto n = CountVoxelLabels(labels);
  std::printf(
      "room %s: %zu voxels; opening %ld structure %ld occluded %ld clutter %ld empty %ld unseen "
      "%ld\n",
      big->id.c_str(), voxels.size(), long(n[0]), long(n[1]), long(n[2]), long(n[3]), long(n[4]),
      long(n[5]));
  EXPECT_GT(voxels.size(), 400000u);
  EXPECT_GT(n[int(VoxelLabel::kStructure)], 5 * n[int(VoxelLabel::kOccludedStructure)]);
  EXPECT_GT(n[int(VoxelLabel::kEmpty)], n[int(VoxelLabel::kClutter)]);
  EXPECT_GT(n[int(VoxelLabel::kOpening)], 0);
}

// An attic, as the BIM import writes one (scenes/bim_sloped_ceilings.cpp): a 4 x 3 m room under
// a gable roof, ridge along x at y = 1.5 m, 2.5 m up; knee walls 1 m; the roof planes at 45 deg.
scenes::GroundTruth AtticTruth() {
  scenes::GroundTruth t;
  t.scene_name = "attic";
  t.rooms.push_back({"R1", "", {{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0.0, 2.5});
  auto wall = [&](const std::string& id, Vec3 o, Vec3 u, double length, Vec3 n,
                  std::vector<Vec3> poly) {
    scenes::StructuralElement e = Wall(id, o, u, length, n);
    e.height = 2.5;
    e.polygons = {std::move(poly)};
    t.elements.push_back(e);
  };
  wall("knee_s", {0, 0, 0}, Vec3::UnitX(), 4.0, Vec3::UnitY(),
       {{0, 0, 0}, {0, 0, 1}, {4, 0, 1}, {4, 0, 0}});
  wall("gable_e", {4, 0, 0}, Vec3::UnitY(), 3.0, -Vec3::UnitX(),
       {{4, 0, 0}, {4, 0, 1}, {4, 1.5, 2.5}, {4, 3, 1}, {4, 3, 0}});
  wall("knee_n", {4, 3, 0}, -Vec3::UnitX(), 4.0, -Vec3::UnitY(),
       {{4, 3, 0}, {4, 3, 1}, {0, 3, 1}, {0, 3, 0}});
  wall("gable_w", {0, 3, 0}, -Vec3::UnitY(), 3.0, Vec3::UnitX(),
       {{0, 3, 0}, {0, 3, 1}, {0, 1.5, 2.5}, {0, 0, 1}, {0, 0, 0}});
  for (auto& e : t.elements) e.height = e.id.rfind("gable", 0) == 0 ? 2.5 : 1.0;
  scenes::StructuralElement floor, south, north;
  floor.id = "floor";
  floor.element_class = scenes::ElementClass::kFloor;
  floor.rooms = {"R1"};
  floor.polygons = {{{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}};
  south.id = "ceiling_R1_1";
  south.element_class = scenes::ElementClass::kCeiling;
  south.rooms = {"R1"};
  south.normal = Vec3(0, 1, -1).normalized();
  south.polygons = {{{0, 0, 1}, {0, 1.5, 2.5}, {4, 1.5, 2.5}, {4, 0, 1}}};
  north = south;
  north.id = "ceiling_R1_2";
  north.normal = Vec3(0, -1, -1).normalized();
  north.polygons = {{{0, 1.5, 2.5}, {0, 3, 1}, {4, 3, 1}, {4, 1.5, 2.5}}};
  t.elements.push_back(floor);
  t.elements.push_back(south);
  t.elements.push_back(north);
  return t;
}

TEST(TruthModels, AnAtticsGablesArePentagonsAndItsRoofIsTwoSlopedCeilings) {
  const scenes::GroundTruth t = AtticTruth();
  const std::vector<Patch> patches = TruthPatches(t, "R1");
  ASSERT_EQ(patches.size(), 7u);
  for (const Patch& p : patches) {
    EXPECT_NO_THROW(ValidatePatch(p, {}, p.id)) << p.id;
    const double area = 0.5 * NewellVector(p.polygon).norm();
    if (p.id.rfind("gable", 0) == 0) {
      EXPECT_EQ(p.polygon.size(), 5u) << p.id;
      EXPECT_NEAR(area, 3.0 + 0.5 * 3.0 * 1.5, 1e-9) << p.id;
    } else if (p.id.rfind("knee", 0) == 0) {
      EXPECT_NEAR(area, 4.0, 1e-9) << p.id;
    } else if (p.cls == SurfaceClass::kCeiling) {
      EXPECT_NEAR(area, 4.0 * 1.5 * std::sqrt(2.0), 1e-9) << p.id;
      EXPECT_NEAR(p.normal.z(), -std::sqrt(0.5), 1e-9) << p.id;  // its own, not level
      EXPECT_NEAR(std::abs(p.normal.y()), std::sqrt(0.5), 1e-9) << p.id;
    }
  }
  // Scored against itself: every face found where it is, as it is.
  const PatchEvaluation e = EvaluatePatches(patches, patches);
  EXPECT_EQ(e.detection[int(SurfaceClass::kWall)].tp, 4);
  EXPECT_EQ(e.detection[int(SurfaceClass::kCeiling)].tp, 2);
  EXPECT_NEAR(e.d_v.max, 0.0, 1e-9);
  EXPECT_NEAR(e.d_h.max, 0.0, 1e-9);
  // A flat ceiling at the ridge is no match for either slope (45 deg off).
  std::vector<Patch> flat = patches;
  for (Patch& p : flat)
    if (p.cls == SurfaceClass::kCeiling) {
      p.normal = -Vec3::UnitZ();
      for (Vec3& v : p.polygon) v.z() = 2.5;
      if (NewellVector(p.polygon).dot(p.normal) < 0.0)
        std::reverse(p.polygon.begin(), p.polygon.end());
    }
  EXPECT_EQ(EvaluatePatches(flat, patches).detection[int(SurfaceClass::kCeiling)].tp, 0);
}

TEST(TruthDsm3, NothingOverAnAtticsRoofIsTheRoomsEmptySpace) {
  // The world is the 2.5 m box; the truth puts a roof inside it. Above the roof is not the
  // room's, so nothing there is empty space of the room, however well a scanner sees it.
  BoxRoom b = MakeBoxRoom(false);
  b.truth = AtticTruth();
  const sim::EmbreeWorld world(b.scene, nullptr);
  const VoxelGrid grid = BoxRoomGrid();
  const auto voxels = AllVoxels(40, 30, 25);
  const auto labels = TruthDsm3(world, b.truth, "R1", grid, voxels, Pose3::Identity(),
                                {Vec3(2.0, 1.5, 1.4)}, WideOpenScanner());
  int empty_over = 0, empty_under = 0;
  for (std::size_t n = 0; n < voxels.size(); ++n) {
    if (labels[n] != int(VoxelLabel::kEmpty)) continue;
    const Vec3 c = grid.Centre(voxels[n]);
    const double roof = 2.5 - std::abs(c.y() - 1.5);
    (c.z() > roof ? empty_over : empty_under)++;
  }
  EXPECT_EQ(empty_over, 0);
  EXPECT_GT(empty_under, 38 * 28 * 9);  // at least the interior under the knee walls' 1 m
}

// ---- Readers ----

#endif

const char* kRunJson =
    R"({"format": "mopad-room-run", "version": 1, "scene": "SCENE", "room": "R1", "seed": 3,
  "X_WM": [[1,0,0,0.5],[0,1,0,-0.25],[0,0,1,0],[0,0,0,1]],
  "files": {"sm1": "sm1.ply", "sm2": "sm2.json", "sm3": "sm3.json", "dsm3": "dsm3.ply"}})";

#ifndef MOPAD_BINARY
std::string Replace(std::string s, const std::string& a, const std::string& b) {
  const auto p = s.find(a);
  if (p != std::string::npos) s.replace(p, a.size(), b);
  return s;
}

using test_support::InputErrorOf;

const char* kSm3Json =
    R"({"format": "mopad-sm3", "version": 1, "room": "R1", "floor_z": 0.0, "ceiling_z": 2.5,
  "patches": [
    {"id": "floor_A", "class": "floor", "plane": {"n": [0, 0, 2], "d": 0},
     "polygon": [[0,0,0],[4,0,0],[4,3,0],[0,3,0]], "support": 1000, "rms": 0.002, "fitted": true},
    {"id": "wall_1A", "class": "wall", "plane": {"n": [0, 1, 0], "d": 0},
     "polygon": [[0,0,0],[4,0,0],[4,0,2.5],[0,0,2.5]], "support": 10, "rms": 0.001, "fitted": true}],
  "adjacency": [[0, 1]]})";

TEST(ModelFiles, Sm3IsReadAndMalformedOnesRejected) {
  const fs::path d = TempDir("sm3");
  const std::string p = (d / "sm3.json").string();
  WriteText(p, kSm3Json);
  const Sm3Model m = ReadSm3(p);
  ASSERT_EQ(m.patches.size(), 2u);
  EXPECT_EQ(m.patches[1].patch.id, "wall_1A");
  EXPECT_EQ(m.patches[1].patch.cls, SurfaceClass::kWall);
  EXPECT_NEAR(m.patches[0].patch.normal.z(), 1.0, 1e-12);  // normalised
  EXPECT_EQ(m.patches[0].support, 1000);
  ASSERT_EQ(m.adjacency.size(), 1u);
  EXPECT_NEAR(m.ceiling_z, 2.5, 1e-12);
  WriteText(p, Replace(kSm3Json, R"("n": [0, 1, 0], )", ""));
  std::string e = InputErrorOf([&] { ReadSm3(p); });
  EXPECT_NE(e.find("sm3.json: error: patches[1].plane.n: missing field"), std::string::npos) << e;
  WriteText(p, Replace(kSm3Json, R"("class": "wall")", R"("class": "door")"));
  EXPECT_NE(InputErrorOf([&] { ReadSm3(p); }).find("patches[1].class: unknown class"),
            std::string::npos);
  WriteText(p, Replace(kSm3Json, R"("format": "mopad-sm3")", R"("format": "mopad-sm2")"));
  EXPECT_NE(InputErrorOf([&] { ReadSm3(p); }).find("wrong file format"), std::string::npos);
  WriteText(p, Replace(kSm3Json, "\"support\": 1000", "\"support\": 1e999999"));
  e = InputErrorOf([&] { ReadSm3(p); });  // a number beyond a double: out_of_range 406
  EXPECT_NE(e.find("malformed JSON"), std::string::npos) << e;
  WriteText(p, Replace(kSm3Json, "[[0, 1]]", "[[0, 7]]"));
  EXPECT_NE(InputErrorOf([&] { ReadSm3(p); }).find("adjacency[0]: patch index out of range"),
            std::string::npos);
  WriteText(p, Replace(kSm3Json, "[4,0,2.5],[0,0,2.5]]", "[4,0,2.5]]").substr(0, 10));
  EXPECT_FALSE(InputErrorOf([&] { ReadSm3(p); }).empty());
  fs::remove_all(d);
}

#endif

// Writes dsm3.ply as docs/models.md specifies (file label values 0 unseen .. 5 opening).
void WriteDsm3Ply(const fs::path& path, const VoxelGrid& g,
                  const std::vector<std::array<int, 3>>& ijk,
                  const std::vector<std::uint8_t>& voxel_labels, std::size_t truncate_bytes = 0) {
  static const char* kFileNames[] = {"unseen",  "empty",  "structure", "occluded_structure",
                                     "clutter", "opening"};
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment mopad_dsm3_voxel_size " << g.voxel_size
    << "\ncomment mopad_dsm3_origin " << g.origin.x() << " " << g.origin.y() << " " << g.origin.z()
    << "\ncomment mopad_dsm3_dims " << g.dims[0] << " " << g.dims[1] << " " << g.dims[2] << "\n";
  for (int v = 0; v < 6; ++v) h << "comment mopad_dsm3_label " << v << " " << kFileNames[v] << "\n";
  h << "element vertex " << ijk.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar scalar_label\n"
       "property int scalar_i\nproperty int scalar_j\nproperty int scalar_k\nend_header\n";
  std::string data = h.str();
  for (std::size_t n = 0; n < ijk.size(); ++n) {
    const Vec3 c = g.Centre(ijk[n]);
    const float xyz[3] = {float(c.x()), float(c.y()), float(c.z())};
    data.append(reinterpret_cast<const char*>(xyz), 12);
    std::uint8_t file_value = 0;
    for (int v = 0; v < 6; ++v)
      if (Dsm3LabelNames()[voxel_labels[n]] == kFileNames[v])
        file_value = static_cast<std::uint8_t>(v);
    data.push_back(static_cast<char>(file_value));
    data.append(reinterpret_cast<const char*>(ijk[n].data()), 12);
  }
  data.resize(data.size() - truncate_bytes);
  WriteText(path, data);
}

#ifndef MOPAD_BINARY
TEST(ModelFiles, Dsm3IsReadWithLabelsMappedByNameAndBadOnesRejected) {
  const fs::path d = TempDir("dsm3");
  const std::string p = (d / "dsm3.ply").string();
  VoxelGrid g;
  g.origin = Vec3(-1, 2, 0.5);
  g.voxel_size = 0.05;
  g.dims = {4, 3, 2};
  const std::vector<std::array<int, 3>> ijk = {{0, 0, 0}, {3, 2, 1}, {1, 2, 0}};
  const std::vector<std::uint8_t> labels = {std::uint8_t(VoxelLabel::kOpening),
                                            std::uint8_t(VoxelLabel::kStructure),
                                            std::uint8_t(VoxelLabel::kUnseen)};
  WriteDsm3Ply(d / "dsm3.ply", g, ijk, labels);
  const Dsm3Voxels v = ReadDsm3(p);
  EXPECT_EQ(v.ijk, ijk);
  EXPECT_EQ(v.labels, labels);
  EXPECT_NEAR(v.grid.voxel_size, 0.05, 1e-12);
  EXPECT_NEAR(v.grid.origin.y(), 2.0, 1e-12);
  EXPECT_EQ(v.grid.dims[0], 4);
  WriteDsm3Ply(d / "dsm3.ply", g, ijk, labels, 5);
  EXPECT_NE(InputErrorOf([&] { ReadDsm3(p); }).find("truncated vertex data"), std::string::npos);
  VoxelGrid small = g;
  small.dims = {2, 3, 2};
  WriteDsm3Ply(d / "dsm3.ply", small, ijk, labels);
  EXPECT_NE(InputErrorOf([&] { ReadDsm3(p); }).find("outside the grid"), std::string::npos);
  WriteText(d / "dsm3.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 0\nend_header\n");
  EXPECT_NE(InputErrorOf([&] { ReadDsm3(p); }).find("mopad_dsm3_voxel_size"), std::string::npos);
  WriteText(d / "poses.tum", "# t x y z qx qy qz qw\n1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1\n");
  const auto pos = ReadTumPositions((d / "poses.tum").string());
  ASSERT_EQ(pos.size(), 2u);
  EXPECT_EQ(pos[1], Vec3(4, 5, 6));
  WriteText(d / "poses.tum", "1.0 1 2\n");
  EXPECT_NE(InputErrorOf([&] { ReadTumPositions((d / "poses.tum").string()); }).find("poses.tum:1"),
            std::string::npos);
  fs::remove_all(d);
}

#endif

// ---- End to end: a run directory written by hand, equal to the truth ----

// one_room's R1 seen from a map frame yawed by 30 deg and shifted: sm3.json holds the truth
// patches in the map frame, dsm3.ply the truth DSM3 with 10 structure voxels relabelled empty,
// scan_poses.tum two scanner positions.
struct HandRun {
  fs::path dir;
  int structure_voxels = 0;
};

HandRun WriteHandRun(const std::string& name) {
  HandRun h;
  h.dir = TempDir(name);
  const std::string spec = MOPAD_SOURCE_DIR "/scenes/one_room.yaml";
  const auto g = scenes::Generate(scenes::LoadSceneSpec(spec));
  Pose3 X_WM = Pose3::Identity();
  X_WM.linear() = Eigen::AngleAxisd(kPi / 6, Vec3::UnitZ()).toRotationMatrix();
  X_WM.translation() = Vec3(1.0, 2.0, 0.0);
  const Pose3 X_MW = X_WM.inverse();
  nlohmann::json run = nlohmann::json::parse(kRunJson);
  run["scene"] = spec;
  run["files"].erase("sm1");
  run["files"].erase("sm2");
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) run["X_WM"][i][k] = X_WM.matrix()(i, k);
  std::ofstream(h.dir / "run.json") << run.dump(2);
  nlohmann::json sm3 = {{"format", "mopad-sm3"},
                        {"version", 1},
                        {"room", "R1"},
                        {"floor_z", 0.0},
                        {"ceiling_z", 2.7}};
  sm3["patches"] = nlohmann::json::array();
  for (const auto& p : TruthPatches(g.truth, "R1")) {
    const Vec3 n = X_MW.linear() * p.normal;
    nlohmann::json poly = nlohmann::json::array();
    for (const auto& v : p.polygon) {
      const Vec3 m = X_MW * v;
      poly.push_back({m.x(), m.y(), m.z()});
    }
    sm3["patches"].push_back(
        {{"id", p.id},
         {"class", SurfaceClassName(p.cls)},
         {"plane", {{"n", {n.x(), n.y(), n.z()}}, {"d", -n.dot(X_MW * p.polygon[0])}}},
         {"polygon", poly},
         {"support", 100},
         {"rms", 0.0},
         {"fitted", true}});
  }
  sm3["adjacency"] = nlohmann::json::array();
  std::ofstream(h.dir / "sm3.json") << sm3.dump(2);
  const std::vector<Vec3> scanners_W = {{1.5, 2.0, 1.4}, {4.5, 3.4, 1.4}};
  {
    std::ofstream f(h.dir / "scan_poses.tum");
    for (std::size_t i = 0; i < scanners_W.size(); ++i) {
      const Vec3 m = X_MW * scanners_W[i];
      f << i << " " << m.x() << " " << m.y() << " " << m.z() << " 0 0 0 1\n";
    }
  }
  // Grid: the room's map-frame bounding box at 0.1 m, every voxel listed.
  Eigen::AlignedBox3d box;
  for (const auto& q : g.truth.rooms[0].polygon)
    for (double z : {0.0, 2.7}) box.extend(X_MW * Vec3(q.x(), q.y(), z));
  VoxelGrid grid;
  grid.voxel_size = 0.1;
  grid.origin = (box.min() / 0.1).array().floor() * 0.1 - 0.1;
  for (int a = 0; a < 3; ++a)
    grid.dims[a] = static_cast<int>(std::ceil((box.max()[a] - grid.origin[a]) / 0.1)) + 1;
  const auto voxels = AllVoxels(grid.dims[0], grid.dims[1], grid.dims[2]);
  const sim::EmbreeWorld world(g.scene, &g.truth);
  std::vector<std::uint8_t> labels =
      TruthDsm3(world, g.truth, "R1", grid, voxels, X_WM, scanners_W);
  int flipped = 0;
  for (auto& l : labels) {
    if (l == std::uint8_t(VoxelLabel::kStructure)) {
      ++h.structure_voxels;
      if (flipped < 10) l = std::uint8_t(VoxelLabel::kEmpty), ++flipped;
    }
  }
  WriteDsm3Ply(h.dir / "dsm3.ply", grid, voxels, labels);
  return h;
}

#ifndef MOPAD_BINARY
TEST(TruthModels, AsBuiltWallsLieInTheirOwnPlanesAndTheDesignScoresAsBefore) {
  scenes::SceneSpec spec =
      scenes::LoadSceneSpec(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
  const auto design = scenes::Generate(spec);
  spec.as_built.flatness_mm = 2.0;
  spec.as_built.lean_sigma_deg = 0.5;  // leaning walls, so the tilt is plain to see
  spec.as_built.seed = 4;
  const auto g = scenes::Generate(spec);
  // The design truth's patches are what they were without the field, bit for bit.
  const auto before = TruthPatches(design.truth, "R1"), now = TruthPatches(g.truth, "R1");
  ASSERT_EQ(before.size(), now.size());
  for (std::size_t i = 0; i < now.size(); ++i) {
    EXPECT_EQ(before[i].polygon, now[i].polygon);
    EXPECT_EQ(before[i].normal, now[i].normal);
  }
  // The as-built truth: planar patches (the evaluator checks planarity) and openings on their
  // walls' planes; a model equal to it scores zero against it and its tilt against the design.
  const scenes::GroundTruth built = scenes::AsBuiltTruth(g.truth, g.truth.as_built);
  std::vector<Patch> model;
  ASSERT_NO_THROW(model = TruthPatches(built, "R1"));
  const PatchEvaluation own = EvaluatePatches(model, model);
  EXPECT_NEAR(own.phi_deg.max, 0.0, 1e-6);
  EXPECT_NEAR(own.d_v.max, 0.0, 1e-9);
  const PatchEvaluation against_design = EvaluatePatches(model, now);
  EXPECT_EQ(against_design.detection[int(SurfaceClass::kWall)].tp, 4);
  EXPECT_GT(against_design.phi_deg.max, 0.05);
  EXPECT_LT(against_design.phi_deg.max, 3.0);
  const auto openings = TruthOpeningPatches(built, "R1");
  ASSERT_FALSE(openings.empty());
  for (const Patch& o : openings) {
    const std::string wall = o.id.substr(o.id.find('@') + 1);
    const auto it =
        std::find_if(model.begin(), model.end(), [&](const Patch& p) { return p.id == wall; });
    ASSERT_NE(it, model.end()) << o.id;
    for (const Vec3& v : o.polygon)
      EXPECT_LT(std::abs(it->normal.dot(v - it->polygon[0])), 1e-6) << o.id;
  }
}

TEST(EvalEndToEnd, HandWrittenRunEqualToTheTruthScoresPerfectly) {
  const HandRun h = WriteHandRun("lib");
  const RunInfo run = runfolder::ReadRunJson((h.dir / "run.json").string());
  const auto g = scenes::Generate(scenes::LoadSceneSpec(run.scene));
  std::vector<Patch> model;
  for (const auto& p : ReadSm3(run.sm3).Patches()) {
    Patch w = p;
    for (auto& v : w.polygon) v = run.X_WM * v;
    w.normal = run.X_WM.linear() * p.normal;
    model.push_back(w);
  }
  const auto truth = TruthPatches(g.truth, "R1");
  const PatchEvaluation e = EvaluatePatches(model, truth);
  EXPECT_EQ(e.detection[int(SurfaceClass::kWall)].tp, 4);
  EXPECT_EQ(e.unmatched_model.size() + e.unmatched_truth.size(), 0u);
  EXPECT_NEAR(e.d_v.max, 0.0, 1e-6);
  EXPECT_NEAR(e.d_h.max, 0.0, 1e-6);
  EXPECT_NEAR(e.phi_deg.max, 0.0, 1e-4);
  IsprsParams ip;
  ip.sample_spacing = 0.05;
  const IsprsResult ir = EvaluateIsprs(model, truth, ip);
  EXPECT_NEAR(ir.all.completeness[0], 1.0, 1e-9);
  EXPECT_NEAR(ir.all.correctness[0], 1.0, 1e-9);
  // DSM3: the truth recomputed from the run's own files; 10 structure voxels were relabelled.
  const Dsm3Voxels dsm = ReadDsm3(run.dsm3);
  std::vector<Vec3> scanners;
  for (const auto& p : ReadTumPositions((h.dir / "scan_poses.tum").string()))
    scanners.push_back(run.X_WM * p);
  const sim::EmbreeWorld world(g.scene, &g.truth);
  const auto t = TruthDsm3(world, g.truth, "R1", dsm.grid, dsm.ijk, run.X_WM, scanners);
  const ConfusionMatrix cm = ComputeDsm3Confusion(t, dsm.labels);
  const int S = int(VoxelLabel::kStructure), E = int(VoxelLabel::kEmpty);
  EXPECT_EQ(cm.At(S, E), 10);
  EXPECT_NEAR(cm.iou[S], double(h.structure_voxels - 10) / h.structure_voxels, 1e-12);
  const auto counts = CountVoxelLabels(t);
  EXPECT_GT(counts[int(VoxelLabel::kClutter)], 0);  // the desk, the door leaf, BSCs
  EXPECT_GT(counts[int(VoxelLabel::kOpening)], 0);  // door D1, window W1
  fs::remove_all(h.dir);
}

#endif

#ifdef MOPAD_BINARY
int RunMopad(const std::string& args, std::string* out) {
  const std::string cmd = std::string(MOPAD_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (p && fgets(buf, sizeof buf, p)) *out += buf;
  const int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(EvalCli, HandWrittenRunEqualToTheTruthScoresPerfectly) {
  const HandRun h = WriteHandRun("cli");
  // As a main-job folder: rooms/R1/run.json.
  const fs::path job = TempDir("cli_job");
  fs::create_directories(job / "rooms");
  fs::rename(h.dir, job / "rooms" / "R1");
  // The mission's own figures (as tools/room_eval.cpp writes them) are carried over.
  WriteText(
      job / "rooms" / "R1" / "evaluation.json",
      R"({"room": "R1", "coverage_of_observable": 0.97, "registration_error_max": )"
      R"({"translation_m": 0.004, "rotation_deg": 0.05}, "sm1_labels": {"points": 1000, "correct": 990}})");
  std::string out;
  ASSERT_EQ(RunMopad("eval " + job.string() + " -o " + (job / "eval").string(), &out), 0) << out;
  EXPECT_NE(out.find("R1"), std::string::npos) << out;
  std::ifstream f(job / "eval" / "evaluation.json");
  const nlohmann::json j = nlohmann::json::parse(f);
  const auto& s = j["summary"];
  EXPECT_EQ(s["detection"]["wall"]["tp"], 4);
  EXPECT_EQ(s["detection"]["wall"]["fn"], 0);
  EXPECT_EQ(s["detection"]["floor"]["tp"], 1);
  EXPECT_EQ(s["detection"]["ceiling"]["tp"], 1);
  for (const char* c : {"wall", "floor", "ceiling", "column"})
    EXPECT_EQ(s["detection"][c]["fp"], 0) << c;
  EXPECT_EQ(s["columns"]["detection"]["n_truth"], 0);  // one_room has no column
  EXPECT_EQ(j["rooms"][0]["columns"]["pairs"].size(), 0u);
  EXPECT_NEAR(s["d_v"]["max"].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(s["d_h"]["max"].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(s["phi_deg"]["max"].get<double>(), 0.0, 1e-4);
  EXPECT_NEAR(s["isprs_completeness"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(s["isprs_correctness"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(s["floorplan_mean_iou"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(s["dsm3_structure_iou"].get<double>(),
              double(h.structure_voxels - 10) / h.structure_voxels, 1e-9);
  EXPECT_NEAR(s["mission"]["coverage_of_observable_min"].get<double>(), 0.97, 1e-12);
  EXPECT_NEAR(s["mission"]["registration_translation_max_m"].get<double>(), 0.004, 1e-12);
  EXPECT_NEAR(s["mission"]["sm1_label_accuracy"].get<double>(), 0.99, 1e-12);
  EXPECT_EQ(j["rooms"][0]["mission"]["room"], "R1");
  std::ifstream md(job / "eval" / "evaluation.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  // The truth DSM3 written beside it reads back with the independent reader: same voxels.
  const Dsm3Voxels robot = ReadDsm3((job / "rooms" / "R1" / "dsm3.ply").string());
  const Dsm3Voxels truth = ReadDsm3((job / "eval" / "dsm3_truth_R1.ply").string());
  EXPECT_EQ(truth.ijk, robot.ijk);
  int differ = 0;
  for (std::size_t n = 0; n < truth.labels.size(); ++n)
    differ += truth.labels[n] != robot.labels[n];
  EXPECT_EQ(differ, 10);
  // --truth overrides the scene's sidecar: without its floor element the model's floor is a FP.
  {
    auto g = scenes::Generate(scenes::LoadSceneSpec(MOPAD_SOURCE_DIR "/scenes/one_room.yaml"));
    auto& el = g.truth.elements;
    el.erase(std::remove_if(el.begin(), el.end(),
                            [](const scenes::StructuralElement& e) {
                              return e.element_class == scenes::ElementClass::kFloor;
                            }),
             el.end());
    scenes::WriteGroundTruth(g.truth, (job / "no_floor.truth.json").string());
    out.clear();
    ASSERT_EQ(
        RunMopad("eval " + job.string() + " --truth " + (job / "no_floor.truth.json").string() +
                     " -o " + (job / "eval_nf").string(),
                 &out),
        0)
        << out;
    std::ifstream fn(job / "eval_nf" / "evaluation.json");
    const nlohmann::json k = nlohmann::json::parse(fn);
    EXPECT_EQ(k["summary"]["detection"]["floor"]["tp"], 0);
    EXPECT_EQ(k["summary"]["detection"]["floor"]["fp"], 1);
    EXPECT_EQ(k["summary"]["detection"]["wall"]["tp"], 4);
  }
  // A folder without runs, and a malformed run.json: exit 2 with one line.
  out.clear();
  EXPECT_EQ(RunMopad("eval " + (job / "eval").string() + " -o " + (job / "x").string(), &out), 2);
  EXPECT_NE(out.find("not a run directory"), std::string::npos) << out;
  WriteText(job / "rooms" / "R1" / "run.json", "{\"format\": \"mopad-room-run\", \"version\": 1}");
  out.clear();
  EXPECT_EQ(RunMopad("eval " + job.string() + " -o " + (job / "x").string(), &out), 2);
  EXPECT_NE(out.find("run.json: error: scene: missing field"), std::string::npos) << out;
  if (!std::getenv("MOPAD_TEST_KEEP")) fs::remove_all(job);
}
#endif

}  // namespace
}  // namespace mopad::evaluation
