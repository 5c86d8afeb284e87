#include "common/params.h"

#include <filesystem>

namespace mopad {

std::string YamlWhere(const std::string& file, const YAML::Node& node) {
  if (node && node.Mark().line >= 0) return file + ":" + std::to_string(node.Mark().line + 1);
  return file;
}

YAML::Node LoadYamlFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path, "cannot open file", "", "an existing YAML file");
  }
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1), "invalid YAML: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(path, std::string("cannot read YAML: ") + e.what());
  }
}

YAML::Node LoadYamlString(const std::string& text, const std::string& name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(name + ":" + std::to_string(e.mark.line + 1), "invalid YAML: " + e.msg);
  }
}

void RejectUnknownKeys(const YAML::Node& node, const std::set<std::string>& known,
                       const std::string& file, const std::string& context) {
  if (!node.IsMap()) return;
  const auto expected = [&] {
    std::string names;
    for (const auto& k : known) names += (names.empty() ? "" : ", ") + k;
    return "one of: " + names;
  };
  for (const auto& kv : node) {
    // A key that is a sequence or a map (`? [a, b]`) names no field.
    if (!kv.first.IsScalar())
      throw InputError(YamlWhere(file, kv.first),
                       context.empty() ? "a key is not a name"
                                       : "a key under '" + context.substr(0, context.size() - 1) +
                                             "' is not a name",
                       kv.first.IsSequence() ? "a sequence" : "a map", expected());
    const std::string key = kv.first.Scalar();
    if (!known.count(key))
      throw InputError(YamlWhere(file, kv.first), "unknown key '" + context + key + "'", "",
                       expected());
  }
}

}  // namespace mopad
