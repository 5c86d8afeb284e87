// `mopad scene ...`: generate, random, info, import, plan, validate, catalogue.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/params.h"
#include "interfaces/object_model_catalogue.h"
#include "scenes/bim_import.h"
#include "scenes/bsc_catalogue.h"
#include "scenes/door_angles.h"
#include "scenes/generator.h"
#include "scenes/gltf_writer.h"
#include "scenes/ground_truth.h"
#include "scenes/plan_view.h"
#include "scenes/random_floor.h"
#include "scenes/scene_check.h"
#include "scenes/scene_loader.h"
#include "scenes/scene_paths.h"
#include "scenes/scene_spec.h"
#include "tools/commands.h"
#include "scenes/scene_summary.h"

namespace mopad::tools {
namespace {

std::string FormatMetres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f", v);
  return buf;
}

void PrintSummary(const scenes::SceneSummary& s) { std::printf("%s\n", scenes::FormatSceneSummary(s).c_str()); }

void GenerateAndWrite(const scenes::SceneSpec& spec, const std::string& out_dir) {
  const scenes::GeneratedScene g = scenes::Generate(spec);
  scenes::WriteGeneratedScene(g, out_dir);
  PrintSummary(scenes::Summarise(g.scene, &g.truth, out_dir + "/scene.glb"));
  std::printf("wrote %s/scene.glb and %s/scene.truth.json\n", out_dir.c_str(), out_dir.c_str());
}

// `scene generate SPEC -o DIR`: a scene folder from a YAML spec.
void AddGenerateCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("generate",
                                    "Generate scene.glb + scene.truth.json from a "
                                    "YAML spec (docs/scene-spec.md)");
  auto spec = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto seed = std::make_shared<std::int64_t>(-1);
  cmd->add_option("spec", *spec, "Scene spec YAML (e.g. scenes/office_5rooms.yaml)")->required();
  cmd->add_option("-o,--output", *out, "Output folder")->required();
  cmd->add_option("--seed", *seed, "Override the spec's seed (furniture, rule-based BSCs)")
      ->check(CLI::NonNegativeNumber);
  cmd->footer(
      "Writes DIR/scene.glb and DIR/scene.truth.json (docs/scene-format.md), and the spec it used, "
      "spec.effective.yaml.");
  cmd->callback([=] {
    scenes::SceneSpec s = scenes::LoadSceneSpec(*spec);
    if (*seed >= 0) s.seed = static_cast<std::uint64_t>(*seed);
    GenerateAndWrite(s, *out);
  });
}

// `scene random --seed S -o DIR`: a random connected office floor.
void AddRandomCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("random", "Generate a random connected office floor");
  auto out = std::make_shared<std::string>();
  auto seed = std::make_shared<std::uint64_t>(1);
  auto rooms = std::make_shared<int>(5);
  auto family = std::make_shared<std::string>("office");
  cmd->add_option("--seed", *seed, "Seed of the layout")->required();
  cmd->add_option("--rooms", *rooms, "Number of rooms, 2-10 (2-40 for the office family)")->default_val(5);
  cmd->add_option("--family", *family,
                  "Layout family: office, corridor (one long corridor), junction (L or T "
                  "corridors), hall (a high hall with a column grid) or mixed (drawn from the seed)")
      ->default_val("office");
  cmd->add_option("-o,--output", *out, "Output folder")->required();
  cmd->footer(
      "Writes DIR/scene.glb and DIR/scene.truth.json (docs/scene-format.md), and the spec it used, "
      "spec.effective.yaml.");
  cmd->callback([=] {
    const scenes::FloorFamily f = scenes::ParseFloorFamily(*family);
    GenerateAndWrite(scenes::RandomFloorSpec(*seed, *rooms, f), *out);
  });
}

// `scene info SCENE`: counts, bounds and rooms of a scene folder or file.
void AddInfoCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("info", "Counts per class, bounding box, triangles, rooms");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("scene", *path,
                  "Scene folder (scene.glb + scene.truth.json) or file (.glb, "
                  ".gltf, .obj, .ply, .fbx, .ifc)")
      ->required();
  cmd->add_flag("--json", *json, "Print JSON instead of a table");
  cmd->callback([=] {
    const scenes::ScenePaths p = scenes::ResolveScene(*path);
    const scenes::Scene sc = scenes::LoadScene(p.geometry);
    std::optional<scenes::GroundTruth> truth;
    if (p.truth) truth = scenes::ReadGroundTruth(*p.truth);
    const scenes::SceneSummary s = scenes::Summarise(sc, truth ? &*truth : nullptr, p.geometry);
    if (*json) {
      std::printf("%s\n", scenes::SceneSummaryJson(s).c_str());
      return;
    }
    PrintSummary(s);
    if (std::filesystem::path(p.geometry).extension() == ".ifc")
      for (const scenes::BimStorey& st : scenes::ListIfcStoreys(p.geometry))
        std::printf("storey '%s' (%s): elevation %s\n", st.name.c_str(), st.global_id.c_str(),
                    st.has_elevation ? (FormatMetres(st.elevation) + " m").c_str() : "not given");
  });
}

// `scene import MODEL -o DIR`: a scene folder with exact truth from a BIM model.
void AddImportCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("import",
                                    "Make a scene folder with exact truth from a BIM "
                                    "model (IFC 2x3 or IFC4, docs/scene-import.md)");
  auto path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto doors = std::make_shared<std::vector<std::string>>();
  auto config = std::make_shared<std::string>();
  // The flags' values; a flag overrides the config only when given (OverrideIfGiven).
  auto flags = std::make_shared<scenes::BimImportParams>();
  cmd->add_option("model", *path,
                  "IFC 2x3 or IFC4 file (or glTF converted from IFC with its spaces)")
      ->required();
  cmd->add_option("-o,--output", *out, "Output folder")->required();
  cmd->add_option("--config", *config,
                  "YAML of BimImportParams (docs/scene-import.md); flags given override it");
  auto* storey = cmd->add_option("--storey", flags->storey,
                                 "Storey Name, node name or GlobalId (default: lowest)");
  auto* angle = cmd->add_option("--door-angle", flags->door_angle_deg,
                                "Opening angle of every door, deg [0, 180]")
                    ->capture_default_str();
  auto* doors_opt =
      cmd->add_option("--doors", *doors, "Per-door angles ID=DEG (ID: D1, GlobalId or IFC Name)")
          ->delimiter(',')
          ->excludes(angle);
  auto* floor = cmd->add_flag("--floor-from-spaces", flags->floor_from_spaces,
                              "Make missing floors from the space footprints");
  auto* ceiling = cmd->add_flag("--ceiling-from-spaces", flags->ceiling_from_spaces,
                                "Make missing ceilings from the space footprints");
  auto* repair = cmd->add_flag("--repair", flags->repair,
                               "Apply every repair the file needs, one line each (without it, "
                               "the import lists them all and exits 2)");
  auto* merge = cmd->add_option("--merge", flags->merge,
                                "Further model whose components are added (repeatable)");
  auto* site = cmd->add_flag("--keep-site", flags->keep_site, "Keep the IfcSite terrain geometry");
  auto* tolerance =
      cmd->add_option("--plane-tolerance", flags->plane_tolerance,
                      "Largest distance of a wall/floor/ceiling face from the space boundary, m")
          ->capture_default_str();
  cmd->footer("Writes DIR/scene.glb and DIR/scene.truth.json (docs/scene-format.md).");
  cmd->callback([=] {
    scenes::BimImportParams params;
    if (!config->empty()) params = LoadParamsFile<scenes::BimImportParams>(*config);
    OverrideIfGiven(storey, flags->storey, params.storey);
    OverrideIfGiven(angle, flags->door_angle_deg, params.door_angle_deg);
    if (doors_opt->count() > 0) params.door_angles_deg = scenes::ParseDoorAngles(*doors, "--doors");
    OverrideIfGiven(floor, flags->floor_from_spaces, params.floor_from_spaces);
    OverrideIfGiven(ceiling, flags->ceiling_from_spaces, params.ceiling_from_spaces);
    OverrideIfGiven(repair, flags->repair, params.repair);
    OverrideIfGiven(merge, flags->merge, params.merge);
    OverrideIfGiven(site, flags->keep_site, params.keep_site);
    OverrideIfGiven(tolerance, flags->plane_tolerance, params.plane_tolerance);
    scenes::BimImport imported;
    try {
      imported = scenes::ImportBim(*path, params);
    } catch (const scenes::BimRepairsNeeded& e) {
      // Every repair in one run; then the one error line (exit 2).
      for (const auto& line : e.repairs) std::printf("needs %s\n", line.c_str());
      std::fflush(stdout);
      throw;
    }
    scenes::WriteBimImport(imported, *out);
    for (const auto& line : imported.report) std::printf("%s\n", line.c_str());
    for (const auto& line : imported.repairs) std::printf("%s\n", line.c_str());
    PrintSummary(scenes::Summarise(imported.scene, &imported.truth, *out + "/scene.glb"));
    std::printf("wrote %s/scene.glb and %s/scene.truth.json\n", out->c_str(), out->c_str());
  });
}

// `scene plan DIR -o PNG`: a plan view of a scene folder and its truth.
void AddPlanCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("plan",
                                    "Draw a plan-view PNG of a scene folder and its "
                                    "truth (walls red, doors green, windows blue)");
  auto path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto config = std::make_shared<std::string>();
  auto flags = std::make_shared<scenes::PlanViewParams>();  // the flags' values
  cmd->add_option("scene", *path, "Scene folder with scene.glb and scene.truth.json")->required();
  cmd->add_option("-o,--output", *out, "PNG file to write")->required();
  cmd->add_option("--config", *config,
                  "YAML of PlanViewParams (docs/scene-import.md); flags given override it");
  auto* pixel =
      cmd->add_option("--pixel-size", flags->pixel_size, "Metres per pixel")->capture_default_str();
  auto* cut =
      cmd->add_option("--cut-height", flags->cut_height, "Section height above the floor, m")
          ->capture_default_str();
  cmd->callback([=] {
    scenes::PlanViewParams p;
    if (!config->empty()) p = LoadParamsFile<scenes::PlanViewParams>(*config);
    OverrideIfGiven(pixel, flags->pixel_size, p.pixel_size);
    OverrideIfGiven(cut, flags->cut_height, p.cut_height);
    const scenes::ScenePaths sp = scenes::ResolveScene(*path);
    if (!sp.truth)
      throw InputError(*path, "no ground truth next to the scene", "",
                       "scene.truth.json beside scene.glb");
    const scenes::Texture t = scenes::RenderPlanView(scenes::LoadScene(sp.geometry),
                                                     scenes::ReadGroundTruth(*sp.truth), p);
    const std::vector<std::uint8_t> png = scenes::EncodePng(t);
    WriteWholeFile(*out, std::string(png.begin(), png.end()));
    std::printf("wrote %s (%d x %d)\n", out->c_str(), t.width, t.height);
  });
}

// `scene validate DIR`: the truth checked against the geometry.
void AddValidateCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("validate",
                                    "Check a generated scene's truth against its "
                                    "geometry (exit 1 if it finds errors)");
  auto path = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "Scene folder with scene.glb and scene.truth.json")->required();
  cmd->callback([=] {
    const scenes::ScenePaths p = scenes::ResolveScene(*path);
    if (!p.truth)
      throw InputError(*path, "no ground truth next to the scene", "",
                       "scene.truth.json beside scene.glb");
    const scenes::Scene sc = scenes::LoadScene(p.geometry);
    const scenes::GroundTruth truth = scenes::ReadGroundTruth(*p.truth);
    const scenes::CheckReport report = scenes::CheckScene(sc, truth);
    for (const auto& w : report.warnings) std::printf("warning: %s\n", w.c_str());
    for (const auto& e : report.errors) std::printf("error: %s\n", e.c_str());
    std::printf("%s: %zu errors, %zu warnings\n", p.geometry.c_str(), report.errors.size(),
                report.warnings.size());
    if (!report.errors.empty()) throw CLI::RuntimeError(1);
  });
}

// `scene catalogue -o DIR`: the BSC object-model catalogue.
void AddCatalogueCommand(CLI::App* scene) {
  auto* cmd = scene->add_subcommand("catalogue",
                                    "Write the BSC object-model catalogue (sizes, "
                                    "colour and depth images): what a robot may "
                                    "know, never where objects are");
  auto out = std::make_shared<std::string>();
  auto pixel = std::make_shared<double>(0.002);
  cmd->add_option("-o,--output", *out, "Output folder")->required();
  cmd->add_option("--pixel-size", *pixel, "Metres per image pixel")
      ->check(CLI::Range(0.0002, 0.05))
      ->default_val(0.002);
  cmd->footer("Writes DIR/catalogue.yaml and per model <class>_colour.ppm and <class>_depth.pfm.");
  cmd->callback([=] {
    const auto catalogue = scenes::MakeObjectModelCatalogue(*pixel);
    interfaces::WriteCatalogue(catalogue, *out);
    std::printf("wrote %zu object models to %s/catalogue.yaml\n", catalogue.models.size(),
                out->c_str());
  });
}

}  // namespace

void RegisterSceneCommands(CLI::App& app) {
  auto* scene = app.add_subcommand("scene", "Generate, inspect and validate scenes");
  scene->require_subcommand(1);
  AddGenerateCommand(scene);
  AddRandomCommand(scene);
  AddInfoCommand(scene);
  AddImportCommand(scene);
  AddPlanCommand(scene);
  AddValidateCommand(scene);
  AddCatalogueCommand(scene);
}

}  // namespace mopad::tools
