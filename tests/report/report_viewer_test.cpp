// The report's 3D view: the fragment carries the model of a run folder, and headless Chromium
// (Debian `chromium`, when installed) draws it with three.js (Debian libjs-three), or with the
// canvas 2D fallback when the library is absent, on a non-blank canvas with no script error.
#include "report/report_viewer.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "modelling/model_io.h"

namespace mopad::report {
namespace {

namespace fs = std::filesystem;

// rooms/R1/sm3.json of a 4 m x 3 m x 2.5 m box room.
std::string BoxRun(const std::string& name) {
  using modelling::PatchClass;
  const fs::path dir = fs::path(testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "rooms" / "R1");
  modelling::StructuralModel m;
  m.room = "R1";
  m.ceiling_z = 2.5;
  auto patch = [](const char* id, PatchClass c, Eigen::Vector3d n,
                  std::vector<Eigen::Vector3d> poly) {
    modelling::StructuralPatch p;
    p.id = id, p.patch_class = c, p.plane.n = n, p.plane.d = -n.dot(poly[0]), p.polygon = poly;
    return p;
  };
  const double h = 2.5;
  m.patches = {
      patch("wall_1", PatchClass::kWall, {0, 1, 0}, {{4, 0, 0}, {0, 0, 0}, {0, 0, h}, {4, 0, h}}),
      patch("wall_2", PatchClass::kWall, {-1, 0, 0}, {{4, 3, 0}, {4, 0, 0}, {4, 0, h}, {4, 3, h}}),
      patch("wall_3", PatchClass::kWall, {0, -1, 0}, {{0, 3, 0}, {4, 3, 0}, {4, 3, h}, {0, 3, h}}),
      patch("wall_4", PatchClass::kWall, {1, 0, 0}, {{0, 0, 0}, {0, 3, 0}, {0, 3, h}, {0, 0, h}}),
      patch("floor", PatchClass::kFloor, {0, 0, 1}, {{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}),
      patch("ceiling", PatchClass::kCeiling, {0, 0, -1},
            {{0, 0, h}, {0, 3, h}, {4, 3, h}, {4, 0, h}})};
  std::ofstream(dir / "rooms" / "R1" / "sm3.json") << modelling::Sm3Json(m);
  return dir.string();
}

nlohmann::json ViewerData(const std::string& html) {
  const std::string open = "id='mopad3d-data'>";
  const auto a = html.find(open);
  const auto b = html.find("</script>", a);
  EXPECT_NE(a, std::string::npos);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

TEST(ReportViewer, TheFragmentCarriesEveryElementOfTheRunsModel) {
  const std::string html = ModelViewerHtml(BoxRun("viewer_box"));
  EXPECT_NE(html.find("<canvas id='mopad3d'"), std::string::npos);
  const auto data = ViewerData(html);
  EXPECT_EQ(data["meshes"].size(), 6u);  // 4 walls, floor, ceiling
  EXPECT_EQ(data["materials"].size(), 3u);
  EXPECT_EQ(data["meshes"][0]["id"], "R1/wall_1");
  EXPECT_EQ(data["meshes"][0]["t"].size(), 6u);            // a quad: two triangles
  EXPECT_EQ(ModelViewerHtml(BoxRun("viewer_box")), html);  // deterministic
  // A folder without models (a drive) gets no view; a malformed model gets a note.
  const fs::path empty = fs::path(testing::TempDir()) / "viewer_empty";
  fs::create_directories(empty);
  EXPECT_EQ(ModelViewerHtml(empty.string()), "");
  const std::string bad = BoxRun("viewer_bad");
  std::ofstream(fs::path(bad) / "rooms" / "R1" / "sm3.json") << "{";
  EXPECT_NE(ModelViewerHtml(bad).find("No 3D view"), std::string::npos);
}

TEST(ReportViewer, TheTruthIsDrawnInTheExportFrameOfTheFirstRoom) {
  const std::string dir = BoxRun("viewer_truth");
  // The room's map frame sits at x = 10 m in the world.
  std::ofstream(fs::path(dir) / "rooms" / "R1" / "run.json")
      << R"({"format": "mopad-room-run", "version": 1, "scene": "s", "room": "R1",
             "X_WM": [[1,0,0,10],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "files": {}})";
  scenes::GroundTruth truth;
  scenes::StructuralElement wall;
  wall.id = "wall_1A";
  wall.polygons = {{{10, 0, 0}, {14, 0, 0}, {14, 0, 2.5}, {10, 0, 2.5}}};
  scenes::StructuralElement ceiling = wall;
  ceiling.element_class = scenes::ElementClass::kCeiling;
  truth.elements = {wall, ceiling};
  const auto data = ViewerData(ModelViewerHtml(dir, &truth));
  ASSERT_EQ(data["truth"].size(), 1u);  // ceilings are left out
  EXPECT_EQ(data["truth"][0][0], 0.0);  // world x = 10 is x = 0 in the room's map
  EXPECT_EQ(data["truth"][0][3], 4.0);
  EXPECT_EQ(ViewerData(ModelViewerHtml(dir))["truth"].size(), 0u);  // no truth given
}

TEST(ReportViewer, InlinesThreeJsWhenInstalledElseNotesTheCanvasFallback) {
  auto count = [](const std::string& text, const std::string& what) {
    int n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const std::string dir = BoxRun("viewer_three");
  const std::string fallback = ModelViewerHtml(dir, nullptr, dir + "/no_three_here");
  EXPECT_NE(fallback.find("three.js was not found in " + dir + "/no_three_here"),
            std::string::npos);
  EXPECT_EQ(count(fallback, "<script>"), 1);  // the view's own script only
  if (!fs::exists(fs::path(kThreeJsDir) / kThreeJsFile))
    GTEST_SKIP() << "Debian libjs-three is not installed (scripts/install-deps.sh)";
  const std::string html = ModelViewerHtml(dir);
  EXPECT_EQ(count(html, "<script>"), 3);  // three.js, OrbitControls, the view
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);
  EXPECT_EQ(html.find("three.js was not found"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);  // nothing loaded from elsewhere
  EXPECT_GT(html.size(), fallback.size() + 800'000);
}

// Headless Chromium's output for `page` with `what` ("--screenshot=PNG" or "--dump-dom"):
// software WebGL (SwiftShader) so three.js gets a context without a GPU.
std::string Chromium(const std::string& page, const std::string& profile, const std::string& what) {
  const std::string cmd =
      "chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
      "--disable-background-networking --enable-logging=stderr --v=0 --user-data-dir=" +
      profile + " --window-size=1000,800 " + what + " file://" + page + " 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), p)) out += buf.data();
  pclose(p);
  return out;
}

// Writes the view of `dir` (library from `three_dir`) in a page that turns red on any script
// error, so an error can never pass as a drawing; returns the page's path.
std::string ViewerPage(const std::string& dir, const std::string& three_dir) {
  const std::string page = dir + "/page.html";
  std::ofstream(page) << "<!DOCTYPE html><html><head><meta charset='utf-8'>"
                      << "<script>window.onerror=function(){document.body.style.background="
                      << "'#ff0000';};</script></head><body style='margin:0'>"
                      << ModelViewerHtml(dir, nullptr, three_dir) << "</body></html>";
  return page;
}

// Asserts a screenshot of `page` shows a drawn model and no red error page.
void ExpectDrawn(const std::string& dir, const std::string& page) {
  const std::string png = dir + "/shot.png";
  const std::string out = Chromium(page, dir + "/profile", "--screenshot=" + png);
  const cv::Mat shot = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty()) << out;
  // The page's console lines (--enable-logging): no uncaught exception, no console.error.
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (line.find(":CONSOLE") != std::string::npos) {
      EXPECT_EQ(line.find("Uncaught"), std::string::npos) << line;
      EXPECT_EQ(line.find("ERROR:CONSOLE"), std::string::npos) << line;
      EXPECT_EQ(line.find("rror"), std::string::npos) << line;
    }
  int red = 0, drawn = 0;
  for (int r = 0; r < shot.rows; ++r)
    for (int c = 0; c < shot.cols; ++c) {
      const cv::Vec3b px = shot.at<cv::Vec3b>(r, c);  // BGR
      if (px[2] > 240 && px[1] < 20 && px[0] < 20) ++red;
      // Model colours: neither the white canvas nor the grey border.
      if (std::abs(px[0] - px[1]) + std::abs(px[1] - px[2]) > 20 || px[0] < 200) ++drawn;
    }
  EXPECT_LT(red, 100) << "a script error turned the page red";
  EXPECT_GT(drawn, 20000) << "the canvas is blank";
}

TEST(ReportViewer, HeadlessChromiumDrawsTheThreeJsViewOnANonBlankCanvasWithoutErrors) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "Debian chromium is not installed (apt-get install chromium)";
  if (!fs::exists(fs::path(kThreeJsDir) / kThreeJsFile))
    GTEST_SKIP() << "Debian libjs-three is not installed (scripts/install-deps.sh)";
  const std::string dir = BoxRun("viewer_chromium");
  const std::string page = ViewerPage(dir, kThreeJsDir);
  ExpectDrawn(dir, page);
  const std::string dom = Chromium(page, dir + "/profile_dom", "--dump-dom");
  EXPECT_NE(dom.find("data-renderer=\"three.js r111\""), std::string::npos) << dom;
}

TEST(ReportViewer, HeadlessChromiumDrawsTheCanvasFallbackWithoutThreeJs) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "Debian chromium is not installed (apt-get install chromium)";
  const std::string dir = BoxRun("viewer_chromium_2d");
  const std::string page = ViewerPage(dir, dir + "/no_three_here");
  ExpectDrawn(dir, page);
  const std::string dom = Chromium(page, dir + "/profile_dom", "--dump-dom");
  EXPECT_NE(dom.find("data-renderer=\"canvas-2d\""), std::string::npos) << dom;
}

}  // namespace
}  // namespace mopad::report
