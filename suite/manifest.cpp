#include "suite/manifest.h"

#include <cstdlib>
#include <filesystem>
#include <set>

#include "common/error.h"
#include "common/params.h"
#include "io/text_file.h"
#include "scenes/random_floor.h"

namespace mopad::suite {

namespace fs = std::filesystem;

namespace {

// The parse context: the file's name (messages) and folder (relative paths).
struct Ctx {
  std::string file;
  fs::path dir;

  std::string Where(const YAML::Node& n) const { return YamlWhere(file, n); }
  std::string Path(const YAML::Node& n) const {
    const fs::path p(Scalar(n, "a path"));
    return (p.is_absolute() ? p : dir / p).lexically_normal().string();
  }
  std::string Scalar(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) throw InputError(Where(n), "expected " + what, "", "a scalar");
    return n.Scalar();
  }
  double Number(const YAML::Node& n, const std::string& key, double lo) const {
    const std::string s = Scalar(n, key);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !(v >= lo))
      throw InputError(Where(n), "bad " + key, "'" + s + "'", "a number >= " + std::to_string(lo));
    return v;
  }
};

std::uint64_t ParseUint(const std::string& s, const std::string& where, const std::string& key) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18)
    throw InputError(where, "bad " + key, "'" + s + "'", "a non-negative integer or a range A-B");
  return std::stoull(s);
}

std::vector<std::uint64_t> IntList(const Ctx& c, const YAML::Node& n, const std::string& key) {
  std::vector<std::uint64_t> out;
  auto add = [&](const YAML::Node& item) {
    for (auto v : ParseIntList(c.file, key, c.Where(item), c.Scalar(item, key))) out.push_back(v);
  };
  if (n.IsSequence()) {
    for (const auto& item : n) add(item);
  } else {
    add(n);
  }
  if (out.empty()) throw InputError(c.Where(n), "empty " + key, "", "at least one value");
  std::set<std::uint64_t> seen;
  for (auto v : out)
    if (!seen.insert(v).second)
      throw InputError(c.Where(n), "repeated value in " + key, std::to_string(v), "each once");
  return out;
}

Limits ParseLimits(const Ctx& c, const YAML::Node& n, Limits base) {
  if (!n.IsMap()) throw InputError(c.Where(n), "limits must be a map", "", "wall_s, memory_mb");
  RejectUnknownKeys(n, {"wall_s", "memory_mb"}, c.file, "limits.");
  if (n["wall_s"]) base.wall_s = c.Number(n["wall_s"], "limits.wall_s", 0.0);
  if (n["memory_mb"]) base.memory_mb = c.Number(n["memory_mb"], "limits.memory_mb", 0.0);
  return base;
}

// The stem of the last named element of `path` ("a/b.yaml" and "a/b/" give "b"); empty for
// a root ("/", "//"), which names nothing (and is its own parent).
std::string Stem(const std::string& path) {
  fs::path p(path);
  while (p.has_relative_path() && p.filename().empty()) p = p.parent_path();
  return p.stem().string();
}

void ParseScene(const Ctx& c, const YAML::Node& n, const Limits& suite_limits,
                std::vector<SceneEntry>& out) {
  if (!n.IsMap())
    throw InputError(c.Where(n), "a scene must be a map", "", "spec:, folder:, random: or import:");
  RejectUnknownKeys(n, {"spec", "folder", "random", "import", "name", "limits"}, c.file, "scenes[].");
  int kinds = (n["spec"] ? 1 : 0) + (n["folder"] ? 1 : 0) + (n["random"] ? 1 : 0) +
              (n["import"] ? 1 : 0);
  if (kinds != 1)
    throw InputError(c.Where(n), "a scene names exactly one source", std::to_string(kinds),
                     "one of spec:, folder:, random:, import:");
  SceneEntry e;
  e.where = c.Where(n);
  if (n["limits"]) e.limits = ParseLimits(c, n["limits"], suite_limits);
  const std::string given_name = n["name"] ? c.Scalar(n["name"], "name") : "";
  if (n["spec"]) {
    e.kind = SceneEntry::Kind::kSpec;
    e.path = c.Path(n["spec"]);
    e.name = Stem(e.path);
  } else if (n["folder"]) {
    e.kind = SceneEntry::Kind::kFolder;
    e.path = c.Path(n["folder"]);
    e.name = Stem(e.path);
  } else if (n["import"]) {
    const YAML::Node& m = n["import"];
    if (!m.IsMap() || !m["file"])
      throw InputError(c.Where(m), "import: needs a map with file:", "", "file, storey, args");
    RejectUnknownKeys(m, {"file", "storey", "args"}, c.file, "import.");
    e.kind = SceneEntry::Kind::kImport;
    e.path = c.Path(m["file"]);
    if (m["storey"]) e.storey = c.Scalar(m["storey"], "import.storey");
    if (m["args"]) {
      if (!m["args"].IsSequence())
        throw InputError(c.Where(m["args"]), "import.args must be a list", "", "CLI arguments");
      for (const auto& a : m["args"]) e.args.push_back(c.Scalar(a, "an argument"));
    }
    e.name = Stem(e.path);
  } else {
    const YAML::Node& m = n["random"];
    if (!m.IsMap() || !m["seeds"] || !m["rooms"])
      throw InputError(c.Where(m), "random: needs seeds: and rooms:", "", "a map");
    RejectUnknownKeys(m, {"seeds", "rooms", "family"}, c.file, "random.");
    if (!given_name.empty())
      throw InputError(c.Where(n["name"]),
                       "random scenes are named random[-<FAMILY>]-s<SEED>-r<ROOMS>");
    std::string family = "office";
    if (m["family"]) {
      family = c.Scalar(m["family"], "a floor family");
      try {
        scenes::ParseFloorFamily(family);
      } catch (const InputError&) {
        throw InputError(c.Where(m["family"]), "bad random.family", "'" + family + "'",
                         "office, corridor, junction, hall or mixed");
      }
    }
    const std::string prefix = family == "office" ? "random-" : "random-" + family + "-";
    for (std::uint64_t s : IntList(c, m["seeds"], "random.seeds")) {
      for (std::uint64_t r : IntList(c, m["rooms"], "random.rooms")) {
        if (r < 2 || r > 10)
          throw InputError(c.Where(m["rooms"]), "bad random.rooms", std::to_string(r), "2-10");
        SceneEntry k = e;
        k.kind = SceneEntry::Kind::kRandom;
        k.random_seed = s;
        k.random_rooms = static_cast<int>(r);
        k.random_family = family;
        k.name = prefix + "s" + std::to_string(s) + "-r" + std::to_string(r);
        out.push_back(k);
      }
    }
    return;
  }
  if (!given_name.empty()) e.name = given_name;
  if (e.name.empty())
    throw InputError(e.where, "the scene's path names no file or folder to call the scene after",
                     "'" + e.path + "'", "a path below the root, or name:");
  out.push_back(e);
}

// A name used in case ids and folder names: letters, digits, '_', '-', '.' only.
void CheckName(const std::string& name, const std::string& where, const std::string& what) {
  if (name.empty() || name == "." || name == ".." ||
      name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") !=
          std::string::npos)
    throw InputError(where, "bad " + what + " name", "'" + name + "'",
                     "letters, digits, '_', '-', '.' (it names folders)");
}

}  // namespace

std::vector<std::uint64_t> ParseIntList(const std::string& /*file*/, const std::string& key,
                                        const std::string& where, const std::string& text) {
  const auto dash = text.find('-');
  if (dash == std::string::npos) return {ParseUint(text, where, key)};
  const std::uint64_t a = ParseUint(text.substr(0, dash), where, key);
  const std::uint64_t b = ParseUint(text.substr(dash + 1), where, key);
  if (b < a || b - a > 100000)
    throw InputError(where, "bad range in " + key, "'" + text + "'", "A-B with A <= B");
  std::vector<std::uint64_t> out;
  for (std::uint64_t v = a; v <= b; ++v) out.push_back(v);
  return out;
}

Manifest ParseManifest(const std::string& text, const std::string& path) {
  const YAML::Node root = LoadYamlString(text, path);
  Ctx c{path, fs::path(path).parent_path()};
  if (!root.IsMap()) throw InputError(path, "a suite manifest must be a YAML map");
  RejectUnknownKeys(root,
                    {"suite", "scenes", "seeds", "configs", "sweeps", "limits", "keep", "run_args",
                     "checks"},
                    path, "");
  Manifest m;
  m.path = path;
  m.text = text;
  m.name = root["suite"] ? c.Scalar(root["suite"], "suite") : Stem(path);
  CheckName(m.name, c.Where(root["suite"]), "suite");
  if (!root["scenes"] || !root["scenes"].IsSequence() || root["scenes"].size() == 0)
    throw InputError(c.Where(root["scenes"] ? root["scenes"] : root), "scenes: missing or empty",
                     "", "a list of scenes");
  if (root["limits"]) m.limits = ParseLimits(c, root["limits"], Limits{});
  for (const auto& s : root["scenes"]) ParseScene(c, s, m.limits, m.scenes);
  std::set<std::string> names;
  for (const auto& s : m.scenes) {
    CheckName(s.name, s.where, "scene");
    if (!names.insert(s.name).second)
      throw InputError(s.where, "two scenes named '" + s.name + "'", "", "name: to tell them apart");
  }
  if (root["seeds"]) m.seeds = IntList(c, root["seeds"], "seeds");
  if (const YAML::Node& cf = root["configs"]) {
    if (!cf.IsMap()) throw InputError(c.Where(cf), "configs must be a map", "", "NAME: overlay");
    for (const auto& kv : cf) {
      ConfigEntry e;
      e.name = kv.first.as<std::string>();
      CheckName(e.name, c.Where(kv.first), "config");
      const YAML::Node& v = kv.second;
      if (v.IsNull()) {
      } else if (v.IsScalar()) {  // a file of its own
        const std::string file = c.Path(v);
        e.yaml = YAML::Dump(LoadYamlFile(file));
      } else if (v.IsMap()) {
        e.yaml = YAML::Dump(v);
      } else {
        throw InputError(c.Where(v), "config '" + e.name + "'", "a list",
                         "a map (inline overlay), a file name or null (the defaults)");
      }
      m.configs.push_back(e);
    }
  }
  if (const YAML::Node& sw = root["sweeps"]) {
    if (!sw.IsSequence()) throw InputError(c.Where(sw), "sweeps must be a list", "", "key/values");
    for (const auto& s : sw) {
      if (!s.IsMap() || !s["key"] || !s["values"] || !s["values"].IsSequence())
        throw InputError(c.Where(s), "bad sweep", "", "{key: a.b.c, values: [...]}");
      RejectUnknownKeys(s, {"key", "values"}, path, "sweeps[].");
      Sweep e;
      e.key = c.Scalar(s["key"], "sweep key");
      CheckName(e.key, c.Where(s["key"]), "sweep key");
      for (const auto& v : s["values"]) {
        e.values.push_back(c.Scalar(v, "a sweep value"));
        CheckName(e.values.back(), c.Where(v), "sweep value");
      }
      if (e.values.empty()) throw InputError(c.Where(s), "sweep without values");
      m.sweeps.push_back(e);
    }
  }
  if (root["keep"]) {
    m.keep = c.Scalar(root["keep"], "keep");
    if (m.keep != "summary" && m.keep != "models" && m.keep != "all")
      throw InputError(c.Where(root["keep"]), "bad keep", m.keep, "summary, models or all");
  }
  if (const YAML::Node& ra = root["run_args"]) {
    if (!ra.IsSequence()) throw InputError(c.Where(ra), "run_args must be a list", "", "arguments");
    for (const auto& a : ra) m.run_args.push_back(c.Scalar(a, "an argument"));
  }
  if (const YAML::Node& ch = root["checks"]) {
    if (!ch.IsSequence()) throw InputError(c.Where(ch), "checks must be a list", "", "check texts");
    for (const auto& x : ch) {
      Check k = ParseCheck(c.Scalar(x, "a check"), c.Where(x));
      (k.stat.empty() ? m.checks : m.pooled_checks).push_back(k);
    }
  }
  return m;
}

Manifest LoadManifest(const std::string& path) {
  return ParseManifest(io::ReadTextFile(path), path);
}

}  // namespace mopad::suite
