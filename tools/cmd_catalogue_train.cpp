// `mopad catalogue train`: trains SM5's colour recogniser from an object-model catalogue alone
// (augmented as scans degrade it) and caches the weights (modelling/components.h).

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "common/params.h"
#include "interfaces/object_model_catalogue.h"
#include "modelling/components.h"
#include "scenes/bsc_catalogue.h"
#include "tools/commands.h"

namespace mopad::tools {

void RegisterCatalogueCommand(CLI::App& app) {
  auto* catalogue =
      app.add_subcommand("catalogue", "Object-model catalogue: train SM5's recogniser");
  catalogue->require_subcommand(1);
  auto* cmd = catalogue->add_subcommand(
      "train",
      "Train the colour recogniser of SM5 from the catalogue's images alone (seeded, "
      "deterministic) and write its weights (OpenCV YAML)");
  auto dir = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto config = std::make_shared<std::string>();
  auto seed = std::make_shared<std::uint64_t>(1);
  auto samples = std::make_shared<int>(0);
  auto paper = std::make_shared<bool>(false);
  cmd->add_option("--catalogue", *dir,
                  "Catalogue folder (mopad scene catalogue); default: the built-in BSC models");
  cmd->add_option("-o,--output", *out, "Weights file to write (.yml)")->required();
  cmd->add_option("--config", *config, "YAML of ComponentTrainingParams");
  auto* seed_opt = cmd->add_option("--seed", *seed, "Augmentation and initialisation seed");
  auto* samples_opt = cmd->add_option("--samples", *samples, "Augmented samples per class")
                          ->check(CLI::Range(1, 100000));
  auto* paper_opt = cmd->add_flag("--paper-pattern", *paper,
                                  "Use the paper's 12-value S, a, b pattern only (no L channel)");
  cmd->callback([=] {
    modelling::ComponentTrainingParams p;
    if (!config->empty()) p = LoadParamsFile<modelling::ComponentTrainingParams>(*config);
    OverrideIfGiven(seed_opt, *seed, p.seed);
    OverrideIfGiven(samples_opt, *samples, p.samples_per_class);
    if (paper_opt->count() > 0) p.lightness = false;
    const interfaces::ObjectModelCatalogue cat =
        dir->empty() ? scenes::MakeObjectModelCatalogue() : interfaces::ReadCatalogue(*dir);
    const auto t0 = std::chrono::steady_clock::now();
    const auto rec = modelling::ComponentRecogniser::Train(cat, p);
    const double t_train =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rec.Save(*out);
    const double acc = rec.Accuracy(50, p.seed + 1000);
    const std::vector<double> per_class = rec.ClassAccuracy(50, p.seed + 1000);
    for (std::size_t k = 0; k < per_class.size(); ++k)
      std::printf("  %-24s %.3f\n",
                  k < cat.models.size() ? cat.models[k].class_name.c_str() : "none", per_class[k]);
    std::printf(
        "trained on %zu classes (%s pattern, %d samples per class) in %.2f s; held-out "
        "accuracy %.4f (look-alike classes count as one); wrote %s\n",
        cat.models.size(), p.lightness ? "S,a,b,L" : "paper S,a,b", p.samples_per_class, t_train,
        acc, out->c_str());
  });
}

}  // namespace mopad::tools
