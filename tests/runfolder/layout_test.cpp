#include "runfolder/layout.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace mopad::runfolder {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("mopad_runfolder_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void Touch(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "{}\n";
}

TEST(RoomFolders, ListsTheRoomsThatHoldTheMarkerInNameOrder) {
  const fs::path d = TempDir("rooms");
  Touch(d / "rooms" / "R2" / "run.json");
  Touch(d / "rooms" / "R10" / "run.json");
  Touch(d / "rooms" / "R1" / "run.json");
  Touch(d / "rooms" / "R3" / "sm3.json");  // a model without a run record
  fs::create_directories(d / "rooms" / "empty");
  const std::vector<std::string> runs = RoomFolders(d.string(), kRunJson);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0], (d / "rooms" / "R1").string());
  EXPECT_EQ(runs[1], (d / "rooms" / "R10").string());
  EXPECT_EQ(runs[2], (d / "rooms" / "R2").string());
  const std::vector<std::string> models = RoomFolders(d.string(), kSm3);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0], (d / "rooms" / "R3").string());
  fs::remove_all(d);
}

TEST(RoomFolders, AFolderHoldingTheMarkerIsOneRoom) {
  const fs::path d = TempDir("one");
  Touch(d / "run.json");
  Touch(d / "rooms" / "R1" / "run.json");  // the folder itself wins: a `mopad room` run
  const std::vector<std::string> runs = RoomFolders(d.string(), kRunJson);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0], d.string());
  fs::remove_all(d);
}

TEST(RoomFolders, NoFolderOrNoRoomGivesNone) {
  EXPECT_TRUE(RoomFolders("/nonexistent/mopad/run", kRunJson).empty());
  const fs::path d = TempDir("none");
  EXPECT_TRUE(RoomFolders(d.string(), kRunJson).empty());
  fs::remove_all(d);
}

TEST(Layout, RoomDirAndJoinSpellTheLayout) {
  EXPECT_EQ(RoomDir("out/run", "R5"), "out/run/rooms/R5");
  EXPECT_EQ(Join("out/run/rooms/R5", kSm4), "out/run/rooms/R5/sm4.json");
}

}  // namespace
}  // namespace mopad::runfolder
