// A room's SM5 beside the robot's next steps (autonomy/background_sm5.h): R1 of
// scenes/two_rooms_door.yaml scanned twice, its SM3 and SM4 built, its components detected in
// place and by BackgroundSm5, which must give the same bytes.

#include "autonomy/background_sm5.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "modelling/room_models.h"
#include "modelling/sm5_io.h"
#include "scenes/bsc_catalogue.h"
#include "sim/scene_world.h"
#include "tests/modelling/sim_scans.h"

namespace mopad::autonomy {
namespace {

using modelling::testing::SimScan;
using modelling::testing::TakeScan;
using modelling::testing::TestTls;

// The robot's catalogue, learnt with the tests' small training (seconds).
const modelling::ComponentRecogniser& Recogniser() {
  static const modelling::ComponentRecogniser r = [] {
    modelling::ComponentTrainingParams p;
    p.samples_per_class = 120;
    p.iterations = 200;
    return modelling::ComponentRecogniser::Train(scenes::MakeObjectModelCatalogue(), p);
  }();
  return r;
}

struct ScannedRoom {
  std::unique_ptr<modelling::RoomModel> model = std::make_unique<modelling::RoomModel>();
  modelling::RoomModels models;
  ScannedRoom() {
    const sim::SceneWorld mw =
        sim::LoadSceneWorld(std::string(MOPAD_SOURCE_DIR) + "/scenes/two_rooms_door.yaml");
    std::uint64_t id = 0;
    for (const Vec2& at : {Vec2(1.5, 2.0), Vec2(3.6, 1.4)}) {
      const SimScan s = TakeScan(*mw.world, TestTls(0.2), at.x(), at.y(), id++);
      model->AddScan(s.scan, s.X_MS);
    }
    models = modelling::BuildRoomModels(*model, {}, {}, {}, {}, "R1", nullptr);
  }
};

TEST(BackgroundSm5, GivesTheBytesOfTheDetectionInPlace) {
  ScannedRoom room;
  const modelling::RoomModels& m = room.models;
  const std::string in_place =
      modelling::Sm5Json(modelling::DetectComponents(m.sm3, m.sm4, m.ortho, Recogniser(), {}));
  ASSERT_NE(in_place.find("\"class\""), std::string::npos) << "no component found: " << in_place;

  BackgroundSm5 sm5([] { return &Recogniser(); }, {});
  sm5.Prepare();                           // the recogniser asked for beside the caller
  EXPECT_FALSE(sm5.Finish().has_value());  // no room started
  sm5.Start(7, std::move(room.model), m.sm3, m.sm4, m.ortho);
  // One room at a time: the next one starts after the last one is collected.
  EXPECT_THROW(sm5.Start(8, nullptr, m.sm3, m.sm4, m.ortho), std::logic_error);
  const std::optional<BackgroundSm5::Result> done = sm5.Finish();
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->key, 7u);
  EXPECT_EQ(done->error, "");
  EXPECT_EQ(modelling::Sm5Json(done->sm5), in_place);
  EXPECT_FALSE(sm5.Finish().has_value());  // collected once
}

// A detection that throws fails that room's SM5, with the message; the owner goes on.
TEST(BackgroundSm5, ADetectionThatFailsIsReportedWithItsRoom) {
  ScannedRoom room;
  const modelling::RoomModels& m = room.models;
  BackgroundSm5 sm5(
      []() -> const modelling::ComponentRecogniser* {
        throw InputError("catalogue.yaml", "object-model catalogue is empty", "0 models",
                         "at least one model");
      },
      {});
  sm5.Start(0, std::move(room.model), m.sm3, m.sm4, m.ortho);
  const std::optional<BackgroundSm5::Result> done = sm5.Finish();
  ASSERT_TRUE(done.has_value());
  EXPECT_NE(done->error.find("object-model catalogue is empty"), std::string::npos) << done->error;
  EXPECT_EQ(done->sm5.room, "R1");
  EXPECT_TRUE(done->sm5.components.empty());
}

}  // namespace
}  // namespace mopad::autonomy
