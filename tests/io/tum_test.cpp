#include "io/tum.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "io/text_file.h"

namespace mopad::io {
namespace {

TEST(Tum, PlanarLineHasTheTumFieldsAndAQuaternionAboutZ) {
  EXPECT_EQ(TumLinePlanar(1.25, 2.0, -3.5, 0.5 * M_PI),
            "1.250 2.000000 -3.500000 0.000000 0.000000 0.000000 0.707106781 0.707106781\n");
}

TEST(Tum, ThreeDLineMatchesThePlanarOneForAPlanarPose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = Eigen::Vector3d(1.0, 2.0, 0.0);
  std::istringstream a(TumLine(4.0, X)), b(TumLinePlanar(4.0, 1.0, 2.0, -0.3));
  for (int k = 0; k < 8; ++k) {
    double x = 0, y = 0;
    a >> x;
    b >> y;
    EXPECT_NEAR(x, y, 1e-9) << "field " << k;
  }
}

TEST(TextFile, WritesTheTextAndANewlineAndNamesAnUnwritablePath) {
  const auto path = std::filesystem::path(testing::TempDir()) / "mopad_io_text.txt";
  WriteTextFile(path.string(), "{\"a\": 1}");
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  EXPECT_EQ(ss.str(), "{\"a\": 1}\n");
  try {
    WriteTextFile("/nonexistent-dir/x.json", "x");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.json"), std::string::npos);
  }
}

TEST(TextFile, AnAtomicWriteReplacesTheFileWholeAndLeavesNoTemporary) {
  const auto path =
      std::filesystem::path(testing::TempDir()) / ("mopad_io_atomic_" + std::to_string(::getpid()));
  WriteFileAtomically(path.string(), "old");
  WriteFileAtomically(path.string(), std::string("new\0bytes", 9));
  EXPECT_EQ(ReadTextFile(path.string()), std::string("new\0bytes", 9));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::filesystem::remove(path);
  try {
    WriteFileAtomically("/nonexistent-dir/x.json", "x");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.json"), std::string::npos);
  }
  try {
    ReadTextFile("/nonexistent-dir/y.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/y.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace mopad::io
