// Random office floors: every seed and room count gives a valid, connected floor with the
// requested number of rooms; layouts vary; the same seed gives the same spec.

#include "scenes/random_floor.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <deque>
#include <iostream>
#include <set>

#include "common/error.h"
#include "common/polygon.h"
#include "scenes/generator.h"
#include "scenes/scene_check.h"
#include "scenes/scene_spec.h"

namespace mopad::scenes {
namespace {

TEST(RandomFloor, SeedsAndRoomCountsGiveValidConnectedFloors) {
  int l_shaped = 0, semi_open = 0, closed = 0, columns = 0;
  int min_walls = 1 << 30, max_walls = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    for (int rooms = kMinRandomRooms; rooms <= kMaxRandomRooms; ++rooms) {
      const SceneSpec spec = RandomFloorSpec(seed, rooms);
      const GeneratedScene g = Generate(spec);
      const CheckReport r = CheckScene(g.scene, g.truth);
      ASSERT_TRUE(r.ok()) << "seed " << seed << " rooms " << rooms << "\n" << r.Summary();
      ASSERT_EQ(r.rooms, rooms) << "seed " << seed;
      ASSERT_GE(r.doors_open, rooms - 1);  // a spanning tree of open doors
      for (const Opening& o : g.truth.openings) {
        if (o.type == OpeningType::kDoor && o.state == DoorState::kOpen && o.rooms.size() == 2) {
          EXPECT_GE(o.u1 - o.u0, 0.8);
        }
      }
      for (const Room& room : g.truth.rooms) l_shaped += room.polygon.size() > 4;
      semi_open += r.doors_semi_open;
      closed += r.doors_closed;
      columns += r.columns;
      min_walls = std::min(min_walls, r.walls - 4 * rooms);
      max_walls = std::max(max_walls, r.walls - 4 * rooms);
      EXPECT_GT(r.windows, 0);
      EXPECT_GT(r.service_components, 0);
      EXPECT_GT(r.furniture, 0);
    }
  }
  std::cout << "180 floors: " << l_shaped << " non-rectangular rooms, " << semi_open
            << " semi-open and " << closed << " closed doors, " << columns << " columns\n";
  EXPECT_GT(l_shaped, 20);
  EXPECT_GT(semi_open, 20);
  EXPECT_GT(closed, 20);
  EXPECT_GT(columns, 0);
  EXPECT_EQ(min_walls, 0);  // some floors all rectangles, some with L/T rooms
  EXPECT_GT(max_walls, 0);
}

// The corridor, junction and hall families: valid connected floors of every size, with the
// shape each family promises, measured on the generated truth.
struct FamilyStats {
  int floors = 0, tees = 0, ells = 0;
};

Eigen::AlignedBox2d BoxOf(const std::vector<Eigen::Vector2d>& poly) {
  Eigen::AlignedBox2d b;
  for (const auto& p : poly) b.extend(p);
  return b;
}

void CheckFamilyFloor(FloorFamily family, std::uint64_t seed, int rooms, FamilyStats* st) {
  const SceneSpec spec = RandomFloorSpec(seed, rooms, family);
  const GeneratedScene g = Generate(spec);
  const CheckReport r = CheckScene(g.scene, g.truth);
  const std::string what = FloorFamilyName(family) + " seed " + std::to_string(seed) + " rooms " +
                           std::to_string(rooms);
  ASSERT_TRUE(r.ok()) << what << "\n" << r.Summary();
  ASSERT_EQ(r.rooms, rooms) << what;
  ASSERT_GE(r.doors_open, rooms - 1) << what;
  ++st->floors;
  const Room& hub = g.truth.rooms.front();
  const Eigen::AlignedBox2d box = BoxOf(hub.polygon);
  // Every office has its own open door to the hub.
  for (const Room& room : g.truth.rooms) {
    if (room.id == hub.id) continue;
    bool door_to_hub = false;
    for (const Opening& o : g.truth.openings)
      door_to_hub |= o.type == OpeningType::kDoor && o.state == DoorState::kOpen &&
                     std::count(o.rooms.begin(), o.rooms.end(), hub.id) &&
                     std::count(o.rooms.begin(), o.rooms.end(), room.id);
    EXPECT_TRUE(door_to_hub) << what << ": " << room.id;
  }
  if (family == FloorFamily::kHall) {
    EXPECT_GE(box.sizes().x(), 20.0 - 1e-9) << what;
    EXPECT_GE(box.sizes().y(), 14.0 - 1e-9) << what;
    EXPECT_GE(hub.ceiling_z - hub.floor_z, 3.4 - 1e-9) << what;
    EXPECT_LE(hub.ceiling_z - hub.floor_z, 4.0 + 1e-9) << what;
    int columns = 0, detectors = 0;
    for (const ColumnSpec& c : spec.columns) columns += c.room == hub.id;
    for (const ServiceComponent& c : g.truth.service_components)
      detectors += c.room == hub.id && c.bsc_class == "smoke_detector";
    EXPECT_GE(columns, 4) << what;
    EXPECT_GE(detectors, static_cast<int>(SignedArea(hub.polygon) / 40.0)) << what;
    return;
  }
  // A corridor: clear width 1.5-2.5 m, at most 40 m long; offices at most ~9 m along it.
  const double width = std::min(box.sizes().x(), box.sizes().y());
  if (family == FloorFamily::kCorridor) {
    EXPECT_GE(width, 1.5 - 1e-9) << what;
    EXPECT_LE(width, 2.5 + 1e-9) << what;
    EXPECT_LE(box.sizes().maxCoeff(), 40.0) << what;
    for (const Room& room : g.truth.rooms) {
      if (room.id == hub.id) continue;
      EXPECT_LE(BoxOf(room.polygon).sizes().x(), 9.6) << what;
    }
  } else {
    st->tees += hub.polygon.size() == 8;
    st->ells += hub.polygon.size() == 6;
  }
}

TEST(RandomFloor, CorridorJunctionAndHallFamiliesKeepTheirShape) {
  for (FloorFamily family : {FloorFamily::kCorridor, FloorFamily::kJunction, FloorFamily::kHall}) {
    FamilyStats st;
    for (std::uint64_t seed = 1; seed <= 4; ++seed)
      for (int rooms = kMinRandomRooms; rooms <= kMaxRandomRooms; ++rooms)
        CheckFamilyFloor(family, seed, rooms, &st);
    EXPECT_EQ(st.floors, 4 * (kMaxRandomRooms - kMinRandomRooms + 1));
    if (family == FloorFamily::kJunction) {
      EXPECT_GT(st.tees, 0);
      EXPECT_GT(st.ells, 0);
    }
  }
}

TEST(RandomFloor, MixedFamilyDrawsEveryFamilyAndLeavesOfficeFloorsAlone) {
  std::set<FloorFamily> seen;
  for (std::uint64_t seed = 1; seed <= 40; ++seed)
    seen.insert(ResolveFloorFamily(seed, 6, FloorFamily::kMixed));
  EXPECT_EQ(seen.size(), 4u);
  EXPECT_EQ(ResolveFloorFamily(5, 6, FloorFamily::kHall), FloorFamily::kHall);
  EXPECT_EQ(SceneSpecToYaml(RandomFloorSpec(7, 6)),
            SceneSpecToYaml(RandomFloorSpec(7, 6, FloorFamily::kOffice)));
  EXPECT_EQ(RandomFloorSpec(7, 6, FloorFamily::kCorridor).name, "random_corridor_s7_r6");
  EXPECT_THROW(ParseFloorFamily("atrium"), InputError);
  EXPECT_EQ(ParseFloorFamily("junction"), FloorFamily::kJunction);
}

// The doors of every room are joined by a path at least 2 x kHalfWidth wide around the
// furniture, the columns and the opened door leaves, measured on the truth alone (a 5 cm
// raster of the points that far from all of them): the generator's 0.8 m robot path, with
// its discretisation's slack. An opened leaf stands in its room like furniture; a chair placed
// 0.24 m from a leaf's free edge cut the only way to a door (random floor 23, 9 rooms).
TEST(RandomFloor, DoorsOfARoomAreJoinedAroundFurnitureAndOpenedLeaves) {
  constexpr double kHalfWidth = 0.3, kRes = 0.05;
  using Vector2d = Eigen::Vector2d;
  auto boundary_distance = [](const Vector2d& p, const std::vector<Vector2d>& poly) {
    double d = 1e9;
    for (std::size_t i = 0; i < poly.size(); ++i)
      d = std::min(d, DistanceToSegment(p, poly[i], poly[(i + 1) % poly.size()]));
    return d;
  };
  auto segment_distance = [&](const Vector2d& p, const std::vector<Vector2d>& poly) {
    return poly.size() > 2 && PointInPolygon(p, poly) ? 0.0 : boundary_distance(p, poly);
  };
  int rooms_checked = 0;
  for (const auto& [seed, rooms] : std::vector<std::pair<std::uint64_t, int>>{
           {23, 9}, {2, 3}, {4, 6}, {5, 4}, {10, 9}, {16, 8}, {32, 7}, {37, 5}}) {
    const GeneratedScene g = Generate(RandomFloorSpec(seed, rooms));
    std::vector<std::vector<Vector2d>> obstacles;
    for (const FurnitureItem& f : g.truth.furniture) {
      const Vector2d c = f.centre.head<2>();
      const Vector2d ex(std::cos(f.yaw), std::sin(f.yaw)), ey(-ex.y(), ex.x());
      const double hw = 0.5 * f.size.x(), hd = 0.5 * f.size.y();
      obstacles.push_back({c - hw * ex - hd * ey, c + hw * ex - hd * ey, c + hw * ex + hd * ey,
                           c - hw * ex + hd * ey});
    }
    for (const StructuralElement& e : g.truth.elements)
      if (e.element_class == ElementClass::kColumn)
        for (const auto& poly : e.polygons) {
          std::vector<Vector2d> plan;
          for (const auto& v : poly) plan.push_back(v.head<2>());
          obstacles.push_back(plan);
        }
    for (const Opening& o : g.truth.openings) {
      if (o.type != OpeningType::kDoor || o.opening_angle <= 0.0) continue;
      // Closed leaf: from the hinge along the wall towards the far jamb; opened by the angle
      // about the hinge axis.
      Eigen::Vector3d d = o.corners[2] - o.corners[0];
      d.z() = 0.0;
      const double width = d.norm();
      const Eigen::Vector3d mid = 0.5 * (o.corners[0] + o.corners[2]);
      if (d.dot(mid - o.hinge_point) < 0.0) d = -d;
      const Eigen::Vector3d rd = Eigen::AngleAxisd(o.opening_angle, o.hinge_axis) * d.normalized();
      const Vector2d h = o.hinge_point.head<2>();
      obstacles.push_back({h, h + width * rd.head<2>()});
    }
    for (const Room& room : g.truth.rooms) {
      Eigen::AlignedBox2d box;
      for (const auto& p : room.polygon) box.extend(p);
      const int nx = static_cast<int>(box.sizes().x() / kRes) + 1;
      const int ny = static_cast<int>(box.sizes().y() / kRes) + 1;
      auto centre = [&](int i, int j) -> Vector2d {
        return box.min() + Vector2d(i + 0.5, j + 0.5) * kRes;
      };
      std::vector<std::uint8_t> free(static_cast<std::size_t>(nx * ny), 0);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const Vector2d p = centre(i, j);
          bool ok = PointInPolygon(p, room.polygon) &&
                    boundary_distance(p, room.polygon) >= kHalfWidth;
          for (std::size_t k = 0; k < obstacles.size() && ok; ++k)
            ok = segment_distance(p, obstacles[k]) >= kHalfWidth;
          free[static_cast<std::size_t>(j * nx + i)] = ok;
        }
      // Door fronts: 0.5 m into the room from each door's centre, snapped to the nearest free
      // cell within 1.2 m (a leaf opened into the room stands in front of its own door: the
      // path reaches the door past the leaf's edge). Semi-open doors are left out: a leaf
      // opened less than 90 deg stands across its own doorway and leaves a wedge of about
      // width x sin(angle) (a 0.8 m door at 50 deg: 0.57 m) that a desk beside it may narrow
      // further; the floor's spanning tree is made of open doors. Closed doors stay in (to be
      // pushed open).
      std::vector<int> fronts;
      for (const Opening& o : g.truth.openings) {
        if (o.type != OpeningType::kDoor ||
            std::find(o.rooms.begin(), o.rooms.end(), room.id) == o.rooms.end())
          continue;
        if (o.opening_angle > 0.0 && o.opening_angle < 0.5 * M_PI - 1e-6) continue;
        const Vector2d a = o.corners[0].head<2>(), b = o.corners[2].head<2>();
        const Vector2d mid = 0.5 * (a + b), t = (b - a).normalized(), n(-t.y(), t.x());
        const Vector2d front =
            PointInPolygon(Vector2d(mid + 0.5 * n), room.polygon) ? Vector2d(mid + 0.5 * n)
                                                                   : Vector2d(mid - 0.5 * n);
        int best = -1;
        double best_d = 1.2;
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i)
            if (free[static_cast<std::size_t>(j * nx + i)] &&
                (centre(i, j) - front).norm() < best_d)
              best_d = (centre(i, j) - front).norm(), best = j * nx + i;
        ASSERT_GE(best, 0) << "seed " << seed << " room " << room.id << " door " << o.id
                           << ": no free cell in front of it";
        fronts.push_back(best);
      }
      if (fronts.size() < 2) continue;
      ++rooms_checked;
      std::vector<std::uint8_t> seen(free.size(), 0);
      std::deque<int> queue{fronts.front()};
      seen[static_cast<std::size_t>(fronts.front())] = 1;
      while (!queue.empty()) {
        const int c = queue.front();
        queue.pop_front();
        const int i = c % nx, j = c / nx;
        for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int ii = i + di, jj = j + dj, n = jj * nx + ii;
          if (ii < 0 || jj < 0 || ii >= nx || jj >= ny || !free[static_cast<std::size_t>(n)] ||
              seen[static_cast<std::size_t>(n)])
            continue;
          seen[static_cast<std::size_t>(n)] = 1;
          queue.push_back(n);
        }
      }
      for (const int f : fronts)
        EXPECT_TRUE(seen[static_cast<std::size_t>(f)])
            << "seed " << seed << " rooms " << rooms << ": room " << room.id
            << " has a door no path of " << 2 * kHalfWidth << " m reaches from its others";
    }
  }
  EXPECT_GT(rooms_checked, 10);
}

TEST(RandomFloor, SameSeedGivesSameSpecDifferentSeedsDiffer) {
  EXPECT_EQ(SceneSpecToYaml(RandomFloorSpec(7, 6)), SceneSpecToYaml(RandomFloorSpec(7, 6)));
  EXPECT_NE(SceneSpecToYaml(RandomFloorSpec(7, 6)), SceneSpecToYaml(RandomFloorSpec(8, 6)));
  // The effective YAML reads back and generates.
  const SceneSpec s = ParseSceneSpec(SceneSpecToYaml(RandomFloorSpec(3, 9)), "random.yaml");
  const GeneratedScene g = Generate(s);
  EXPECT_TRUE(CheckScene(g.scene, g.truth).ok());
}

TEST(RandomFloor, RoomCountOutOfRangeIsAnInputError) {
  EXPECT_THROW(RandomFloorSpec(1, 1), InputError);
  EXPECT_THROW(RandomFloorSpec(1, 41), InputError);
  try {
    RandomFloorSpec(1, 41);
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "error: rooms out of range; got 41, expected [2, 40]");
  }
  try {
    RandomFloorSpec(1, 11, FloorFamily::kCorridor);
    ADD_FAILURE() << "11 rooms of the corridor family were accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "error: rooms out of range; got 11, expected [2, 10] for the corridor family");
  }
}

TEST(RandomFloor, FortyRoomOfficeFloorsAreValidAndEveryRoomIsReachable) {
  // The scaling benchmark's floors: 20 and 40 offices, each a checked scene.
  for (int rooms : {20, 40}) {
    const SceneSpec spec = RandomFloorSpec(31, rooms);
    ASSERT_EQ(static_cast<int>(spec.rooms.size()), rooms);
    const GeneratedScene g = Generate(spec);
    const CheckReport check = CheckScene(g.scene, g.truth);
    EXPECT_TRUE(check.ok()) << rooms << " rooms";
    EXPECT_EQ(check.unreachable_rooms, 0) << rooms << " rooms";
  }
}

}  // namespace
}  // namespace mopad::scenes
