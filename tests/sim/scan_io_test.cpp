#include "io/scan_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "sim/tls_scanner.h"
#include "tests/sim/test_scenes.h"

namespace mopad::io {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("mopad_scan_io_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TlsScan SmallScan() {
  scenes::Scene s;
  sim::testing::AddMaterial(s, "wood", 0.6f, 0.4f, 0.2f);
  sim::testing::AddRoomBox(s, Eigen::Vector3f(-3, -4, -1.5f), Eigen::Vector3f(5, 4, 2), 0);
  sim::EmbreeWorld world(std::move(s));
  sim::TlsParams p;
  p.step_deg = 1.0;
  p.mount_xyz = {0, 0, 0};
  sim::ScanRequest req;
  req.seed = 3;
  req.scan_id = 42;
  req.start_time = 12.5;
  req.X_WB.translation() = Eigen::Vector3d(0.2, 0.1, 0);
  req.X_WB.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return sim::TlsScanner(world, p).Scan(req);
}

void ExpectSameGrid(const TlsScan& a, const TlsScan& b, bool exact) {
  ASSERT_EQ(a.rows, b.rows);
  ASSERT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.points.size(), b.points.size());
  const float tol = exact ? 0.0f : 1e-5f;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const auto &p = a.points[i], &q = b.points[i];
    ASSERT_EQ(p.valid(), q.valid()) << i;
    EXPECT_EQ(p.row, q.row);
    EXPECT_EQ(p.column, q.column);
    if (!p.valid()) continue;
    EXPECT_NEAR(p.x, q.x, tol);
    EXPECT_NEAR(p.y, q.y, tol);
    EXPECT_NEAR(p.z, q.z, tol);
    EXPECT_NEAR(p.intensity, q.intensity, tol);
    EXPECT_EQ(p.r, q.r);
    EXPECT_EQ(p.g, q.g);
    EXPECT_EQ(p.b, q.b);
    if (exact) {
      EXPECT_EQ(p.range, q.range);
      EXPECT_EQ(p.timestamp, q.timestamp);
    }
  }
}

TEST(ScanIo, TlsScanPlyRoundTrip) {
  const TlsScan scan = SmallScan();
  const std::string path = TempPath("scan.ply");
  WriteTlsScanPly(path, scan);
  const TlsScan back = ReadTlsScanPly(path);
  EXPECT_EQ(back.scan_id, 42u);
  EXPECT_EQ(back.start_time, 12.5);
  EXPECT_EQ(back.azimuth_step, scan.azimuth_step);
  EXPECT_EQ(back.elevation_max, scan.elevation_max);
  EXPECT_TRUE(back.X_MS_estimate.isApprox(scan.X_MS_estimate, 0.0));
  EXPECT_TRUE(back.X_BS.isApprox(scan.X_BS, 0.0));
  ExpectSameGrid(scan, back, true);
  // The header names every field as CloudCompare and Open3D expect.
  const PointCloud cloud = ReadPly(path);
  for (const char* f :
       {"scalar_intensity", "scalar_range", "scalar_row", "scalar_column", "scalar_timestamp"})
    EXPECT_NE(cloud.Field(f), nullptr) << f;
  EXPECT_EQ(cloud.colors.size(), cloud.points.size());
  std::remove(path.c_str());
}

TEST(ScanIo, TlsScanPtxRoundTrip) {
  const TlsScan scan = SmallScan();
  const std::string path = TempPath("scan.ptx");
  WriteTlsScanPtx(path, scan);
  const TlsScan back = ReadTlsScanPtx(path);
  EXPECT_TRUE(back.X_MS_estimate.isApprox(scan.X_MS_estimate, 1e-12));
  ExpectSameGrid(scan, back, false);
  std::remove(path.c_str());
}

TEST(ScanIo, GenericLabelledCloudRoundTrip) {
  PointCloud c;
  c.comments = {"made by a test"};
  c.points = {Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(-4, 5.5f, 6)};
  c.colors = {{1, 2, 3}, {250, 251, 252}};
  c.fields.push_back({"scalar_label", PlyType::kUInt8, {7, 9}});
  c.fields.push_back({"scalar_id", PlyType::kInt32, {-1, 123456}});
  c.fields.push_back({"scalar_t", PlyType::kFloat64, {0.125, 1e9 + 0.5}});
  const std::string path = TempPath("cloud.ply");
  WritePly(path, c);
  const PointCloud b = ReadPly(path);
  EXPECT_EQ(b.comments, c.comments);
  EXPECT_EQ(b.points, c.points);
  EXPECT_EQ(b.colors, c.colors);
  ASSERT_EQ(b.fields.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(b.fields[i].name, c.fields[i].name);
    EXPECT_EQ(b.fields[i].type, c.fields[i].type);
    EXPECT_EQ(b.fields[i].values, c.fields[i].values);
  }
  std::remove(path.c_str());
}

TEST(ScanIo, ReadersRejectBadFiles) {
  const std::string path = TempPath("bad.ply");
  {
    std::ofstream f(path);
    f << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n";
  }
  try {
    ReadPly(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported PLY format"), std::string::npos) << e.what();
  }
  {
    std::ofstream f(path, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nproperty "
         "float y\n"
         "property float z\nend_header\n";
    f.write("\0\0\0\0", 4);
  }
  EXPECT_THROW(ReadPly(path), InputError);  // truncated
  EXPECT_THROW(ReadTlsScanPly(path), InputError);
  EXPECT_THROW(ReadPly(TempPath("missing.ply")), InputError);
  std::remove(path.c_str());
}

// Runs only where Debian's CloudCompare is installed: it must load the scan with every field.
TEST(ScanIo, CloudCompareOpensTheScanWithAllFields) {
  if (std::system("command -v CloudCompare > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "CloudCompare not on PATH";
  const TlsScan scan = SmallScan();
  const std::string ply = TempPath("cc.ply");
  WriteTlsScanPly(ply, scan);
  const std::string dir = std::filesystem::path(ply).parent_path().string();
  const std::string cmd =
      "cd " + dir +
      " && QT_QPA_PLATFORM=offscreen timeout 120 CloudCompare -SILENT -NO_TIMESTAMP -O " + ply +
      " -C_EXPORT_FMT ASC -ADD_HEADER -SAVE_CLOUDS > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  // CloudCompare writes <name>.asc (or <name>_<n>.asc) beside the input.
  std::string asc;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(std::filesystem::path(ply).stem().string(), 0) == 0 &&
        e.path().extension() == ".asc")
      asc = e.path();
  }
  ASSERT_FALSE(asc.empty());
  std::ifstream in(asc);
  std::string header;
  std::getline(in, header);
  for (const char* f : {"intensity", "range", "row", "column", "timestamp"})
    EXPECT_NE(header.find(f), std::string::npos) << f << " missing from: " << header;
  std::size_t lines = 0;
  for (std::string l; std::getline(in, l);) ++lines;
  std::size_t valid = 0;
  for (const auto& p : scan.points) valid += p.valid();
  EXPECT_EQ(lines, valid);
  std::remove(asc.c_str());
  std::remove(ply.c_str());
}

}  // namespace
}  // namespace mopad::io
