#include "suite/runner.h"

#include <signal.h>
#include <string.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/format.h"
#include "io/text_file.h"
#include "suite/figures.h"
#include "suite/outputs.h"

namespace mopad::suite {

namespace fs = std::filesystem;

namespace {

std::atomic<int> g_stop_signal{0};
extern "C" void OnSuiteStop(int sig) { g_stop_signal = sig; }

std::string SceneDir(const std::string& out, const SceneEntry& s) {
  return (fs::path(out) / "scenes" / s.name).string();
}

// Makes a random floor or a BIM import into DIR/scenes/<name> (once per suite folder). Returns
// "" or the reason it failed (the last line of the command's stderr).
std::string PrepareScene(const SceneEntry& s, const RunOptions& o, const Limits& limits) {
  const std::string dir = SceneDir(o.out_dir, s);
  if (fs::is_regular_file(fs::path(dir) / "scene.truth.json")) return "";
  fs::remove_all(dir);
  fs::create_directories(fs::path(dir).parent_path());
  ProcessSpec p;
  p.argv = {o.program, "scene"};
  if (s.kind == SceneEntry::Kind::kRandom) {
    p.argv.insert(p.argv.end(), {"random", "--seed", std::to_string(s.random_seed), "--rooms",
                                 std::to_string(s.random_rooms), "--family", s.random_family,
                                 "-o", dir});
  } else {
    p.argv.insert(p.argv.end(), {"import", s.path, "-o", dir});
    if (!s.storey.empty()) p.argv.insert(p.argv.end(), {"--storey", s.storey});
    p.argv.insert(p.argv.end(), s.args.begin(), s.args.end());
  }
  p.stdout_path = dir + ".log";
  p.stderr_path = dir + ".err";
  p.wall_limit_s = limits.wall_s;
  p.memory_limit_mb = limits.memory_mb;
  ProcessPool pool;
  pool.Start(0, p);
  std::vector<std::pair<int, ProcessOutcome>> done;
  while (done.empty()) done = pool.Wait(1.0);
  const ProcessOutcome& r = done[0].second;
  if (r.end == ProcessOutcome::End::kExited && r.exit_code == 0 &&
      fs::is_regular_file(fs::path(dir) / "scene.truth.json"))
    return "";
  const std::string last = LastLine(p.stderr_path);
  return "scene " + s.name + " could not be made: " + (last.empty() ? "no message" : last);
}

std::string TruthPath(const SceneEntry& s, const std::string& case_dir, const std::string& out) {
  switch (s.kind) {
    case SceneEntry::Kind::kSpec: return (fs::path(case_dir) / "scene" / "scene.truth.json").string();
    case SceneEntry::Kind::kFolder: return (fs::path(s.path) / "scene.truth.json").string();
    default: return (fs::path(SceneDir(out, s)) / "scene.truth.json").string();
  }
}

CaseResult Skeleton(const Manifest& m, const Case& c) {
  CaseResult r;
  r.id = c.id;
  r.group = c.group;
  r.scene = m.scenes[c.scene].name;
  r.seed = c.seed;
  r.config = c.config;
  r.sweep = c.sweep;
  r.dir = "cases/" + c.id;
  return r;
}

// The progress line (a terminal only): done / running / not passed, elapsed, estimate.
void Progress(bool on, std::size_t done, std::size_t total, std::size_t running,
              std::size_t bad, double elapsed, double case_s_sum, std::size_t measured, int jobs) {
  if (!on) return;
  std::string est = "-";
  if (measured > 0) {
    const double left = (case_s_sum / measured) * static_cast<double>(total - done) /
                        std::max(1, jobs);
    est = FormatFixed(left, 0) + " s";
  }
  std::fprintf(stdout, "\r\033[K[%s s] %zu/%zu done, %zu running, %zu not passed, about %s left",
               FormatFixed(elapsed, 0).c_str(), done, total, running, bad, est.c_str());
  std::fflush(stdout);
}

}  // namespace

std::uint64_t FolderBytes(const std::string& dir) {
  std::uint64_t n = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec))
    if (it->is_regular_file(ec)) n += it->file_size(ec);
  return n;
}

std::vector<std::string> RunArgs(const Manifest& m, const Case& c, const std::string& case_dir,
                                 const std::string& scene_dir, const std::string& keep,
                                 bool has_config) {
  const SceneEntry& s = m.scenes[c.scene];
  std::vector<std::string> a = {"run", "-q", "--seed", std::to_string(c.seed), "-o", case_dir,
                                "--keep", keep};
  if (s.kind == SceneEntry::Kind::kSpec) a.insert(a.end(), {"--spec", s.path});
  else if (s.kind == SceneEntry::Kind::kFolder) a.insert(a.end(), {"--scene", s.path});
  else a.insert(a.end(), {"--scene", scene_dir});
  if (has_config) a.insert(a.end(), {"--config", (fs::path(case_dir) / "suite.config.yaml").string()});
  a.insert(a.end(), m.run_args.begin(), m.run_args.end());
  return a;
}

CaseResult Classify(const Manifest& m, const Case& c, const ProcessOutcome& outcome,
                    const std::string& case_dir, const std::string& truth_path,
                    const std::string& stderr_last_line) {
  CaseResult r = Skeleton(m, c);
  r.wall_s = outcome.wall_s;
  r.peak_rss_mb = outcome.peak_rss_mb;
  const std::string said = stderr_last_line.empty() ? "no message on stderr" : stderr_last_line;
  switch (outcome.end) {
    case ProcessOutcome::End::kTimedOut:
      r.verdict = "timeout";
      r.message = "over the wall-time limit of " + FormatShortest(c.limits.wall_s) + " s; killed";
      break;
    case ProcessOutcome::End::kOverMemory:
      r.verdict = "crashed";
      r.message = "killed by the runner: resident memory over the limit of " +
                  FormatShortest(c.limits.memory_mb) + " MB";
      break;
    case ProcessOutcome::End::kSignalled:
      r.verdict = "crashed";
      r.message = "killed by signal " + std::to_string(outcome.signal) + " (" +
                  strsignal(outcome.signal) + "); last stderr line: " + said;
      break;
    case ProcessOutcome::End::kExited:
      if (outcome.exit_code != 0) {
        r.verdict = "error";
        r.message = (outcome.exit_code == 2   ? "input error (exit 2): "
                     : outcome.exit_code == 3 ? "internal error (exit 3): "
                                              : "exit code " + std::to_string(outcome.exit_code) +
                                                    ": ") +
                    said;
        break;
      }
      {
        std::vector<std::string> paths;
        for (const auto* list : {&m.checks, &m.pooled_checks})
          for (const Check& k : *list)
            for (const std::string& f : {k.figure, k.bound_figure})
              if (f.rfind("summary.", 0) == 0 || f.rfind("eval.", 0) == 0) paths.push_back(f);
        const CaseFiles files = ReadCaseFiles(case_dir, truth_path);
        r.figures = ExtractFigures(files, paths);
        if (!files.summary.is_object()) {
          r.verdict = "error";
          r.message = "exit 0 but no readable summary.json in " + r.dir;
          break;
        }
        std::string failed;
        for (const Check& k : m.checks) {
          const CheckResult cr = Evaluate(k, r.figures);
          r.checks.push_back(ToOutcome(cr));
          if (!cr.passed) failed += (failed.empty() ? "" : "; ") + Describe(cr);
        }
        r.verdict = failed.empty() ? "passed" : "failed";
        r.message = failed;
      }
      break;
  }
  r.bytes_written = FolderBytes(case_dir);
  return r;
}

namespace {

// DIR for this manifest: a new folder gets the manifest's copy; with --resume the copy must be
// the same bytes, and finished cases (case.json) are read back.
std::vector<std::optional<CaseResult>> OpenFolder(const Manifest& m, const RunOptions& o,
                                                  const std::vector<Case>& cases) {
  const fs::path out(o.out_dir);
  fs::create_directories(out / "cases");
  const fs::path copy = out / kManifestCopy;
  if (fs::exists(copy)) {
    if (!o.resume)
      throw InputError(o.out_dir, "the folder holds a suite already", "",
                       "--resume to finish it, or a new folder");
    if (io::ReadTextFile(copy.string()) != m.text)
      throw InputError(o.out_dir, "the folder's suite.manifest.yaml differs from " + m.path, "",
                       "the same manifest to --resume");
  } else {
    io::WriteFileAtomically(copy.string(), m.text);
  }
  std::vector<std::optional<CaseResult>> results(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path cj = out / "cases" / cases[i].id / kCaseJson;
    if (o.resume && fs::is_regular_file(cj))
      results[i] = CaseResultFromJson(nlohmann::json::parse(io::ReadTextFile(cj.string())),
                                      cj.string());
  }
  return results;
}

// Makes the random floors and imports the unfinished cases need; scene index -> the failure.
std::map<std::size_t, std::string> PrepareScenes(const Manifest& m, const RunOptions& o,
                                                 const std::vector<Case>& cases,
                                                 const std::vector<std::size_t>& pending) {
  std::map<std::size_t, std::string> errors;
  if (o.command) return errors;
  std::set<std::size_t> need;
  for (std::size_t i : pending) {
    const SceneEntry& s = m.scenes[cases[i].scene];
    if (s.kind == SceneEntry::Kind::kRandom || s.kind == SceneEntry::Kind::kImport)
      need.insert(cases[i].scene);
  }
  for (std::size_t si : need) {
    if (!o.quiet) std::printf("making scene %s\n", m.scenes[si].name.c_str());
    const std::string e = PrepareScene(m.scenes[si], o, m.scenes[si].limits.value_or(m.limits));
    if (!e.empty()) errors[si] = e;
  }
  return errors;
}

// The running suite: starts cases, classifies their ends, writes each case.json.
class SuiteLoop {
 public:
  SuiteLoop(const Manifest& m, const RunOptions& o, const std::vector<Case>& cases,
            std::vector<std::optional<CaseResult>>& results)
      : m_(m), o_(o), cases_(cases), results_(results), out_(o.out_dir),
        keep_(o.keep.empty() ? m.keep : o.keep) {
    for (const auto& r : results_)
      if (r) ++done_, bad_ += r->verdict != "passed";
  }

  // Runs `pending`; false when a stop signal came (running cases killed).
  bool Run(const std::vector<std::size_t>& pending,
           const std::map<std::size_t, std::string>& scene_error) {
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t next = 0;
    while (next < pending.size() || pool_.Running() > 0) {
      if (g_stop_signal != 0) {
        pool_.KillAll();
        return false;
      }
      while (next < pending.size() &&
             pool_.Running() < static_cast<std::size_t>(std::max(1, o_.jobs))) {
        const std::size_t i = pending[next++];
        if (auto e = scene_error.find(cases_[i].scene); e != scene_error.end()) {
          fs::remove_all(CaseDir(i));
          CaseResult r = Skeleton(m_, cases_[i]);
          r.verdict = "error";
          r.message = e->second;
          Finish(i, r);
        } else {
          Start(i);
        }
      }
      for (auto& [tag, outcome] : pool_.Wait(0.5)) {
        const std::size_t i = static_cast<std::size_t>(tag);
        const std::string dir = CaseDir(i).string();
        Finish(i, Classify(m_, cases_[i], outcome, dir,
                           TruthPath(m_.scenes[cases_[i].scene], dir, o_.out_dir),
                           LastLine((CaseDir(i) / "suite.stderr.log").string())));
      }
      Progress(o_.progress, done_, cases_.size(), pool_.Running(), bad_,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
               case_s_sum_, measured_, o_.jobs);
    }
    if (o_.progress) std::printf("\r\033[K");
    return true;
  }
  std::size_t Done() const { return done_; }

 private:
  fs::path CaseDir(std::size_t i) const { return out_ / "cases" / cases_[i].id; }

  void Start(std::size_t i) {
    const Case& c = cases_[i];
    const fs::path dir = CaseDir(i);
    fs::remove_all(dir);  // an unfinished earlier attempt
    fs::create_directories(dir);
    ProcessSpec p;
    if (o_.command) {
      p.argv = o_.command(c, dir.string());
    } else {
      const std::string cfg = CaseConfigYaml(m_, c);
      if (!cfg.empty()) io::WriteFileAtomically((dir / "suite.config.yaml").string(), cfg);
      p.argv = RunArgs(m_, c, dir.string(), SceneDir(o_.out_dir, m_.scenes[c.scene]), keep_,
                       !cfg.empty());
      p.argv.insert(p.argv.begin(), o_.program);
    }
    p.stdout_path = (dir / "suite.stdout.log").string();
    p.stderr_path = (dir / "suite.stderr.log").string();
    p.wall_limit_s = c.limits.wall_s;
    p.memory_limit_mb = c.limits.memory_mb;
    pool_.Start(static_cast<int>(i), p);
  }

  void Finish(std::size_t i, CaseResult r) {
    const fs::path dir = CaseDir(i);
    fs::create_directories(dir);
    io::WriteFileAtomically((dir / kCaseJson).string(), ToJson(r).dump(1) + "\n");
    ++done_;
    bad_ += r.verdict != "passed";
    case_s_sum_ += r.wall_s;
    ++measured_;
    if (o_.progress) std::printf("\r\033[K");
    if (!o_.quiet)
      std::printf("[%zu/%zu] %s: %s%s%s\n", done_, cases_.size(), r.id.c_str(),
                  r.verdict.c_str(), r.message.empty() ? "" : ": ", r.message.c_str());
    std::fflush(stdout);
    results_[i] = std::move(r);
  }

  const Manifest& m_;
  const RunOptions& o_;
  const std::vector<Case>& cases_;
  std::vector<std::optional<CaseResult>>& results_;
  const fs::path out_;
  const std::string keep_;
  ProcessPool pool_;
  std::size_t done_ = 0, bad_ = 0, measured_ = 0;
  double case_s_sum_ = 0.0;
};

}  // namespace

int RunSuite(const Manifest& m, const RunOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Case> cases;
  for (const Case& c : ExpandCases(m))
    if (o.shard.Contains(c)) cases.push_back(c);
  std::vector<std::optional<CaseResult>> results = OpenFolder(m, o, cases);
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < cases.size(); ++i)
    if (!results[i]) pending.push_back(i);
  if (!o.quiet) {
    std::string what = std::to_string(cases.size()) + " cases";
    if (o.shard.count > 1)
      what += " (shard " + std::to_string(o.shard.index) + "/" + std::to_string(o.shard.count) + ")";
    if (pending.size() < cases.size())
      what += ", " + std::to_string(cases.size() - pending.size()) + " finished before";
    std::printf("suite %s: %s, %d at a time, into %s\n", m.name.c_str(), what.c_str(), o.jobs,
                o.out_dir.c_str());
  }
  g_stop_signal = 0;
  struct sigaction sa {}, old_int{}, old_term{};
  sa.sa_handler = OnSuiteStop;
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  const auto scene_error = PrepareScenes(m, o, cases, pending);
  SuiteLoop loop(m, o, cases, results);
  const bool finished = loop.Run(pending, scene_error);
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  if (!finished) {
    std::printf("\nsuite: interrupted (signal %d); %zu of %zu cases finished; "
                "`mopad suite run %s -o %s --resume` finishes it\n",
                g_stop_signal.load(), loop.Done(), cases.size(), m.path.c_str(),
                o.out_dir.c_str());
    return 130;
  }
  std::vector<CaseResult> list;
  for (auto& r : results) list.push_back(*r);
  const SuiteSummary s = WriteSuiteOutputs(o.out_dir, m, list);
  if (!o.quiet) {
    int pooled_failed = 0;
    for (const auto& p : s.pooled_checks) pooled_failed += !p.passed;
    std::printf("suite %s: %d cases: %d passed, %d failed, %d error, %d timeout, %d crashed; "
                "%d of %zu pooled checks failed (%.0f s); wrote %s/{suite.json,junit.xml,"
                "scoreboard.md,scoreboard.html}\n",
                m.name.c_str(), s.totals.at("cases"), s.totals.at("passed"), s.totals.at("failed"),
                s.totals.at("error"), s.totals.at("timeout"), s.totals.at("crashed"),
                pooled_failed, s.pooled_checks.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                o.out_dir.c_str());
  }
  return s.all_passed ? 0 : 1;
}

}  // namespace mopad::suite
