#include "suite/cases.h"

#include <yaml-cpp/yaml.h>

#include "common/error.h"
#include "common/params.h"

namespace mopad::suite {

std::vector<Case> ExpandCases(const Manifest& m) {
  std::vector<ConfigEntry> configs = m.configs;
  const bool named = !configs.empty();
  if (!named) configs.push_back(ConfigEntry{});
  // The sweep points: the cross product of the sweeps' values, first sweep outermost.
  std::vector<std::vector<std::pair<std::string, std::string>>> points{{}};
  for (const Sweep& s : m.sweeps) {
    std::vector<std::vector<std::pair<std::string, std::string>>> next;
    for (const auto& p : points)
      for (const auto& v : s.values) {
        auto q = p;
        q.emplace_back(s.key, v);
        next.push_back(q);
      }
    points = next;
  }
  std::vector<Case> out;
  for (std::size_t si = 0; si < m.scenes.size(); ++si) {
    const SceneEntry& scene = m.scenes[si];
    for (const ConfigEntry& cfg : configs) {
      for (const auto& point : points) {
        std::string group = scene.name;
        if (named) group += "/" + cfg.name;
        for (const auto& [k, v] : point) group += "/" + k + "=" + v;
        for (std::uint64_t seed : m.seeds) {
          Case c;
          c.index = out.size();
          c.group = group;
          c.id = group + "/seed-" + std::to_string(seed);
          c.scene = si;
          c.seed = seed;
          c.config = cfg.name;
          c.sweep = point;
          c.limits = scene.limits ? *scene.limits : m.limits;
          out.push_back(c);
        }
      }
    }
  }
  return out;
}

Shard ParseShard(const std::string& text) {
  const auto slash = text.find('/');
  Shard s;
  try {
    if (slash == std::string::npos) throw std::invalid_argument(text);
    std::size_t a = 0, b = 0;
    s.index = std::stoi(text.substr(0, slash), &a);
    s.count = std::stoi(text.substr(slash + 1), &b);
    if (a != slash || b != text.size() - slash - 1) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    throw InputError("--shard", "bad shard", "'" + text + "'", "I/N, e.g. 2/3");
  }
  if (s.count < 1 || s.index < 1 || s.index > s.count)
    throw InputError("--shard", "bad shard", "'" + text + "'", "I/N with 1 <= I <= N");
  return s;
}

std::string CaseConfigYaml(const Manifest& m, const Case& c) {
  YAML::Node root(YAML::NodeType::Map);
  for (const ConfigEntry& e : m.configs)
    if (e.name == c.config && !e.yaml.empty()) root = LoadYamlString(e.yaml, "config " + e.name);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  for (const auto& [key, value] : c.sweep) {
    YAML::Node node = root;
    std::string rest = key;
    for (auto dot = rest.find('.'); dot != std::string::npos; dot = rest.find('.')) {
      const std::string part = rest.substr(0, dot);
      YAML::Node child = node[part];
      if (!child.IsMap()) {
        node[part] = YAML::Node(YAML::NodeType::Map);
        child = node[part];
      }
      node.reset(child);
      rest = rest.substr(dot + 1);
    }
    node[rest] = YAML::Load(value);
  }
  if (root.size() == 0) return "";
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace mopad::suite
