#pragma once
// Parameter structs: plain aggregates with defaults, one field list drives YAML load, save,
// validation and the effective config each run writes beside its results.
//
//   struct FooParams {
//     double max_range = 30.0;  ///< m, (0, 1000]
//     int rays = 7;             ///< count, [1, 64]
//     template <class V> void Visit(V& v) {
//       v("max_range", max_range, Bounds{1e-9, 1000.0});
//       v("rays", rays, Bounds{1, 64});
//     }
//   };
//   FooParams p = LoadParamsFile<FooParams>("foo.yaml");   // defaults, then the file
//
// Loading starts from the defaults, rejects unknown keys and wrong types with
// `file:line: error: ...`, and checks every bound. Nested structs with Visit() nest in YAML.
// Fields are scalars (numbers, booleans, strings), std::vector of scalars (a YAML sequence),
// std::map<std::string, scalar> (a YAML map; Bounds apply to its values) or params structs.
// Composing: `v("part", part)` nests a member's keys under "part"; `part.Visit(v)` lists them
// at this level (the keys of a struct that holds another are then those of both).

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "common/error.h"

namespace mopad {

/// Closed interval a numeric field must lie in.
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
};

/// "file:line" for a YAML node (line is 1-based); just "file" if the node has no mark.
std::string YamlWhere(const std::string& file, const YAML::Node& node);
/// Reads a YAML file, translating missing files and parser errors into InputError.
YAML::Node LoadYamlFile(const std::string& path);
/// Parses YAML text (for tests and embedded defaults); `name` is used in messages.
YAML::Node LoadYamlString(const std::string& text, const std::string& name);
/// Throws InputError for any key of `node` (a map) that is not in `known`.
void RejectUnknownKeys(const YAML::Node& node, const std::set<std::string>& known,
                       const std::string& file, const std::string& context);

template <class T, class = void>
struct HasVisit : std::false_type {};
template <class T>
struct HasVisit<T, std::void_t<decltype(std::declval<T&>().Visit(std::declval<int&>()))>>
    : std::true_type {};

template <class T, class = void>
struct HasValidate : std::false_type {};
template <class T>
struct HasValidate<T, std::void_t<decltype(std::declval<const T&>().Validate())>>
    : std::true_type {};

namespace detail {

template <class T>
struct IsVector : std::false_type {};
template <class T, class A>
struct IsVector<std::vector<T, A>> : std::true_type {};
template <class T>
struct IsStringMap : std::false_type {};
template <class T, class C, class A>
struct IsStringMap<std::map<std::string, T, C, A>> : std::true_type {};

template <class T>
std::string TypeName() {
  if constexpr (std::is_same_v<T, bool>)
    return "a boolean";
  else if constexpr (std::is_integral_v<T>)
    return "an integer";
  else if constexpr (std::is_floating_point_v<T>)
    return "a number";
  else if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else
    return "a value";
}

template <class T>
void CheckBounds(const std::string& where, const std::string& key, const T& value, Bounds b) {
  if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    const double v = static_cast<double>(value);
    if (!std::isfinite(v) || v < b.lo || v > b.hi) {
      throw InputError(where, "parameter '" + key + "' out of range", std::to_string(value),
                       "[" + std::to_string(b.lo) + ", " + std::to_string(b.hi) + "]");
    }
  } else if constexpr (IsVector<T>::value) {
    for (const auto& x : value) CheckBounds(where, key, x, b);
  } else if constexpr (IsStringMap<T>::value) {
    for (const auto& [name, x] : value) CheckBounds(where, key + "." + name, x, b);
  }
}

/// Reads fields from a YAML map, starting from the struct's current (default) values.
class YamlReader {
 public:
  YamlReader(const YAML::Node& node, std::string file, std::string prefix)
      : node_(node), file_(std::move(file)), prefix_(std::move(prefix)) {}

  template <class T>
  void operator()(const char* key, T& value, Bounds b = {}) {
    known_.insert(key);
    const YAML::Node child = node_[key];
    const std::string name = prefix_ + key;
    if (!child) return;  // keep the default
    const std::string where = YamlWhere(file_, child);
    if constexpr (HasVisit<T>::value) {
      if (!child.IsMap()) throw InputError(where, "'" + name + "' must be a map");
      YamlReader sub(child, file_, name + ".");
      value.Visit(sub);
      sub.Finish();
    } else {
      try {
        if constexpr (IsVector<T>::value) {
          if (!child.IsSequence()) throw YAML::Exception(child.Mark(), "not a sequence");
        } else if constexpr (IsStringMap<T>::value) {
          if (!child.IsMap()) throw YAML::Exception(child.Mark(), "not a map");
        } else if (!child.IsScalar()) {
          throw YAML::Exception(child.Mark(), "not a scalar");
        }
        value = child.as<T>();
      } catch (const YAML::Exception&) {
        throw InputError(where, "wrong type for '" + name + "'", Describe(child), TypeName<T>());
      }
      CheckBounds(where, name, value, b);
    }
  }
  void Finish() const { RejectUnknownKeys(node_, known_, file_, prefix_); }

 private:
  static std::string Describe(const YAML::Node& n) {
    if (n.IsScalar()) return "'" + n.Scalar() + "'";
    if (n.IsSequence()) return "a sequence";
    if (n.IsMap()) return "a map";
    return "null";
  }
  const YAML::Node& node_;
  std::string file_, prefix_;
  std::set<std::string> known_;
};

/// Writes fields into a YAML map.
class YamlWriter {
 public:
  explicit YamlWriter(YAML::Node& node) : node_(node) {}
  template <class T>
  void operator()(const char* key, const T& value, Bounds = {}) {
    if constexpr (HasVisit<T>::value) {
      YAML::Node child(YAML::NodeType::Map);
      YamlWriter sub(child);
      const_cast<T&>(value).Visit(sub);
      node_[key] = child;
    } else {
      node_[key] = value;
    }
  }

 private:
  YAML::Node& node_;
};

/// Checks every field's bounds (for structs built in code rather than loaded), and the checks
/// of every nested params struct that has its own `Validate()` (relations between fields, names
/// of profiles), so that one ValidateParams before any work refuses all that its parts would.
class BoundsChecker {
 public:
  explicit BoundsChecker(std::string context) : context_(std::move(context)) {}
  template <class T>
  void operator()(const char* key, const T& value, Bounds b = {}) {
    if constexpr (HasVisit<T>::value) {
      BoundsChecker sub(context_ + key + ".");
      const_cast<T&>(value).Visit(sub);
      if constexpr (HasValidate<T>::value) {
        try {
          value.Validate();
        } catch (const InputError& e) {
          // Its message names the field within the struct; the prefix says which struct.
          throw InputError(context_ + key + ": " + e.what());
        }
      }
    } else {
      CheckBounds("", context_ + key, value, b);
    }
  }

 private:
  std::string context_;
};

}  // namespace detail

/// Loads a params struct from a YAML map node (defaults for absent keys).
template <class T>
T LoadParams(const YAML::Node& node, const std::string& file) {
  T params;
  if (!node || node.IsNull()) return params;
  if (!node.IsMap()) throw InputError(YamlWhere(file, node), "parameters must be a YAML map");
  detail::YamlReader reader(node, file, "");
  params.Visit(reader);
  reader.Finish();
  return params;
}

template <class T>
T LoadParamsFile(const std::string& path) {
  return LoadParams<T>(LoadYamlFile(path), path);
}

/// Serialises every field (the effective config).
template <class T>
YAML::Node SaveParams(const T& params) {
  YAML::Node node(YAML::NodeType::Map);
  detail::YamlWriter writer(node);
  const_cast<T&>(params).Visit(writer);
  return node;
}

/// Throws InputError naming the first field outside its bounds, or the first nested params
/// struct whose own Validate() refuses its values (the struct's own Validate(), if any, is its
/// caller's to call: it usually calls this).
template <class T>
void ValidateParams(const T& params, const std::string& context = "") {
  detail::BoundsChecker checker(context);
  const_cast<T&>(params).Visit(checker);
}

/// Fields of a params struct that Visit() does not reach: byte ranges of `params` (and of its
/// nested params structs, recursively) that no visited field covers, beyond the padding the
/// alignment of the next field allows, and fields visited twice. Empty when the one field list
/// is complete. For tests: a round trip through YAML cannot see a field Visit() forgets (it
/// keeps its default on both sides). A forgotten field smaller than the padding before the next
/// one (a bool beside bools) can escape it.
template <class T>
std::vector<std::string> FieldsMissingFromVisit(const T& params, const std::string& context = "");

namespace detail {

struct VisitedField {
  std::size_t offset, size, align;
  std::string key;
};

class FieldRecorder {
 public:
  FieldRecorder(const void* base, std::string context, std::vector<std::string>& problems)
      : base_(static_cast<const char*>(base)), context_(std::move(context)), problems_(problems) {}
  template <class U>
  void operator()(const char* key, const U& value, Bounds = {}) {
    fields_.push_back({static_cast<std::size_t>(reinterpret_cast<const char*>(&value) - base_),
                       sizeof(U), alignof(U), key});
    if constexpr (HasVisit<U>::value) {
      for (auto& p : FieldsMissingFromVisit(value, context_ + key + "."))
        problems_.push_back(std::move(p));
    }
  }
  void Check(std::size_t struct_size, std::size_t struct_align) {
    std::sort(fields_.begin(), fields_.end(),
              [](const VisitedField& a, const VisitedField& b) { return a.offset < b.offset; });
    std::size_t end = 0;
    std::string after = "(start)";
    for (const VisitedField& f : fields_) {
      if (f.offset < end) {
        problems_.push_back(context_ + f.key + ": visited twice or overlapping '" + after + "'");
      } else if (f.offset - end >= f.align) {
        problems_.push_back(context_ + ": " + std::to_string(f.offset - end) + " bytes between '" +
                            after + "' and '" + f.key + "' are not visited");
      }
      end = std::max(end, f.offset + f.size);
      after = f.key;
    }
    if (struct_size - end >= struct_align)
      problems_.push_back(context_ + ": " + std::to_string(struct_size - end) + " bytes after '" +
                          after + "' are not visited");
  }

 private:
  const char* base_;
  std::string context_;
  std::vector<std::string>& problems_;
  std::vector<VisitedField> fields_;
};

}  // namespace detail

template <class T>
std::vector<std::string> FieldsMissingFromVisit(const T& params, const std::string& context) {
  std::vector<std::string> problems;
  detail::FieldRecorder recorder(&params, context, problems);
  const_cast<T&>(params).Visit(recorder);
  recorder.Check(sizeof(T), alignof(T));
  return problems;
}

}  // namespace mopad
