#pragma once
// `mopad suite slurm SUITE.yaml -o DIR`: a suite on a Slurm cluster (docs/suites.md, "Slurm").
// Writes DIR/submit.sh, which submits
//   - a job array of N tasks (`--array=0-(N-1)%K`, at most K at once): task i runs
//     `mopad suite run SUITE.yaml -o DIR/shards/i --shard (i+1)/N --jobs C` with C CPUs and logs
//     to DIR/logs/<array job>_<i>.out. A shard whose cases ran but did not all pass (exit 1, a
//     verdict) ends the task successfully; bad input (2), an internal error (3) or a signal fail
//     it;
//   - a merge job depending on every task (`--dependency=afterok:<array job>`, cancelled when a
//     task failed) running `mopad suite merge DIR/shards/0 ... DIR/shards/N-1 -o DIR`,
// and prints "array <id>" and "merge <id>" (`sbatch --parsable`). Every path in the script is
// absolute, so it runs from any folder of a machine that sees the same files (a cluster's shared
// filesystem). sbatch takes further options from its SBATCH_* environment (time limit, account).

#include <string>

#include "common/params.h"

namespace mopad::suite {

struct SlurmParams {
  int shards = 4;         ///< array tasks N, each one shard of the suite, [1, 1000]
  int throttle = 0;       ///< at most K tasks at once (`%K`), [0, 1000]; 0: N (no limit)
  int cpus_per_task = 1;  ///< CPUs per task, also the shard's `--jobs`, [1, 1024]
  std::string partition;  ///< Slurm partition (letters, digits, `_.,-`); empty: the default

  template <class V>
  void Visit(V& v) {
    v("shards", shards, Bounds{1, 1000});
    v("throttle", throttle, Bounds{0, 1000});
    v("cpus_per_task", cpus_per_task, Bounds{1, 1024});
    v("partition", partition);
  }
};

/// What the jobs run: absolute paths (the current folder of a job is not the caller's).
struct SlurmJob {
  std::string mopad;    ///< the mopad binary the jobs run
  std::string suite;    ///< the suite manifest (SUITE.yaml)
  std::string out_dir;  ///< DIR: shards/, logs/, submit.sh and the merged suite
  SlurmParams params;
};

/// Checks `job`: InputError naming the option (a relative path, a bound, a partition name with
/// other characters, a throttle above the shard count) before anything is written.
void ValidateSlurmJob(const SlurmJob& job);

/// The text of submit.sh for `job` (validated first). Deterministic: the same job gives the
/// same bytes.
std::string SubmitScript(const SlurmJob& job);

/// `text` quoted for a POSIX shell: inside single quotes, each ' written as '\''.
std::string ShellQuote(const std::string& text);

struct SubmittedJobs {
  std::string array_id;  ///< the job array's id
  std::string merge_id;  ///< the merge job's id
};

/// Runs `bash script` (a submit.sh written by SubmitScript) and reads the job ids it prints.
/// InputError when sbatch is not on the PATH, or the script fails (sbatch's own message is on
/// stderr) or prints no ids.
SubmittedJobs RunSubmitScript(const std::string& script);

}  // namespace mopad::suite
