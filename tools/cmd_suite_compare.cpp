// `mopad suite compare BASE NEW [-o OUT]`: the change of every figure per scene group between two
// suite folders, against the noise of their seed repetitions (suite/compare.h); prints Markdown,
// writes OUT/compare.md and OUT/compare.json; exit 1 on a regression beyond noise.
// `mopad suite slurm SUITE.yaml -o DIR [--submit]`: writes DIR/submit.sh, a Slurm job array of
// suite shards and a merge job (suite/slurm.h), and submits it when asked.
// docs/suites.md, "Comparing suites" and "Slurm".
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "common/error.h"
#include "common/params.h"
#include "io/text_file.h"
#include "suite/compare.h"
#include "suite/slurm.h"
#include "tools/commands.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;

void RegisterCompare(CLI::App& suite) {
  auto* cmd = suite.add_subcommand(
      "compare", "Compare two suites' figures per scene group, against seed-to-seed noise");
  struct Args {
    std::string base, next, out, config, base_config, new_config;
    suite::CompareParams params;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("BASE", a->base, "The reference suite folder (its suite.json)")->required();
  cmd->add_option("NEW", a->next, "The suite folder to judge (its suite.json)")->required();
  cmd->add_option("-o,--output", a->out, "Also write OUT/compare.md and OUT/compare.json");
  cmd->add_option("--config", a->config, "YAML of comparison parameters (docs/suites.md)");
  auto* alpha = cmd->add_option("--alpha", a->params.alpha,
                                "Significance level of the two-sided U test (default 0.05)");
  auto* min_effect =
      cmd->add_option("--min-effect", a->params.min_relative_effect,
                      "Smallest change that counts, as a fraction of |BASE mean| (default 0.01)");
  auto* figures = cmd->add_option("--figure", a->params.figures,
                                  "Compare only this figure (repeatable; default: all)");
  cmd->add_option("--base-config", a->base_config,
                  "Only BASE's cases of this config, against NEW's of --new-config (BASE and NEW "
                  "may be one folder): their groups meet as <scene>/<base>-><new>");
  cmd->add_option("--new-config", a->new_config, "Only NEW's cases of this config");
  cmd->footer(
      "Exit 0: no regression beyond noise; 1: a figure regressed beyond noise or a case no "
      "longer completes; 2: bad input.");
  cmd->callback([a, alpha, min_effect, figures] {
    suite::CompareParams params;
    if (!a->config.empty()) params = LoadParamsFile<suite::CompareParams>(a->config);
    OverrideIfGiven(alpha, a->params.alpha, params.alpha);
    OverrideIfGiven(min_effect, a->params.min_relative_effect, params.min_relative_effect);
    OverrideIfGiven(figures, a->params.figures, params.figures);
    ValidateParams(params);
    if (a->base_config.empty() != a->new_config.empty())
      throw InputError("--base-config/--new-config", "give both or neither");
    suite::SuiteResults base = suite::ReadSuiteResults(a->base);
    suite::SuiteResults next = suite::ReadSuiteResults(a->next);
    if (!a->base_config.empty()) {
      const std::string label = a->base_config + "->" + a->new_config;
      base = suite::SelectConfig(base, a->base_config, label);
      next = suite::SelectConfig(next, a->new_config, label);
    }
    const suite::Comparison c = suite::CompareSuites(base, next, params);
    const std::string md = suite::CompareMarkdown(c);
    if (!a->out.empty()) {
      std::error_code ec;
      fs::create_directories(a->out, ec);
      if (ec) throw InputError(a->out, "cannot create the output folder", ec.message());
      io::WriteTextFile((fs::path(a->out) / "compare.md").string(), md);
      io::WriteTextFile((fs::path(a->out) / "compare.json").string(),
                        suite::CompareJson(c).dump(2));
    }
    std::fputs(md.c_str(), stdout);
    if (c.Regressed()) throw CLI::RuntimeError(1);
  });
}

void RegisterSlurm(CLI::App& suite) {
  auto* cmd = suite.add_subcommand(
      "slurm", "Write (and submit) a Slurm job array running a suite in shards, then merging");
  struct Args {
    std::string manifest, out, mopad;
    suite::SlurmParams params;
    bool submit = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("SUITE", a->manifest, "The suite manifest (SUITE.yaml)")->required();
  cmd->add_option("-o,--output", a->out, "Folder of the suite: submit.sh, shards/, logs/")
      ->required();
  cmd->add_option("--shards", a->params.shards, "Array tasks, one shard each (default 4)");
  cmd->add_option("--throttle", a->params.throttle, "At most K tasks at once (default: all)");
  cmd->add_option("--cpus-per-task", a->params.cpus_per_task,
                  "CPUs per task, also each shard's --jobs (default 1)");
  cmd->add_option("--partition", a->params.partition, "Slurm partition (default: the cluster's)");
  cmd->add_option("--mopad", a->mopad,
                  "The mopad binary the jobs run (default: this one); a cluster's shared path");
  cmd->add_flag("--submit", a->submit, "Run submit.sh (sbatch) and print the job ids");
  cmd->footer("Writes DIR/submit.sh; the merged suite lands in DIR (docs/suites.md, \"Slurm\").");
  cmd->callback([a] {
    std::error_code ec;
    suite::SlurmJob job;
    job.mopad = a->mopad.empty() ? fs::read_symlink("/proc/self/exe", ec).string()
                                 : fs::absolute(a->mopad).lexically_normal().string();
    if (ec) throw InputError("/proc/self/exe", "cannot find this binary; give --mopad PATH");
    if (!fs::is_regular_file(job.mopad) || access(job.mopad.c_str(), X_OK) != 0)
      throw InputError(job.mopad, "--mopad: not an executable file");
    if (!fs::is_regular_file(a->manifest)) throw InputError(a->manifest, "no such suite manifest");
    job.suite = fs::absolute(a->manifest).lexically_normal().string();
    job.out_dir = fs::absolute(a->out).lexically_normal().string();
    if (!job.out_dir.empty() && job.out_dir.back() == '/') job.out_dir.pop_back();
    job.params = a->params;
    const std::string script = suite::SubmitScript(job);  // validates before writing
    fs::create_directories(job.out_dir, ec);
    if (ec) throw InputError(job.out_dir, "cannot create the output folder", ec.message());
    const std::string path = (fs::path(job.out_dir) / "submit.sh").string();
    io::WriteTextFile(path, script);
    fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add, ec);
    if (!a->submit) {
      std::printf("wrote %s (submit with: bash %s)\n", path.c_str(), path.c_str());
      return;
    }
    const suite::SubmittedJobs jobs = suite::RunSubmitScript(path);
    std::printf("wrote %s\narray job %s (%d shards)\nmerge job %s (after the array)\n",
                path.c_str(), jobs.array_id.c_str(), job.params.shards, jobs.merge_id.c_str());
  });
}

}  // namespace

void RegisterSuiteCompareCommands(CLI::App& suite) {
  RegisterCompare(suite);
  RegisterSlurm(suite);
}

}  // namespace mopad::tools
