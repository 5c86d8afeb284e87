// `mopad run`: the main job. Until the closed-loop mission lands (issues 4-6), it generates the
// default scene, takes one simulated terrestrial scan per room and writes the scans, a summary
// and a report. Scan positions here are chosen by the *harness* from the truth (a free spot in
// each room), not by the robot: the next-best-scan planner will replace this.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/params.h"
#include "interfaces/scan_io.h"
#include "scenes/generator.h"
#include "scenes/scene_spec.h"
#include "sim/embree_world.h"
#include "sim/tls_scanner.h"
#include "sim/tls_truth.h"
#include "tools/commands.h"
#include "tools/default_scene.h"
#include "tools/mission_world.h"
#include "tools/report.h"
#include "tools/scene_summary.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a) {
  return std::chrono::duration<double>(Clock::now() - a).count();
}

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

void RegisterRunCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run", "Main job: generate the default scene, scan it, write results and a report");
  auto out = std::make_shared<std::string>("out/run");
  auto spec_path = std::make_shared<std::string>();
  auto seed = std::make_shared<std::uint64_t>(1);
  auto step = std::make_shared<double>(0.2);
  auto profile = std::make_shared<std::string>("riegl_vz400");
  cmd->add_option("-o,--output", *out, "Output folder")->default_val("out/run");
  cmd->add_option("--spec", *spec_path, "Scene spec YAML (default: the embedded office_5rooms)");
  cmd->add_option("--seed", *seed, "Run seed (sensor noise)")->default_val(1);
  cmd->add_option("--step-deg", *step, "TLS angular step in degrees")
      ->check(CLI::Range(0.0024, 10.0))
      ->default_val(0.2);
  cmd->add_option("--profile", *profile, "TLS profile")->default_val("riegl_vz400");
  cmd->callback([=] {
    const auto t_start = Clock::now();
    const fs::path dir(*out);
    fs::create_directories(dir / "scans");

    // 1. The world (truth side).
    const scenes::SceneSpec spec =
        spec_path->empty() ? scenes::ParseSceneSpec(kDefaultSceneSpec, kDefaultSceneSpecName)
                           : scenes::LoadSceneSpec(*spec_path);
    auto t0 = Clock::now();
    scenes::GeneratedScene g = scenes::Generate(spec);
    scenes::WriteGeneratedScene(g, (dir / "scene").string());
    const double t_generate = Seconds(t0);
    const SceneSummary summary = Summarise(g.scene, &g.truth, (dir / "scene/scene.glb").string());
    std::printf("scene: %s, %zu rooms, %zu walls, %zu doors, %zu windows, %zu service "
                "components, %zu triangles (%.2f s)\n",
                spec.name.c_str(), summary.rooms, summary.walls, summary.doors, summary.windows,
                summary.bsc_total, summary.triangles, t_generate);

    t0 = Clock::now();
    const scenes::GroundTruth truth = g.truth;
    sim::EmbreeWorld world(std::move(g.scene), &truth);
    const double t_world = Seconds(t0);

    sim::TlsParams tls = sim::TlsProfile(*profile);
    tls.step_deg = *step;
    ValidateParams(tls, "tls.");
    sim::TlsScanner scanner(world, tls);
    {
      std::ofstream eff(dir / "tls.effective.yaml");
      eff << YAML::Dump(SaveParams(tls)) << "\n";
    }

    // 2. One scan per room at a harness-chosen free spot.
    ReportInput report;
    report.title = "OpenMoPAD run: " + spec.name;
    report.truth = &truth;
    ReportTable scans_table{"Scans",
                            {"scan", "room", "x (m)", "y (m)", "valid points", "time (s)"},
                            {}};
    nlohmann::ordered_json scans_json = nlohmann::json::array();
    std::uint64_t total_points = 0;
    double t_scanning = 0.0;
    for (std::size_t i = 0; i < truth.rooms.size(); ++i) {
      const scenes::Room& room = truth.rooms[i];
      const Eigen::Vector2d xy = FreeSpotInRoom(truth, room);
      sim::ScanRequest req;
      req.seed = *seed;
      req.scan_id = i;
      req.X_WB = Pose2{xy.x(), xy.y(), 0.0}.To3d(room.floor_z);
      t0 = Clock::now();
      sim::TlsTruth scan_truth;
      const interfaces::TlsScan scan = scanner.Scan(req, &scan_truth);
      char name[32];
      std::snprintf(name, sizeof name, "scan_%03zu", i);
      interfaces::WriteTlsScanPly((dir / "scans" / (std::string(name) + ".ply")).string(), scan);
      sim::WriteTlsTruthPly((dir / "scans" / (std::string(name) + ".truth.ply")).string(), scan,
                            scan_truth);
      const double t_scan = Seconds(t0);
      t_scanning += t_scan;

      std::uint64_t valid = 0;
      ReportScan rs;
      rs.name = name;
      const Pose3 X_WS = req.X_WB * scanner.X_BS();
      rs.position = X_WS.translation();
      for (std::size_t k = 0; k < scan.points.size(); ++k) {
        const auto& p = scan.points[k];
        if (!p.valid()) continue;
        ++valid;
        // Plan-view slice for the report: a horizontal band around scanner height.
        if (k % 7 == 0 && std::abs(p.z) < 0.3) {
          const Eigen::Vector3d w = X_WS * Eigen::Vector3d(p.x, p.y, p.z);
          rs.plan_points.emplace_back(static_cast<float>(w.x()), static_cast<float>(w.y()));
        }
      }
      total_points += valid;
      report.scans.push_back(std::move(rs));
      scans_table.rows.push_back({name, room.id, Fixed(xy.x(), 2), Fixed(xy.y(), 2),
                                  std::to_string(valid), Fixed(t_scan, 2)});
      scans_json.push_back({{"scan", name},
                            {"room", room.id},
                            {"X_WB", {xy.x(), xy.y(), room.floor_z, 0.0}},
                            {"pulses", scan.points.size()},
                            {"valid_points", valid},
                            {"seconds", t_scan},
                            {"file", std::string("scans/") + name + ".ply"}});
      std::printf("%s in %s at (%.2f, %.2f): %llu points (%.2f s)\n", name, room.id.c_str(),
                  xy.x(), xy.y(), static_cast<unsigned long long>(valid), t_scan);
    }

    // 3. Summary and report.
    nlohmann::ordered_json j;
    j["job"] = "run";
    j["scene"] = {{"spec", spec_path->empty() ? kDefaultSceneSpecName : *spec_path},
                  {"name", spec.name},
                  {"rooms", summary.rooms},
                  {"walls", summary.walls},
                  {"doors", summary.doors},
                  {"windows", summary.windows},
                  {"service_components", summary.bsc_total},
                  {"triangles", summary.triangles}};
    j["seed"] = *seed;
    j["tls"] = {{"profile", tls.name}, {"step_deg", tls.step_deg}};
    j["scans"] = scans_json;
    j["total_valid_points"] = total_points;
    j["seconds"] = {{"generate", t_generate},
                    {"build_world", t_world},
                    {"scanning", t_scanning},
                    {"total", Seconds(t_start)}};
    std::ofstream(dir / "summary.json") << j.dump(2) << "\n";

    report.subtitle = "Default scene, one simulated " + tls.name + " scan per room at " +
                      Fixed(tls.step_deg, 3) +
                      " deg (harness placement; the autonomous mission replaces it). Seed " +
                      std::to_string(*seed) + ".";
    report.tables.push_back({"Scene",
                             {"item", "count"},
                             {{"rooms", std::to_string(summary.rooms)},
                              {"walls", std::to_string(summary.walls)},
                              {"doors (open / semi-open / closed)",
                               std::to_string(summary.doors) + " (" +
                                   std::to_string(summary.doors_open) + " / " +
                                   std::to_string(summary.doors_semi_open) + " / " +
                                   std::to_string(summary.doors_closed) + ")"},
                              {"windows", std::to_string(summary.windows)},
                              {"service components", std::to_string(summary.bsc_total)},
                              {"furniture", std::to_string(summary.furniture)},
                              {"triangles", std::to_string(summary.triangles)}}});
    ReportTable bsc{"Service components per class", {"class", "N"}, {}};
    for (const auto& [cls, n] : summary.bsc_per_class) bsc.rows.push_back({cls, std::to_string(n)});
    report.tables.push_back(std::move(bsc));
    report.tables.push_back(std::move(scans_table));
    report.tables.push_back({"Timing",
                             {"step", "seconds"},
                             {{"generate scene", Fixed(t_generate, 2)},
                              {"build ray-casting world", Fixed(t_world, 2)},
                              {"scanning + writing", Fixed(t_scanning, 2)},
                              {"total", Fixed(Seconds(t_start), 2)}}});
    WriteHtmlReport(report, (dir / "report.html").string());
    WriteMarkdownReport(report, (dir / "report.md").string());
    std::printf("%zu scans, %llu points in %.1f s; wrote %s/{summary.json,report.html,report.md}\n",
                report.scans.size(), static_cast<unsigned long long>(total_points),
                Seconds(t_start), dir.string().c_str());
  });
}

}  // namespace mopad::tools
