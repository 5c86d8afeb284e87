#pragma once
// The deliverables of a run folder (docs/exports.md), written to DIR/export/:
//   model.ifc    IFC4 of the robot's model (ifc_export.h)
//   model.glb    semantic glTF, one node per element (gltf_export.h)
//   sm1.las      the SM1 clouds as LAS 1.4 point format 7 (las_export.h)
//   export.json  what was written: the export frame, per-class counts, the LAS histogram
// Robot side: reads only the run's model files (run_folder.h), links modelling and io.
// Same run folder, same bytes (no paths, times or wall clock in any file).

#include <string>
#include <vector>

#include "exports/ifc_export.h"
#include "exports/las_export.h"

namespace mopad::exports {

enum class ExportKind { kIfc, kGltf, kLas };

struct ExportParams {
  IfcExportParams ifc;
  LasExportParams las;

  template <class V>
  void Visit(V& v) {
    v("ifc", ifc);
    v("las", las);
  }
};

struct ExportResult {
  std::string dir;                 ///< DIR/export
  std::vector<std::string> files;  ///< written, in order (export.json last)
  std::string summary;             ///< a few lines for the console
};

/// Writes the selected exports of the run folder `run_dir` into run_dir/export/ (created) plus
/// export.json. InputError for a folder without models, a malformed model file, LAS asked for
/// and no sm1.ply, or a file that cannot be written.
ExportResult WriteExports(const std::string& run_dir, const std::vector<ExportKind>& kinds,
                          const ExportParams& params = {});

/// Every export: model.ifc, model.glb, and sm1.las when some room has an sm1.ply (else left out
/// and said in the summary). The one call for the main job, after its rooms are written.
ExportResult WriteAllExports(const std::string& run_dir);

}  // namespace mopad::exports
