// The report's figures: coverage against scans per room, the wall orthoimages with the robot's
// openings and components drawn over them, and the paper's Table 3 from the evaluator's one
// table builder.
#include "report/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "evaluation/metrics_components.h"
#include "modelling/model_io.h"
#include "modelling/orthoimage.h"
#include "modelling/sm5_io.h"
#include "report/report_walls.h"

namespace mopad::report {
namespace {

namespace fs = std::filesystem;

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Report, CoveragePlotHasOnePointPerScanAndTheThresholdLine) {
  const std::string robot_only = CoveragePlotSvg({"R1", {0.5, 0.8, 0.93}, {}}, 0.9);
  EXPECT_EQ(Count(robot_only, "<circle class='robot'"), 3);
  EXPECT_EQ(Count(robot_only, "<circle class='evaluator'"), 0);
  EXPECT_EQ(Count(robot_only, "class='threshold'"), 1);
  // Share 0 at y = 170, share 1 at y = 20: 0.9 at 35, the third scan (0.93) at x = 300.
  EXPECT_NE(robot_only.find("y1='35.0' y2='35.0'"), std::string::npos) << robot_only;
  EXPECT_NE(robot_only.find("cx='300.0' cy='30.5'"), std::string::npos) << robot_only;
  const std::string both = CoveragePlotSvg({"R1", {0.5, 0.8}, {0.4, 0.7}}, 0.0);
  EXPECT_EQ(Count(both, "<circle class='robot'"), 2);
  EXPECT_EQ(Count(both, "<circle class='evaluator'"), 2);
  EXPECT_EQ(Count(both, "class='threshold'"), 0);
}

TEST(Report, PlanViewDrawsOneSquarePerPlanPixelAScanHits) {
  ReportInput in;
  ReportScan scan;
  scan.name = "R1/0";
  // 900 px over the 8 m from the nearest to the farthest point (112.5 px per metre): the first
  // two points, 4 mm apart, share a pixel; the other two have their own.
  scan.plan_points = {{1.001f, 1.001f}, {1.005f, 1.005f}, {2.0f, 1.0f}, {9.0f, 1.0f}};
  in.scans = {scan};
  const std::string svg = PlanSvg(in);
  EXPECT_EQ(Count(svg, "class='scan-points'"), 1);
  EXPECT_EQ(Count(svg, "h1v1h-1z"), 3) << svg;
}

TEST(Report, HtmlHasOneCoveragePlotPerRoomAndTheComponentTable) {
  const fs::path dir = fs::path(testing::TempDir()) / "report_html";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ReportInput in;
  in.title = "t";
  in.coverage = {{"R1", {0.6, 0.95}, {}}, {"R2", {0.4, 0.7, 0.85, 0.92}, {}}};
  in.coverage_threshold = 0.9;
  // Two switches in the truth, one found, and one false socket.
  using evaluation::ComponentRecord;
  const std::vector<ComponentRecord> truth{
      {"t1", "switch", "wall_1", {1, 0, 1}, {0, 1, 0}, 0.0, ""},
      {"t2", "switch", "wall_1", {3, 0, 1}, {0, 1, 0}, 0.0, ""}};
  const std::vector<ComponentRecord> model{
      {"m1", "switch", "wall_1", {1.001, 0, 1}, {0, 1, 0}, 0.95, "colour+depth"},
      {"m2", "socket_x1", "wall_1", {2, 0, 0.3}, {0, 1, 0}, 0.5, "depth"}};
  const auto table = evaluation::ComponentsTable(evaluation::EvaluateComponents(model, truth));
  in.tables.push_back({"Table 3", table.header, table.rows, table.centre_errors});
  WriteHtmlReport(in, (dir / "report.html").string());
  const std::string html = Slurp(dir / "report.html");
  EXPECT_EQ(Count(html, "class='coverage'"), 2);
  EXPECT_EQ(Count(html, "<circle class='robot'"), 6);
  EXPECT_EQ(Count(html, "class='threshold'"), 2);
  // Table 3: a row per class (socket_x1, switch) and "all", then the centre errors.
  EXPECT_NE(html.find("<th>TP alpha &gt; 0.9 %</th>"), std::string::npos) << html;
  EXPECT_NE(html.find("<tr><td>switch</td><td>2</td><td>50.0</td><td>50.0</td><td>0.0</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr><td>all</td><td>2</td><td>50.0</td><td>50.0</td><td>50.0</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<p>Centre error on the host plane (mm)"), std::string::npos);
}

// rooms/R1 of a 4 m x 3 m x 2.5 m box room with SM4 (a door and a window on wall_1, a door on
// wall_2), SM5 (a switch on wall_1, a detector on the ceiling) and orthoimages of wall_1 and
// wall_2 at 2 cm (200 x 125 and 150 x 125 pixels).
std::string WallsRun(const std::string& name) {
  using modelling::PatchClass;
  const fs::path dir = fs::path(testing::TempDir()) / name;
  const fs::path room = dir / "rooms" / "R1";
  fs::remove_all(dir);
  fs::create_directories(room / "orthoimages");
  modelling::StructuralModel m;
  m.room = "room_1";  // the robot's name; the folder is the truth room's
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
      patch("ceiling", PatchClass::kCeiling, {0, 0, -1},
            {{0, 0, h}, {0, 3, h}, {4, 3, h}, {4, 0, h}})};
  std::ofstream(room / "sm3.json") << modelling::Sm3Json(m);
  const auto f1 = modelling::PatchFrame::Of(m.patches[0]);
  const auto f2 = modelling::PatchFrame::Of(m.patches[1]);
  auto opening = [](const char* id, modelling::OpeningType t, const char* host,
                    const modelling::PatchFrame& f, double u0, double u1, double v0, double v1) {
    modelling::DetectedOpening o;
    o.id = id, o.type = t, o.host = host, o.state = modelling::DoorState::kOpen;
    o.opening_angle_deg = 90, o.confidence = 1;
    o.corners = {f.ToMap(u0, v0), f.ToMap(u1, v0), f.ToMap(u1, v1), f.ToMap(u0, v1)};
    return o;
  };
  modelling::Sm4Model sm4{
      "R1",
      {opening("opening_1", modelling::OpeningType::kDoor, "wall_1", f1, 1.0, 2.0, 0.0, 2.0),
       opening("opening_2", modelling::OpeningType::kWindow, "wall_1", f1, 2.5, 3.5, 1.0, 2.0),
       opening("opening_3", modelling::OpeningType::kDoor, "wall_2", f2, 0.5, 1.4, 0.0, 2.0)}};
  modelling::WriteSm4Files(room.string(), sm4, {});
  modelling::Sm5Model sm5{"R1", {}};
  modelling::DetectedComponent sw;
  sw.id = "bsc_1", sw.class_name = "switch", sw.host = "wall_1", sw.alpha = 0.95;
  sw.centre = f1.ToMap(0.5, 1.2), sw.normal = f1.n, sw.size = {0.08, 0.12, 0.03};
  modelling::DetectedComponent smoke = sw;
  smoke.id = "bsc_2", smoke.class_name = "smoke_detector", smoke.host = "ceiling";
  smoke.centre = {2, 1.5, h}, smoke.normal = {0, 0, -1};
  sm5.components = {sw, smoke};
  modelling::WriteSm5File(room.string(), sm5);
  for (const auto& [id, f] : {std::pair{"wall_1", f1}, std::pair{"wall_2", f2}}) {
    modelling::Orthoimage img(f, 0.02, static_cast<int>(std::ceil(f.width / 0.02 - 1e-9)), 125);
    for (double u = 0.01; u < f.width; u += 0.02)
      for (double v = 0.01; v < h; v += 0.02) img.AddPoint(u, v, 0.0, {200, 190, 170});
    modelling::WriteOrthoimagePngs(img, (room / "orthoimages" / id).string());
  }
  return dir.string();
}

TEST(ReportWalls, EachWallImageCarriesItsOpeningsAndComponentsInItsUvFrame) {
  const std::string html = WallImagesHtml(WallsRun("report_walls"));
  // wall_3 has no image: two figures.
  ASSERT_EQ(Count(html, "<figure class='wall'"), 2) << html;
  const auto wall_2 = html.find("data-wall='wall_2'");
  ASSERT_NE(wall_2, std::string::npos);
  const std::string fig1 = html.substr(0, wall_2), fig2 = html.substr(wall_2);
  EXPECT_EQ(Count(fig1, "<rect class='opening door'"), 1);
  EXPECT_EQ(Count(fig1, "<rect class='opening window'"), 1);
  EXPECT_EQ(Count(fig1, "<rect class='component'"), 1);  // the ceiling's detector is not here
  EXPECT_EQ(Count(fig2, "<rect class='opening door'"), 1);
  EXPECT_EQ(Count(fig2, "<rect class='opening window'"), 0);
  EXPECT_EQ(Count(fig2, "<rect class='component'"), 0);
  // 125 rows of 2 cm are shown as they are: 50 px per metre, v = 2.5 m at y = 0. The door
  // (u 1-2 m, v 0-2 m) and the switch (8 x 12 cm around u 0.5, v 1.2).
  EXPECT_NE(fig1.find("<svg xmlns='http://www.w3.org/2000/svg' width='200' height='125'"),
            std::string::npos);
  EXPECT_NE(fig1.find("x='50.0' y='25.0' width='50.0' height='100.0'"), std::string::npos) << fig1;
  EXPECT_NE(fig1.find("x='23.0' y='62.0' width='4.0' height='6.0'"), std::string::npos) << fig1;
  EXPECT_NE(fig1.find("opening_1 door, open"), std::string::npos);
  EXPECT_NE(fig1.find("<figcaption>R1 (room_1) wall_1: 4.00 m x 2.50 m, 2 openings, 1 component"),
            std::string::npos)
      << fig1;
  EXPECT_NE(fig1.find(">switch</text>"), std::string::npos);
  EXPECT_NE(fig1.find("href='data:image/jpeg;base64,/9j/"), std::string::npos);  // JPEG magic
  EXPECT_EQ(WallImagesHtml(WallsRun("report_walls")), html);                     // deterministic
}

TEST(ReportWalls, TallImagesAreDownscaledAndAFolderWithoutImagesHasNone) {
  const std::string dir = WallsRun("report_walls_tall");
  const fs::path room = fs::path(dir) / "rooms" / "R1";
  // wall_1 at 5 mm: 800 x 500 pixels, shown 256 x 160.
  modelling::StructuralModel m = modelling::ReadSm3((room / "sm3.json").string());
  const auto f1 = modelling::PatchFrame::Of(m.patches[0]);
  modelling::Orthoimage img(f1, 0.005, 800, 500);
  img.AddPoint(1, 1, 0, {255, 255, 255});
  modelling::WriteOrthoimagePngs(img, (room / "orthoimages" / "wall_1").string());
  const std::string html = WallImagesHtml(dir);
  EXPECT_NE(html.find("width='256' height='" + std::to_string(kWallImageRows) + "'"),
            std::string::npos);
  // The door at 160 / 2.5 = 64 px per metre.
  EXPECT_NE(html.find("x='64.0' y='32.0' width='64.0' height='128.0'"), std::string::npos) << html;
  fs::remove_all(room / "orthoimages");
  EXPECT_EQ(WallImagesHtml(dir), "");
}

}  // namespace
}  // namespace mopad::report
