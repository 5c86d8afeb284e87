#pragma once
// Cases: the manifest's scenes x configs x sweep values x seeds, in that nesting order (seeds
// innermost, so a group's seeds sit together). Each case has a stable id,
//
//   <group>/seed-<n>,   group = <scene>[/<config>][/<key>=<value>...]
//
// (the config part only when the manifest names configs; one part per sweep), that depends on
// the manifest alone: never on the shard count, the order cases finish in, or --jobs. The id
// is also the case's folder under DIR/cases/.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "suite/manifest.h"

namespace mopad::suite {

struct Case {
  std::size_t index = 0;  ///< position in the manifest's order (0-based)
  std::string id;
  std::string group;
  std::size_t scene = 0;  ///< index into Manifest::scenes
  std::uint64_t seed = 1;
  std::string config;     ///< "" when the manifest names no configs
  std::vector<std::pair<std::string, std::string>> sweep;  ///< key, value (manifest order)
  Limits limits;          ///< the scene's limits, else the suite's
};

std::vector<Case> ExpandCases(const Manifest& m);

/// `--shard I/N`: case k belongs to shard (k mod N) + 1, so shards are disjoint, cover all cases
/// and each gets a spread of scenes.
struct Shard {
  int index = 1;  ///< 1-based, [1, count]
  int count = 1;  ///< >= 1
  bool Contains(const Case& c) const { return static_cast<int>(c.index % count) + 1 == index; }
};
/// Parses "I/N"; InputError otherwise.
Shard ParseShard(const std::string& text);

/// The YAML text of the case's --config: the config overlay with each sweep key set (dotted
/// keys nest). "" when the case has neither.
std::string CaseConfigYaml(const Manifest& m, const Case& c);

}  // namespace mopad::suite
