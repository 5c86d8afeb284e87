// Random office floors: every seed and room count gives a valid, connected floor with the
// requested number of rooms; layouts vary; the same seed gives the same spec.

#include "scenes/random_floor.h"

#include <gtest/gtest.h>

#include <iostream>

#include "common/error.h"
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
  EXPECT_THROW(RandomFloorSpec(1, 11), InputError);
  try {
    RandomFloorSpec(1, 11);
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "error: rooms out of range; got 11, expected [2, 10]");
  }
}

}  // namespace
}  // namespace mopad::scenes
