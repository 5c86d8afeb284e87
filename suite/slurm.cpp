#include "suite/slurm.h"

#include <sys/wait.h>

#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <utility>

#include "common/error.h"

namespace mopad::suite {
namespace {

namespace fs = std::filesystem;

bool OnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    std::error_code ec;
    if (!dir.empty() && fs::is_regular_file(fs::path(dir) / program, ec)) return true;
  }
  return false;
}

// The job array's task: shard i + 1 of N into DIR/shards/i (a quoted here-document: the shell
// that runs submit.sh expands nothing in it; the task's shell expands $i).
std::string TaskScript(const SlurmJob& job) {
  const SlurmParams& p = job.params;
  const std::string shards = ShellQuote((fs::path(job.out_dir) / "shards").string() + "/");
  return "#!/usr/bin/env bash\n"
         "i=${SLURM_ARRAY_TASK_ID:?not a task of a Slurm job array}\n"
         "rc=0\n" +
         ShellQuote(job.mopad) + " suite run " + ShellQuote(job.suite) + " -o " + shards +
         "\"$i\" --shard \"$((i + 1))/" + std::to_string(p.shards) + "\" --jobs " +
         std::to_string(p.cpus_per_task) +
         " || rc=$?\n"
         "# 1: the shard ran and a case did not pass, a verdict the merged suite reports\n"
         "[ \"$rc\" -eq 1 ] && rc=0\n"
         "exit \"$rc\"\n";
}

std::string MergeScript(const SlurmJob& job) {
  std::string cmd = "#!/usr/bin/env bash\nexec " + ShellQuote(job.mopad) + " suite merge";
  for (int i = 0; i < job.params.shards; ++i) {
    cmd += ' ';
    cmd += ShellQuote((fs::path(job.out_dir) / "shards" / std::to_string(i)).string());
  }
  return cmd + " -o " + ShellQuote(job.out_dir) + "\n";
}

}  // namespace

std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void ValidateSlurmJob(const SlurmJob& job) {
  const SlurmParams& p = job.params;
  for (const auto& [option, path] :
       {std::pair<std::string, std::string>{"the mopad binary", job.mopad},
        {"SUITE.yaml", job.suite},
        {"-o", job.out_dir}})
    if (!fs::path(path).is_absolute())
      throw InputError("mopad suite slurm", option + ": not an absolute path", path);
  ValidateParams(p);
  if (p.throttle > p.shards)
    throw InputError("mopad suite slurm", "--throttle above --shards", std::to_string(p.throttle),
                     "at most " + std::to_string(p.shards) + ", or 0 for no limit");
  for (const char c : p.partition)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == ',' ||
          c == '-'))
      throw InputError("mopad suite slurm", "--partition: not a partition name",
                       "'" + p.partition + "'", "letters, digits and _ . , -");
}

std::string SubmitScript(const SlurmJob& job) {
  ValidateSlurmJob(job);
  const SlurmParams& p = job.params;
  const fs::path out(job.out_dir);
  const std::string name = "mopad-suite-" + fs::path(job.suite).stem().string();
  const std::string partition = p.partition.empty() ? "" : " --partition=" + p.partition;
  const int throttle = p.throttle == 0 ? p.shards : p.throttle;
  std::string s =
      "#!/usr/bin/env bash\n"
      "# Submits suite " +
      job.suite + " to Slurm as " + std::to_string(p.shards) + " shards (at most " +
      std::to_string(throttle) + " at once) and a merge job into " + job.out_dir +
      ".\n"
      "# Written by `mopad suite slurm` (docs/suites.md, \"Slurm\"); prints the job ids.\n"
      "set -euo pipefail\n"
      "mkdir -p " +
      ShellQuote((out / "logs").string()) + " " + ShellQuote((out / "shards").string()) + "\n";
  s += "array_id=$(sbatch --parsable --job-name=" + ShellQuote(name) + " --array=0-" +
       std::to_string(p.shards - 1) + "%" + std::to_string(throttle) +
       " --cpus-per-task=" + std::to_string(p.cpus_per_task) + partition +
       " --output=" + ShellQuote((out / "logs" / "%A_%a.out").string()) + " <<'MOPAD_TASK'\n" +
       TaskScript(job) +
       "MOPAD_TASK\n)\n"
       "array_id=${array_id%%;*}  # --parsable prints id;cluster on federated clusters\n";
  s += "merge_id=$(sbatch --parsable --job-name=" + ShellQuote(name + "-merge") +
       " --dependency=afterok:\"$array_id\" --kill-on-invalid-dep=yes" + partition +
       " --output=" + ShellQuote((out / "logs" / "%j_merge.out").string()) + " <<'MOPAD_MERGE'\n" +
       MergeScript(job) +
       "MOPAD_MERGE\n)\n"
       "merge_id=${merge_id%%;*}\n"
       "echo \"array $array_id\"\n"
       "echo \"merge $merge_id\"\n";
  return s;
}

SubmittedJobs RunSubmitScript(const std::string& script) {
  if (!OnPath("sbatch"))
    throw InputError("mopad suite slurm", "--submit: sbatch not found on the PATH", "",
                     "a Slurm client (scripts/slurm-local.sh starts a local Slurm)");
  FILE* pipe = popen(("bash " + ShellQuote(script)).c_str(), "r");
  if (!pipe) throw InputError(script, "cannot run the script");
  std::string output;
  std::array<char, 256> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) output += buf.data();
  const int status = pclose(pipe);
  if (status != 0)
    throw InputError(script, "submission failed (sbatch's message is above)",
                     "exit " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : status));
  SubmittedJobs jobs;
  std::istringstream lines(output);
  std::string key, id;
  while (lines >> key >> id) {
    if (key == "array") jobs.array_id = id;
    if (key == "merge") jobs.merge_id = id;
  }
  if (jobs.array_id.empty() || jobs.merge_id.empty())
    throw InputError(script, "no job ids in the script's output", output,
                     "'array ID' and 'merge ID' lines");
  return jobs;
}

}  // namespace mopad::suite
