#include "exports/exports.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/format.h"
#include "exports/gltf_export.h"
#include "io/text_file.h"

namespace mopad::exports {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

bool Has(const std::vector<ExportKind>& kinds, ExportKind k) {
  return std::find(kinds.begin(), kinds.end(), k) != kinds.end();
}

Json IfcCountsJson(const IfcCounts& c) {
  Json j{{"IfcSpace", c.spaces},       {"IfcWall", c.walls},     {"IfcSlab", c.slabs},
         {"IfcCovering", c.coverings}, {"IfcColumn", c.columns}, {"IfcOpeningElement", c.openings},
         {"IfcDoor", c.doors},         {"IfcWindow", c.windows}};
  for (const auto& [entity, n] : c.components) j[entity] = n;
  return j;
}

Json LasJson(const LasExportSummary& s) {
  Json hist = Json::object();
  for (int code = kLasCodeFirst; code <= kLasCodeLast; ++code)
    hist[std::to_string(code) + " " + ToString(static_cast<LasCode>(code))] = s.histogram[code];
  return {{"points", s.points},
          {"rooms", s.rooms},
          {"min", {s.min.x(), s.min.y(), s.min.z()}},
          {"max", {s.max.x(), s.max.y(), s.max.z()}},
          {"classification", hist}};
}

}  // namespace

ExportResult WriteExports(const std::string& run_dir, const std::vector<ExportKind>& kinds,
                          const ExportParams& params) {
  const RunFolder run = ReadRunFolder(run_dir);
  const BuildingModel model = BuildBuildingModel(run);
  ExportResult result;
  const fs::path out = fs::path(run_dir) / "export";
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string(), "cannot create the folder", ec.message());
  result.dir = out.string();
  Json j;
  j["format"] = "mopad-export";
  j["version"] = 1;
  j["frame"] = model.frame_note;
  j["rooms"] = Json::array();
  for (const auto& r : run.rooms) j["rooms"].push_back(r.id);
  j["floor_model"] = run.floor.has_value();
  if (Has(kinds, ExportKind::kIfc)) {
    IfcCounts counts;
    io::WriteTextFile((out / "model.ifc").string(), IfcText(model, params.ifc, &counts));
    result.files.push_back((out / "model.ifc").string());
    j["model.ifc"] = IfcCountsJson(counts);
    result.summary += FormatNumbers("model.ifc: %.0f walls, %.0f slabs, %.0f coverings, ",
                                    counts.walls, counts.slabs, counts.coverings) +
                      FormatNumbers("%.0f columns, %.0f doors, %.0f windows, %.0f spaces\n",
                                    counts.columns, counts.doors, counts.windows, counts.spaces);
  }
  if (Has(kinds, ExportKind::kGltf)) {
    const int nodes = WriteSemanticGlb(model, (out / "model.glb").string());
    result.files.push_back((out / "model.glb").string());
    j["model.glb"] = {{"element_nodes", nodes}};
    result.summary += FormatNumbers("model.glb: %.0f element nodes\n", nodes);
  }
  if (Has(kinds, ExportKind::kLas)) {
    const LasExportSummary s = WriteSm1Las(run, (out / "sm1.las").string(), params.las);
    result.files.push_back((out / "sm1.las").string());
    j["sm1.las"] = LasJson(s);
    result.summary += FormatNumbers("sm1.las: %.0f points from %.0f rooms\n",
                                    static_cast<double>(s.points), s.rooms);
  }
  io::WriteTextFile((out / "export.json").string(), j.dump(1) + "\n");
  result.files.push_back((out / "export.json").string());
  return result;
}

ExportResult WriteAllExports(const std::string& run_dir) {
  std::vector<ExportKind> kinds = {ExportKind::kIfc, ExportKind::kGltf};
  const RunFolder run = ReadRunFolder(run_dir);
  bool any_sm1 = false;
  for (const auto& r : run.rooms) any_sm1 = any_sm1 || !r.sm1_path.empty();
  if (any_sm1) kinds.push_back(ExportKind::kLas);
  ExportResult result = WriteExports(run_dir, kinds);
  if (!any_sm1) result.summary += "sm1.las: not written (no room has an sm1.ply)\n";
  return result;
}

}  // namespace mopad::exports
