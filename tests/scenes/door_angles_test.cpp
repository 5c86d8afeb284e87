// Door angles given by hand ("ID=DEG"): the one parser (well-formed items, a bad id, a bad
// angle, a missing '=', each refused in one line naming the option and the item) and setting
// them on a spec.

#include "scenes/door_angles.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "common/error.h"
#include "scenes/scene_spec.h"
#include "tests/input_error_of.h"

namespace mopad::scenes {
namespace {

using test_support::InputErrorOf;

std::string ParseError(const std::string& item) {
  return InputErrorOf([&] { ParseDoorAngles({item}, "--door"); });
}

TEST(DoorAngles, WellFormedItemsGiveTheirAnglesById) {
  const DoorAngles a =
      ParseDoorAngles({"D2=30", "D1=0", "D3=180", "D4=90.5", "Tür=1=45"}, "--door");
  ASSERT_EQ(a.size(), 5u);
  EXPECT_EQ(a.at("D1"), 0.0);
  EXPECT_EQ(a.at("D2"), 30.0);
  EXPECT_EQ(a.at("D3"), 180.0);
  EXPECT_EQ(a.at("D4"), 90.5);
  // The id is everything before the last '=' (an IFC Name may hold one).
  EXPECT_EQ(a.at("Tür=1"), 45.0);
  EXPECT_TRUE(ParseDoorAngles({}, "--door").empty());
}

TEST(DoorAngles, ABadIdIsRefused) {
  EXPECT_EQ(ParseError("=30"),
            "--door: error: malformed door angle; got '=30', expected ID=DEG with DEG in [0, 180]");
  EXPECT_EQ(InputErrorOf([] {
              ParseDoorAngles({"D1=30", "D1=40"}, "--doors");
            }),
            "--doors: error: door given twice; got 'D1', expected once");
}

TEST(DoorAngles, ABadAngleIsRefused) {
  for (const std::string item :
       {"D1=", "D1=abc", "D1=30abc", "D1=30 ", "D1=-5", "D1=180.001", "D1=nan", "D1=inf"})
    EXPECT_EQ(ParseError(item), "--door: error: malformed door angle; got '" + item +
                                    "', expected ID=DEG with DEG in [0, 180]");
}

TEST(DoorAngles, AMissingEqualsSignIsRefused) {
  EXPECT_EQ(ParseError("D1"),
            "--door: error: malformed door angle; got 'D1', expected ID=DEG with DEG in [0, 180]");
  EXPECT_EQ(ParseError("D1:30"),
            "--door: error: malformed door angle; got 'D1:30', expected "
            "ID=DEG with DEG in [0, 180]");
}

TEST(DoorAngles, SetOnASpecChangesOnlyTheNamedDoors) {
  SceneSpec spec;
  spec.doors.resize(2);
  spec.doors[0].id = "D1";
  spec.doors[0].angle_deg = 90.0;
  spec.doors[1].id = "D2";
  spec.doors[1].angle_deg = 10.0;
  SetDoorAngles(ParseDoorAngles({"D1=0"}, "--door"), "--door", &spec);
  EXPECT_EQ(spec.doors[0].angle_deg, 0.0);
  EXPECT_EQ(spec.doors[1].angle_deg, 10.0);
  EXPECT_EQ(InputErrorOf([&] {
              SetDoorAngles({{"D9", 30.0}}, "--door", &spec);
            }),
            "--door: error: unknown door; got 'D9', expected a door of the spec");
}

}  // namespace
}  // namespace mopad::scenes
