// `mopad dataset RUN_DIR -o DIR [--tolerance M]`: a run's registered scans with per-point
// semantic and instance labels from the truth, their poses, the label tables and the truth, for
// learning and offline methods (evaluation/dataset.h, docs/dataset.md).
#include <cstdio>
#include <memory>
#include <string>

#include "evaluation/dataset.h"
#include "tools/commands.h"

namespace mopad::tools {

void RegisterDatasetCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "dataset",
      "Write a run's scans with per-point semantic and instance labels from the truth, their "
      "poses and the truth, for learning and offline methods (docs/dataset.md)");
  auto run_dir = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto tolerance = std::make_shared<double>(0.05);
  cmd->add_option("RUN_DIR", *run_dir, "A main-job folder (rooms/*/run.json) or a room run")
      ->required();
  cmd->add_option("-o,--output", *out, "Output folder")->required();
  cmd->add_option("--tolerance", *tolerance,
                  "m, (0, 1]: a point is labelled by the truth surface its beam meets within this "
                  "distance of it (default 0.05)");
  cmd->footer("Writes DIR/dataset.json, DIR/scans/<room>/<k>.ply and DIR/truth.json.");
  cmd->callback([=] {
    std::fputs(evaluation::WriteDataset(*run_dir, *out, *tolerance).text.c_str(), stdout);
  });
}

}  // namespace mopad::tools
