// `mopad export ifc|las|gltf|all RUN_DIR`: the deliverables of a run folder (docs/exports.md),
// written to RUN_DIR/export/ by exports::WriteExports.
#include <cstdio>
#include <memory>
#include <string>

#include "exports/exports.h"
#include "tools/commands.h"

namespace mopad::tools {

void RegisterExportCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "export",
      "Write a run's deliverables to RUN_DIR/export/: model.ifc (IFC4), model.glb (semantic "
      "glTF), sm1.las (LAS 1.4, point format 7) and export.json (what was written)");
  auto what = std::make_shared<std::string>();
  auto run_dir = std::make_shared<std::string>();
  cmd->add_option("WHAT", *what,
                  "ifc (model.ifc), gltf (model.glb), las (sm1.las) or all (the three; sm1.las "
                  "only when a room has sm1.ply); export.json is always written")
      ->required()
      ->check(CLI::IsMember({"ifc", "gltf", "las", "all"}));
  cmd->add_option("RUN_DIR", *run_dir,
                  "A main-job folder (rooms/<ID>/sm3.json, optional floor/) or a room folder")
      ->required();
  cmd->callback([=] {
    exports::ExportResult r;
    if (*what == "all") {
      r = exports::WriteAllExports(*run_dir);
    } else {
      const exports::ExportKind kind = *what == "ifc"    ? exports::ExportKind::kIfc
                                       : *what == "gltf" ? exports::ExportKind::kGltf
                                                         : exports::ExportKind::kLas;
      r = exports::WriteExports(*run_dir, {kind});
    }
    std::fputs(r.summary.c_str(), stdout);
    for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
  });
}

}  // namespace mopad::tools
