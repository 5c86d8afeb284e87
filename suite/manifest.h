#pragma once
// A suite manifest (docs/suites.md): the YAML file `mopad suite run` reads. Scenes, seeds,
// configs and sweeps are crossed into cases (suite/cases.h); limits bound each case's process;
// checks are thresholds on the case's figures (suite/checks.h). Parsing starts from the
// defaults below and rejects unknown keys with `file:line: error: ...` (mopad::InputError).
//
// Relative paths in the manifest (spec files, scene folders, BIM files, config files) are
// resolved against the manifest's own folder, so a suite runs the same from any directory.
// Files named by the manifest are not opened here: a missing or malformed scene file is the
// case's error verdict, not the suite's.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "suite/checks.h"

namespace mopad::suite {

/// Per-case resource limits; 0 means "no limit".
struct Limits {
  double wall_s = 0.0;     ///< s, wall-clock time of the case's process, >= 0
  double memory_mb = 0.0;  ///< MB (10^6 bytes), resident memory of the case's process, >= 0
};

/// One scene of the suite, as the case's `mopad run` receives it.
struct SceneEntry {
  enum class Kind { kSpec, kFolder, kRandom, kImport };
  Kind kind = Kind::kSpec;
  /// the group's first part: file stem, folder name, random-s<S>-r<R> (office floors) or
  /// random-<family>-s<S>-r<R>, ...
  std::string name;
  std::string path;  ///< kSpec: spec file; kFolder: scene folder; kImport: BIM file (resolved)
  std::uint64_t random_seed = 0;   ///< kRandom: `mopad scene random --seed`
  int random_rooms = 0;            ///< kRandom: `--rooms`, 2-10
  std::string random_family = "office";  ///< kRandom: `--family` (scenes/random_floor.h)
  std::string storey;              ///< kImport: `--storey` ("" = the importer's default)
  std::vector<std::string> args;   ///< kImport: further `mopad scene import` arguments
  std::optional<Limits> limits;    ///< this scene's limits (keys it omits: the suite's)
  std::string where;               ///< manifest file:line, for messages
};

/// A named config overlay: YAML over FloorMissionParams' defaults (`mopad run --config`).
struct ConfigEntry {
  std::string name;
  std::string yaml;  ///< the overlay as YAML text ("" = the defaults)
};

/// A swept parameter: a dotted key of FloorMissionParams and its values (YAML scalars).
struct Sweep {
  std::string key;
  std::vector<std::string> values;
};

struct Manifest {
  std::string name;  ///< `suite:` (default: the file's stem)
  std::string path;  ///< the manifest's path as given
  std::string text;  ///< the manifest's bytes (a suite folder keeps a copy for merge/resume)
  std::vector<SceneEntry> scenes;
  std::vector<std::uint64_t> seeds{1};
  std::vector<ConfigEntry> configs;  ///< empty: one unnamed config (the defaults)
  std::vector<Sweep> sweeps;
  Limits limits;
  std::string keep = "summary";         ///< `mopad run --keep` of every case
  std::vector<std::string> run_args;    ///< further `mopad run` arguments (e.g. --step-deg 0.5)
  std::vector<Check> checks;            ///< per case
  std::vector<Check> pooled_checks;     ///< per group, over its seeds (mean/min/max)
};

/// Parses manifest text; `path` names it in messages and anchors relative paths.
Manifest ParseManifest(const std::string& text, const std::string& path);
/// Reads and parses a manifest file.
Manifest LoadManifest(const std::string& path);

/// "1-3" / 7 / [1, "4-6"] style integer lists (a YAML scalar or sequence); InputError at file:line.
std::vector<std::uint64_t> ParseIntList(const std::string& file, const std::string& key,
                                        const std::string& where, const std::string& text);

}  // namespace mopad::suite
