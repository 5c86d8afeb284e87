#include "runfolder/run_record.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "common/error.h"
#include "io/text_file.h"
#include "tests/input_error_of.h"

namespace mopad::runfolder {
namespace {

namespace fs = std::filesystem;

const char* kRunJsonText =
    R"({"format": "mopad-room-run", "version": 1, "scene": "SCENE", "room": "R1", "seed": 3,
  "X_WM": [[1,0,0,0.5],[0,1,0,-0.25],[0,0,1,0],[0,0,0,1]],
  "files": {"sm1": "sm1.ply", "sm2": "sm2.json", "sm3": "sm3.json", "dsm3": "dsm3.ply"}})";

fs::path TempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("mopad_run_record_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void WriteText(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string Replace(std::string s, const std::string& a, const std::string& b) {
  const auto p = s.find(a);
  if (p != std::string::npos) s.replace(p, a.size(), b);
  return s;
}

using test_support::InputErrorOf;

TEST(RunRecord, RunJsonIsReadAndMalformedOnesRejected) {
  const fs::path d = TempDir("read");
  const std::string path = (d / "run.json").string();
  WriteText(path, kRunJsonText);
  const RunRecord r = ReadRunJson(path);
  EXPECT_EQ(r.room, "R1");
  EXPECT_EQ(r.seed, 3u);
  EXPECT_NEAR(r.X_WM.translation().x(), 0.5, 1e-12);
  EXPECT_NEAR(r.X_WM.translation().y(), -0.25, 1e-12);
  EXPECT_EQ(r.sm3, (d / "sm3.json").string());
  EXPECT_EQ(r.sm4, "");  // not in "files": not written
  WriteText(path, Replace(kRunJsonText, R"("X_WM")", R"("X_MW")"));
  EXPECT_NE(InputErrorOf([&] { ReadRunJson(path); }).find("X_WM: missing field"),
            std::string::npos);
  WriteText(path, Replace(kRunJsonText, R"("version": 1)", R"("version": 2)"));
  const std::string v = InputErrorOf([&] { ReadRunJson(path); });
  EXPECT_NE(v.find("run.json: error: version"), std::string::npos) << v;
  WriteText(path, Replace(kRunJsonText, "[0,0,1,0]", "[0,0,2,0]"));
  EXPECT_NE(InputErrorOf([&] { ReadRunJson(path); }).find("rigid"), std::string::npos);
  WriteText(path, "{\"format\": ");
  EXPECT_NE(InputErrorOf([&] { ReadRunJson(path); }).find("malformed JSON"), std::string::npos);
  WriteText(path, "{\"format\": 1e999999}");  // out_of_range 406, not a parse_error
  EXPECT_NE(InputErrorOf([&] { ReadRunJson(path); }).find("malformed JSON"), std::string::npos);
  EXPECT_NE(InputErrorOf([&] { ReadRunJson((d / "nothing.json").string()); }).find("cannot read"),
            std::string::npos);
  fs::remove_all(d);
}

TEST(RunRecord, WhatIsWrittenReadsBack) {
  const fs::path d = TempDir("round");
  RunRecord w;
  w.scene = "/scenes/office";
  w.doors = {"D1=45", "D2=0"};
  w.room = "R2";
  w.seed = 17;
  w.X_WM = Pose3::Identity();
  w.X_WM.translation() = Vec3(1.5, -2.0, 0.0);
  w.X_WM.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
  WriteRunJson(d.string(), w);
  const RunRecord r = ReadRunJson((d / "run.json").string());
  EXPECT_EQ(r.dir, d.string());
  EXPECT_EQ(r.scene, w.scene);
  EXPECT_EQ(r.doors, w.doors);
  EXPECT_EQ(r.room, w.room);
  EXPECT_EQ(r.seed, w.seed);
  EXPECT_TRUE(r.X_WM.isApprox(w.X_WM, 1e-15));
  EXPECT_EQ(r.sm1, (d / "sm1.ply").string());
  EXPECT_EQ(r.sm4, (d / "sm4.json").string());
  EXPECT_EQ(r.dsm3, (d / "dsm3.ply").string());
  // One newline ends the file.
  const std::string text = io::ReadTextFile((d / "run.json").string());
  ASSERT_GE(text.size(), 2u);
  EXPECT_EQ(text.substr(text.size() - 2), "}\n");
  fs::remove_all(d);
}

}  // namespace
}  // namespace mopad::runfolder
