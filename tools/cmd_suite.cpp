// `mopad suite run|merge` (docs/suites.md): CI scene suites, each case a `mopad run` of this
// binary in its own process.
#include <unistd.h>

#include <filesystem>

#include "common/error.h"
#include "runfolder/keep.h"
#include "suite/manifest.h"
#include "suite/merge.h"
#include "suite/runner.h"
#include "tools/commands.h"

namespace mopad::tools {
namespace {

namespace fs = std::filesystem;

struct SuiteRunArgs {
  std::string manifest, out, shard = "1/1", keep;
  int jobs = 1;
  bool resume = false, quiet = false;
};

void AddRun(CLI::App* suite) {
  auto a = std::make_shared<SuiteRunArgs>();
  auto* cmd = suite->add_subcommand(
      "run", "Run a suite manifest: every case a `mopad run` in its own process and folder");
  cmd->add_option("manifest", a->manifest, "Suite manifest YAML (e.g. suites/smoke.yaml)")
      ->required();
  cmd->add_option("-o,--output", a->out, "Suite folder")->required();
  cmd->add_option("--jobs", a->jobs, "Cases at a time (the results do not depend on it)")
      ->check(CLI::Range(1, 256))
      ->default_val(1);
  cmd->add_option("--shard", a->shard,
                  "Run shard I of N (case k belongs to shard k mod N + 1); join with `suite merge`")
      ->default_val("1/1");
  cmd->add_flag("--resume", a->resume,
                "Finish the suite in the output folder: finished cases are kept, the others run");
  cmd->add_option("--keep", a->keep,
                  "What each case folder keeps: summary, models or all (default: the manifest's "
                  "keep:, else summary)")
      ->check(CLI::IsMember({"summary", "models", "all"}));
  cmd->add_flag("-q,--quiet", a->quiet, "No per-case lines");
  cmd->footer(
      "Writes DIR/suite.json, junit.xml, scoreboard.md, scoreboard.html and DIR/cases/<id>/ "
      "(the run folder, case.json, the case's stdout and stderr). Exit code 0 when every case "
      "passed and every pooled check holds, 1 otherwise, 2 for bad input.");
  cmd->callback([a] {
    const suite::Manifest m = suite::LoadManifest(a->manifest);
    suite::RunOptions o;
    o.out_dir = a->out;
    o.jobs = a->jobs;
    o.shard = suite::ParseShard(a->shard);
    o.resume = a->resume;
    o.keep = a->keep;
    o.quiet = a->quiet;
    o.progress = isatty(fileno(stdout)) != 0 && !a->quiet;
    o.program = fs::read_symlink("/proc/self/exe").string();
    const int code = suite::RunSuite(m, o);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

void AddMerge(CLI::App* suite) {
  auto dirs = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  auto* cmd = suite->add_subcommand(
      "merge", "Join suite folders of one manifest (shards) into one suite folder");
  cmd->add_option("dirs", *dirs, "Suite folders (each from `mopad suite run --shard`)")
      ->required();
  cmd->add_option("-o,--output", *out, "The joined suite folder")->required();
  cmd->add_flag("-q,--quiet", *quiet, "No summary line");
  cmd->callback([dirs, out, quiet] {
    const int code = suite::MergeSuites(*dirs, *out, *quiet);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace

void RegisterSuiteCommands(CLI::App& app) {
  auto* suite = app.add_subcommand("suite", "CI scene suites: many missions, one verdict");
  suite->require_subcommand(1);
  AddRun(suite);
  AddMerge(suite);
  RegisterSuiteCompareCommands(*suite);
}

}  // namespace mopad::tools
